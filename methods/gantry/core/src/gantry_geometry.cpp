#include "trueaxis/core/gantry_frames.hpp"

#include "trueaxis/core/fit_accumulator.hpp"

namespace trueaxis::core {

namespace {

// a x b normalised; false when the sine of their angle is below kMinLineSin.
bool unit_cross(const Vec3& a, const Vec3& b, Vec3& out) {
  const Vec3 c = a.cross(b);
  const double s = c.norm();
  if (!(s >= kMinLineSin)) return false;
  out = c / s;
  return true;
}

Mat3 columns(const Vec3& x, const Vec3& y, const Vec3& z) {
  Mat3 r;
  r.col(0) = x;
  r.col(1) = y;
  r.col(2) = z;
  return r;
}

}  // namespace

Result<Rigid3> global_frame_from(const Plane3& bed, const Plane3& side_1, const Plane3& side_2,
                                 const Vec3& gantry_x) {
  if (!all_finite(gantry_x)) return Status::kNotFinite;
  const double gantry_norm = gantry_x.norm();
  const double bed_norm = bed.normal.norm();
  if (!(gantry_norm > 0.0) || !(bed_norm > 0.0)) return Status::kArgumentOutOfRange;
  const Vec3 z0 = orient(bed.normal / bed_norm, Vec3::UnitZ());
  if (!(z0.z() >= kMinBedNormalZ)) return Status::kBedNotLevel;
  const Result<Vec3> origin = three_plane_point(bed, side_1, side_2);
  if (!origin.ok()) return origin.status();

  const Vec3 x = gantry_x / gantry_norm;
  Vec3 y;
  if (!unit_cross(z0, x, y)) return Status::kAxesParallel;
  const Vec3 z = x.cross(y);
  return Rigid3{columns(x, y, z), origin.value()};
}

Result<SubGeometry> sub_frame_from(const Vec3 axes[3], Axis master, const Line3& c_axis,
                                   const Vec3& tool_direction, const Line3& a_axis, double swing_mm,
                                   const Vec3& gantry_x, double min_ac_sin) {
  if (!std::isfinite(swing_mm) || !all_finite(tool_direction)) return Status::kNotFinite;
  const double tool_norm = tool_direction.norm();
  if (swing_mm < 0.0 || !(tool_norm > 0.0)) return Status::kArgumentOutOfRange;
  const Vec3 c_raw = c_axis.direction.normalized();
  if (!(std::abs(c_raw.dot(tool_direction)) >= kMinToolCos * tool_norm)) {
    return Status::kToolDirectionAmbiguous;
  }
  const Line3 c_line{c_axis.point_mm, orient(c_raw, tool_direction)};
  const Line3 a_line{a_axis.point_mm, a_axis.direction.normalized()};
  const Result<CommonPerpendicular> cp = common_perpendicular(c_line, a_line, min_ac_sin);
  if (!cp.ok()) return cp.status();

  for (int k = 0; k < 3; ++k) {
    if (!all_finite(axes[k])) return Status::kNotFinite;
    if (!(axes[k].norm() > 0.0)) return Status::kArgumentOutOfRange;
  }
  const Vec3 x = axes[0].normalized();
  const Vec3 y = axes[1].normalized();
  const Vec3 z = axes[2].normalized();
  Vec3 xp = Vec3::Zero();
  Vec3 yp = Vec3::Zero();
  Vec3 zp = Vec3::Zero();
  bool ok = false;
  switch (master) {
    case Axis::kX:  // y' = z x x, z' = x x y'
      xp = x;
      ok = unit_cross(z, xp, yp);
      zp = xp.cross(yp);
      break;
    case Axis::kY:  // x' = y x z, z' = x' x y
      yp = y;
      ok = unit_cross(yp, z, xp);
      zp = xp.cross(yp);
      break;
    case Axis::kZ:  // x' = y x z, y' = z x x'
      zp = z;
      ok = unit_cross(y, zp, xp);
      yp = zp.cross(xp);
      break;
  }
  if (!ok) return Status::kAxesParallel;
  if (!(xp.dot(gantry_x) > 0.0) || !(x.dot(gantry_x) > 0.0)) return Status::kAxisOppositeGantry;

  SubGeometry g;
  g.c = c_line.direction;
  g.a = a_line.direction;
  g.wrist_centre_mm = cp.value().foot_1_mm;
  g.tracker_T_sub = Rigid3{columns(xp, yp, zp), g.wrist_centre_mm + swing_mm * g.c};
  g.a_c_offset_mm = cp.value().length_mm;
  g.a_c_angle_deg = cp.value().angle_deg;
  return g;
}

}  // namespace trueaxis::core
