// M4, the spindle's tool axis as a screw: the method as one type (method.hpp).
#pragma once

#include "trueaxis/macros/method.hpp"
#include "trueaxis/macros/spindle/spindle_macros.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"

namespace trueaxis::macros::spindle {

struct Method : Shape {
  static constexpr const char* kName = "spindle";
  static constexpr MethodBlock kBlock = spindle::kBlock;
  static constexpr StatusBlock kStatusBlock{1300, 1399};
  static constexpr List<core::StatusInfo> kStatuses = list_of(spindle::kStatuses);
  static constexpr List<MacroInfo> kMacros = list_of(spindle::kMacros);
  static constexpr SessionLimit kLimits[] = {{"", "balls", 2}, {"", "samples_per_angle_bin", core::kMaxBinCount}};
  static constexpr SessionInfo kSession{core::kSpindleBins, "angle bins of 2 deg per ball (any sampling, any number of revolutions)",
                                        "S spindle angle (#19, deg), T ball 1 or 2 (#20), ball centre X, Y, Z "
                                        "(#24..#26, mm, analyser frame)",
                                        kMacroSessionClear, kMacroSessionAdd, kMacroBuild, list_of(kLimits)};
  static constexpr GateInfo kGateTable[] = {
      {"spacing", kBallSpacingImplausible, {var::kSpindleMaxSpacingError, 0, 0},
       "the distance between the balls' mean centres against V - U"},
      {"ball_distance", kBallsTooClose, {var::kSpindleMinBallSpacing, 0, 0},
       "the balls' distance along the tool, V - U (both files in metres?)"},
      {"fit", core::Status::kFitBeyondNoise, {var::kSpindleProbeNoise, var::kSpindleFormAllowance, var::kGateConfidence},
       "each ball's residuals (3 n - 4 degrees of freedom) against the probe noise and the form allowance"},
      {"change", core::Status::kChangeBeyondLimit, {var::kSpindleMaxChange, 0, 0},
       "with R = 1: the tool-tip error at V against the stored model's, every 10 deg; M = 1 confirms"},
  };
  static constexpr List<GateInfo> kGates = list_of(kGateTable);
  static constexpr CheckInfo kCheck{kMacroCheck, list_of(spindle::kCheckFigureKinds)};
  static constexpr List<CheckFigureInfo> kLogFigures = list_of(spindle::kCheckFigureKinds);  // the screw's six parameters
  using State = spindle::State;
  using Table = ModelRecord;
  static StoredTable<Table>& table(State& s) { return s.table; }
};

}  // namespace trueaxis::macros::spindle
