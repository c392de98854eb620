// Leveling an inclined face on a cradle table (docs/METHODS.md M1): the table angles
// (C, A) that turn the probed face horizontal.
//
// Conventions
//  1. Machine: a cradle table. A tilts the cradle about the machine's X axis, C
//     turns the table about the table's own Z axis. A point fixed to the table,
//     written p_table with the table at zero, is at
//         p_machine = Rx(A_phys) Rz(C_phys) p_table
//     (rotations about the table's centre of rotation; for normals the centre does
//     not matter).
//  2. Signs (ISO 841): A_phys = a_sign * A_cmd and C_phys = c_sign * C_cmd, with
//     sign +1 when a positive command turns the table by the right-hand rule
//     about +X (+Z), and -1 for a table that turns the other way. Every angle this
//     file takes or returns is a commanded angle in degrees.
//  3. The face normal is oriented outward, towards the spindle: the fitted normal
//     is flipped to agree with `outward_hint_machine` (machine frame, table at the
//     probe pose; the zero vector means +Z, the spindle side).
//  4. Solutions. With n = (nx, ny, nz) the outward normal at table zero and
//     rho = sqrt(nx^2 + ny^2):
//         C1 = atan2(nx, ny),  A1 = atan2(rho, nz)   (physical angles)
//         C2 = C1 + 180 deg,   A2 = -A1
//     Both satisfy Rx(A) Rz(C) n = +Z. atan2, not the seed's atan, keeps the
//     face right side up in every quadrant.
//  5. A face already level has no defined C: both solutions keep C at the current
//     position (its representative nearest it, if it lies outside the C limits)
//     and set A = 0. Level means facing up (nz > 0) with a tilt no larger
//     than the normal's 1-sigma direction error sigma / s_v (item 7), so that
//     probe noise on a level face never swings C; with a perfect probe
//     (sigma = 0) only rho == 0 is level. A face facing down (nz < 0) is never
//     level: it needs A near +-180 deg.
//  6. C is written as the representative (C + k 360) nearest to the current C
//     inside the C travel limits. A solution is reachable when its A lies inside
//     the A limits and such a representative exists. Of the reachable ones the one
//     with the smaller |dA| + |dC| is chosen; on a tie, solution 1. A tie is
//     two costs within kLevelTieDeg of each other, so that rounding (another
//     libm, another compiler) cannot turn an exact tie into a different choice.
//  7. Uncertainty: probe noise sigma (mm, 1 sigma, along the normal) gives the
//     fitted normal an error with covariance sigma^2 diag(1/s_u^2, 1/s_v^2) in the
//     fit's in-plane axes (plane_fit.hpp). The tilt's standard uncertainty is the
//     first-order (GUM) propagation along the direction in which tilt grows; at a
//     tilt of exactly zero, where tilt is not differentiable, it is sigma / s_v, the
//     largest 1-sigma error of the normal's direction. C's uncertainty is the
//     propagation across it, divided by sin(tilt), capped at 180 deg.
//  8. The face as probed: machine_tilt_deg is the angle between the outward
//     normal in the machine frame (the fitted normal, oriented as convention 3,
//     table wherever it stood while probing) and machine +Z: the face's tilt
//     from horizontal at the probe pose, which no axis model enters.
//     machine_tilt_sigma_arcsec is its 1 sigma by convention 7's rule with
//     machine +Z in place of table +Z. With the table at zero on the ideal axes
//     (probe_pose 0, 0) both equal tilt_deg and tilt_sigma_arcsec bit for bit.
//  9. Outliers: with 5 or more points, the point whose standardised residual
//     r_i / (sigma sqrt(1 - h_ii)) is largest is reported when that exceeds
//     kOutlierLimit. With 4 points the residuals are all equally large, so a bad
//     point shows only in the flatness.
//
// Status codes: those of fit_plane, plus kNotFinite (pose or hint),
// kConfigInvalid, kPointsTooClose (the normal's 1-sigma direction error sigma / s_v
// exceeds max_direction_sigma_deg), kOrientationAmbiguous (|cos| between normal
// and hint below kOrientationMinCos or below 3 sigma / s_v, where probe noise could
// flip the side), kUnreachable.
#pragma once

#include <cstddef>

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr double kOrientationMinCos = 1e-6;  // the face within 0.2" of perpendicular to the hint
inline constexpr double kOutlierLimit = 4.0;        // standardised residual, in units of sigma

struct LevelConfig {
  double a_min_deg = -120.0;
  double a_max_deg = 120.0;
  double c_min_deg = -100000.0;
  double c_max_deg = 100000.0;
  double a_sign = 1.0;  // +1 or -1, convention 2
  double c_sign = 1.0;
  double probe_sigma_mm = 0.0005;
  double max_direction_sigma_deg = 0.1;
};

struct TablePose {
  double a_deg = 0.0;
  double c_deg = 0.0;
};

struct LevelInput {
  const Vec3* points_mm = nullptr;  // machine frame, table at probe_pose
  std::size_t count = 0;
  TablePose probe_pose;             // commanded table position while probing
  TablePose current_pose;           // commanded table position now
  Vec3 outward_hint_machine = Vec3::Zero();
};

struct LevelSolution {
  double c_deg = 0.0;
  double a_deg = 0.0;
  bool reachable = false;
};

struct LevelResult {
  LevelSolution chosen;
  LevelSolution other;
  Vec3 normal_table = Vec3::UnitZ();  // outward unit normal, table at zero
  double tilt_deg = 0.0;              // angle between normal_table and +Z
  double tilt_sigma_arcsec = 0.0;
  double c_sigma_arcsec = 0.0;
  double direction_sigma_arcsec = 0.0;  // sigma / s_v: the worst-case 1-sigma direction error
  double flatness_mm = 0.0;
  std::size_t count = 0;
  std::size_t outlier_point = 0;  // 1-based; 0 when none is flagged
  double max_standardized_residual = 0.0;
  double machine_tilt_deg = 0.0;          // convention 8: the tilt at the probe pose, machine frame
  double machine_tilt_sigma_arcsec = 0.0;
};

[[nodiscard]] Status validate(const LevelConfig& config);

[[nodiscard]] Result<LevelResult> level_face(const LevelInput& input, const LevelConfig& config);

// A solution at commanded angles (deg): C moved to its representative nearest the
// current C inside the C limits, reachable when A and that C are inside the
// limits (convention 6). Shared with the calibrated leveling (rigidity_leveling.hpp).
LevelSolution level_solution(double c_deg, double a_deg, const TablePose& current, const LevelConfig& config);

// Convention 6's tie: costs closer than this (deg) are equal.
inline constexpr double kLevelTieDeg = 1e-9;

// Convention 6's choice: the reachable one of s1, s2 with the smaller |dA| + |dC|
// (s1 on a tie, within kLevelTieDeg; s1 when neither is reachable) becomes `chosen`.
void order_level_solutions(const LevelSolution& s1, const LevelSolution& s2, const TablePose& current,
                           LevelSolution& chosen, LevelSolution& other);

// R_machine_table for commanded angles: p_machine = R * p_table (convention 1, 2).
Mat3 table_rotation(const TablePose& pose, const LevelConfig& config);

}  // namespace trueaxis::core
