#include "rigidity_pipeline.hpp"

#include "trueaxis/core/so3.hpp"

namespace trueaxis::core::detail {

namespace {

double wrap_pi(double angle_rad) {
  const double w = std::remainder(angle_rad, 2.0 * kPi);
  return w == -kPi ? kPi : w;
}

// Distance of two lines (p, u), (q, v), u and v unit: the common perpendicular's
// length, or the lines' distance when they are parallel to working precision.
double line_distance(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v) {
  const Vec3 w = u.cross(v);
  const Vec3 d = q - p;
  const double s = w.norm();
  if (s > 1e-12) return std::abs(d.dot(w)) / s;
  return (d - d.dot(u) * u).norm();
}

}  // namespace

Mat3 frame_axes(const Vec3& x_axis, const Vec3& normal) {
  Mat3 e;
  e.col(0) = x_axis;
  e.col(1) = normal.cross(x_axis);
  e.col(2) = normal;
  return e;
}

Status evaluate_rigidity(const RigidityPoseFrame* poses, std::size_t count, std::size_t reference,
                         double min_a_arc_deg, RigidityEvaluation& out) {
  Vec3 centres[kMaxAPoses];
  double a_deg[kMaxAPoses];
  for (std::size_t i = 0; i < count; ++i) {
    centres[i] = poses[i].centre;
    a_deg[i] = poses[i].a_deg;
  }
  CircleFitOptions a_options;
  a_options.angles_deg = a_deg;
  a_options.min_arc_deg = min_a_arc_deg;
  const Result<CircleFit> a_fit = fit_circle(centres, count, a_options);
  if (!a_fit.ok()) return Status::kAAxisUndetermined;
  const Vec3 a0 = a_fit.value().centre_mm;
  const Vec3 na = a_fit.value().normal;
  out.a_point = a0;
  out.a_direction = na;

  const RigidityPoseFrame& ref = poses[reference];
  const Mat3 e_ref = frame_axes(ref.x_axis, ref.normal);
  const Vec3 r_ref = ref.centre - a0;
  const Vec3 r_ref_plane = r_ref - na.dot(r_ref) * na;
  for (std::size_t i = 0; i < count; ++i) {
    if (i == reference) {
      out.rotvec[i] = Vec3::Zero();
      out.theta[i] = 0.0;
      out.a_error[i] = 0.0;
      out.origin_offset[i] = Vec3::Zero();
      continue;
    }
    const Vec3 r = poses[i].centre - a0;
    const Vec3 r_plane = r - na.dot(r) * na;
    const double dis_angle = std::atan2(na.dot(r_ref_plane.cross(r_plane)), r_ref_plane.dot(r_plane));
    // The branch nearest the commanded turn, so A spans beyond 180 deg stay continuous.
    const double commanded = deg_to_rad(poses[i].a_deg - ref.a_deg);
    const double a_error = wrap_pi(dis_angle - commanded);
    const double theta = commanded + a_error;
    const Mat3 turn = so3_exp(theta * na);
    const Mat3 e_theory = turn * e_ref;
    const Mat3 e_actual = frame_axes(poses[i].x_axis, poses[i].normal);
    out.rotvec[i] = so3_log(e_actual * e_theory.transpose());
    out.theta[i] = theta;
    out.a_error[i] = a_error;
    out.origin_offset[i] = poses[i].centre - (a0 + turn * r_ref);
  }
  out.offset_mm = line_distance(ref.centre, ref.normal, a0, na);
  out.squareness_rad = angle_between(ref.normal, na) - 0.5 * kPi;
  return Status::kOk;
}

}  // namespace trueaxis::core::detail

namespace trueaxis::core {

void prepare_rigidity_table(RigidityTable& t) {
  const std::size_t m = t.pose_count;
  t.reference_axes = detail::frame_axes(t.poses[t.reference].c_x_axis, t.poses[t.reference].c_direction);
  for (std::size_t i = 0; i < m; ++i) t.rotation[i] = so3_exp(t.poses[i].rotvec_rad);
  for (std::size_t i = 0; i < m; ++i) {
    t.geodesic_step_rad[i] = i + 1 < m ? so3_log(t.rotation[i].transpose() * t.rotation[i + 1]) : Vec3::Zero();
    t.spline_m[i] = Vec3::Zero();
  }
  if (m < 3) return;
  // Natural spline, knots A (deg): h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
  // = 6 (slope_i - slope_{i-1}) for the interior knots, M = 0 at both ends; the
  // system is diagonally dominant, so Thomas' elimination needs no pivoting.
  double c_prime[kMaxAPoses] = {};
  Vec3 r_prime[kMaxAPoses];
  for (std::size_t i = 1; i + 1 < m; ++i) {
    const double h0 = t.poses[i].a_deg - t.poses[i - 1].a_deg;
    const double h1 = t.poses[i + 1].a_deg - t.poses[i].a_deg;
    const Vec3 rhs = 6.0 * ((t.poses[i + 1].rotvec_rad - t.poses[i].rotvec_rad) / h1 -
                            (t.poses[i].rotvec_rad - t.poses[i - 1].rotvec_rad) / h0);
    const double below = i > 1 ? h0 : 0.0;
    const double den = 2.0 * (h0 + h1) - below * (i > 1 ? c_prime[i - 1] : 0.0);
    c_prime[i] = h1 / den;
    r_prime[i] = (rhs - below * (i > 1 ? r_prime[i - 1] : Vec3::Zero())) / den;
  }
  t.spline_m[m - 2] = r_prime[m - 2];
  for (std::size_t i = m - 2; i-- > 1;) t.spline_m[i] = r_prime[i] - c_prime[i] * t.spline_m[i + 1];
}

}  // namespace trueaxis::core
