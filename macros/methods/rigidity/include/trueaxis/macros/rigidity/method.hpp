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
                                        9830, 9831, 9832, list_of(kLimits)};
  using State = rigidity::State;
  using Table = RigidityTableRecord;
  static StoredTable<Table>& table(State& s) { return s.table; }
  // M1 levels on the calibrated axes with the stored table (services.hpp).
  static void provide(State& s, Services& services) { services.calibrated_axes = &s.table; }
};

}  // namespace trueaxis::macros::rigidity
