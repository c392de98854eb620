// M1, three-point auto-level: its rows of the register map, its outputs, its
// blocks and its status codes (docs/METHODS.md M1). Its descriptor is
// method.hpp.
//
// Conventions
//  1. Configuration #500..#509 (block #500..#599), the point list of 9811
//     #1001..#1096 (block #1000..#1999).
//  2. Outputs #100..#118 of 9810, 9811 and 9814; #100..#110 of 9815 (the
//     ball through the session's touches). Interface version 1 named the
//     result variables #100..#116 after them (level_c ...); the map keeps those
//     names (the descriptor's kNamedResults: the first kNamedLevelOutputs).
//     #117, #118 (the tilt in the machine frame at the probe pose and its sigma,
//     issue 17 item 5) came later and are named only in the macros' outputs.
//  3. Status codes: block 1000..1099 (1000 touches_coplanar, 9815); the two
//     it owned before the block (203, 204) keep their numbers.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/plane_fit.hpp"
#include "trueaxis/core/sphere_fit.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kLevelC = 100;
inline constexpr std::uint16_t kLevelA = 101;
inline constexpr std::uint16_t kLevelOtherC = 102;
inline constexpr std::uint16_t kLevelOtherA = 103;
inline constexpr std::uint16_t kLevelNormalX = 104;
inline constexpr std::uint16_t kLevelNormalY = 105;
inline constexpr std::uint16_t kLevelNormalZ = 106;
inline constexpr std::uint16_t kLevelTilt = 107;
inline constexpr std::uint16_t kLevelTiltSigma = 108;
inline constexpr std::uint16_t kLevelCSigma = 109;
inline constexpr std::uint16_t kLevelDirectionSigma = 110;
inline constexpr std::uint16_t kLevelFlatness = 111;
inline constexpr std::uint16_t kLevelPointCount = 112;
inline constexpr std::uint16_t kLevelOutlierPoint = 113;
inline constexpr std::uint16_t kLevelMaxResidual = 114;
inline constexpr std::uint16_t kLevelOtherReachable = 115;
inline constexpr std::uint16_t kLevelAxesUsed = 116;
inline constexpr std::uint16_t kLevelMachineTilt = 117;
inline constexpr std::uint16_t kLevelMachineTiltSigma = 118;

inline constexpr std::uint16_t kBallCentreX = 100;  // 9815
inline constexpr std::uint16_t kBallCentreY = 101;
inline constexpr std::uint16_t kBallCentreZ = 102;
inline constexpr std::uint16_t kBallRadius = 103;
inline constexpr std::uint16_t kBallCentreSigmaX = 104;
inline constexpr std::uint16_t kBallCentreSigmaY = 105;
inline constexpr std::uint16_t kBallCentreSigmaZ = 106;
inline constexpr std::uint16_t kBallRadiusSigma = 107;
inline constexpr std::uint16_t kBallRmsResidual = 108;
inline constexpr std::uint16_t kBallMaxResidual = 109;
inline constexpr std::uint16_t kBallPointCount = 110;

inline constexpr std::uint16_t kLevelSessionCount = 100;     // 9812, 9813
inline constexpr std::uint16_t kLevelSessionCapacity = 101;  // 9812, 9813

inline constexpr std::uint16_t kAMin = 500;
inline constexpr std::uint16_t kAMax = 501;
inline constexpr std::uint16_t kCMin = 502;
inline constexpr std::uint16_t kCMax = 503;
inline constexpr std::uint16_t kASign = 504;
inline constexpr std::uint16_t kCSign = 505;
inline constexpr std::uint16_t kProbeSigma = 506;
inline constexpr std::uint16_t kMaxDirectionSigma = 507;
inline constexpr std::uint16_t kLevelAxes = 508;
inline constexpr std::uint16_t kLevelCheckTolerance = 509;

inline constexpr std::uint16_t kPointList = 1001;
inline constexpr std::uint16_t kPointListCount = static_cast<std::uint16_t>(3 * core::kMaxPlanePoints);
}  // namespace var

