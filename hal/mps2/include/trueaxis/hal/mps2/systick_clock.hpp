// The Cortex-M SysTick timer as trueaxis's hal::Clock on the MPS2 board.
//
// Contract
//  1. SysTick counts down from 2^24 - 1 at the CPU clock (CLKSOURCE = 1); every
//     wrap raises the SysTick exception, whose handler (SysTick_Handler, defined
//     here) adds 2^24 to a 64-bit software count. ticks() = wraps * 2^24 + the
//     ticks elapsed since the last wrap, read without a race (the wrap count is
//     read before and after the counter, and again when they differ).
//  2. Precondition: the SysTick exception is not masked for longer than one wrap
//     (2^24 ticks, 0.67 s at 25 MHz), or the clock loses a wrap.
//  3. There is one SysTick per core: construct one SysTickClock, in main, and
//     pass it by reference. Constructing it (re)starts the count at 0.
//  4. now_us() = ticks * 10^6 / cpu_hz, exact (no 64-bit overflow before 2^64 us).
//  5. QEMU: the MPS2 boards clock the CPU at 25 MHz. Under `-icount shift=6`
//     each instruction takes 64 ns of virtual time, i.e. 1.6 SysTick ticks, so
//     instructions = ticks / 1.6 (kTicksPer10Instructions / 10).
#pragma once

#include <cstdint>

#include "trueaxis/hal/clock.hpp"

namespace trueaxis::hal::mps2 {

inline constexpr std::uint32_t kCpuHz = 25'000'000;           // QEMU mps2-an500 SYSCLK
inline constexpr std::uint64_t kTicksPer10Instructions = 16;  // under -icount shift=6

class SysTickClock final : public Clock {
 public:
  explicit SysTickClock(std::uint32_t cpu_hz = kCpuHz);

  // CPU clock ticks since construction.
  std::uint64_t ticks() const;

 private:
  std::uint64_t do_now_us() override;

  std::uint32_t cpu_hz_;
};

}  // namespace trueaxis::hal::mps2
