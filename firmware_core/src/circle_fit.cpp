#include "trueaxis/core/circle_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <limits>

namespace trueaxis::core {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// The solver works on q = (p - origin) * inv_scale: centred on the centroid and of
// unit RMS extent, so its tolerances are absolute and the same for a 1 mm circle
// far from the origin and a 1 m one at it.
struct Scaling {
  Vec3 origin = Vec3::Zero();
  double scale = 1.0;
  double inv_scale = 1.0;
  Vec3 apply(const Vec3& p) const { return (p - origin) * inv_scale; }
};

struct Circle {
  Vec3 c = Vec3::Zero();
  Vec3 n = Vec3::UnitZ();
  double r = 1.0;
};

struct NormalEquations {
  Mat6 jtj = Mat6::Zero();
  Vec6 jtr = Vec6::Zero();
  double cost = 0.0;  // sum of squared 3-D distances
};

// Steps in scaled units (the points' RMS extent is 1), relative to 1 + r: below
// kBasinStep the Gauss-Newton step is trusted without a cost test, below
// kStepTol the iteration has converged, and below kFloorStep a step that no
// longer shrinks is rounding.
constexpr double kStepTol = 1e-13;
constexpr double kFloorStep = 1e-9;
constexpr double kBasinStep = 1e-6;
constexpr double kMaxLambda = 1e12;

void tangent_basis(const Vec3& n, Vec3& u, Vec3& v) {
  u = n.unitOrthogonal();
  v = n.cross(u);
}

// The two residuals of one point: out of plane h, in plane rho - r; the radial unit w.
struct PointResidual {
  double h;
  double radial;
  double rho;
  Vec3 d;
  Vec3 w;
};

PointResidual residual(const Circle& x, const Vec3& q, const Vec3& fallback_w) {
  PointResidual e;
  e.d = q - x.c;
  e.h = x.n.dot(e.d);
  const Vec3 in_plane = e.d - e.h * x.n;
  e.rho = in_plane.norm();
  // A point on the axis has no radial direction; any in-plane one gives the
  // right residual and a valid (one-sided) derivative.
  e.w = e.rho > 0.0 ? Vec3(in_plane / e.rho) : fallback_w;
  e.radial = e.rho - x.r;
  return e;
}

double cost(const Vec3* p, std::size_t count, const Scaling& s, const Circle& x) {
  double sum = 0.0;
  const Vec3 fallback = x.n.unitOrthogonal();
  for (std::size_t i = 0; i < count; ++i) {
    const PointResidual e = residual(x, s.apply(p[i]), fallback);
    sum += e.h * e.h + e.radial * e.radial;
  }
  return sum;
}

// J^T J and J^T r of the 2n residuals over (c, a, b, r), the normal's tangent
// parameters along (u, v): dn/da = u, dn/db = v.
NormalEquations accumulate(const Vec3* p, std::size_t count, const Scaling& s, const Circle& x, const Vec3& u,
                           const Vec3& v) {
  NormalEquations ne;
  for (std::size_t i = 0; i < count; ++i) {
    const PointResidual e = residual(x, s.apply(p[i]), u);
    const double ud = u.dot(e.d);
    const double vd = v.dot(e.d);
    Vec6 jh;
    jh << -x.n, ud, vd, 0.0;
    Vec6 jr;
    if (e.rho > 0.0) {
      jr << -e.w, -e.h * ud / e.rho, -e.h * vd / e.rho, -1.0;
    } else {
      jr << -e.w, 0.0, 0.0, -1.0;
    }
    ne.jtj.selfadjointView<Eigen::Lower>().rankUpdate(jh);
    ne.jtj.selfadjointView<Eigen::Lower>().rankUpdate(jr);
    ne.jtr += jh * e.h + jr * e.radial;
    ne.cost += e.h * e.h + e.radial * e.radial;
  }
  ne.jtj = ne.jtj.selfadjointView<Eigen::Lower>();
  return ne;
}

Circle apply_step(const Circle& x, const Vec6& delta, const Vec3& u, const Vec3& v) {
  Circle y;
  y.c = x.c + delta.head<3>();
  y.n = (x.n + delta(3) * u + delta(4) * v).normalized();
  y.r = x.r + delta(5);
  return y;
}

// Orientation evidence S of convention 4, for the normal `n`.
double orientation_evidence(const Vec3* p, std::size_t count, const Scaling& s, const Circle& x,
                            const double* angles_deg) {
  double evidence = 0.0;
  Vec3 prev = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 d = s.apply(p[i]) - x.c;
    const Vec3 q = d - x.n.dot(d) * x.n;
    if (i > 0) {
      const double qq = prev.norm() * q.norm();
      const double sin_phase = qq > 0.0 ? x.n.dot(prev.cross(q)) / qq : 0.0;
      const double weight = angles_deg != nullptr ? std::sin(deg_to_rad(angles_deg[i] - angles_deg[i - 1])) : 1.0;
      evidence += weight * sin_phase;
    }
    prev = q;
  }
  return evidence;
}

