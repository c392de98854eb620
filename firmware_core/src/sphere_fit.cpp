#include "trueaxis/core/sphere_fit.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace trueaxis::core {

namespace {

using Mat4 = Eigen::Matrix<double, 4, 4>;
using Vec4 = Eigen::Matrix<double, 4, 1>;

// The algebraic fit (convention 2) on the centred points q: the centre (in q)
// and the radius.
bool algebraic(const Vec3* q, std::size_t count, Vec3& centre, double& radius) {
  Mat4 a = Mat4::Zero();
  Vec4 b = Vec4::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec4 row(2.0 * q[i].x(), 2.0 * q[i].y(), 2.0 * q[i].z(), 1.0);
    a.noalias() += row * row.transpose();
    b.noalias() += row * q[i].squaredNorm();
  }
  const Eigen::LDLT<Mat4> ldlt(a);
  if (ldlt.info() != Eigen::Success) return false;
  const Vec4 x = ldlt.solve(b);
  centre = x.head<3>();
  const double r2 = x(3) + centre.squaredNorm();
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  radius = std::sqrt(r2);
  return true;
}

}  // namespace

Result<SphereFit> fit_sphere(const Vec3* points_mm, std::size_t count, double radius_mm, double sigma_mm) {
  if (count < 4) return Status::kTooFewPoints;
  if (count > kMaxSpherePoints) return Status::kTooManyPoints;
  if (!std::isfinite(radius_mm) || !std::isfinite(sigma_mm)) return Status::kNotFinite;
  if (radius_mm < 0.0 || sigma_mm < 0.0) return Status::kArgumentOutOfRange;
  for (std::size_t i = 0; i < count; ++i) {
    if (!all_finite(points_mm[i])) return Status::kNotFinite;
  }

  Vec3 centroid = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) centroid += points_mm[i];
  centroid /= static_cast<double>(count);
  Vec3 q[kMaxSpherePoints];
  Mat3 scatter = Mat3::Zero();
  double max_span = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    q[i] = points_mm[i] - centroid;
    scatter.noalias() += q[i] * q[i].transpose();
    max_span = std::max(max_span, q[i].norm());
  }
  if (max_span < kCoincidentSpan_mm) return Status::kPointsCoincident;
  // Singular values of the centred points: square roots of the scatter's eigenvalues.
  const Eigen::SelfAdjointEigenSolver<Mat3> es(scatter, Eigen::EigenvaluesOnly);
  const Vec3 ev = es.eigenvalues().cwiseMax(0.0);  // ascending
  if (!(std::sqrt(ev(0)) >= kCollinearRatio * std::sqrt(ev(2)))) return Status::kNotIdentifiable;

  const bool fixed = radius_mm > 0.0;
  Vec3 c;
  double r = 0.0;
  if (!algebraic(q, count, c, r)) return Status::kNoConvergence;
  if (fixed) r = radius_mm;

  SphereFit fit;
  Mat4 jtj = Mat4::Identity();
  for (int it = 1;; ++it) {
    jtj.setZero();
    Vec4 jte = Vec4::Zero();
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3 d = q[i] - c;
      const double len = d.norm();
      if (!(len > 0.0)) return Status::kNoConvergence;
      const Vec4 j(-d.x() / len, -d.y() / len, -d.z() / len, -1.0);
      const double e = len - r;
      jtj.noalias() += j * j.transpose();
      jte.noalias() += j * e;
    }
    if (fixed) {
      jtj.row(3).setZero();
      jtj.col(3).setZero();
      jtj(3, 3) = 1.0;
      jte(3) = 0.0;
    }
    const Eigen::LDLT<Mat4> ldlt(jtj);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return Status::kNoConvergence;
    const Vec4 step = -ldlt.solve(jte);
    if (!all_finite(Vec3(step.head<3>())) || !std::isfinite(step(3))) return Status::kNoConvergence;
    c += step.head<3>();
    if (!fixed) r += step(3);
    fit.iterations = it;
    if (step.head<3>().norm() < kSphereStepTolerance * std::max(r, 1.0)) break;
    if (it >= kSphereMaxIterations) return Status::kNoConvergence;
  }

  // Convention 4 at the solution (the last J^T J is within a step of it): the
  // diagonal of its inverse, a column at a time (a vector right-hand side keeps
  // Eigen's solver off the heap).
  const Eigen::LDLT<Mat4> ldlt(jtj);
  Vec4 variance = Vec4::Zero();
  for (int k = 0; k < 4; ++k) variance(k) = ldlt.solve(Vec4::Unit(k))(k) * (sigma_mm * sigma_mm);
  double sum_sq = 0.0;
  double worst = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double e = (q[i] - c).norm() - r;
    sum_sq += e * e;
    worst = std::max(worst, std::fabs(e));
  }
  fit.centre_mm = centroid + c;
  fit.radius_mm = r;
  fit.centre_sigma_mm = Vec3(std::sqrt(variance(0)), std::sqrt(variance(1)), std::sqrt(variance(2)));
  fit.radius_sigma_mm = fixed ? 0.0 : std::sqrt(variance(3));
  fit.rms_residual_mm = std::sqrt(sum_sq / static_cast<double>(count));
  fit.max_residual_mm = worst;
  fit.count = count;
  return fit;
}

}  // namespace trueaxis::core
