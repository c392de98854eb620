#include "trueaxis/core/fit_accumulator.hpp"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace trueaxis::core {

namespace {

// s += (a b^T + b a^T) / 2: a rank-one update kept exactly symmetric, so the
// eigen-solver, which reads one triangle, sees the same matrix the sums hold.
void add_symmetric(Mat3& s, const Vec3& a, const Vec3& b) {
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      const double v = 0.5 * (a(i) * b(j) + a(j) * b(i));
      s(i, j) += v;
      if (j != i) s(j, i) += v;
    }
  }
}

// Eigenvalues l[0] >= l[1] >= l[2] >= 0 of the scatter and their unit eigenvectors.
struct Principal {
  double l[3] = {0.0, 0.0, 0.0};
  Vec3 e[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
};

Status principal_axes(const PointAccumulator& acc, std::size_t min_count, Principal& out) {
  // Finite points can still overflow the sums (coordinates beyond ~1e150 mm).
  if (!acc.finite() || !all_finite(acc.mean_mm()) || !all_finite(acc.scatter_mm2()) ||
      !all_finite(acc.index_moment_mm())) {
    return Status::kNotFinite;
  }
  if (acc.count() < min_count) return Status::kTooFewPoints;
  const double n = static_cast<double>(acc.count());
  if (!(std::sqrt(acc.scatter_mm2().trace() / n) >= kCoincidentSpan_mm)) return Status::kPointsCoincident;

  // Not computeDirect(): its closed-form cubic loses the small eigenvalues that
  // carry the plane's residual and the line's width.
  const Eigen::SelfAdjointEigenSolver<Mat3> es(acc.scatter_mm2());
  // Cannot fail for a finite symmetric 3x3; kept so no unchecked value escapes.
  if (es.info() != Eigen::Success) return Status::kNotFinite;
  for (int k = 0; k < 3; ++k) {
    out.l[k] = std::max(0.0, es.eigenvalues()(2 - k));  // the solver sorts ascending
    out.e[k] = es.eigenvectors().col(2 - k).normalized();
  }
  return Status::kOk;
}

}  // namespace

void PointAccumulator::add(const Vec3& p_mm) {
  if (!all_finite(p_mm)) {
    finite_ = false;
    return;
  }
  if (count_ == 0) origin_mm_ = p_mm;
  ++count_;
  const double n = static_cast<double>(count_);
  const Vec3 q = p_mm - origin_mm_;
  const Vec3 before = q - shifted_mean_mm_;
  shifted_mean_mm_ += before / n;
  const Vec3 after = q - shifted_mean_mm_;
  add_symmetric(scatter_mm2_, before, after);
  index_moment_mm_ += (0.5 * n) * after;
}

void PointAccumulator::merge(const PointAccumulator& other) {
  finite_ = finite_ && other.finite_;
  if (other.count_ == 0) return;
  if (count_ == 0) {
    const bool finite = finite_;
    *this = other;
    finite_ = finite;
    return;
  }
  const double na = static_cast<double>(count_);
  const double nb = static_cast<double>(other.count_);
  const double n = na + nb;
  // Origins first: their difference is exact when they are close, the means
  // are small; neither sum meets the distance from the frame's origin.
  const Vec3 delta = (other.origin_mm_ - origin_mm_) + (other.shifted_mean_mm_ - shifted_mean_mm_);
  shifted_mean_mm_ += (nb / n) * delta;
  scatter_mm2_ += other.scatter_mm2_;
  add_symmetric(scatter_mm2_, (na * nb / n) * delta, delta);
  index_moment_mm_ += other.index_moment_mm_ + (0.5 * na * nb) * delta;
  count_ += other.count_;
}

Result<StreamPlaneFit> fit_plane(const PointAccumulator& acc) {
  Principal pc;
  const Status status = principal_axes(acc, 3, pc);
  if (status != Status::kOk) return status;
  const double s_u = std::sqrt(pc.l[0]);
  const double s_v = std::sqrt(pc.l[1]);
  if (!(s_v >= kCollinearRatio * s_u)) return Status::kPointsCollinear;

  StreamPlaneFit fit;
  fit.centroid_mm = acc.mean_mm();
  fit.axis_u = pc.e[0];
  fit.axis_v = pc.e[1];
  fit.normal = fit.axis_u.cross(fit.axis_v).normalized();
  fit.spread_u_mm = s_u;
  fit.spread_v_mm = s_v;
  fit.rms_residual_mm = std::sqrt(pc.l[2] / static_cast<double>(acc.count()));
  fit.count = acc.count();
  return fit;
}

Result<LineFit> fit_line(const PointAccumulator& acc) {
  Principal pc;
  const Status status = principal_axes(acc, 2, pc);
  if (status != Status::kOk) return status;
  const double s_along = std::sqrt(pc.l[0]);
  const double s_1 = std::sqrt(pc.l[1]);
  if (!(s_1 <= kLineWidthRatio * s_along)) return Status::kPointsNotOnLine;

  const double n = static_cast<double>(acc.count());
  const double index_scatter = n * (n * n - 1.0) / 12.0;  // sum (k - kbar)^2, > 0 for n >= 2
  Vec3 direction = pc.e[0];
  double advance = direction.dot(acc.index_moment_mm()) / index_scatter;
  if (advance < 0.0) {
    direction = -direction;
    advance = -advance;
  }

  LineFit fit;
  fit.point_mm = acc.mean_mm();
  fit.direction = direction;
  fit.axis_1 = pc.e[1];
  fit.axis_2 = direction.cross(pc.e[1]).normalized();
  fit.spread_along_mm = s_along;
  fit.spread_1_mm = s_1;
  fit.spread_2_mm = std::sqrt(pc.l[2]);
  fit.rms_residual_mm = std::sqrt((pc.l[1] + pc.l[2]) / n);
  fit.advance_per_sample_mm = advance;
  fit.count = acc.count();
  return fit;
}

Mat2 normal_covariance_rad2(const StreamPlaneFit& fit, double sigma_mm) {
  const double s2 = sigma_mm * sigma_mm;
  Mat2 c = Mat2::Zero();
  c(0, 0) = s2 / (fit.spread_u_mm * fit.spread_u_mm);
  c(1, 1) = s2 / (fit.spread_v_mm * fit.spread_v_mm);
  return c;
}

Mat2 direction_covariance_rad2(const LineFit& fit, double sigma_mm) {
  const double v = sigma_mm * sigma_mm / (fit.spread_along_mm * fit.spread_along_mm);
  return v * Mat2::Identity();
}

Mat3 centroid_covariance_mm2(const LineFit& fit, double sigma_mm) {
  return (sigma_mm * sigma_mm / static_cast<double>(fit.count)) * Mat3::Identity();
}

}  // namespace trueaxis::core