Status validate(const Vec3* points_mm, std::size_t count, const CircleFitOptions& o) {
  if (count < 3) return Status::kTooFewPoints;
  if (count > kMaxCirclePoints) return Status::kTooManyPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!all_finite(points_mm[i])) return Status::kNotFinite;
    if (o.angles_deg != nullptr && !std::isfinite(o.angles_deg[i])) return Status::kNotFinite;
  }
  for (double value : {o.point_sigma_mm, o.min_arc_deg, o.max_centre_sigma_mm}) {
    if (!std::isfinite(value)) return Status::kNotFinite;
    if (value < 0.0) return Status::kArgumentOutOfRange;
  }
  return Status::kOk;
}

double arc_span_deg(const Vec3* p, std::size_t count, const CircleFit& fit) {
  std::array<double, kMaxCirclePoints> phase;
  for (std::size_t i = 0; i < count; ++i) phase[i] = circle_phase_rad(fit, p[i]);
  std::sort(phase.begin(), phase.begin() + static_cast<std::ptrdiff_t>(count));
  double gap = phase[0] + 2.0 * kPi - phase[count - 1];
  for (std::size_t i = 1; i < count; ++i) gap = std::max(gap, phase[i] - phase[i - 1]);
  return std::max(0.0, 360.0 - rad_to_deg(gap));
}

