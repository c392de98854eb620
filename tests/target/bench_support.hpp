// Instruction counting on the MPS2 board under QEMU's `-icount shift=6`, shared
// by the target benches: SysTick runs 1.6 ticks per instruction there
// (systick_clock.hpp). A calibration loop of known length checks that the
// emulator really counts instructions before any figure is believed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/hal/mps2/semihosting.hpp"
#include "trueaxis/hal/mps2/systick_clock.hpp"

namespace trueaxis::bench {

namespace mps2 = trueaxis::hal::mps2;

inline std::uint64_t ticks_to_instructions(std::uint64_t ticks) {
  return (ticks * 10 + mps2::kTicksPer10Instructions / 2) / mps2::kTicksPer10Instructions;
}

template <std::size_t N>
std::uint64_t median(std::uint64_t (&v)[N]) {
  for (std::size_t i = 1; i < N; ++i) {
    for (std::size_t j = i; j > 0 && v[j - 1] > v[j]; --j) {
      const std::uint64_t t = v[j];
      v[j] = v[j - 1];
      v[j - 1] = t;
    }
  }
  return v[N / 2];
}

inline void print(const char* label, std::uint64_t value, const char* unit) {
  mps2::console_write(label);
  mps2::console_write_uint(value);
  mps2::console_write(unit);
}

// The cost of reading the clock twice (ticks), the median of 9 tries.
inline std::uint64_t clock_overhead(const mps2::SysTickClock& clock) {
  std::uint64_t samples[9];
  for (std::uint64_t& s : samples) {
    const std::uint64_t t0 = clock.ticks();
    const std::uint64_t t1 = clock.ticks();
    s = t1 - t0;
  }
  return median(samples);
}

// Runs a loop of 2 * kLoops instructions and prints what the clock measured;
// true when that is within 0.1 % (the emulator counts instructions).
inline bool calibrated(const mps2::SysTickClock& clock, std::uint64_t overhead) {
  constexpr std::uint32_t kLoops = 10000;  // 2 instructions each (subs, bne)
  const std::uint64_t c0 = clock.ticks();
  std::uint32_t n = kLoops;
  asm volatile(
      "1: subs %0, %0, #1\n"
      "   bne 1b\n"
      : "+r"(n)
      :
      : "cc");
  const std::uint64_t measured = ticks_to_instructions(clock.ticks() - c0 - overhead);
  print("calibration: ", measured, " instructions measured for ");
  print("", 2 * std::uint64_t{kLoops}, " executed\n");
  return measured + 20 >= 2 * kLoops && measured <= 2 * kLoops + 20;
}

}  // namespace trueaxis::bench
