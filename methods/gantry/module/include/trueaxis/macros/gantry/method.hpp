// M2, gantry zero frames: the method as one type (method.hpp).
#pragma once

#include "trueaxis/macros/gantry/gantry_macros.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/method.hpp"

namespace trueaxis::macros::gantry {

struct Method : Shape {
  static constexpr const char* kName = "gantry";
  static constexpr MethodBlock kBlock = gantry::kBlock;
  static constexpr StatusBlock kStatusBlock{1200, 1299};
  static constexpr List<core::StatusInfo> kStatuses = list_of(gantry::kStatuses);
  static constexpr List<MacroInfo> kMacros = list_of(gantry::kMacros);
  // docs/INTERFACE.md: group sizes "are limited by capacities that the map states".
  static constexpr SessionLimit kLimits[] = {
      {"group_capacity", "bed", kMaxPlanePoints},      {"group_capacity", "side_1", kMaxPlanePoints},
      {"group_capacity", "side_2", kMaxPlanePoints},   {"group_capacity", "gantry_K", kMaxPassPoints},
      {"group_capacity", "spN_x_K", kMaxPassPoints},   {"group_capacity", "spN_y_K", kMaxPassPoints},
      {"group_capacity", "spN_z_K", kMaxPassPoints},   {"group_capacity", "spN_c", kMaxCirclePoints},
      {"group_capacity", "spN_a", kMaxCirclePoints},   {"", "passes", kMaxPasses},
      {"", "sub_machines", core::kMaxSubMachines},
  };
  static constexpr SessionInfo kSession{kSessionCapacity, "points",
                                        "group T, Q, D (#20, #17, #7), point X, Y, Z (#24..#26, mm, tracker frame)",
                                        kMacroSessionClear, kMacroSessionAdd, kMacroBuild, list_of(kLimits)};
  static constexpr GateInfo kGateTable[] = {
      {"bed_span", kBedSpanImplausible, {var::kGantryMinBedSpan, 0, 0}, "the bed points' span (points in metres?)"},
      {"swing", kSwingImplausible, {var::kGantryMinSwing, 0, 0}, "each sub-machine's swing length (MACHINE in metres?)"},
      {"nominal_origin", kOriginOffNominal, {var::kGantryMaxNominalOffset, 0, 0},
       "each sub-machine's measured origin against the nominal origin its 9822 gave (a swing length or tool direction typed wrong?)"},
      {"fit", core::Status::kFitBeyondNoise, {var::kGantryTrackerNoise, var::kGantryTrackerNoisePerM, var::kGateConfidence},
       "each sub-machine's C and A circle residuals (2 n - 6 degrees of freedom) against the tracker's noise a + b r"},
      {"change", core::Status::kChangeBeyondLimit, {var::kGantryMaxOriginChange, var::kGantryMaxAngleChange, 0},
       "with R = 1: each stored sub-machine's origin move and axes' turn; M = 1 confirms"},
  };
  static constexpr List<GateInfo> kGates = list_of(kGateTable);
  static constexpr CheckInfo kCheck{kMacroCheck, list_of(gantry::kCheckFigureKinds)};
  static constexpr List<CheckFigureInfo> kLogFigures = list_of(gantry::kLogFigureKinds);
  using State = gantry::State;
  using Table = FramesRecord;
  static StoredTable<Table>& table(State& s) { return s.table; }
};

}  // namespace trueaxis::macros::gantry