template <typename AngleAt>
CircularMean circular_mean(std::size_t count, AngleAt angle_at) {
  double sum_sin = 0.0;
  double sum_cos = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    sum_sin += std::sin(angle_at(i));
    sum_cos += std::cos(angle_at(i));
  }
  CircularMean m;
  const double n = static_cast<double>(count);
  m.resultant_length = std::min(1.0, std::hypot(sum_sin, sum_cos) / n);
  if (m.resultant_length == 0.0) return m;
  m.mean_rad = std::atan2(sum_sin, sum_cos);
  if (count > 1) {
    double sum_sq = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      const double s = std::sin(angle_at(i) - m.mean_rad);
      sum_sq += s * s;
    }
    m.standard_error_rad = std::sqrt(sum_sq / (n * (n - 1.0)));
  }
  return m;
}

}  // namespace

Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count) {
  return fit_circle(points_mm, count, CircleFitOptions{});
}

Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count, const CircleFitOptions& options) {
  const Status valid = validate(points_mm, count, options);
  if (valid != Status::kOk) return valid;
  const Vec3* p = points_mm;

  Scaling s;
  for (std::size_t i = 0; i < count; ++i) s.origin += p[i];
  s.origin /= static_cast<double>(count);
  double sum_sq = 0.0;
  double max_span = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    sum_sq += (p[i] - s.origin).squaredNorm();
    max_span = std::max(max_span, (p[i] - s.origin).norm());
  }
  if (max_span < kCircleCoincidentSpan_mm) return Status::kPointsCoincident;
  s.scale = std::sqrt(sum_sq / static_cast<double>(count));
  s.inv_scale = 1.0 / s.scale;

  // Initial guess: the scatter matrix's plane (normal equations suffice: the
  // refinement below fixes what they lose), then the Kasa circle in it.
  Mat3 scatter = Mat3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 q = s.apply(p[i]);
    scatter += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(scatter);
  const Vec3 lambda = es.eigenvalues();  // ascending
  if (!(lambda(1) >= kCircleCollinearRatio * kCircleCollinearRatio * lambda(2))) return Status::kPointsCollinear;
  const Vec3 e1 = es.eigenvectors().col(2);
  const Vec3 e2 = es.eigenvectors().col(1);
  Mat2 m = Mat2::Zero();
  Vec2 rhs = Vec2::Zero();
  double z_mean = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 q = s.apply(p[i]);
    const Vec2 xy(e1.dot(q), e2.dot(q));
    z_mean += xy.squaredNorm();
  }
  z_mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 q = s.apply(p[i]);
    const Vec2 xy(e1.dot(q), e2.dot(q));
    m += xy * xy.transpose();
    rhs += xy * (xy.squaredNorm() - z_mean);
  }
  const Vec2 ab = 0.5 * m.ldlt().solve(rhs);
  Circle x;
  x.c = ab(0) * e1 + ab(1) * e2;
  x.n = es.eigenvectors().col(0).normalized();
  x.r = std::sqrt(z_mean + ab.squaredNorm());

  Vec3 u;
  Vec3 v;
  tangent_basis(x.n, u, v);
  NormalEquations ne = accumulate(p, count, s, x, u, v);
  double damping = 1e-3;
  bool converged = false;
  int iterations = 0;
  double last_basin_step = std::numeric_limits<double>::infinity();
  while (!converged && iterations < kCircleMaxIterations) {
    ++iterations;
    // Near the minimum the cost's decrease falls below its rounding long before
    // the parameters stop moving along the weak directions of a short arc; there
    // the undamped Gauss-Newton step is taken without a cost test.
    const Vec6 gauss_newton = ne.jtj.ldlt().solve(-ne.jtr);
    const double step = gauss_newton.norm();
    const double size = 1.0 + x.r;
    if (step < kBasinStep * size) {
      x = apply_step(x, gauss_newton, u, v);
      tangent_basis(x.n, u, v);
      ne = accumulate(p, count, s, x, u, v);
      // Converged when the step is negligible, or when it has stopped shrinking
      // at the rounding floor (that of a short arc's ill-conditioned directions).
      converged = step < kStepTol * size || (step < kFloorStep * size && step > 0.9 * last_basin_step);
      last_basin_step = step;
      continue;
    }
    Mat6 a = ne.jtj;
    for (int k = 0; k < 6; ++k) a(k, k) += damping * std::max(ne.jtj(k, k), 1e-30);
    const Vec6 delta = a.ldlt().solve(-ne.jtr);
    const Circle trial = apply_step(x, delta, u, v);
    const double trial_cost = trial.r > 0.0 ? cost(p, count, s, trial) : std::numeric_limits<double>::infinity();
    if (trial_cost <= ne.cost) {
      x = trial;
      damping = std::max(damping * 0.1, 1e-12);
      tangent_basis(x.n, u, v);
      ne = accumulate(p, count, s, x, u, v);
    } else {
      damping *= 10.0;
      if (damping > kMaxLambda) break;
    }
  }
  if (!converged || !(x.r > 0.0) || !all_finite(x.c) || !all_finite(x.n)) return Status::kNoConvergence;

  if (orientation_evidence(p, count, s, x, options.angles_deg) < 0.0) x.n = -x.n;

  CircleFit fit;
  fit.centre_mm = s.origin + s.scale * x.c;
  fit.normal = x.n;
  fit.radius_mm = s.scale * x.r;
  fit.count = count;
  fit.iterations = iterations;
  fit.axis_u = x.n.unitOrthogonal();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 d = s.apply(p[i]) - x.c;
    const Vec3 q = d - x.n.dot(d) * x.n;
    if (q.norm() > 1e-9 * x.r) {
      fit.axis_u = q.normalized();
      break;
    }
  }
  fit.axis_v = fit.normal.cross(fit.axis_u);

  // Covariance at the solution, in (axis_u, axis_v) for the normal (convention 5).
  const NormalEquations final_ne = accumulate(p, count, s, x, fit.axis_u, fit.axis_v);
  const Eigen::LLT<Mat6> llt(final_ne.jtj);
  if (llt.info() != Eigen::Success) return Status::kPointsCollinear;
  Mat6 cov = llt.solve(Mat6::Identity());
  // Per unit noise in mm: lengths keep their scale (residuals and parameters
  // scale alike), the normal's angles gain 1 / scale.
  Vec6 unscale;
  unscale << 1.0, 1.0, 1.0, s.inv_scale, s.inv_scale, 1.0;
  cov = unscale.asDiagonal() * cov * unscale.asDiagonal();

  fit.dof = 2 * count - 6;
  const double ssr_mm2 = final_ne.cost * s.scale * s.scale;
  const bool sigma_from_data = !(options.point_sigma_mm > 0.0);
  if (sigma_from_data) {
    fit.sigma_mm = fit.dof > 0 ? std::sqrt(ssr_mm2 / static_cast<double>(fit.dof)) : 0.0;
  } else {
    fit.sigma_mm = options.point_sigma_mm;
  }
  fit.covariance = fit.sigma_mm * fit.sigma_mm * cov;
  const Eigen::SelfAdjointEigenSolver<Mat3> centre_es(fit.centre_covariance_mm2(), Eigen::EigenvaluesOnly);
  fit.centre_sigma_mm = std::sqrt(std::max(0.0, centre_es.eigenvalues()(2)));

  double max_sq = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const PointResidual e = residual(x, s.apply(p[i]), fit.axis_u);
    max_sq = std::max(max_sq, e.h * e.h + e.radial * e.radial);
  }
  fit.max_distance_mm = s.scale * std::sqrt(max_sq);
  fit.rms_distance_mm = std::sqrt(ssr_mm2 / static_cast<double>(count));
  fit.arc_deg = arc_span_deg(p, count, fit);

  if (fit.arc_deg < options.min_arc_deg) return Status::kArcTooShort;
  if (options.max_centre_sigma_mm > 0.0) {
    if (sigma_from_data && fit.dof == 0) return Status::kTooFewPoints;
    if (fit.centre_sigma_mm > options.max_centre_sigma_mm) return Status::kArcTooShort;
  }
  return fit;
}

double circle_phase_rad(const CircleFit& fit, const Vec3& p_mm) {
  const Vec3 d = p_mm - fit.centre_mm;
  return std::atan2(fit.axis_v.dot(d), fit.axis_u.dot(d));
}

Result<CircularMean> circular_mean_rad(const double* angles_rad, std::size_t count) {
  if (count == 0) return Status::kTooFewPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(angles_rad[i])) return Status::kNotFinite;
  }
  return circular_mean(count, [angles_rad](std::size_t i) { return angles_rad[i]; });
}

Result<CircularMean> circle_phase_offset_rad(const CircleFit& fit, const Vec3* points_mm, const double* angles_deg,
                                             std::size_t count) {
  if (count == 0) return Status::kTooFewPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!all_finite(points_mm[i]) || !std::isfinite(angles_deg[i])) return Status::kNotFinite;
  }
  return circular_mean(count, [&](std::size_t i) {
    return circle_phase_rad(fit, points_mm[i]) - deg_to_rad(angles_deg[i]);
  });
}

}  // namespace trueaxis::core
