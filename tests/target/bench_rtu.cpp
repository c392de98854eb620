// Bench: Cortex-M7 instructions of one Modbus RTU request, from its first byte
// to the reply frame built (ModbusRtu::receive for every byte, then the poll()
// that ends the frame: CRC, ModbusCore::respond, the module, the reply's CRC),
// measured with SysTick under QEMU's instruction counting (bench_support.hpp).
// The framer's clock is a fake advanced by the bench, so the line's silences
// cost nothing here; the UART is not involved.
//
// Run: the custom target run_bench_rtu (qemu ... -icount shift=6 -kernel bench_rtu_target).
#include <cstddef>
#include <cstdint>

#include "bench_support.hpp"
#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/hal/mps2/semihosting.hpp"
#include "trueaxis/hal/mps2/systick_clock.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/modbus/modbus_rtu.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace mps2 = trueaxis::hal::mps2;
namespace macros = trueaxis::macros;
using trueaxis::bench::median;
using trueaxis::bench::print;
using trueaxis::bench::ticks_to_instructions;

constexpr int kRuns = 9;

class LineClock final : public trueaxis::hal::Clock {
 public:
  std::uint64_t now = 1'000'000;

 private:
  std::uint64_t do_now_us() override { return now; }
};

// | 1 | fc | ... | CRC | into `frame`; returns its length.
std::size_t frame_of(const std::uint8_t* pdu, std::size_t length, std::uint8_t* frame) {
  frame[0] = 1;
  for (std::size_t i = 0; i < length; ++i) frame[1 + i] = pdu[i];
  const std::uint16_t crc = trueaxis::modbus::crc16_modbus(frame, 1 + length);
  frame[1 + length] = static_cast<std::uint8_t>(crc);
  frame[2 + length] = static_cast<std::uint8_t>(crc >> 8);
  return 3 + length;
}

std::uint64_t instructions_per_request(const mps2::SysTickClock& clock, trueaxis::modbus::ModbusRtu& rtu, LineClock& line,
                                       const std::uint8_t* frame, std::size_t length, std::uint64_t overhead,
                                       std::size_t& reply_bytes) {
  static std::uint8_t reply[trueaxis::modbus::kRtuMaxFrameBytes];
  std::uint64_t samples[kRuns];
  for (std::uint64_t& s : samples) {
    line.now += 10'000;
    const std::uint64_t t0 = clock.ticks();
    for (std::size_t i = 0; i < length; ++i) static_cast<void>(rtu.receive(frame[i], reply));
    line.now += 10'000;
    reply_bytes = rtu.poll(reply);
    s = clock.ticks() - t0 - overhead;
  }
  return ticks_to_instructions(median(samples));
}

}  // namespace

int main() {
  static trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  static mps2::SysTickClock clock;
  static macros::Module module(storage, clock);
  static_cast<void>(module.start());
  static trueaxis::modbus::ModbusCore core(module);
  static LineClock line;
  static trueaxis::modbus::ModbusRtu rtu(core, line, 1, 19200);
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) {
    mps2::console_write("bench_rtu: not run under -icount shift=6; no figures\n");
    return 1;
  }
  static std::uint8_t frame[trueaxis::modbus::kRtuMaxFrameBytes];
  struct Case {
    const char* name;
    std::uint8_t pdu[16];
    std::size_t length;
  };
  // #1 (registers 4..7); #100..#130 (400..523); write #1 = 2.0; FC 0x41.
  const Case cases[] = {
      {"FC3 read of 1 variable (8-byte request, 13-byte reply): ", {0x03, 0, 4, 0, 4}, 5},
      {"FC3 read of 31 variables (8-byte request, 253-byte reply): ", {0x03, 0x01, 0x90, 0, 124}, 5},
      {"FC16 write of 1 variable (17-byte request, 8-byte reply): ", {0x10, 0, 4, 0, 4, 8, 0x40, 0, 0, 0, 0, 0, 0, 0}, 14},
      {"FC 0x41 (exception 01): ", {0x41, 0, 0, 0, 1}, 5},
  };
  bool replied = true;
  for (const Case& c : cases) {
    const std::size_t n = frame_of(c.pdu, c.length, frame);
    std::size_t reply_bytes = 0;
    const std::uint64_t instructions = instructions_per_request(clock, rtu, line, frame, n, overhead, reply_bytes);
    print(c.name, instructions, " instructions");
    print(", reply ", reply_bytes, " bytes\n");
    replied = replied && reply_bytes > 0;
  }
  return replied ? 0 : 1;
}
