// The module served over Modbus RTU on the board's UART0: the firmware an
// integrator flashes, as QEMU runs it (docs/GUIDE.md, "Modbus RTU on the
// firmware image (QEMU)").
//
// Conventions
//  1. Slave address 1, 19200 baud (the UART itself is 8N1, cmsdk_uart.hpp 2;
//     the framer times 11-bit characters, so its 3.5-character silence is
//     2006 us). The time source of the framer is the SysTick clock, the same
//     one the module reads. TRUEAXIS_RTU_BAUD builds it for another rate:
//     rtu_server_qemu_target is this image at 2400 baud (16 ms of silence),
//     the one the conformance test drives under QEMU, because QEMU hands the
//     bytes of a pseudo-terminal to the UART one main-loop turn at a time, and
//     on a busy host a turn can take longer than 19200 baud's 2 ms: a request
//     then arrives torn, as it would on a line with gaps.
//  2. The loop: a byte in the UART goes to the framer; with none, the framer
//     is polled for the end of a frame, and while no frame is being received
//     the module makes one bounded step (module.hpp) if a macro is running. A
//     step never runs between two bytes of a frame: the byte after it would be
//     read late, and a step longer than 3.5 characters would tear the frame.
//     A reply is sent whole before the next byte is read.
//  3. It prints one line on the semihosting console when it is ready (so run
//     it with -semihosting) and serves until QEMU is stopped.
#include <cstdint>

#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/hal/mps2/cmsdk_uart.hpp"
#include "trueaxis/hal/mps2/semihosting.hpp"
#include "trueaxis/hal/mps2/systick_clock.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/modbus/modbus_rtu.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

static_assert(trueaxis::hal::mps2::kBoardNvBytes >= trueaxis::macros::kRequiredStorageBytes,
              "the board's storage must hold every persistent record (macros/records.hpp)");

namespace {

constexpr std::uint8_t kSlaveAddress = 1;
#ifndef TRUEAXIS_RTU_BAUD
#define TRUEAXIS_RTU_BAUD 19200
#endif
constexpr std::uint32_t kBaud = TRUEAXIS_RTU_BAUD;

}  // namespace

int main() {
  namespace mps2 = trueaxis::hal::mps2;
  namespace macros = trueaxis::macros;
  namespace modbus = trueaxis::modbus;
  static trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  static mps2::SysTickClock clock;
  static macros::Module module(storage, clock);
  static_cast<void>(module.start());  // unreadable storage: the map's defaults
  static trueaxis::modbus::ModbusCore core(module);
  static trueaxis::modbus::ModbusRtu rtu(core, clock, kSlaveAddress, kBaud);
  static mps2::CmsdkUart uart(mps2::kUart0Base, kBaud, mps2::kCpuHz);
  static std::uint8_t reply[trueaxis::modbus::kRtuMaxFrameBytes];

  mps2::console_write("rtu_server: slave ");
  mps2::console_write_uint(kSlaveAddress);
  mps2::console_write(", ");
  mps2::console_write_uint(kBaud);
  mps2::console_write(" baud on UART0\n");
  for (;;) {
    std::uint8_t byte = 0;
    std::size_t n = 0;
    if (uart.read(byte)) {
      n = rtu.receive(byte, reply);
    } else {
      n = rtu.poll(reply);
      if (n == 0 && !rtu.receiving() && module.busy()) module.step();
    }
    if (n > 0) uart.write(reply, n);
  }
}
