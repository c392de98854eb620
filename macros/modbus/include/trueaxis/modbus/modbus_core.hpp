// The Modbus protocol core: one request PDU in, the response PDU (or the
// exception) out. Knows nothing of sockets, serial lines or frames; the
// transports (the TCP server of host_sim/modbus_server.hpp, the RTU framer of
// modbus_rtu.hpp) cut the frames and wrap what respond() writes. Firmware side:
// no allocation, no exceptions, built for the Cortex-M7 too.
//
// Contract
//  1. `pdu` is the function code and its data (no MBAP header), `length` bytes.
//  2. respond() writes the response PDU into `response` (room for kMaxPduBytes)
//     and returns its length: the normal response, or the exception response
//     | fc | 0x80 | code | (2 bytes). When the exception is not kNone the
//     variables are unchanged.
//  3. Served: FC3, FC16, FC23 (write first, then read, as the standard says; the
//     read range is checked by the map before the write is applied, so a request
//     whose read would be refused changes nothing). FC6 can never write a whole
//     variable: exception 02. Any other function code, 0x80..0xFF included:
//     exception 01 (noted in #9007 as bad_function).
//  4. The checks, in the order of the Modbus Application Protocol V1.1b3 (6.3,
//     6.12, 6.17 and their state diagrams), each refusing before the next runs:
//       a. function code not served                                -> 01;
//       b. PDU length not the one its header fields imply (a truncated or
//          over-long PDU), quantity 0 or above the function's maximum
//          (FC3 125, FC16 123, FC23 read 125 / write 121), byte count not
//          twice the write quantity                                 -> 03;
//       c. start + quantity past register 0xFFFF                    -> 02
//          (noted as undefined);
//       d. the map (register_codec.hpp): whole variables, at most 31 per read
//          and 30 per write, defined numbers, access, values, busy -> 02, 03,
//          06 or 04, noted in #9007 by the map.
//     The faults of b are refused before the request reaches the map and are
//     not noted in #9007 (it holds map faults; #9007 keeps its last value).
//  5. The one place where module faults (AccessFault) become exception codes:
//     every refusal goes through modbus_exception() (var_info.hpp, the table
//     the JSON map publishes) here; no transport maps faults itself.
//  6. Stack: about 0.5 KiB (the read words and the write words); no state
//     between calls but the module's.
//  7. `client` names who sent the request (a TCP connection; kRtuMaster for
//     a serial line's one master): the module grants the macro interface to one
//     client at a time (module.hpp contract 8) and refuses another's writes
//     there with exception 06 (interface_held in #9007).
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/modbus/register_codec.hpp"
#include "trueaxis/macros/variable_access.hpp"

namespace trueaxis::modbus {

// The largest PDU Modbus allows (MBAP length 254 minus the unit id).
inline constexpr std::size_t kMaxPduBytes = 253;

// The function codes the core serves (contract 3), for the transports too.
inline constexpr std::uint8_t kFcReadHolding = 0x03;
inline constexpr std::uint8_t kFcWriteSingle = 0x06;
inline constexpr std::uint8_t kFcWriteMultiple = 0x10;
inline constexpr std::uint8_t kFcReadWriteMultiple = 0x17;

class ModbusCore {
 public:
  explicit ModbusCore(VariableAccess& vars) : vars_(vars) {}

  // Contract 2.
  [[nodiscard]] std::size_t respond(const std::uint8_t* pdu, std::size_t length, std::uint8_t* response,
                                    ClientId client = kLocalClient);

 private:
  // What a served request read: `count` registers from protocol `address`.
  struct ReadWords {
    std::uint16_t address = 0;
    std::uint16_t count = 0;
    std::uint16_t words[kMaxVariablesPerRead * kRegistersPerVariable] = {};
  };

  ModbusException decide(const std::uint8_t* pdu, std::size_t length, ReadWords& read);
  ModbusException read_holding(const std::uint8_t* pdu, std::size_t length, ReadWords& read);
  ModbusException write_multiple(const std::uint8_t* pdu, std::size_t length);
  ModbusException read_write_multiple(const std::uint8_t* pdu, std::size_t length, ReadWords& read);
  ModbusException write_single(std::size_t length);

  ModbusException read_into(std::uint16_t address, std::uint16_t quantity, ReadWords& read);
  ModbusException write_from(std::uint16_t address, std::uint16_t quantity, const std::uint8_t* bytes);
  ModbusException past_last_register(std::uint16_t address, std::uint16_t quantity);

  VariableAccess& vars_;
  ClientId client_ = kLocalClient;  // the request being answered (contract 7)
};

}  // namespace trueaxis::modbus
