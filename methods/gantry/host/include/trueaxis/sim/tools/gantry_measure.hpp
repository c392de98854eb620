// Measuring the virtual gantry (gantry_machine.hpp) with the virtual laser
// tracker (laser_tracker.hpp) as an operator would for M2, and the files of
// docs/INTERFACE.md "M2 gantry": the samples CSV, the MACHINE CSV and, for tests and
// the demo's comparison, OUT.json holding the TRUE values. Host only.
//
// Conventions
//  1. Groups and order (docs/INTERFACE.md): `bed` (pads A, B, C, D in turn, each a
//     pad_grid x pad_grid grid 10 mm inside its top face), `side_1` (pad A's -X
//     face, side_cols along Y x side_rows down Z, 15 mm inside its edges and 10 mm
//     inside top and bottom), `side_2` (its -Y face, along X likewise), `gantry_K`
//     (K = 1..passes: pass_points positions evenly over the whole travel, in the
//     positive direction), then per sub-machine N in order: `spN_x_K`,
//     `spN_y_K`, `spN_z_K` (the SMR, head at A = C = 0, the axis moved over its
//     whole stroke in the positive direction, the others home), `spN_c`
//     (circle_points C angles evenly from c_from_deg to c_to_deg, A = 0, axes
//     home), `spN_a` (A from a_from_deg to a_to_deg likewise, C = 0). Every
//     pass repeats the same stops; only the noise differs.
//  2. Noise is drawn in file order, three deviates per point (laser_tracker.hpp
//     convention 3), so one seed gives one file.
//  3. Numbers: samples with 9 decimals (mm), MACHINE with 9 decimals; the JSON
//     with 15 significant digits. It carries one key more than OUT.json,
//     `"truth": true`; its `origin_sigma_mm` values are 0 (a truth has no
//     uncertainty), its `bed_flatness_mm` the model's 0 (coplanar pads), and its
//     `gantry_straightness_mm` the bow's over this plan's stops (gantry_machine.hpp
//     convention 3).
//  4. MACHINE's tool direction is the sub-machine's NOMINAL tool direction
//     (tool_nominal, frame M) written in the tracker frame.
#pragma once

#include <string>
#include <vector>

#include "trueaxis/sim/instruments/laser_tracker.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"

namespace trueaxis::sim {

struct GantryPlan {
  int pad_grid = 5;       // 25 points per pad
  int side_rows = 4;      // 20 points per side face
  int side_cols = 5;
  int passes = 3;
  int pass_points = 15;
  int circle_points = 24;
  double c_from_deg = 0.0;
  double c_to_deg = 345.0;
  double a_from_deg = -90.0;
  double a_to_deg = 90.0;
};

struct TrackerSample {
  std::string group;
  core::Vec3 p_mm;  // tracker frame
};

// The tracker placed in front of the gantry (laser_tracker.hpp convention 2):
// centred on the bed's length, in front of the machine's front (front_y_mm).
LaserTracker place_tracker(const GantryMachine& machine, const TrackerPlacement& placement,
                           const TrackerSpec& spec = TrackerSpec{}, bool noise = true);

// The gantry travel positions of one pass (convention 1).
std::vector<double> gantry_stops(const GantryMachine& machine, const GantryPlan& plan);

// Every sample in file order (conventions 1-2).
std::vector<TrackerSample> measure_gantry(const GantryMachine& machine, const LaserTracker& tracker,
                                          const GantryPlan& plan, SimRng& rng);

// The file texts. `comment` lines (without '#') head the samples file.
std::string samples_csv_text(const std::vector<TrackerSample>& samples, const std::vector<std::string>& comment);
// With nominal_origins, each row also gives the sub-machine's origin in the
// global frame, rounded to 0.1 mm as a drawing would give it (origin_x_mm ..).
std::string machine_csv_text(const GantryMachine& machine, const LaserTracker& tracker, bool nominal_origins = false);
std::string truth_json_text(const GantryMachine& machine, const LaserTracker& tracker, const GantryPlan& plan);

}  // namespace trueaxis::sim
