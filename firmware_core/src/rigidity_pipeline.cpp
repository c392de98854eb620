#include "rigidity_pipeline.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

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
                         double min_a_arc_deg, RigidityEvaluation& out, RigidityScratch& work) {
  for (std::size_t i = 0; i < count; ++i) {
    work.centres[i] = poses[i].centre;
    work.a_deg[i] = poses[i].a_deg;
  }
  CircleFitOptions a_options;
  a_options.angles_deg = work.a_deg;
  a_options.min_arc_deg = min_a_arc_deg;
  if (fit_circle(work.centres, count, a_options, work.circle_work, work.circle) != Status::kOk) {
    return Status::kAAxisUndetermined;
  }
  const Vec3 a0 = work.circle.centre_mm;
  const Vec3 na = work.circle.normal;
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

namespace {

// Natural cubic spline through (knot_i, y_i): its second derivatives M_i, zero at
// both ends. Interior knots: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
// = 6 (slope_i - slope_{i-1}); diagonally dominant, so Thomas' elimination needs
// no pivoting. T is double or Vec3.
template <typename T, typename Y>
void natural_spline(const RigidityTable& t, Y y, T* out, const T& zero) {
  const std::size_t m = t.pose_count;
  for (std::size_t i = 0; i < m; ++i) out[i] = zero;
  if (m < 3) return;
  double c_prime[kMaxAPoses] = {};
  T r_prime[kMaxAPoses];
  for (std::size_t i = 1; i + 1 < m; ++i) {
    const double h0 = t.poses[i].a_deg - t.poses[i - 1].a_deg;
    const double h1 = t.poses[i + 1].a_deg - t.poses[i].a_deg;
    const T rhs = 6.0 * ((y(i + 1) - y(i)) / h1 - (y(i) - y(i - 1)) / h0);
    const double below = i > 1 ? h0 : 0.0;
    const double den = 2.0 * (h0 + h1) - below * (i > 1 ? c_prime[i - 1] : 0.0);
    c_prime[i] = h1 / den;
    r_prime[i] = (rhs - below * (i > 1 ? r_prime[i - 1] : zero)) / den;
  }
  out[m - 2] = r_prime[m - 2];
  for (std::size_t i = m - 2; i-- > 1;) out[i] = r_prime[i] - c_prime[i] * out[i + 1];
}

// Not-a-knot cubic splines through (knot_i, y_i): their second derivatives M_i.
// The third derivative is continuous at the second and the second-to-last
// knots, so a smooth law (sin A) keeps its curvature at the ends of the range,
// where the natural spline forces it to zero. Three knots: the parabola through
// them. The (at most 16 x 16) system is solved densely by Gaussian elimination
// with partial pivoting; it runs when a table is built or loaded, never in a
// query. Its matrix depends on the knots only: not_a_knot_factor reduces it
// once (more than three knots) for every spline of the table, and
// not_a_knot_spline applies the same steps to each right-hand side.

// The matrix reduced in work.a: U on and above the diagonal, below it the
// multiplier of each row at its step; work.pivot[col] the row swapped into
// col at step col (the rows' parts left of col stay where their step put them).
void not_a_knot_factor(const RigidityTable& t, RigiditySplineWork& work) {
  const std::size_t m = t.pose_count;
  const auto h = [&t](std::size_t i) { return t.poses[i + 1].a_deg - t.poses[i].a_deg; };
  double(&a)[kMaxAPoses][kMaxAPoses] = work.a;
  std::fill(&a[0][0], &a[0][0] + m * kMaxAPoses, 0.0);
  a[0][0] = h(1);
  a[0][1] = -(h(0) + h(1));
  a[0][2] = h(0);
  for (std::size_t i = 1; i + 1 < m; ++i) {
    a[i][i - 1] = h(i - 1);
    a[i][i] = 2.0 * (h(i - 1) + h(i));
    a[i][i + 1] = h(i);
  }
  a[m - 1][m - 3] = h(m - 2);
  a[m - 1][m - 2] = -(h(m - 3) + h(m - 2));
  a[m - 1][m - 1] = h(m - 3);
  for (std::size_t col = 0; col < m; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < m; ++r) {
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    }
    work.pivot[col] = static_cast<std::uint8_t>(pivot);
    for (std::size_t c = col; c < m; ++c) std::swap(a[col][c], a[pivot][c]);
    for (std::size_t r = col + 1; r < m; ++r) {
      const double f = a[r][col] / a[col][col];
      for (std::size_t c = col + 1; c < m; ++c) a[r][c] -= f * a[col][c];
      a[r][col] = f;
    }
  }
}

// T is double or Vec3; `work` as not_a_knot_factor left it (more than three knots).
template <typename T, typename Y>
void not_a_knot_spline(const RigidityTable& t, Y y, T* out, const T& zero, const RigiditySplineWork& work) {
  const std::size_t m = t.pose_count;
  for (std::size_t i = 0; i < m; ++i) out[i] = zero;
  if (m < 3) return;
  const auto h = [&t](std::size_t i) { return t.poses[i + 1].a_deg - t.poses[i].a_deg; };
  if (m == 3) {
    const T second = 2.0 * ((y(2) - y(1)) / h(1) - (y(1) - y(0)) / h(0)) / (h(0) + h(1));
    for (std::size_t i = 0; i < 3; ++i) out[i] = second;
    return;
  }
  const double(&a)[kMaxAPoses][kMaxAPoses] = work.a;
  T rhs[kMaxAPoses];
  rhs[0] = zero;
  rhs[m - 1] = zero;
  for (std::size_t i = 1; i + 1 < m; ++i) rhs[i] = 6.0 * ((y(i + 1) - y(i)) / h(i) - (y(i) - y(i - 1)) / h(i - 1));
  for (std::size_t col = 0; col < m; ++col) {
    std::swap(rhs[col], rhs[work.pivot[col]]);
    for (std::size_t r = col + 1; r < m; ++r) rhs[r] = rhs[r] - a[r][col] * rhs[col];
  }
  for (std::size_t r = m; r-- > 0;) {
    T v = rhs[r];
    for (std::size_t c = r + 1; c < m; ++c) v = v - a[r][c] * out[c];
    out[r] = v / a[r][r];
  }
}

}  // namespace

