// libFuzzer target: the transport-free Modbus core (macros/modbus_core.hpp), the
// code both the TCP and the RTU server run, in front of a real module on RAM
// storage built afresh for every input.
//
// Input: up to kMaxRequests requests, each | length u8 | PDU (length bytes) |;
// after each one the module steps, as the servers do after every request, so a
// sequence can unlock, start a macro and write while it runs.
//
// Invariants checked for every request (modbus_core.hpp contract 2 and 3):
//  1. the response is 2..kMaxPduBytes bytes;
//  2. an exception response is exactly | fc | 0x80 | code |, code one of
//     01, 02, 03, 04, 06;
//  3. a refused request changes no variable (all of the map, bit for bit, but
//     #9007 and #9010, which count refusals), not the unlock, and not one byte
//     of storage; a served FC3 changes nothing either;
//  4. a normal response echoes the function code and has the length its
//     request implies: FC3 and FC23 2 + 2 x read quantity with that byte count,
//     FC16 the echo of address and quantity. Only FC3, FC16 and FC23 succeed.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "trueaxis/modbus/modbus_core.hpp"

namespace {

using trueaxis::fuzz::FreshBench;
using trueaxis::fuzz::Input;
using trueaxis::fuzz::ModuleBench;
using trueaxis::fuzz::Snapshot;
using trueaxis::modbus::kMaxPduBytes;

constexpr int kMaxRequests = 16;

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

bool is_exception_code(std::uint8_t code) {
  return code == 1 || code == 2 || code == 3 || code == 4 || code == 6;
}

void check_normal(const std::uint8_t* pdu, std::size_t length, const std::uint8_t* response, std::size_t n) {
  const std::uint8_t fc = pdu[0];
  FUZZ_CHECK(response[0] == fc);
  FUZZ_CHECK(fc == 0x03 || fc == 0x10 || fc == 0x17);
  if (fc == 0x10) {
    FUZZ_CHECK(n == 5);
    FUZZ_CHECK(length >= 5 && std::memcmp(response + 1, pdu + 1, 4) == 0);
    return;
  }
  FUZZ_CHECK(length >= 5);
  const std::uint16_t read_quantity = be16(pdu + 3);
  FUZZ_CHECK(read_quantity >= 1 && read_quantity <= 125);
  FUZZ_CHECK(n == 2u + 2u * read_quantity);
  FUZZ_CHECK(response[1] == 2u * read_quantity);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static FreshBench fresh;
  static Snapshot before;
  static Snapshot after;
  static unsigned char before_bytes[FreshBench::kBytes];
  static unsigned char after_bytes[FreshBench::kBytes];
  ModuleBench& b = fresh.make();
  FUZZ_CHECK(b.module.start() == trueaxis::core::Status::kOk);
  trueaxis::modbus::ModbusCore core(b.module);

  Input in(data, size);
  for (int r = 0; r < kMaxRequests && !in.empty(); ++r) {
    std::uint8_t pdu[256];
    const std::size_t length = in.take(pdu, in.u8());
    // Room for the largest PDU plus a guard the core must never touch.
    std::uint8_t response[kMaxPduBytes + 16];
    std::memset(response, 0xA5, sizeof response);

    fresh.save(before_bytes);
    const std::size_t n = core.respond(pdu, length, response);

    FUZZ_CHECK(n >= 2 && n <= kMaxPduBytes);
    for (std::size_t i = kMaxPduBytes; i < sizeof response; ++i) FUZZ_CHECK(response[i] == 0xA5);
    const std::uint8_t fc = length > 0 ? pdu[0] : 0;
    const bool refused = (response[0] & 0x80) != 0;
    if (refused) {
      FUZZ_CHECK(n == 2);
      FUZZ_CHECK(response[0] == (fc | 0x80));
      FUZZ_CHECK(is_exception_code(response[1]));
    } else {
      check_normal(pdu, length, response, n);
    }
    // Walking the map is slow; most refusals leave every byte of the bench as
    // it was, and only the others need it. The walk reads the clock, so the
    // state after the request is put back once it is done.
    if ((refused || fc == 0x03) && !fresh.same_as(before_bytes)) {
      fresh.save(after_bytes);
      fresh.restore(before_bytes);
      before.take(b);
      fresh.restore(after_bytes);
      after.take(b);
      fresh.restore(after_bytes);
      const std::uint16_t changed = Snapshot::first_changed(before, after);
      if (changed != 0) std::fprintf(stderr, "variable #%u changed\n", static_cast<unsigned>(changed));
      FUZZ_CHECK(changed == 0);
      FUZZ_CHECK(before.nv == after.nv);
      FUZZ_CHECK(before.unlocked == after.unlocked);
    }
    b.module.step();
  }
  return 0;
}
