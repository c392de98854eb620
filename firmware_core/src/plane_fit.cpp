#include "trueaxis/core/plane_fit.hpp"

#include <Eigen/SVD>

namespace trueaxis::core {

Result<PlaneFit> fit_plane(const Vec3* points_mm, std::size_t count) {
  if (count < 3) return Status::kTooFewPoints;
  if (count > kMaxPlanePoints) return Status::kTooManyPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!all_finite(points_mm[i])) return Status::kNotFinite;
  }

  Vec3 centroid = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) centroid += points_mm[i];
  centroid /= static_cast<double>(count);

  double max_span = 0.0;
  Mat3 r = Mat3::Zero();  // upper-triangular factor of the centred point matrix
  for (std::size_t i = 0; i < count; ++i) {
    Vec3 row = points_mm[i] - centroid;
    max_span = std::max(max_span, row.norm());
    for (int j = 0; j < 3; ++j) {
      const double rho = std::hypot(r(j, j), row(j));
      if (rho == 0.0) continue;
      const double c = r(j, j) / rho;
      const double s = row(j) / rho;
      for (int k = j; k < 3; ++k) {
        const double top = c * r(j, k) + s * row(k);
        row(k) = -s * r(j, k) + c * row(k);
        r(j, k) = top;
      }
    }
  }
  if (max_span < kCoincidentSpan_mm) return Status::kPointsCoincident;

  const Eigen::JacobiSVD<Mat3> svd(r, Eigen::ComputeFullV);
  const Vec3 sv = svd.singularValues();
  if (!(sv(1) >= kCollinearRatio * sv(0))) return Status::kPointsCollinear;

  PlaneFit fit;
  fit.centroid_mm = centroid;
  fit.axis_u = svd.matrixV().col(0).normalized();
  fit.axis_v = svd.matrixV().col(1).normalized();
  fit.normal = fit.axis_u.cross(fit.axis_v).normalized();
  fit.spread_u_mm = sv(0);
  fit.spread_v_mm = sv(1);
  fit.count = count;

  double lo = 0.0;
  double hi = 0.0;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double d = plane_distance_mm(fit, points_mm[i]);
    lo = (i == 0) ? d : std::min(lo, d);
    hi = (i == 0) ? d : std::max(hi, d);
    sum_sq += d * d;
  }
  fit.flatness_mm = hi - lo;
  fit.rms_residual_mm = std::sqrt(sum_sq / static_cast<double>(count));
  return fit;
}

}  // namespace trueaxis::core
