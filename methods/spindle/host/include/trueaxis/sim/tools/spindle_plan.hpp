// The spindle method's plan (planner.hpp): what `trueaxis-calibrate plan spindle` measures, and its model.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

// M4: the analyser's encoder-synchronous sampling (spindle_analyser.hpp
// convention 1) of the simulator's spindle (realistic_spindle), balls at
// ball_mm below the gauge line, each centre read to sigma_mm per axis.
struct SpindlePlan {
  int revolutions = 3;
  int samples_per_revolution = 72;
  double ball_mm[2] = {50.0, 150.0};
  double sigma_mm = 15e-6;
};
std::shared_ptr<const PlanModel> spindle_model(const SpindlePlan& plan);

}  // namespace trueaxis::sim
