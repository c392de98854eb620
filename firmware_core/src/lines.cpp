#include "trueaxis/core/lines.hpp"

namespace trueaxis::core {

namespace {

bool valid_threshold(double x) { return std::isfinite(x) && x > 0.0 && x <= 1.0; }

}  // namespace

Result<CommonPerpendicular> common_perpendicular(const Line3& line_1, const Line3& line_2, double min_sin) {
  if (!all_finite(line_1.point_mm) || !all_finite(line_1.direction) || !all_finite(line_2.point_mm) ||
      !all_finite(line_2.direction) || std::isnan(min_sin)) {
    return Status::kNotFinite;
  }
  const double norm_1 = line_1.direction.norm();
  const double norm_2 = line_2.direction.norm();
  if (!(norm_1 > 0.0) || !(norm_2 > 0.0) || !valid_threshold(min_sin)) return Status::kArgumentOutOfRange;
  const Vec3 d1 = line_1.direction / norm_1;
  const Vec3 d2 = line_2.direction / norm_2;
  const Vec3 n = d1.cross(d2);
  const double sin_angle = n.norm();
  if (!(sin_angle >= min_sin)) return Status::kAxesParallel;

  const Vec3 w = line_2.point_mm - line_1.point_mm;
  const double n2 = sin_angle * sin_angle;
  CommonPerpendicular cp;
  cp.s_1_mm = w.cross(d2).dot(n) / n2;
  cp.s_2_mm = w.cross(d1).dot(n) / n2;
  cp.foot_1_mm = line_1.point_mm + cp.s_1_mm * d1;
  cp.foot_2_mm = line_2.point_mm + cp.s_2_mm * d2;
  cp.length_mm = std::abs(w.dot(n)) / sin_angle;
  cp.angle_deg = rad_to_deg(angle_between(d1, d2));
  cp.direction = n / sin_angle;
  return cp;
}

double line_distance_mm(const Line3& line, const Vec3& p_mm) {
  const Vec3 d = line.direction.normalized();
  const Vec3 w = p_mm - line.point_mm;
  return (w - w.dot(d) * d).norm();
}

Result<Vec3> three_plane_point(const Plane3& plane_1, const Plane3& plane_2, const Plane3& plane_3,
                               double min_det) {
  const Plane3* planes[3] = {&plane_1, &plane_2, &plane_3};
  Vec3 n[3];
  for (int i = 0; i < 3; ++i) {
    if (!all_finite(planes[i]->point_mm) || !all_finite(planes[i]->normal)) return Status::kNotFinite;
    const double norm = planes[i]->normal.norm();
    if (!(norm > 0.0)) return Status::kArgumentOutOfRange;
    n[i] = planes[i]->normal / norm;
  }
  if (std::isnan(min_det)) return Status::kNotFinite;
  if (!valid_threshold(min_det)) return Status::kArgumentOutOfRange;
  const Vec3 n23 = n[1].cross(n[2]);
  const Vec3 n31 = n[2].cross(n[0]);
  const Vec3 n12 = n[0].cross(n[1]);
  const double det = n[0].dot(n23);
  if (!(std::abs(det) >= min_det)) return Status::kPlanesDegenerate;
  const Vec3& origin = plane_1.point_mm;
  const double b2 = n[1].dot(plane_2.point_mm - origin);
  const double b3 = n[2].dot(plane_3.point_mm - origin);
  // b_1 = 0: the first plane passes through the origin chosen.
  return Vec3(origin + (b2 * n31 + b3 * n12) / det);
}

}  // namespace trueaxis::core
