// M3 compensation: the rigidity table queried at any commanded A, the theory
// and actual frames of the table at (A, C), and the conversions between them
// (docs/METHODS.md M3 S300, docs/INTERFACE.md macro 9833, docs/METHODS.md "M3 design notes").
//
// Conventions
//  1. Frames and units as rigidity_table.hpp: machine frame, mm, commanded
//     angles in degrees, rotation vectors in radians in machine coordinates.
//  2. Range. A query at commanded A inside [A_1, A_m] (the table's first and
//     last poses, both included) interpolates between the bracketing poses k,
//     k + 1. Outside it the query is refused (kOutsideMeasuredRange) unless
//     `clamp`, which takes the nearest end pose's values. At a pose's own A
//     every blend returns that pose's values exactly (bit for bit).
//  3. Blends of the rotation vector rv, w = (A - A_k) / (A_{k+1} - A_k):
//       kLinear   rv = (1 - w) rv_k + w rv_{k+1};
//       kGeodesic R = R_k exp(w log(R_k^T R_{k+1})), rv = log(R), R_i = exp(rv_i)
//                 (the constant-speed path on SO(3); log(R_k^T R_{k+1}) is
//                 precomputed in the table);
//       kCubic    the natural cubic spline through (A_i, rv_i), per component
//                 (docs/INTERFACE.md's blend 2), second derivatives M precomputed in
//                 the table; kCubicNotAKnot the same with the not-a-knot end
//                 conditions, which keep a smooth law's curvature at the ends of
//                 the range where the natural spline forces it to zero (a
//                 gravity-like sin A deflection of 50" misses by 1.1" near the
//                 ends with kCubic and by 0.1" with kCubicNotAKnot, poses 30 deg
//                 apart). Both:
//                 rv = y_k + t (b + t (M_k / 2 + t (M_{k+1} - M_k) / (6 h))),
//                 t = A - A_k, h = A_{k+1} - A_k,
//                 b = (y_{k+1} - y_k) / h - h (2 M_k + M_{k+1}) / 6.
//  4. The A positioning error e(A) and the origin offset d(A) interpolate
//     linearly for kLinear and kGeodesic, and along their own not-a-knot cubic
//     splines for kCubic and kCubicNotAKnot (a sin-like e(A) of 80" misses by about 2.7" midway
//     between poses 30 deg apart when linear: 2.6 um at 200 mm). theta(A) = deg2rad(A - A_ref) + e(A): with
//     `clamp` outside the range, A itself still turns the frames and e, d, rv
//     are the end pose's (the nearest measured correction, not a frozen frame).
//  5. Frames at commanded (A, C), as rigid transforms machine_T_table (a table
//     point q: origin at the C centre, axes of the reference pose's actual frame
//     at C = 0, turning with C about its Z):
//       theory: R_T = R(nA, theta(A)) E_ref Rz(C),
//               t_T = a0 + R(nA, theta(A)) (c_ref - a0);
//       actual: R_A = exp(rv(A)) R(nA, theta(A)) E_ref Rz(C),  t_A = t_T + d(A).
//     Rz(C) is the right-hand turn by the commanded C about the table's Z (the
//     measured C direction): the table carries the axes' senses, so no sign
//     configuration applies.
//  6. actual_T_theory = machine_T_table_actual * machine_T_table_theory^-1 maps
//     where the ideal (theory) machine would put a table point to where the real
//     one puts it: points with point(), directions with direction(); its
//     inverse() maps back.
//
// Status codes: kNoTable (pose_count below 2 or above kMaxAPoses), kNotFinite
// (A or C), kOutsideMeasuredRange (A outside the range without clamp),
// kArgumentOutOfRange (an unknown blend).
#pragma once

#include <cstdint>

#include "trueaxis/core/rigid_transform.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

enum class Blend : std::uint8_t { kLinear = 0, kGeodesic = 1, kCubic = 2, kCubicNotAKnot = 3 };

// The rotation vector (rad, machine) at commanded A (conventions 2, 3). The
// real-time query: a bracket search over <= 16 poses and a few flops (one exp
// and one log for kGeodesic).
[[nodiscard]] Result<Vec3> rigidity_rotvec_rad(const RigidityTable& table, double a_deg, Blend blend, bool clamp);

struct RigidityState {
  Vec3 rotvec_rad = Vec3::Zero();
  double a_error_rad = 0.0;          // e(A)
  double theta_rad = 0.0;            // the A axis's actual turn from the reference
  Vec3 origin_offset_mm = Vec3::Zero();  // d(A)
};

// Everything the frames need at commanded A (conventions 2-4).
[[nodiscard]] Result<RigidityState> rigidity_state(const RigidityTable& table, double a_deg, Blend blend, bool clamp);

struct RigidityFrames {
  RigidTransform machine_T_table_theory;
  RigidTransform machine_T_table_actual;
};

// The theory and actual frames of the table at commanded (A, C) (convention 5).
[[nodiscard]] Result<RigidityFrames> rigidity_frames(const RigidityTable& table, double a_deg, double c_deg,
                                                     Blend blend, bool clamp);

// The actual frame's rotation alone, machine_T_table_actual.rotation of
// rigidity_frames (the same arithmetic, without the translations): what the
// calibrated leveling iterates on.
[[nodiscard]] Status rigidity_actual_axes(const RigidityTable& table, double a_deg, double c_deg, Blend blend,
                                          bool clamp, Mat3& axes);

// actual_T_theory at commanded (A, C) (convention 6): machine theory -> machine actual.
[[nodiscard]] Result<RigidTransform> rigidity_correction(const RigidityTable& table, double a_deg, double c_deg,
                                                         Blend blend, bool clamp);

}  // namespace trueaxis::core
