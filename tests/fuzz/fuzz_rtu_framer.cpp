// libFuzzer target: the Modbus RTU framer (macros/modbus_rtu.hpp) in front of a
// real module on RAM storage, fed one byte at a time with a clock the input
// sets, as the board's server loop (tests/target/rtu_server_main.cpp) feeds it.
//
// Input: | baud u8 | address u8 | then operations until the input ends, each
// starting with a code byte:
//   code bit 3 clear: a byte arrives; | code | byte |
//   code bits 3, 4 = 1, 0: a poll();   | code |
//   code bits 3, 4 = 1, 1: set_address(a); | code | a |
// Code bits 0..2 choose when the byte or the poll happens, as the silence after
// the previous byte's character (see gap_us): 0, one character, the frame
// silence minus 1 / exactly / plus 1 microsecond, one second, no time at all
// after the previous byte (a FIFO drained in a burst), 1.5 characters. A poll is
// never earlier than the operation before it (the clock never goes back). The
// baud comes from kBauds; the address byte is handed to the constructor as is.
// After the input a last poll comes exactly one frame silence after the last
// byte. After a poll that returned nothing while no frame is being received,
// a busy module steps, as in the server loop.
//
// Oracle: an independent reading of conventions 1-7 of modbus_rtu.hpp (its own
// character and silence times, its own cutting of frames by the byte times,
// its own bitwise CRC-16/MODBUS, its own address and broadcast rules) and a
// second module with its own ModbusCore that is handed the PDUs the reading
// says reach the core, in the same order. Checked after every operation:
//  1. receive()/poll() return a reply exactly when the reading ends a frame for
//     this slave with a good CRC, and that reply is byte for byte | address |
//     the second core's response to the same PDU | CRC (bitwise) |, at most
//     kRtuMaxFrameBytes, and nothing is written past kRtuMaxFrameBytes of the
//     reply buffer; so broadcasts, other addresses, bad CRCs, short and long
//     frames produce nothing;
//  2. every counter equals the reading's count, receiving() its state,
//     address() and silence_us() its values, set_address() its verdict;
// and after the input: both modules in the same state (every variable bit for
// bit, the unlock, every byte of storage), so no discarded frame and no
// broadcast read was executed, and every broadcast write was.
//
// Replaying one input with FUZZ_RTU_TRACE=1 in the environment prints the
// reference's counters and the operations' times and replies to stderr.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "crc16_reference.hpp"
#include "fuzz_support.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/modbus/modbus_rtu.hpp"

namespace {

using trueaxis::fuzz::FreshBench;
using trueaxis::fuzz::Input;
using trueaxis::fuzz::ModuleBench;
using trueaxis::fuzz::Snapshot;

constexpr std::uint32_t kBauds[8] = {1200, 2400, 9600, 19200, 19201, 38400, 57600, 115200};
constexpr std::size_t kReplyRoom = 256;  // convention 6, read independently
constexpr std::size_t kGuard = 32;

// The line's clock: the framer reads whatever the target last put here.
class LineClock final : public trueaxis::hal::Clock {
 public:
  std::uint64_t now = 1'000'000;
  int reads = 0;

 private:
  std::uint64_t do_now_us() override {
    ++reads;
    return now;
  }
};

// The reading of conventions 2, 4, 5 and 7, with the reference core behind it.
struct Reference {
  trueaxis::modbus::ModbusCore& core;
  std::uint64_t character_us;  // convention 2: 11 bits a character, rounded up
  std::uint64_t silence_us;    // 3.5 characters, 1750 us above 19200 baud, rounded up
  std::uint8_t address;
  // The frame in progress: its first bytes and how many it has had in all.
  std::uint8_t frame[300] = {};
  std::size_t count = 0;
  std::uint64_t last_byte_us = 0;
  // Counters in RtuCounters' order.
  std::uint32_t served = 0, broadcasts = 0, ignored_reads = 0, other_address = 0, bad_crc = 0, too_short = 0,
                too_long = 0;
  // The reply the reading expects from the operation just done.
  std::uint8_t reply[512] = {};
  std::size_t reply_bytes = 0;
  int core_calls = 0;

  Reference(trueaxis::modbus::ModbusCore& c, std::uint32_t baud, std::uint8_t requested)
      : core(c),
        character_us((11ull * 1'000'000ull + baud - 1) / baud),
        silence_us(baud <= 19200 ? (35ull * 1'100'000ull + baud - 1) / baud : 1750),
        address(requested >= 1 && requested <= 247 ? requested : 1) {}

