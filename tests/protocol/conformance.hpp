// The Modbus conformance suite (issue 8): one table of request PDUs with the
// exact response each must get, run over every transport that serves the
// module: the protocol core in this process (protocol_tests), Modbus TCP against
// trueaxis-sim (test_sim_conformance) and Modbus RTU against the firmware image
// under QEMU (test_rtu_qemu). Each transport adds its own framing cases.
//
// What a case asserts
//  1. The response PDU, byte for byte: the normal response with the values the
//     table put there before, or | fc | 0x80 | code | for an exception.
//  2. No state change: the state (every variable of the product's map but
//     #9007 access_fault and #9010 failed_unlocks, which note refusals by
//     design) read before and after the case is the same, but for the
//     variables the case names in `changes` (a served write).
//
// The expected responses are written from the Modbus Application Protocol
// V1.1b3 (6.3, 6.12, 6.17, 7) and docs/INTERFACE.md ("Encoding": #N is registers
// 4N..4N+3, the binary64 most significant word first), with their own
// encoding of doubles; nothing here calls the code under test to decide what is
// right. The list of variables read for the state comes from the map
// (macros::kRegisterMap): it decides what is read, not what is expected.
//
// No Catch2 here: test_rtu_qemu is a plain program.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace trueaxis::conformance {

using Bytes = std::vector<std::uint8_t>;

struct Case {
  std::string name;
  Bytes pdu;                           // function code and data
  Bytes reply;                         // the whole response PDU
  std::vector<std::uint16_t> changes;  // variables a served write may change
};

// A transport under test: one request PDU out, its response PDU back.
class Transport {
 public:
  virtual ~Transport() = default;
  // False, with `why`, when no valid response came (time-out, closed, bad frame).
  virtual bool exchange(const Bytes& pdu, Bytes& reply, std::string& why) = 0;
};

// The values the whole map holds, as registers, in the order of state_runs().
using State = std::vector<std::uint16_t>;

struct Run {
  std::uint16_t first;
  std::uint16_t count;  // at most 31 variables: one FC3 request
};

// The contiguous runs of product variables read for the state (contract 2).
const std::vector<Run>& state_runs();

// The runs the table's requests address (#1..#9, #100..#130, #500..#508,
// #1001..#1031, #9000..#9006): a transport where a request is slow (RTU under
// QEMU) reads these around each case and the whole state every few cases.
const std::vector<Run>& addressed_runs();

// Reads the variables of `runs` through `t`; false with `why` when a read fails.
bool read_state(Transport& t, State& state, std::string& why, const std::vector<Run>& runs = state_runs());

// The variables of `runs` whose values differ between two states, but for `allowed`.
std::vector<std::uint16_t> changed_variables(const State& before, const State& after,
                                             const std::vector<std::uint16_t>& allowed,
                                             const std::vector<Run>& runs = state_runs());

// The table, in the order it must run (earlier cases set the values later ones
// read). Starts from any state: its first cases write what the others expect.
std::vector<Case> pdu_cases();

struct Outcome {
  std::size_t cases = 0;
  std::vector<std::string> failures;  // "<case>: <what>"
};

// Runs `cases` over `t`, reading the state before and after each (contract 2).
// With `full_every` > 0, only addressed_runs() are read around each case, and
// the whole state every `full_every` cases and after the last, where it may
// differ only in the variables the cases since the last whole read name.
Outcome run_cases(Transport& t, const std::vector<Case>& cases, std::size_t full_every = 0);

// Helpers for transport-specific cases.
std::string hex(const Bytes& b);
void put16(Bytes& b, std::uint32_t v);
// The four registers of a binary64, most significant first, as 8 bytes.
Bytes value_bytes(double v);
Bytes fc3(std::uint32_t address, std::uint32_t quantity);
// FC16 of the given values to whole variables from #first.
Bytes fc16_values(std::uint16_t first, const std::vector<double>& values);
// The FC3 response for the given values.
Bytes fc3_reply(const std::vector<double>& values);

}  // namespace trueaxis::conformance
