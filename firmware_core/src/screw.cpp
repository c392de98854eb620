#include "trueaxis/core/screw.hpp"

#include "trueaxis/core/so3.hpp"

namespace trueaxis::core {

namespace {

// A unit vector perpendicular to unit u, from u alone: u crossed with the
// coordinate axis it is least aligned with (|u x e| >= sqrt(2 / 3)).
Vec3 any_perpendicular(const Vec3& u) {
  Eigen::Index k = 0;
  u.cwiseAbs().minCoeff(&k);
  return u.cross(Vec3::Unit(k)).normalized();
}

}  // namespace

Result<PluckerLine> plucker_from_point(const Vec3& point_mm, const Vec3& direction) {
  if (!all_finite(point_mm) || !all_finite(direction)) return Status::kNotFinite;
  // Scaled first so that neither 1e-200 nor 1e200 under- or overflows in the norm.
  const double largest = direction.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) return Status::kArgumentOutOfRange;
  const Vec3 scaled = direction / largest;
  PluckerLine line;
  line.direction = scaled / scaled.norm();
  const Vec3 m = point_mm.cross(line.direction);
  line.moment_mm = m - line.direction.dot(m) * line.direction;
  if (!all_finite(line.moment_mm)) return Status::kArgumentOutOfRange;
  return line;
}

PluckerLine transform_line(const Rigid3& a_T_b, const PluckerLine& line_b) {
  PluckerLine line_a;
  line_a.direction = a_T_b.R * line_b.direction;
  line_a.moment_mm = a_T_b.R * line_b.moment_mm + a_T_b.t.cross(line_a.direction);
  return line_a;
}

Mat6 line_transform_matrix(const Rigid3& a_T_b) {
  Mat6 m = Mat6::Zero();
  m.topLeftCorner<3, 3>() = a_T_b.R;
  m.bottomLeftCorner<3, 3>() = hat(a_T_b.t) * a_T_b.R;
  m.bottomRightCorner<3, 3>() = a_T_b.R;
  return m;
}

Rigid3 rotation_about_line(const PluckerLine& axis, double angle_rad) {
  const Vec3 c = closest_point_to_origin(axis);
  Rigid3 motion;
  motion.R = so3_exp(angle_rad * axis.direction);
  motion.t = c - motion.R * c;
  return motion;
}

Result<ScrewError> screw_error(const PluckerLine& ideal, const PluckerLine& actual) {
  const Vec3& u1 = ideal.direction;
  const Vec3& u2 = actual.direction;
  if (!all_finite(u1) || !all_finite(ideal.moment_mm) || !all_finite(u2) || !all_finite(actual.moment_mm)) {
    return Status::kNotFinite;
  }
  if (!(std::abs(u1.squaredNorm() - 1.0) <= kPluckerTolerance) ||
      !(std::abs(u2.squaredNorm() - 1.0) <= kPluckerTolerance)) {
    return Status::kArgumentOutOfRange;
  }

  const double cos_theta = u1.dot(u2);
  // u2 -+ u1 is exact to the ulp where the directions nearly agree (or nearly
  // oppose), so the small cross product keeps its relative accuracy.
  const Vec3 n = cos_theta >= 0.0 ? Vec3(u1.cross(u2 - u1)) : Vec3(u1.cross(u2 + u1));
  const double sin_theta = n.norm();
  const Vec3 c1 = closest_point_to_origin(ideal);
  const Vec3 c2 = closest_point_to_origin(actual);
  const Vec3 w = c2 - c1;

  ScrewError e;
  e.theta_rad = std::atan2(sin_theta, cos_theta);
  if (sin_theta < kParallelSin) {
    const Vec3 v = w - w.dot(u2) * u2;
    e.parallel = true;
    e.distance_mm = v.norm();
    e.offset_mm = e.distance_mm;
    e.axis = e.distance_mm > 0.0 ? Vec3(v / e.distance_mm) : any_perpendicular(u1);
    e.foot_1_mm = c1;
    e.foot_2_mm = c1 + v;
    return e;
  }
  e.axis = n / sin_theta;
  e.offset_mm = w.dot(e.axis);
  e.distance_mm = std::abs(e.offset_mm);
  e.foot_1_mm = c1 + (w.cross(u2).dot(e.axis) / sin_theta) * u1;
  e.foot_2_mm = c2 + (w.cross(u1).dot(e.axis) / sin_theta) * u2;
  if (!all_finite(e.foot_1_mm) || !all_finite(e.foot_2_mm)) return Status::kArgumentOutOfRange;
  return e;
}

}  // namespace trueaxis::core
