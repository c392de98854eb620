// The CMSDK APB UART of the MPS2 board (ARM Cortex-M System Design Kit TRM,
// DDI 0479, 4.3), polled: no interrupts, no FIFO (one byte each way).
//
// Conventions
//  1. Registers from the base: DATA 0x00 (one byte in or out), STATE 0x04
//     (bit 0 TX buffer full, bit 1 RX buffer full, bit 2 TX overrun, bit 3 RX
//     overrun; an overrun bit is cleared by writing 1 to it), CTRL 0x08 (bit 0
//     TX enable, bit 1 RX enable; the interrupt enables, bits 2..5, stay 0),
//     INTSTATUS/INTCLEAR 0x0C, BAUDDIV 0x10 (PCLK / baud, at least 16).
//  2. The frame format is fixed by the hardware: 8 data bits, no parity, one
//     stop bit (10 bits per character). Modbus RTU's 11-bit characters
//     (even parity, or no parity with two stop bits) cannot be made on this
//     UART; on QEMU, whose serial backends have no bit timing, it does not
//     matter, on a line it would need the board's other UARTs or an adapter.
//  3. QEMU mps2-an500 (hw/arm/mps2.c): UART0 at 0x40004000 is the first
//     -serial device; PCLK is the 25 MHz SYSCLK. QEMU takes a byte from its
//     backend only while the RX buffer is empty, so it never overruns; on
//     hardware a byte not read within one character time is lost and noted
//     (rx_overruns()).
//  4. One CmsdkUart per UART, constructed once (it programs the UART).
#pragma once

#include <cstddef>
#include <cstdint>

namespace trueaxis::hal::mps2 {

inline constexpr std::uintptr_t kUart0Base = 0x40004000;

class CmsdkUart {
 public:
  // Programs BAUDDIV = pclk_hz / baud (at least 16) and enables TX and RX.
  CmsdkUart(std::uintptr_t base, std::uint32_t baud, std::uint32_t pclk_hz);

  // Takes the received byte if there is one; false when the RX buffer is empty.
  bool read(std::uint8_t& byte);

  // Sends `length` bytes, waiting while the TX buffer is full.
  void write(const std::uint8_t* bytes, std::size_t length);

  // RX overruns seen by read() since construction.
  std::uint32_t rx_overruns() const { return rx_overruns_; }

 private:
  volatile std::uint32_t& reg(std::uintptr_t offset) const;

  std::uintptr_t base_;
  std::uint32_t rx_overruns_ = 0;
};

}  // namespace trueaxis::hal::mps2
