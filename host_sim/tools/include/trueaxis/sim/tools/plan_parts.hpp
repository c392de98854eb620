// What the methods' plan models (methods/<name>/host/src/<name>_plan.cpp) share.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"

namespace trueaxis::sim::plan_parts {

// The module's text for a refusal, as a flow reports it.
inline std::string refusal(core::Status s) { return module_error_text(static_cast<int>(s)); }

// #X, #Y, #Z = p, after `first` (planner.hpp contract 6).
inline std::vector<std::pair<std::uint16_t, double>> with_xyz(std::vector<std::pair<std::uint16_t, double>> first,
                                                              const core::Vec3& p) {
  first.push_back({macros::var::kArgX, p.x()});
  first.push_back({static_cast<std::uint16_t>(macros::var::kArgX + 1), p.y()});
  first.push_back({static_cast<std::uint16_t>(macros::var::kArgX + 2), p.z()});
  return first;
}

}  // namespace trueaxis::sim::plan_parts