namespace level {

// Its macros, named once: the descriptor (kMacros, kSession, kCheck), the
// host's flows and plans use these names (docs/INTERFACE.md has the numbers).
inline constexpr std::uint16_t kMacroThreePoint = 9810;
inline constexpr std::uint16_t kMacroPoints = 9811;
inline constexpr std::uint16_t kMacroSessionClear = 9812;
inline constexpr std::uint16_t kMacroSessionAdd = 9813;
inline constexpr std::uint16_t kMacroSessionCompute = 9814;
inline constexpr std::uint16_t kMacroSessionBall = 9815;
inline constexpr std::uint16_t kMacroCheck = 9816;

inline constexpr MethodBlock kBlock{"level", 500, 599, 1000, 1999};

// Points the streaming session (9812..9814) holds: as many as the plane fit takes.
inline constexpr std::uint16_t kSessionCapacity = static_cast<std::uint16_t>(core::kMaxPlanePoints);

inline constexpr core::LevelConfig kDefaults{};

// 9816's tolerance of the tilt after leveling (#509), arcsec.
inline constexpr double kDefaultCheckToleranceArcsec = 10.0;

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(var::kAMin, -360.0, 360.0, kDefaults.a_min_deg, "a_min", "deg", "A-axis travel: lower limit."),
  rows::config(var::kAMax, -360.0, 360.0, kDefaults.a_max_deg, "a_max", "deg", "A-axis travel: upper limit."),
  rows::config(var::kCMin, -rows::kBig, rows::kBig, kDefaults.c_min_deg, "c_min", "deg", "C-axis travel: lower limit."),
  rows::config(var::kCMax, -rows::kBig, rows::kBig, kDefaults.c_max_deg, "c_max", "deg", "C-axis travel: upper limit."),
  rows::sign_config(var::kASign, kDefaults.a_sign, "a_sign", "A direction: +1 when +A turns the table right-handed about +X, -1 when it turns it the other way (ISO 841)."),
  rows::sign_config(var::kCSign, kDefaults.c_sign, "c_sign", "C direction: +1 when +C turns the table right-handed about +Z, -1 otherwise."),
  rows::config(var::kProbeSigma, 0.0, 1.0, kDefaults.probe_sigma_mm, "probe_sigma", "mm", "Touch-probe repeatability, 1 sigma."),
  rows::config(var::kMaxDirectionSigma, 1e-6, 90.0, kDefaults.max_direction_sigma_deg, "max_direction_sigma", "deg", "Leveling refuses points whose normal would be uncertain by more than this (1 sigma)."),
  {var::kLevelAxes, 1, Access::kConfig, ValueKind::kInteger, 0.0, 1.0, 0.0, "level_axes", "",
   "Leveling runs on 0: the ideal axes Rx(A) Rz(C); 1: the calibrated axes of the stored rigidity table (M3)."},
  rows::config(var::kLevelCheckTolerance, 1e-3, 1e6, kDefaultCheckToleranceArcsec, "level_check_tolerance", "arcsec",
               "Leveling check (9816): the tolerance of the face's tilt, probed again after leveling."),
  rows::data_block(var::kPointList, var::kPointListCount, "level_points", "mm", "Macro 9811: X, Y, Z of points 1..32, interleaved, machine frame."),
};

// The check's one figure (check.hpp convention 1): the re-probe after leveling.
inline constexpr CheckFigureInfo kCheckFigureKinds[] = {
  {1, "tilt_after_leveling", "arcsec", "The face's tilt in the machine frame, probed again after leveling (9814's #117 in arcsec); stored 0, the face level; its sigma 9814's #118."},
};

