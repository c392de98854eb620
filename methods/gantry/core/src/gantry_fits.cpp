#include "trueaxis/core/gantry_fits.hpp"

#include <algorithm>

namespace trueaxis::core {

namespace {

Status check_group(PointSpan g, std::size_t min_count, std::size_t max_count) {
  if (g.count == 0 || g.points_mm == nullptr) return Status::kMissingGroup;
  if (g.count > max_count) return Status::kTooManyPoints;
  for (std::size_t i = 0; i < g.count; ++i) {
    if (!all_finite(g.points_mm[i])) return Status::kNotFinite;
  }
  if (g.count < min_count) return Status::kTooFewPoints;
  return Status::kOk;
}

PointAccumulator accumulate(PointSpan g) {
  PointAccumulator acc;
  for (std::size_t i = 0; i < g.count; ++i) acc.add(g.points_mm[i]);
  return acc;
}

struct PassEstimate {
  Vec3 direction = Vec3::UnitX();
  Mat3 slope_covariance = Mat3::Zero();  // rad^2, in the plane perpendicular to direction (convention 4)
  double stroke_mm = 0.0;
  double straightness_mm = 0.0;
  double rms_residual_mm = 0.0;
};

Result<PassEstimate> fit_pass(PointSpan g, const PointNoise& noise) {
  const Status status = check_group(g, kMinPassPoints, kMaxGroupPoints);
  if (status != Status::kOk) return status;
  const Result<LineFit> line = fit_line(accumulate(g));
  if (!line.ok()) return line.status();
  const LineFit& f = line.value();

  double t_min = 0.0;
  double t_max = 0.0;
  double max_distance = 0.0;
  double stt = 0.0;
  double weighted = 0.0;        // sum sigma_i^2 t_i^2
  Mat3 scatter = Mat3::Zero();  // sum q_i q_i^T of the perpendicular residuals q_i
  for (std::size_t i = 0; i < g.count; ++i) {
    const Vec3 w = g.points_mm[i] - f.point_mm;
    const double t = f.direction.dot(w);
    t_min = std::min(t_min, t);
    t_max = std::max(t_max, t);
    const Vec3 q = w - t * f.direction;
    max_distance = std::max(max_distance, q.norm());
    scatter += q * q.transpose();
    stt += t * t;
    if (noise.modelled()) {
      const double s = noise.sigma_mm(g.points_mm[i]);
      weighted += s * s * t * t;
    }
  }
  PassEstimate p;
  p.direction = f.direction;
  const double n = static_cast<double>(g.count);
  if (noise.modelled()) {
    p.slope_covariance = weighted / (stt * stt) * (Mat3::Identity() - f.direction * f.direction.transpose());
  } else {
    // The perpendicular residuals' scatter over n - 2 degrees of freedom per
    // component: the noise's covariance across the line, whatever its shape.
    p.slope_covariance = scatter / ((n - 2.0) * stt);
  }
  p.stroke_mm = t_max - t_min;
  p.straightness_mm = 2.0 * max_distance;
  p.rms_residual_mm = f.rms_residual_mm;
  return p;
}

}  // namespace

Status check_noise(const PointNoise& noise) {
  if (!std::isfinite(noise.distance_sigma_mm) || !std::isfinite(noise.range_sigma_per_mm) ||
      !all_finite(noise.tracker_mm)) {
    return Status::kNotFinite;
  }
  if (noise.distance_sigma_mm < 0.0 || noise.range_sigma_per_mm < 0.0) return Status::kArgumentOutOfRange;
  return Status::kOk;
}

Result<PlaneEstimate> fit_plane_group(PointSpan points, const PointNoise& noise) {
  Status status = check_noise(noise);
  if (status != Status::kOk) return status;
  status = check_group(points, kMinPlanePoints, kMaxGroupPoints);
  if (status != Status::kOk) return status;
  const Result<StreamPlaneFit> fit = fit_plane(accumulate(points));
  if (!fit.ok()) return fit.status();
  const StreamPlaneFit& f = fit.value();

  const double n = static_cast<double>(points.count);
  const double sxx = f.spread_u_mm * f.spread_u_mm;
  const double syy = f.spread_v_mm * f.spread_v_mm;
  const double sigma2_data = n * f.rms_residual_mm * f.rms_residual_mm / (n - 3.0);
  double h_min = 0.0;
  double h_max = 0.0;
  Mat3 cov = Mat3::Zero();
  for (std::size_t i = 0; i < points.count; ++i) {
    const Vec3 w = points.points_mm[i] - f.centroid_mm;
    const double h = f.normal.dot(w);
    h_min = i == 0 ? h : std::min(h_min, h);
    h_max = i == 0 ? h : std::max(h_max, h);
    const Vec3 g(1.0 / n, f.axis_u.dot(w) / sxx, f.axis_v.dot(w) / syy);
    double s2 = sigma2_data;
    if (noise.modelled()) {
      const double s = noise.sigma_mm(points.points_mm[i]);
      s2 = s * s;
    }
    cov += s2 * (g * g.transpose());
  }
  PlaneEstimate p;
  p.centroid_mm = f.centroid_mm;
  p.normal = f.normal;
  p.axis_u = f.axis_u;
  p.axis_v = f.axis_v;
  p.flatness_mm = h_max - h_min;
  p.rms_residual_mm = f.rms_residual_mm;
  p.covariance = cov;
  p.count = f.count;
  return p;
}

PlaneEstimate orient_plane(const PlaneEstimate& plane, const Vec3& hint) {
  PlaneEstimate p = plane;
  p.normal = orient(plane.normal, hint);
  return p;
}

Plane3 perturbed_plane(const PlaneEstimate& plane, const Vec3& delta) {
  return {plane.centroid_mm + delta(0) * plane.normal,
          (plane.normal - delta(1) * plane.axis_u - delta(2) * plane.axis_v).normalized()};
}

Result<AxisEstimate> fit_axis_passes(const PointSpan* passes, std::size_t pass_count, const PointNoise& noise) {
  const Status status = check_noise(noise);
  if (status != Status::kOk) return status;
  if (pass_count == 0 || passes == nullptr) return Status::kMissingGroup;
  if (pass_count > kMaxPasses) return Status::kTooManyPoints;

  AxisEstimate axis;
  Vec3 first = Vec3::Zero();
  Vec3 sum = Vec3::Zero();
  Mat3 sum_cov = Mat3::Zero();
  for (std::size_t k = 0; k < pass_count; ++k) {
    const Result<PassEstimate> pass = fit_pass(passes[k], noise);
    if (!pass.ok()) return pass.status();
    const PassEstimate& p = pass.value();
    if (k == 0) first = p.direction;
    if (!(p.direction.dot(first) > 0.0)) return Status::kPassesDisagree;
    sum += p.direction;
    sum_cov += p.slope_covariance;
    axis.stroke_mm = std::max(axis.stroke_mm, p.stroke_mm);
    axis.straightness_mm = std::max(axis.straightness_mm, p.straightness_mm);
    axis.rms_residual_mm = std::max(axis.rms_residual_mm, p.rms_residual_mm);
    axis.residual_ssr_mm2 += static_cast<double>(passes[k].count) * p.rms_residual_mm * p.rms_residual_mm;
    axis.point_count += passes[k].count;
  }
  // |sum| = K |m| >= |first| > 0: every d_k has a positive component along d_1.
  const double norm = sum.norm();
  axis.direction = sum / norm;
  const Mat3 proj = Mat3::Identity() - axis.direction * axis.direction.transpose();
  axis.covariance = proj * sum_cov * proj / (norm * norm);
  axis.pass_count = pass_count;
  return axis;
}

Status fit_circle_group(PointSpan points, const PointNoise& noise, double min_arc_deg, CircleFitWork& work,
                        CircleFit& out) {
  Status status = check_noise(noise);
  if (status != Status::kOk) return status;
  status = check_group(points, kMinCirclePoints, kMaxCirclePoints);
  if (status != Status::kOk) return status;
  CircleFitOptions options;
  options.min_arc_deg = min_arc_deg;
  if (noise.modelled()) {
    double sum = 0.0;
    for (std::size_t i = 0; i < points.count; ++i) {
      const double s = noise.sigma_mm(points.points_mm[i]);
      sum += s * s;
    }
    options.point_sigma_mm = std::sqrt(sum / static_cast<double>(points.count));
  }
  return fit_circle(points.points_mm, points.count, options, work, out);
}

Line3 perturbed_circle_axis(const CircleFit& circle, const Eigen::Matrix<double, 6, 1>& delta) {
  return {circle.centre_mm + delta.head<3>(),
          (circle.normal + delta(3) * circle.axis_u + delta(4) * circle.axis_v).normalized()};
}

}  // namespace trueaxis::core
