// trueaxis-calibrate's one table of methods. The files' text follows
// docs/INTERFACE.md "Calibration flows", which is the definition; this is the
// short form `trueaxis-calibrate METHOD --help` prints.
#include "trueaxis/sim/tools/calibrate.hpp"

#include <string>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::sim {

namespace {

// clang-format off
const CalibrateMethod kMethods[] = {
  {"rigidity", "M3 AC-axis rigidity: a ball on the table measured at several A while C turns",
   "SAMPLES.csv: a_deg,c_deg,x_mm,y_mm,z_mm\n"
   "  a_deg, c_deg       the commanded A and C (deg)\n"
   "  x_mm, y_mm, z_mm   the calibration ball's centre at that pose (mm, machine coordinates)\n"
   "  Rows whose a_deg agree within 1e-6 deg form one A pose, in any order; one pose at A = 0\n"
   "  (the reference); 3..16 poses, each with at least 4 distinct C over an arc of at least\n"
   "  #600 (45 deg by default) and at most 36 samples; at most 512 samples in all.\n"
   "MACHINE.csv: not read.\n",
   calibrate_rigidity, store_rigidity, "rigidity", rigidity_kins_file, 9834, 1.0},
  {"gantry", "M2 gantry zero frames: laser-tracker points of the bed, the gantry and each sub-machine",
   "SAMPLES.csv: group,x_mm,y_mm,z_mm\n"
   "  group              bed, side_1, side_2, gantry_K, spN_x_K, spN_y_K, spN_z_K, spN_c, spN_a\n"
   "                     (N the sub-machine 1..8, K the pass 1..4; no leading zeros)\n"
   "  x_mm, y_mm, z_mm   a tracker point (mm, tracker frame, levelled: +Z up)\n"
   "  Passes in measuring order along the axis' positive direction, circles in order of\n"
   "  increasing angle; a group's rows need not be adjacent.\n"
   "MACHINE.csv (--machine, required): sub_machine,swing_mm,tool_x,tool_y,tool_z\n"
   "  sub_machine        N, 1..8, each once; a row for every sub-machine SAMPLES measures, and\n"
   "                     points for every row (or --sub-machines N,N...: the ones measured)\n"
   "  swing_mm           the A axis' swing length, wrist centre to tool tip (mm)\n"
   "  tool_x, tool_y, tool_z  the nominal tool direction, tracker frame (only its sense is used)\n",
   calibrate_gantry, store_gantry, "gantry", nullptr, 9824, 0.0},
  {"spindle", "M4 spindle tool axis: a spindle analyser's two balls over whole revolutions",
   "SAMPLES.csv: phi_deg,ball,x_mm,y_mm,z_mm\n"
   "  phi_deg            the spindle angle from M19's zero, growing in the M03 sense (deg; may pass 360)\n"
   "  ball               1 (nearer the spindle) or 2\n"
   "  x_mm, y_mm, z_mm   the ball's centre (mm, analyser frame)\n"
   "  Per ball at least 8 distinct angles, at most 360, no gap wider than #800 (45 deg by default).\n"
   "MACHINE.csv (--machine, required): name,value rows, each of these names once (mm):\n"
   "  bearing_spacing_mm           upper to lower bearing plane (checked, shown in the report)\n"
   "  gauge_from_upper_bearing_mm  O1, the upper bearing seat's centre, to the gauge line\n"
   "  ball_1_mm, ball_2_mm         the balls' centres below the gauge line, 0 <= ball 1 < ball 2\n"
   "  tool_length_mm               the tool tip below the gauge line (where the tip error is given)\n",
   calibrate_spindle, store_spindle, "spindle", spindle_kins_file, 9845, 1.0},
};
// clang-format on

}  // namespace

bool has_stored_table(VariableClient& client, const CalibrateMethod& method, bool& has, FlowResult& fail) {
  const double qr[2] = {method.stored_query_q, 1.0};  // Q, R = 1: the stored table
  if (!client.write(macros::var::kArgQ, 2, qr)) {
    fail.error = client.failure_text();
    return false;
  }
  const MacroOutcome outcome = client.run_macro(method.stored_query, 20000);
  if (outcome.status != 2 && outcome.status != 3) {
    fail.error = client.failure_text() + " while asking for the stored table (macro " +
                 std::to_string(method.stored_query) + ")";
    return false;
  }
  // Any answer but no_table means a table was stored (a damaged one too).
  has = !(outcome.status == 3 && outcome.error == static_cast<int>(core::Status::kNoTable));
  return true;
}

CalibrateMethods calibrate_methods() { return {kMethods, sizeof kMethods / sizeof kMethods[0]}; }

const macros::RecordSpec* stored_record(const char* name) {
  using Built = macros::BuiltMethods;
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    if (std::string(Built::kNames[i]) == name && Built::kHasTable[i]) return &Built::kTableRecordOf[i];
  }
  return nullptr;
}

macros::CheckInfo check_of(const char* name) {
  using Built = macros::BuiltMethods;
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    if (std::string(Built::kNames[i]) == name) return Built::kChecks[i];
  }
  return {};
}

const CalibrateMethod* find_calibrate_method(const std::string& name) {
  for (const CalibrateMethod& m : calibrate_methods()) {
    if (name == m.name) return &m;
  }
  return nullptr;
}

std::string calibrate_method_names() {
  std::string names;
  const CalibrateMethods all = calibrate_methods();
  for (std::size_t i = 0; i < all.count; ++i) {
    names += i == 0 ? "" : (i + 1 == all.count ? " or " : ", ");
    names += all.first[i].name;
  }
  return names;
}

}  // namespace trueaxis::sim