  // Convention 3: the silence before time t; a frame ends at >= silence_us.
  bool silence_reached(std::uint64_t t) const {
    return static_cast<std::int64_t>(t - last_byte_us) - static_cast<std::int64_t>(character_us) >=
           static_cast<std::int64_t>(silence_us);
  }

  void end_frame() {
    const std::size_t n = count;
    count = 0;
    if (n < 4) {
      ++too_short;
      return;
    }
    if (n > 256) {
      ++too_long;
      return;
    }
    const unsigned sent = frame[n - 2] + 256u * frame[n - 1];
    if (trueaxis::test::crc16_bitwise(frame, n - 2) != sent) {
      ++bad_crc;
      return;
    }
    const std::uint8_t to = frame[0];
    const std::uint8_t function = frame[1];
    if (to == 0) {
      if (function == 3 || function == 23) {
        ++ignored_reads;
        return;
      }
      ++broadcasts;
      std::uint8_t dropped[512];
      ++core_calls;
      (void)core.respond(frame + 1, n - 3, dropped, trueaxis::macros::kRtuMaster);
      return;
    }
    if (to != address) {
      ++other_address;
      return;
    }
    ++served;
    ++core_calls;
    const std::size_t pdu = core.respond(frame + 1, n - 3, reply + 1, trueaxis::macros::kRtuMaster);
    FUZZ_CHECK(pdu >= 2 && pdu <= 253);
    reply[0] = address;
    const std::uint16_t crc = trueaxis::test::crc16_bitwise(reply, 1 + pdu);
    reply[1 + pdu] = static_cast<std::uint8_t>(crc & 0xFF);
    reply[2 + pdu] = static_cast<std::uint8_t>(crc >> 8);
    reply_bytes = 3 + pdu;
  }

  void byte(std::uint64_t t, std::uint8_t b) {
    reply_bytes = 0;
    if (count > 0 && silence_reached(t)) end_frame();
    if (count < sizeof frame) frame[count] = b;
    ++count;
    last_byte_us = t;
  }

  void poll(std::uint64_t t) {
    reply_bytes = 0;
    if (count > 0 && silence_reached(t)) end_frame();
  }

