// M3, AC-axis rigidity: the method as one type (method.hpp).
#pragma once

#include "trueaxis/macros/method.hpp"
#include "trueaxis/macros/rigidity/rigidity_macros.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/services.hpp"

namespace trueaxis::macros::rigidity {

struct Method : Shape {
  static constexpr const char* kName = "rigidity";
  static constexpr MethodBlock kBlock = rigidity::kBlock;
  static constexpr StatusBlock kStatusBlock{1100, 1199};
  static constexpr List<core::StatusInfo> kStatuses = list_of(rigidity::kStatuses);
  static constexpr List<MacroInfo> kMacros = list_of(rigidity::kMacros);
  static constexpr SessionLimit kLimits[] = {{"", "max_pose_samples", kMaxPoseSamples},
                                             {"", "max_poses", core::kMaxAPoses}};
  static constexpr SessionInfo kSession{kSessionCapacity, "samples",
                                        "A, C (#1, #3, deg), ball centre X, Y, Z (#24..#26, mm)",
                                        kMacroSessionClear, kMacroSessionAdd, kMacroBuild, list_of(kLimits)};
  static constexpr GateInfo kGateTable[] = {
      {"fit", core::Status::kFitBeyondNoise, {var::kRigidityBallNoise, var::kGateConfidence, 0},
       "each pose's C-circle residuals (2 n - 6 degrees of freedom) against the ball noise"},
      {"a_error", kAErrorImplausible, {var::kRigidityMaxAError, 0, 0}, "each pose's A positioning error"},
      {"c_radius", kCRadiusImplausible, {var::kRigidityMinCRadius, 0, 0}, "the ball's radius about C at the reference pose"},
      {"change", core::Status::kChangeBeyondLimit, {var::kRigidityMaxChange, 0, 0},
       "with R = 1: each pose's rotation vector against the stored table's at its A; M = 1 confirms"},
  };
  static constexpr List<GateInfo> kGates = list_of(kGateTable);
  static constexpr CheckInfo kCheck{kMacroCheck, list_of(rigidity::kCheckFigureKinds)};
  static constexpr List<CheckFigureInfo> kLogFigures = list_of(rigidity::kLogFigureKinds);
  using State = rigidity::State;
  using Table = RigidityTableRecord;
  static StoredTable<Table>& table(State& s) { return s.table; }
  // M1 levels on the calibrated axes with the stored table (services.hpp).
  static void provide(State& s, Services& services) { services.calibrated_axes = &s.table; }
};

}  // namespace trueaxis::macros::rigidity
