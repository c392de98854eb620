// M1, three-point and N-point auto-level: the method as one type (method.hpp).
#pragma once

#include "trueaxis/macros/level/level_macros.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/method.hpp"

namespace trueaxis::macros::level {

struct Method : Shape {
  static constexpr const char* kName = "level";
  static constexpr MethodBlock kBlock = level::kBlock;
  static constexpr StatusBlock kStatusBlock{1000, 1099};
  static constexpr List<core::StatusInfo> kStatuses = list_of(level::kStatuses);
  static constexpr List<MacroInfo> kMacros = list_of(level::kMacros);
  static constexpr SessionInfo kSession{kSessionCapacity, "points", "X, Y, Z (#24..#26, mm, machine frame)",
                                        kMacroSessionClear, kMacroSessionAdd, kMacroSessionCompute, {}, kMacroSessionBall};  // 9815: a ball from the touches
  // Interface version 1 named the results #100..#116 after M1's outputs.
  static constexpr List<OutputInfo> kNamedResults{kLevelOutputs, kNamedLevelOutputs};
  static constexpr CheckInfo kCheck{kMacroCheck, list_of(level::kCheckFigureKinds)};
  using State = level::State;
  using Table = NoTable;
};

}  // namespace trueaxis::macros::level
