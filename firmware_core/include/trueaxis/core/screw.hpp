// Plucker lines and the screw (dual-angle) error between two lines: the tool axis
// of docs/METHODS.md M4 and its error against the ideal axis.
//
// Conventions
//  1. A PluckerLine is (u, m): u the unit direction, m = p x u the moment (mm) of
//     any point p of the line about the frame's origin (docs/METHODS.md M4's
//     L = (l, m, n; p, q, r) with (p, q, r) = O4* x (l, m, n)). u . m = 0. The
//     point of the line closest to the origin is u x m; a point q lies on the line
//     when q x u = m, and its distance from the line is |m - q x u|. Reversing u
//     (and so m) gives the same line, the other way round.
//  2. plucker_from_point normalises the direction and removes from m the
//     rounding along u: its lines have |u| = 1 and u . m = 0 to a few ulps, and
//     transform_line keeps both to rounding (R orthonormal, lines.hpp). Functions
//     that return a plain value assume such a line; screw_error checks |u| and
//     ignores any component of m along u (c = u x m drops it).
//  3. A rigid transform a_T_b (lines.hpp convention 5: p_a = R p_b + t) moves a
//     line written in frame b into frame a:
//         u_a = R u_b,   m_a = R m_b + t x (R u_b),
//     i.e. [u_a; m_a] = [[R, 0], [[t]x R, R]] [u_b; m_b] (line_transform_matrix);
//     with t = 0 it is docs/METHODS.md M4's diag(R, R). rotation_about_line(axis, phi)
//     turns by phi (rad, right-hand rule about axis.u) about a line that need not
//     pass through the origin: R = exp(phi [u]x), t = c - R c, c = u x m.
//  4. The screw error from the ideal line L1 = (u1, m1) to the actual L2 = (u2, m2):
//     the actual line is the ideal one turned by theta about the common
//     perpendicular and moved along it by offset (the dual angle theta + eps offset):
//       theta_rad in [0, pi] = atan2(|u1 x u2|, u1 . u2) (exact near 0 and pi; the
//                 cross product is taken as u1 x (u2 -+ u1), the difference being
//                 exact to the ulp there);
//       axis      = (u1 x u2) / |u1 x u2|: turning u1 by +theta about axis gives u2;
//       offset_mm = (foot_2 - foot_1) . axis, signed; distance_mm = |offset_mm|;
//       foot_1 = c1 + s1 u1, foot_2 = c2 + s2 u2 with c_i = u_i x m_i, w = c2 - c1,
//       s1 = ((w x u2) . axis) / |u1 x u2|, s2 = ((w x u1) . axis) / |u1 x u2|
//       (lines.hpp convention 2).
//     Sign: the reciprocal product u1 . m2 + u2 . m1 = (c1 - c2) . (u1 x u2)
//     = -offset_mm sin(theta) (docs/METHODS.md M4's -d_e sin theta, d_e signed along
//     axis). The code takes offset_mm as w . axis, which is that product over
//     sin(theta) without its cancellation: the product is a difference of terms of
//     size |m| (1e4 mm at 10 m) whose result is offset sin(theta).
//  5. Parallel lines: when |u1 x u2| < kParallelSin the lines are treated as
//     parallel (parallel = true): foot_1 = c1 (L1's point closest to the origin),
//     foot_2 the point of L2 closest to foot_1, distance_mm = offset_mm =
//     |foot_2 - foot_1| >= 0, axis = (foot_2 - foot_1) / distance_mm (for exactly
//     parallel lines that is u1 x (m2' - m1) / |m2' - m1|, m2' = m2 with u2 turned
//     to u1). Coincident lines: distance 0, feet equal, axis a unit vector
//     perpendicular to u1 chosen from u1 alone. theta_rad keeps its value (0 or pi
//     for exactly parallel lines; turning u1 by pi about any axis perpendicular to
//     it gives -u1). For 0 < |u1 x u2| < kParallelSin the axis is perpendicular
//     to u2 and off perpendicular to u1 by at most |u1 x u2|.
//     Why 1e-12: above it the common perpendicular is computed to working
//     accuracy, but it lies |w| / sin(theta) along the lines, where the lines'
//     separation has shrunk to distance_mm: for 1 um of separation at 1e-12 rad
//     that is 1e9 mm away, and a few-ulp error in a direction (1e-15 rad) turns
//     the axis by 1e-3 rad. Below it, the separation at foot_1 is reported, and
//     within 10 m of the origin the separation of the two lines changes by less
//     than 1e-12 x 1e4 mm = 1e-8 mm. The step between the two branches is
//     geometric (the separation here versus the shortest one, far away), not
//     numeric.
//  6. Accuracy, eps = numeric_limits<double>::epsilon(), checked in
//     tests/core/test_screw.cpp on 100,000 pairs built from their screw (measured
//     worst in brackets): theta within 4 eps theta of the angle of the directions
//     as given [2.1]; axis perpendicular to both directions within 2.5 eps [1.0];
//     offset_mm within 6 (eps size + |offset| (eps / sin theta)^2) of the
//     construction, size = the coordinates' size in mm [2.6] (1e-11 mm at 10 m);
//     the feet within 6 eps (size / sin theta + |offset| / sin^2 theta) [2.8],
//     which is their condition (the rounding of the inputs), not this code's.
//
// Status codes: plucker_from_point returns kNotFinite (a non-finite point or
// direction) and kArgumentOutOfRange (a zero direction, or a moment too large for
// a double); screw_error returns kNotFinite (a non-finite coordinate) and
// kArgumentOutOfRange (a direction whose |u|^2 differs from 1 by more than
// kPluckerTolerance, i.e. not a line made here, or coordinates so large that a
// foot overflows).
#pragma once

