// Driving the module in a target bench: writes that must succeed, and a macro run
// to its end with the instructions of its longest step (bench_support.hpp).
#pragma once

#include <cstdint>

#include "bench_support.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::bench {

inline bool write_n(macros::Module& mod, std::uint16_t first, std::uint16_t n, const double* v) {
  return mod.write(first, n, v) == macros::AccessFault::kNone;
}

// Runs a macro to its end; the longest step (instructions), the step count and,
// when `longest_at` is given, which step (1-based) was the longest. True when it
// ended done (not in error).
inline bool run(macros::Module& mod, const mps2::SysTickClock& clock, std::uint64_t overhead, double macro,
                std::uint64_t& longest, std::uint64_t& steps, std::uint64_t* longest_at = nullptr) {
  if (!write_n(mod, macros::var::kCmd, 1, &macro)) return false;
  longest = steps = 0;
  while (mod.busy()) {
    const std::uint64_t t0 = clock.ticks();
    mod.step();
    const std::uint64_t n = ticks_to_instructions(clock.ticks() - t0 - overhead);
    ++steps;
    if (n > longest && longest_at != nullptr) *longest_at = steps;
    longest = n > longest ? n : longest;
  }
  return mod.value(macros::var::kStatus) == static_cast<double>(macros::MacroState::kDone);
}

}  // namespace trueaxis::bench