void prepare_rigidity_table(RigidityTable& t) {
  RigiditySplineWork work;
  prepare_rigidity_table(t, work);
}

void prepare_rigidity_table(RigidityTable& t, RigiditySplineWork& work) {
  const std::size_t m = t.pose_count;
  t.reference_axes = detail::frame_axes(t.poses[t.reference].c_x_axis, t.poses[t.reference].c_direction);
  for (std::size_t i = 0; i < m; ++i) t.rotation[i] = so3_exp(t.poses[i].rotvec_rad);
  for (std::size_t i = 0; i < m; ++i) {
    t.geodesic_step_rad[i] = i + 1 < m ? so3_log(t.rotation[i].transpose() * t.rotation[i + 1]) : Vec3::Zero();
  }
  natural_spline(t, [&t](std::size_t i) { return t.poses[i].rotvec_rad; }, t.spline_m, Vec3(Vec3::Zero()));
  if (m > 3) not_a_knot_factor(t, work);
  not_a_knot_spline(t, [&t](std::size_t i) { return t.poses[i].rotvec_rad; }, t.spline_k, Vec3(Vec3::Zero()), work);
  not_a_knot_spline(t, [&t](std::size_t i) { return t.poses[i].a_error_rad; }, t.spline_e, 0.0, work);
  not_a_knot_spline(t, [&t](std::size_t i) { return t.poses[i].origin_offset_mm; }, t.spline_d,
                    Vec3(Vec3::Zero()), work);
}

}  // namespace trueaxis::core