// What 9810, 9811 and 9814 put in #100..#118.
inline constexpr OutputInfo kLevelOutputs[] = {
  {var::kLevelC, "level_c", "deg", "Leveling: C of the chosen solution (absolute, commanded)."},
  {var::kLevelA, "level_a", "deg", "Leveling: A of the chosen solution (absolute, commanded)."},
  {var::kLevelOtherC, "level_other_c", "deg", "Leveling: C of the other solution."},
  {var::kLevelOtherA, "level_other_a", "deg", "Leveling: A of the other solution."},
  {var::kLevelNormalX, "level_normal_x", "", "Leveling: X of the face's outward unit normal, table at zero."},
  {var::kLevelNormalY, "level_normal_y", "", "Leveling: Y of the outward unit normal, table at zero."},
  {var::kLevelNormalZ, "level_normal_z", "", "Leveling: Z of the outward unit normal, table at zero."},
  {var::kLevelTilt, "level_tilt", "deg", "Leveling: the face's tilt from horizontal, table at zero."},
  {var::kLevelTiltSigma, "level_tilt_sigma", "arcsec", "Leveling: standard uncertainty (1 sigma) of the tilt from the probe repeatability."},
  {var::kLevelCSigma, "level_c_sigma", "arcsec", "Leveling: standard uncertainty of C (capped at 180 deg; large when the face is nearly level)."},
  {var::kLevelDirectionSigma, "level_direction_sigma", "arcsec", "Leveling: largest 1-sigma error of the normal's direction."},
  {var::kLevelFlatness, "level_flatness", "mm", "Leveling: flatness (max minus min distance to the fitted plane); 0 for 3 points."},
  {var::kLevelPointCount, "level_point_count", "", "Leveling: number of points used."},
  {var::kLevelOutlierPoint, "level_outlier_point", "", "Leveling: number of the point flagged as an outlier (5 or more points), 0 if none."},
  {var::kLevelMaxResidual, "level_max_residual", "sigma", "Leveling: largest standardised residual (5 or more points)."},
  {var::kLevelOtherReachable, "level_other_reachable", "", "Leveling: 1 when the other solution is inside the travel limits too, else 0."},
  {var::kLevelAxesUsed, "level_axes_used", "", "Leveling: the axes it ran on, 0 ideal, 1 calibrated (level_axes, #508)."},
  {var::kLevelMachineTilt, "level_machine_tilt", "deg", "Leveling: the face's tilt from horizontal in the machine frame, with the table where it was probed (A = #1, C = #3), on either axes: an operator's check after leveling."},
  {var::kLevelMachineTiltSigma, "level_machine_tilt_sigma", "arcsec", "Leveling: standard uncertainty (1 sigma) of that tilt from the probe repeatability."},
};
// The outputs interface version 1 named the results #100..#116 after (convention 2).
inline constexpr std::size_t kNamedLevelOutputs = 17;
static_assert(kLevelOutputs[kNamedLevelOutputs - 1].number == var::kLevelAxesUsed, "named results end at #116");

// What 9815 puts in #100..#110 (sphere_fit.hpp).
inline constexpr OutputInfo kBallOutputs[] = {
  {var::kBallCentreX, "ball_centre_x", "mm", "Ball: X of the centre of the sphere through the session's touches."},
  {var::kBallCentreY, "ball_centre_y", "mm", "Ball: Y of the centre."},
  {var::kBallCentreZ, "ball_centre_z", "mm", "Ball: Z of the centre."},
  {var::kBallRadius, "ball_radius", "mm", "Ball: the sphere's radius (the ball's plus the stylus tip's; R when R > 0)."},
  {var::kBallCentreSigmaX, "ball_centre_sigma_x", "mm", "Ball: 1 sigma of the centre's X from the probe repeatability (#506)."},
  {var::kBallCentreSigmaY, "ball_centre_sigma_y", "mm", "Ball: 1 sigma of the centre's Y."},
  {var::kBallCentreSigmaZ, "ball_centre_sigma_z", "mm", "Ball: 1 sigma of the centre's Z."},
  {var::kBallRadiusSigma, "ball_radius_sigma", "mm", "Ball: 1 sigma of the radius (0 when R fixed it)."},
  {var::kBallRmsResidual, "ball_rms_residual", "mm", "Ball: root mean square of the touches' distances from the sphere."},
  {var::kBallMaxResidual, "ball_max_residual", "mm", "Ball: the largest distance of a touch from the sphere."},
  {var::kBallPointCount, "ball_point_count", "", "Ball: number of touches used."},
};

// What 9812 and 9813 put in #100, #101.
inline constexpr OutputInfo kSessionOutputs[] = {
  {var::kLevelSessionCount, "level_session_count", "", "Points in the leveling session after this macro."},
  {var::kLevelSessionCapacity, "level_session_capacity", "", "Points the leveling session holds at most."},
};
// Its status codes (block 1000..1099).
inline constexpr core::Status kTouchesCoplanar = static_cast<core::Status>(1000);

inline constexpr core::StatusInfo kStatuses[] = {
  {core::Status::kOrientationAmbiguous, "orientation_ambiguous", "The face is perpendicular to the orientation hint: give its outward direction in I, J, K."},
  {core::Status::kUnreachable, "unreachable", "Neither leveling solution lies inside the rotary axes' travel limits."},
  {kTouchesCoplanar, "touches_coplanar", "Macro 9815: the touches lie in one plane (on one circle of the ball), so they do not determine its centre: touch the ball also at its top or on another circle."},
};
// clang-format on

}  // namespace level
}  // namespace trueaxis::macros