  bool set_address(std::uint8_t a) {
    if (a == 0 || a > 247) return false;
    address = a;
    return true;
  }
};

// Code bits 0..2: when the operation happens, after the previous byte's time.
std::uint64_t offset_us(unsigned code, const Reference& r) {
  const std::uint64_t c = r.character_us;
  switch (code & 7u) {
    case 0: return c;                     // back to back
    case 1: return c + c;                 // one character of silence
    case 2: return c + r.silence_us - 1;  // just short of the frame silence
    case 3: return c + r.silence_us;      // exactly the frame silence
    case 4: return c + r.silence_us + 1;
    case 5: return c + 1'000'000;         // a second
    case 6: return 0;                     // same instant as the previous byte
    default: return c + (3 * c) / 2;      // 1.5 characters: not applied
  }
}

struct Served {
  std::uint8_t buffer[kReplyRoom + kGuard];
  std::size_t n = 0;
};

void check_same(const trueaxis::modbus::ModbusRtu& rtu, const Reference& ref, const Served& out) {
  const trueaxis::modbus::RtuCounters& c = rtu.counters();
  FUZZ_CHECK(c.served == ref.served);
  FUZZ_CHECK(c.broadcasts == ref.broadcasts);
  FUZZ_CHECK(c.ignored_reads == ref.ignored_reads);
  FUZZ_CHECK(c.other_address == ref.other_address);
  FUZZ_CHECK(c.bad_crc == ref.bad_crc);
  FUZZ_CHECK(c.too_short == ref.too_short);
  FUZZ_CHECK(c.too_long == ref.too_long);
  FUZZ_CHECK(rtu.receiving() == (ref.count > 0));
  FUZZ_CHECK(rtu.address() == ref.address);
  FUZZ_CHECK(rtu.silence_us() == ref.silence_us);
  for (std::size_t i = kReplyRoom; i < sizeof out.buffer; ++i) FUZZ_CHECK(out.buffer[i] == 0xA5);
  FUZZ_CHECK(out.n == ref.reply_bytes);
  if (out.n == 0) return;
  FUZZ_CHECK(out.n >= 5 && out.n <= kReplyRoom);
  FUZZ_CHECK(out.buffer[0] == ref.address);
  FUZZ_CHECK(trueaxis::test::crc16_bitwise(out.buffer, out.n - 2) == out.buffer[out.n - 2] + 256u * out.buffer[out.n - 1]);
  FUZZ_CHECK(std::memcmp(out.buffer, ref.reply, out.n) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static FreshBench served_bench;
  static FreshBench reference_bench;
  static Snapshot served_state;
  static Snapshot reference_state;
  static const bool trace = std::getenv("FUZZ_RTU_TRACE") != nullptr;

  ModuleBench& served_module = served_bench.make();
  FUZZ_CHECK(served_module.module.start() == trueaxis::core::Status::kOk);
  trueaxis::modbus::ModbusCore served_core(served_module.module);
  ModuleBench& reference_module = reference_bench.make();
  FUZZ_CHECK(reference_module.module.start() == trueaxis::core::Status::kOk);
  trueaxis::modbus::ModbusCore reference_core(reference_module.module);

  Input in(data, size);
  const std::uint32_t baud = kBauds[in.u8() & 7u];
  const std::uint8_t address = in.u8();
  LineClock clock;
  trueaxis::modbus::ModbusRtu rtu(served_core, clock, address, baud);
  Reference ref(reference_core, baud, address);
  Served out;
  std::memset(out.buffer, 0xA5, sizeof out.buffer);
  check_same(rtu, ref, out);

  std::uint64_t last_byte = clock.now;  // the time the offsets count from
  int clock_reads = 0;
  const auto poll_at = [&](std::uint64_t t) {
    clock.now = t;
    std::memset(out.buffer, 0xA5, sizeof out.buffer);
    out.n = rtu.poll(out.buffer);
    ref.poll(t);
    if (trace) std::fprintf(stderr, "poll at +%llu: reply %zu\n", static_cast<unsigned long long>(t - 1'000'000), out.n);
    check_same(rtu, ref, out);
    // Convention 3: one clock read per poll() at most (none is needed while
    // no frame is open).
    FUZZ_CHECK(clock.reads - clock_reads <= 1);
    clock_reads = clock.reads;
    // The server loop's step: only when no frame is open and nothing was sent.
    const bool idle = out.n == 0 && !rtu.receiving();
    FUZZ_CHECK(served_module.module.busy() == reference_module.module.busy());
    if (idle && served_module.module.busy()) {
      served_module.module.step();
      reference_module.module.step();
    }
  };

  while (!in.empty()) {
    const std::uint8_t code = in.u8();
    const std::uint64_t at = last_byte + offset_us(code, ref);
    const std::uint64_t t = at > clock.now ? at : clock.now;
    if ((code & 0x08u) == 0) {
      const std::uint8_t byte = in.u8();
      clock.now = t;
      std::memset(out.buffer, 0xA5, sizeof out.buffer);
      out.n = rtu.receive(byte, out.buffer);
      ref.byte(t, byte);
      if (trace) {
        std::fprintf(stderr, "byte %02x at +%llu: reply %zu\n", byte, static_cast<unsigned long long>(t - 1'000'000),
                     out.n);
      }
      check_same(rtu, ref, out);
      FUZZ_CHECK(clock.reads - clock_reads == 1);
      clock_reads = clock.reads;
      last_byte = t;
    } else if ((code & 0x10u) == 0) {
      poll_at(t);
    } else {
      const std::uint8_t a = in.u8();
      FUZZ_CHECK(rtu.set_address(a) == ref.set_address(a));
      FUZZ_CHECK(rtu.address() == ref.address);
    }
  }
  // The frame still open (if any) ends exactly at the silence.
  const std::uint64_t end = last_byte + ref.character_us + ref.silence_us;
  poll_at(end > clock.now ? end : clock.now);
  FUZZ_CHECK(!rtu.receiving());
  if (trace) {
    std::fprintf(stderr,
                 "baud %u address %u: served %u broadcasts %u ignored_reads %u other_address %u bad_crc %u "
                 "too_short %u too_long %u\n",
                 static_cast<unsigned>(baud), static_cast<unsigned>(ref.address), static_cast<unsigned>(ref.served),
                 static_cast<unsigned>(ref.broadcasts), static_cast<unsigned>(ref.ignored_reads),
                 static_cast<unsigned>(ref.other_address), static_cast<unsigned>(ref.bad_crc),
                 static_cast<unsigned>(ref.too_short), static_cast<unsigned>(ref.too_long));
  }

  served_state.take(served_module);
  reference_state.take(reference_module);
  FUZZ_CHECK(served_state.bits == reference_state.bits);
  FUZZ_CHECK(served_state.nv == reference_state.nv);
  FUZZ_CHECK(served_state.unlocked == reference_state.unlocked);
  return 0;
}
