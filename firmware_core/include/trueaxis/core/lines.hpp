// Lines, planes and rigid transforms in 3-D: the common perpendicular of two
// lines, the point common to three planes, and Rigid3 (docs/METHODS.md M2 S1, S3, S4).
//
// Conventions
//  1. Lengths in millimetres, in whatever frame the caller uses; every output is
//     in that frame. A line is a point and a direction, a plane a point and a
//     normal; the directions and normals need not be unit (they are normalised
//     here) but must be finite and non-zero.
//  2. Common perpendicular of lines L1 = p1 + s d1 and L2 = p2 + t d2 (unit d1,
//     d2), with n = d1 x d2 and w = p2 - p1:
//         s = ((w x d2) . n) / |n|^2,   t = ((w x d1) . n) / |n|^2,
//     foot_1 = p1 + s d1, foot_2 = p2 + t d2; length = |w . n| / |n| (>= 0).
//     This is docs/METHODS.md S3's T = R_C + h c with h = <R_A - R_C, n'> / <c, n'>
//     (L1 = C, L2 = A): both are the closest points of the two lines. The cross
//     products avoid the cancellation of 1 - (d1 . d2)^2. angle_deg is the angle
//     between d1 and d2 in [0, 180] (atan2, exact near 0 and 180); `direction`
//     is n / |n|, the unit vector from foot_1 to foot_2 when length > 0 up to sign
//     (foot_2 - foot_1 = ((w . n) / |n|^2) n).
//  3. Nearly parallel lines: the feet move by (a displacement across the lines) /
//     sin(angle), so the perpendicular is refused with kAxesParallel when
//     |n| = sin(angle) < min_sin (default kMinLineSin = 1e-3: a 1 um error in
//     either line would move a foot by more than 1 mm). Parallel lines have a
//     distance but no common perpendicular foot: parallel_distance_mm gives it.
//  4. Three planes n_i . x = n_i . p_i (unit n_i) meet in
//         x = p_1 + [ b_1 (n_2 x n_3) + b_2 (n_3 x n_1) + b_3 (n_1 x n_2) ] / D,
//     b_i = n_i . (p_i - p_1), D = n_1 . (n_2 x n_3) (Cramer's rule, taken
//     relative to p_1 so that the b_i are of the size of the planes' separation,
//     not of the distance from the frame's origin). |D| is the volume of the
//     normals' parallelepiped: 1 for three perpendicular planes, 0 when two are
//     parallel or all three share a direction; a 1 um error in a plane moves the
//     point by up to about 1 um / |D|. |D| < min_det (default kMinPlanesDet = 1e-3)
//     gives kPlanesDegenerate.
//  5. Rigid3 { R, t } maps points of frame b into frame a when named a_T_b:
//     p_a = R p_b + t; directions: v_a = R v_b. compose(a_T_b, b_T_c) = a_T_c,
//     inverse(a_T_b) = b_T_a. R is assumed orthonormal (det +1); nothing here
//     re-orthonormalises it.
//
// Status codes: kNotFinite (a non-finite input), kArgumentOutOfRange (a zero
// direction or normal, or a threshold not in (0, 1]), kAxesParallel (item 3),
// kPlanesDegenerate (item 4).
#pragma once

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

using Mat4 = Eigen::Matrix<double, 4, 4>;

inline constexpr double kMinLineSin = 1e-3;
inline constexpr double kMinPlanesDet = 1e-3;

struct Line3 {
  Vec3 point_mm = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();
};

struct Plane3 {
  Vec3 point_mm = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
};

struct CommonPerpendicular {
  Vec3 foot_1_mm = Vec3::Zero();  // on line 1
  Vec3 foot_2_mm = Vec3::Zero();  // on line 2
  double s_1_mm = 0.0;            // foot_1 = p1 + s_1 d1 (unit d1)
  double s_2_mm = 0.0;            // foot_2 = p2 + s_2 d2 (unit d2)
  double length_mm = 0.0;         // |foot_2 - foot_1| >= 0
  double angle_deg = 0.0;         // between the directions, [0, 180]
  Vec3 direction = Vec3::UnitZ(); // unit d1 x d2 / |d1 x d2|
};

// The common perpendicular of two lines (convention 2, 3).
[[nodiscard]] Result<CommonPerpendicular> common_perpendicular(const Line3& line_1, const Line3& line_2,
                                                               double min_sin = kMinLineSin);

// Distance (mm) of a point from a line (any direction length > 0).
double line_distance_mm(const Line3& line, const Vec3& p_mm);

// The point common to three planes (convention 4).
[[nodiscard]] Result<Vec3> three_plane_point(const Plane3& plane_1, const Plane3& plane_2,
                                             const Plane3& plane_3, double min_det = kMinPlanesDet);

// A rigid transform a_T_b: p_a = R p_b + t (convention 5).
struct Rigid3 {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
};

// a_T_c = a_T_b * b_T_c.
inline Rigid3 compose(const Rigid3& a_T_b, const Rigid3& b_T_c) {
  return {a_T_b.R * b_T_c.R, a_T_b.R * b_T_c.t + a_T_b.t};
}

// b_T_a from a_T_b.
inline Rigid3 inverse(const Rigid3& a_T_b) {
  const Mat3 r_t = a_T_b.R.transpose();
  return {r_t, -(r_t * a_T_b.t)};
}

// p_a = a_T_b p_b (a point, mm).
inline Vec3 apply_point(const Rigid3& a_T_b, const Vec3& p_b_mm) { return a_T_b.R * p_b_mm + a_T_b.t; }

// v_a = R_a_b v_b (a direction: no translation).
inline Vec3 apply_direction(const Rigid3& a_T_b, const Vec3& v_b) { return a_T_b.R * v_b; }

// The 4x4 homogeneous matrix [[R, t], [0 0 0 1]].
inline Mat4 homogeneous(const Rigid3& a_T_b) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = a_T_b.R;
  m.topRightCorner<3, 1>() = a_T_b.t;
  return m;
}

}  // namespace trueaxis::core
