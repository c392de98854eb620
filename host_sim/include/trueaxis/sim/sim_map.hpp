// The simulator's own variables: not part of the module, served only by
// trueaxis-sim, and published in register_map.json with "simulator_only": true.
// They live at #12000.., outside every range the module defines, so an
// integrator's PLC program can never come to depend on them.
#pragma once

#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::sim {

namespace simvar {
inline constexpr std::uint16_t kFirst = 12000;
inline constexpr std::uint16_t kAxisA = 12000;
inline constexpr std::uint16_t kAxisC = 12001;
inline constexpr std::uint16_t kProbeX = 12002;
inline constexpr std::uint16_t kProbeY = 12003;
inline constexpr std::uint16_t kProbeInto = 12004;
inline constexpr std::uint16_t kLastProbeX = 12005;
inline constexpr std::uint16_t kLastProbeY = 12006;
inline constexpr std::uint16_t kLastProbeZ = 12007;
inline constexpr std::uint16_t kProbeSigma = 12008;
inline constexpr std::uint16_t kHold = 12009;
inline constexpr std::uint16_t kTrueNormalX = 12010;
inline constexpr std::uint16_t kTrueNormalY = 12011;
inline constexpr std::uint16_t kTrueNormalZ = 12012;
inline constexpr std::uint16_t kTrueTilt = 12013;
inline constexpr std::uint16_t kLast = 12013;
}  // namespace simvar

namespace detail {
using macros::Access;
using macros::ValueKind;
inline constexpr double kBig = 1e5;
}  // namespace detail

// clang-format off
inline constexpr macros::VarInfo kSimMap[] = {
  {12000, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_axis_a", "deg", "Simulator: the virtual table's A position (commanded); writing moves it."},
  {12001, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_axis_c", "deg", "Simulator: the virtual table's C position (commanded); writing moves it."},
  {12002, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_probe_x", "mm", "Simulator: machine X at which the next probe comes down."},
  {12003, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_probe_y", "mm", "Simulator: machine Y at which the next probe comes down."},
  {12004, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 16383.0, 0.0, "sim_probe_into", "", "Simulator: write a work-offset X number (5221, 5241, .., 5321) or a point-list X number (1001, 1004, ..): the probe comes down at (sim_probe_x, sim_probe_y) and stores the touch point X, Y, Z there."},
  {12005, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_x", "mm", "Simulator: X of the last touch point (machine frame)."},
  {12006, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_y", "mm", "Simulator: Y of the last touch point."},
  {12007, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_z", "mm", "Simulator: Z of the last touch point."},
  {12008, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, 0.0, 1.0, 0.0005, "sim_probe_sigma", "mm", "Simulator: the virtual probe's noise, 1 sigma per coordinate."},
  {12009, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 1.0, 0.0, "sim_hold", "", "Simulator: 1 keeps a commanded macro busy (not run) until set back to 0; for testing the busy handshake."},
  {12010, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_normal_x", "", "Simulator ground truth: X of the face's outward unit normal, table at zero."},
  {12011, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_normal_y", "", "Simulator ground truth: Y of the outward unit normal, table at zero."},
  {12012, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 1.0, "sim_true_normal_z", "", "Simulator ground truth: Z of the outward unit normal, table at zero."},
  {12013, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, 0.0, 180.0, 0.0, "sim_true_tilt", "deg", "Simulator ground truth: the face's tilt from horizontal at the table's present position."},
};
// clang-format on

static_assert(macros::map_is_well_formed(kSimMap, sizeof(kSimMap) / sizeof(kSimMap[0])), "kSimMap: unsorted, overlapping or inconsistent entry");
inline constexpr std::size_t kSimMapSize = sizeof(kSimMap) / sizeof(kSimMap[0]);

constexpr const macros::VarInfo* find_sim_var(std::uint16_t number) {
  return macros::find_in(kSimMap, kSimMapSize, number);
}

}  // namespace trueaxis::sim
