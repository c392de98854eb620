// Ground truth for the M3 rigidity tests: a cradle with known errors, written
// from the physical description in long double with Eigen::AngleAxis, sharing
// nothing with firmware_core's pipeline (no circle fit, no so3_exp/log).
//
// The machine (all in machine coordinates, mm, long double):
//  1. The cradle turns about the A axis line (a_point, a_dir) by the actual
//     angle alpha(A) = A + e0 + e1 A + e2 sin(2 A) for commanded A (rad inside).
//  2. On the cradle, with the cradle at alpha = 0, the C axis is the line
//     (c_point, c_dir); the table turns about it by the commanded C exactly.
//  3. The C table is tilted by an A-dependent small rotation about the point
//     c_centre (the C axis's point at the ball's height): its rotation vector,
//     in the cradle's frame at alpha = 0, is w(A) = k1 sin(A) w1 + k2 A w2
//     (gravity-like plus a term growing with A); w(0) = 0.
//  4. Table coordinates q: origin c_centre, axes E0 = [x0, c_dir x x0, c_dir]
//     with x0 towards the ball at C = 0. A table point q is in the machine at
//         a_point + R(a_dir, alpha(A)) (c_centre + exp(w(A)) E0 Rz(C) q - a_point).
//     At the reference (A = 0) this frame is R(a_dir, alpha(0)) E0 at
//     a_point + R(a_dir, alpha(0)) (c_centre - a_point): the pipeline's table frame.
// What follows from it (the values the pipeline must find):
//  - actual axes at A: R(a_dir, alpha) exp(w) E0; theory axes: R(a_dir, alpha) E0;
//  - rotvec(A) = log(R(alpha) exp(w) R(alpha)^T) = R(a_dir, alpha(A)) w(A);
//  - theta(A) = alpha(A) - alpha(0); a_error(A) = theta(A) - A;
//  - the C centres lie on the circle about the A axis with centre the foot of
//    c_centre on it: the A axis point; origin offsets 0;
//  - C-to-A offset = distance of the lines (c_point, c_dir), (a_point, a_dir);
//    squareness = angle(c_dir, a_dir) - 90 deg (both invariant under the A turn).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "reference.hpp"

namespace trueaxis::test {

using QuatL = Eigen::Quaternion<long double>;
using AngleAxisL = Eigen::AngleAxis<long double>;

struct Cradle {
  Vec3L a_point{12.5L, -40.25L, 310.0L};
  Vec3L a_dir = Vec3L(1.0L, 1.2e-4L, -0.8e-4L).normalized();  // ~30" off X
  Vec3L c_point = Vec3L(12.5L, -40.25L, 310.0L) + Vec3L(7.0L, 0.030L, -150.0L);  // 30 um off the A axis
  Vec3L c_dir = Vec3L(-5e-5L, 1.5e-4L, 1.0L).normalized();  // ~30" off square
  Vec3L ball_at_zero = Vec3L(12.5L, -40.25L, 310.0L) + Vec3L(7.0L + 100.0L, 60.0L, -100.0L);
  long double e0 = 3e-5L, e1 = 2e-5L, e2 = 1.5e-5L;  // A positioning error law, rad
  long double k1 = 1.2e-4L;                           // ~25"
  Vec3L w1 = Vec3L(0.2L, 1.0L, 0.3L).normalized();
  long double k2 = 3e-5L;
  Vec3L w2 = Vec3L(1.0L, -0.4L, 0.5L).normalized();

  static Mat3L rot(const Vec3L& unit_axis, long double angle) { return AngleAxisL(angle, unit_axis).toRotationMatrix(); }
  static Mat3L rot_vec(const Vec3L& w) {
    const long double t = w.norm();
    return t == 0.0L ? Mat3L::Identity() : rot(w / t, t);
  }

  long double alpha(long double a_deg) const {
    const long double a = deg_l(a_deg);
    return a + e0 + e1 * a + e2 * std::sin(2.0L * a);
  }
  Vec3L w(long double a_deg) const {
    const long double a = deg_l(a_deg);
    return k1 * std::sin(a) * w1 + k2 * a * w2;
  }
  Vec3L c_centre() const { return c_point + c_dir * c_dir.dot(ball_at_zero - c_point); }
  Mat3L e0_axes() const {
    const Vec3L x0 = (ball_at_zero - c_centre()).normalized();
    Mat3L e;
    e.col(0) = x0;
    e.col(1) = c_dir.cross(x0);
    e.col(2) = c_dir;
    return e;
  }
  Vec3L ball_table() const { return e0_axes().transpose() * (ball_at_zero - c_centre()); }

  // machine_T_table, actual and theory (deformation-free), at commanded (A, C).
  Mat3L actual_rotation(long double a_deg, long double c_deg) const {
    return rot(a_dir, alpha(a_deg)) * rot_vec(w(a_deg)) * e0_axes() * rot(Vec3L::UnitZ(), deg_l(c_deg));
  }
  Mat3L theory_rotation(long double a_deg, long double c_deg) const {
    return rot(a_dir, alpha(a_deg)) * e0_axes() * rot(Vec3L::UnitZ(), deg_l(c_deg));
  }
  Vec3L origin(long double a_deg) const { return a_point + rot(a_dir, alpha(a_deg)) * (c_centre() - a_point); }
  Vec3L point(long double a_deg, long double c_deg, const Vec3L& q) const {
    return origin(a_deg) + actual_rotation(a_deg, c_deg) * q;
  }
  Vec3L ball(long double a_deg, long double c_deg) const { return point(a_deg, c_deg, ball_table()); }

  // The values the pipeline must find.
  Vec3L rotvec(long double a_deg) const { return rot(a_dir, alpha(a_deg)) * w(a_deg); }
  long double theta(long double a_deg) const { return alpha(a_deg) - alpha(0.0L); }
  long double a_error(long double a_deg) const { return theta(a_deg) - deg_l(a_deg); }
  Vec3L a_axis_point() const { return a_point + a_dir * a_dir.dot(c_centre() - a_point); }
  long double offset() const {
    const Vec3L n = c_dir.cross(a_dir);
    return std::abs((a_point - c_point).dot(n)) / n.norm();
  }
  long double squareness() const { return angle_l(c_dir, a_dir) - kPiL / 2.0L; }
};

}  // namespace trueaxis::test
