// The level method's plan (planner.hpp): what `trueaxis-calibrate plan level` measures, and its model.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

// M1: probe points (x, y, machine frame, table at zero) on the simulator's
// inclined face (FaceConfig), each read to sigma_mm per coordinate.
struct LevelPlan {
  std::vector<std::pair<double, double>> points;
  double sigma_mm = 0.0005;
};
// trueaxis-level's triangle: three points on a circle of radius side / sqrt(3).
LevelPlan level_plan(double side_mm);
std::shared_ptr<const PlanModel> level_model(const LevelPlan& plan);

}  // namespace trueaxis::sim