#include <limits>

#include "trueaxis/core/lines.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// |u1 x u2| below which two lines are treated as parallel (convention 5).
inline constexpr double kParallelSin = 1e-12;
// How far |u|^2 of a line's direction may be from 1 (a few thousand roundings).
inline constexpr double kPluckerTolerance = 4096.0 * std::numeric_limits<double>::epsilon();

struct PluckerLine {
  Vec3 direction = Vec3::UnitZ();  // u, unit
  Vec3 moment_mm = Vec3::Zero();   // m = p x u
};

// The line through point_mm along direction (any finite non-zero length).
[[nodiscard]] Result<PluckerLine> plucker_from_point(const Vec3& point_mm, const Vec3& direction);

// The same from a Line3 (lines.hpp).
[[nodiscard]] inline Result<PluckerLine> plucker_from_line(const Line3& line) {
  return plucker_from_point(line.point_mm, line.direction);
}

// (u; m) as one 6-vector, the form line_transform_matrix acts on.
inline Vec6 plucker_vector(const PluckerLine& line) {
  Vec6 v;
  v << line.direction, line.moment_mm;
  return v;
}

// The point of the line closest to the frame's origin: u x m.
inline Vec3 closest_point_to_origin(const PluckerLine& line) { return line.direction.cross(line.moment_mm); }

// Distance (mm) of a point from the line: |m - q x u|.
inline double line_distance_mm(const PluckerLine& line, const Vec3& q_mm) {
  return (line.moment_mm - q_mm.cross(line.direction)).norm();
}

// The line a_T_b moves a line written in frame b into frame a (convention 3).
PluckerLine transform_line(const Rigid3& a_T_b, const PluckerLine& line_b);

// The 6x6 matrix of transform_line: [[R, 0], [[t]x R, R]] (convention 3).
Mat6 line_transform_matrix(const Rigid3& a_T_b);

// The rigid motion turning by angle_rad about the line `axis` (convention 3).
Rigid3 rotation_about_line(const PluckerLine& axis, double angle_rad);

struct ScrewError {
  double theta_rad = 0.0;          // [0, pi]
  double distance_mm = 0.0;        // |offset_mm| >= 0
  double offset_mm = 0.0;          // (foot_2 - foot_1) . axis
  Vec3 axis = Vec3::UnitX();       // unit, the common perpendicular (convention 4, 5)
  Vec3 foot_1_mm = Vec3::Zero();   // on the ideal line
  Vec3 foot_2_mm = Vec3::Zero();   // on the actual line
  bool parallel = false;           // |u1 x u2| < kParallelSin: feet chosen (convention 5)
};

// The screw error from the ideal line to the actual one (conventions 4, 5).
[[nodiscard]] Result<ScrewError> screw_error(const PluckerLine& ideal, const PluckerLine& actual);

}  // namespace trueaxis::core
