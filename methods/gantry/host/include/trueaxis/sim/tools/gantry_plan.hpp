// The gantry method's plan (planner.hpp): what `trueaxis-calibrate plan gantry` measures, and its model.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/instruments/laser_tracker.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

// M2: the simulator's gantry (realistic_gantry) and tracker placement
// (TrackerPlacement, at tracker_distance_m), measured by gantry_measure.hpp's plan; the tracker's stated noise
// (laser_tracker.hpp convention 3: radial and transverse).
struct GantryPlanSpec {
  int pad_grid = 5;
  int side_rows = 4;
  int side_cols = 5;
  int passes = 3;
  int pass_points = 15;
  int circle_points = 24;
  double c_from_deg = 0.0;
  double c_to_deg = 345.0;
  double a_from_deg = -90.0;
  double a_to_deg = 90.0;
  double radial_mpe_mm = 0.010;      // read as 2 sigma
  double transverse_mpe_mm = 0.015;
  double transverse_mpe_per_m_mm = 0.006;
  double tracker_distance_m = 2.5;   // in front of the machine (laser_tracker.hpp convention 2)
  double a_limit_deg = 120.0;        // the candidates' widest A arc (contract 5)
};
std::shared_ptr<const PlanModel> gantry_model(const GantryPlanSpec& plan);
// Its measuring plan (gantry_measure.hpp) and the tracker's noise and place.
GantryPlan gantry_measuring_plan(const GantryPlanSpec& spec);
TrackerSpec gantry_tracker_spec(const GantryPlanSpec& spec);
TrackerPlacement gantry_tracker_placement(const GantryPlanSpec& spec);

}  // namespace trueaxis::sim
