// The rigidity method's plan (planner.hpp): what `trueaxis-calibrate plan rigidity` measures, and its model.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

// M3: A poses, each with its C positions, the ball at ball_table_mm on the
// table (table coordinates, calibration_ball.hpp), its centre read to
// sigma_mm per coordinate; on the simulator's cradle (realistic errors).
struct RigidityPlan {
  std::vector<std::pair<double, std::vector<double>>> poses;  // (A, C positions), deg
  core::Vec3 ball_table_mm = core::Vec3(200.0, 0.0, 50.0);
  double sigma_mm = 0.001;
  double a_min_deg = -120.0;  // the candidates' A range (contract 5)
  double a_max_deg = 120.0;
  CradlePivot pivot;           // the cradle's nominal pivot (cradle_machine.hpp convention 1)
};
// A from a_from to a_to every a_step (0 included), C every c_step over a turn.
RigidityPlan rigidity_plan(double a_from, double a_to, double a_step, double c_step);
std::shared_ptr<const PlanModel> rigidity_model(const RigidityPlan& plan);

}  // namespace trueaxis::sim
