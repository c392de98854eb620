// The macros the module runs, by number, and the context a handler sees.
//
// Contract of a handler
//  1. It reads any variable through MacroContext::in() and writes results only
//     through MacroContext::out(), which stages them.
//  2. It returns a Status. The module copies the staged results into #100..#199
//     only when that is kOk; on any other status every result and every stored
//     table stays as it was.
//  3. Each handler's header comment lists its inputs, outputs and status codes.
#pragma once

#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::macros {

inline constexpr std::size_t kResultSlots = var::kResultLast - var::kResultFirst + 1;

class MacroContext {
 public:
  // values: every variable of the map, in slot order (register_map.hpp slot_of).
  MacroContext(const double* values, double* staged_results) : values_(values), staged_(staged_results) {}

  // The value of #number; 0 for a number the map does not define.
  double in(std::uint16_t number) const {
    const std::size_t slot = slot_of(number);
    return slot < kVariableCount ? values_[slot] : 0.0;
  }

  // Stage a result; numbers outside #100..#199 are ignored.
  void out(std::uint16_t number, double value) {
    if (number >= var::kResultFirst && number <= var::kResultLast) staged_[number - var::kResultFirst] = value;
  }

 private:
  const double* values_;
  double* staged_;
};

using MacroFn = core::Status (*)(MacroContext&);

struct MacroInfo {
  std::uint16_t number;
  MacroFn run;
  const char* name;
  const char* description;
};

// Macro 9810: three-point auto-level (INTERFACE.md, METHODS.md M1).
//  In:  P1 = G57 X,Y,Z (#5281..#5283), P2 = G58 (#5301..), P3 = G59 (#5321..), mm,
//       machine frame, probed with the table at A = #1, C = #3 (deg); optional
//       outward direction I, J, K (#4..#6, machine frame as probed; 0,0,0 = +Z).
//       Configuration #500..#507.
//  Out: #100..#115 (register_map.hpp).
//  Status: those of core::level_face.
core::Status run_level_3pt(MacroContext& ctx);

// Macro 9811: N-point auto-level, 3 <= Q (#17) <= 32 points from the point list
// #1001.. (X, Y, Z interleaved); otherwise as 9810. kArgumentOutOfRange when Q is
// not a whole number in 3..32.
core::Status run_level_points(MacroContext& ctx);

inline constexpr MacroInfo kMacroTable[] = {
    {9810, &run_level_3pt, "level_3pt",
     "Three-point auto-level: table angles that make the face through G57, G58, G59 horizontal."},
    {9811, &run_level_points, "level_points",
     "N-point auto-level: least-squares plane through the point list, with flatness and outlier flag."},
};

constexpr const MacroInfo* find_macro(std::uint16_t number) {
  for (const MacroInfo& m : kMacroTable) {
    if (m.number == number) return &m;
  }
  return nullptr;
}

}  // namespace trueaxis::macros
