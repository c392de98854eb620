// Leveling an inclined face on the calibrated, imperfect axes (docs/METHODS.md M1
// "what the product must add", docs/METHODS.md "M3 design notes"): the commanded (C, A) that turn
// the probed face horizontal on the actual table frames of a rigidity table.
//
// Conventions
//  1. Shapes, limits and choice as leveling.hpp (LevelConfig, LevelInput,
//     LevelResult; conventions 3, 6, 7, 9 there), so a caller can swap
//     level_face for level_on_table. The plane fit, the outward orientation and
//     the diagnostics (flatness, tilt and C uncertainties, direction sigma,
//     outliers) are level_face's, run with its travel limits opened; the axes'
//     errors (arc-seconds) change them only to second order. The tilt in the
//     machine frame at the probe pose (machine_tilt_deg and its sigma,
//     leveling.hpp convention 8) is level_face's exactly: no axis model enters it.
//  2. The table carries the axes' senses (rigidity_compensation.hpp convention
//     5): config.a_sign and c_sign are validated but not used.
//  3. Table normal: q = (E_act(A0) Rz(C0))^T n_machine, from the frames at the
//     probe pose (A0, C0) (rigidity_frames, `blend`). normal_table = q and
//     tilt_deg = angle(q, table Z).
//  4. Solutions: (A, C) with E_act(A) Rz(C) q = +Z. Initial guesses: the two
//     closed-form solutions of the same equation on the measured but rigid axes
//     (rv = 0, e = 0): with a = E_ref^T nA and z = E_ref^T Z, p = Rz(C) q is on
//     the cone p.e_z = q.e_z and on the cone p.a = z.a, p = alpha a + beta e_z
//     +- gamma (a x e_z) (Paden-Kahan subproblem 2); C turns q to p about e_z,
//     theta turns p to z about a. Then Newton on (v_x, v_y), v = E_act(A) Rz(C) q,
//     with dv/dC exact and dv/dA = (pi / 180) nA x v (the axes' slow variation
//     neglected: the iteration still converges, linearly at a rate of order
//     |d rv / dA|), until angle(v, +Z) <= kCalibratedLevelTolerance_rad.
//  5. A face level within the normal's 1-sigma direction error (leveling.hpp
//     convention 5), or one whose tilt is below the axes' own misalignment (the
//     cones do not meet: no exact solution exists), keeps C (the current C when
//     level; the cones' nearest point otherwise) and gets the A that brings its
//     normal nearest +Z: (nA x v).Z = 0 with v.Z maximal. Both solutions are that one.
//  6. Range: the iterations use the table clamped; a solution whose A lies
//     outside the table's A range is unreachable unless `clamp` (then the end
//     poses' corrections hold there). The probe pose is subject to the same rule
//     (kOutsideMeasuredRange).
//
// Status codes: those of level_face (kConfigInvalid, kNotFinite, the plane fit's,
// kPointsTooClose, kOrientationAmbiguous), of rigidity_frames (kNoTable,
// kOutsideMeasuredRange), kNoConvergence (Newton did not reach the tolerance in
// kCalibratedLevelMaxIterations), kUnreachable (neither solution reachable).
#pragma once

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/rigidity_compensation.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::core {

inline constexpr double kCalibratedLevelTolerance_rad = 1e-12;
inline constexpr int kCalibratedLevelMaxIterations = 40;

[[nodiscard]] Result<LevelResult> level_on_table(const LevelInput& input, const LevelConfig& config,
                                                 const RigidityTable& table, Blend blend, bool clamp);

}  // namespace trueaxis::core
