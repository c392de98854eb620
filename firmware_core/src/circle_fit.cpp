#include "trueaxis/core/circle_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>

#include "trueaxis/core/so3.hpp"

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

using NormalEquations = CircleFitWork::NormalEquations;

void clear(NormalEquations& ne) {
  ne.jtj.setZero();
  ne.jtr.setZero();
  ne.cost = 0.0;
}

// The solver's circle: an anchor point m on it near the points, the frame
// (t, w, n) there (tangent, towards the centre, normal; columns of `frame`) and
// the signed curvature k: centre m + w / k, radius 1 / |k|. Unlike (c, r) this
// stays well conditioned on short arcs, where the centre and radius run off
// together along a long flat valley, and it is smooth through k = 0 (a line).
struct Anchored {
  Vec3 m = Vec3::Zero();
  Mat3 frame = Mat3::Identity();
  double k = 1.0;
};

// Steps in scaled units (the points' RMS extent is 1): below kBasinStep the
// Gauss-Newton step is trusted without a cost test, below kStepTol the iteration
// has converged, and below kFloorStep a step that no longer shrinks is rounding.
constexpr double kStepTol = 1e-14;
constexpr double kFloorStep = 1e-9;
constexpr double kBasinStep = 1e-6;
constexpr double kMaxLambda = 1e12;
// A radius beyond this many times the points' extent is a line.
constexpr double kArcTooShortRadius = 1e12;

// A point q in the anchor frame, (x, y, z) = frame^T (q - m), and its residuals:
// z out of the plane, and the signed in-plane distance sgn(k) (rho - r) written
// without cancellation:
//     e = (k s^2 - 2 y) / (1 + sqrt(k^2 x^2 + (k y - 1)^2)),   s^2 = x^2 + y^2,
// with its partial derivatives in x, y and k.
struct AnchoredResidual {
  double x, y, z, e, e_x, e_y, e_k;
};

AnchoredResidual anchored_residual(const Anchored& a, const Vec3& q) {
  const Vec3 l = a.frame.transpose() * (q - a.m);
  AnchoredResidual r{l(0), l(1), l(2), 0.0, 0.0, 0.0, 0.0};
  const double s2 = r.x * r.x + r.y * r.y;
  const double ky1 = a.k * r.y - 1.0;
  const double d = std::sqrt(a.k * a.k * r.x * r.x + ky1 * ky1);  // k rho; 0 only at the centre
  const double b = 1.0 + d;
  r.e = (a.k * s2 - 2.0 * r.y) / b;
  const double inv_d = d > 0.0 ? 1.0 / d : 0.0;
  r.e_x = (2.0 * a.k * r.x - r.e * a.k * a.k * r.x * inv_d) / b;
  r.e_y = (2.0 * ky1 - r.e * a.k * ky1 * inv_d) / b;
  r.e_k = (s2 - r.e * (a.k * r.x * r.x + ky1 * r.y) * inv_d) / b;
  return r;
}

double anchored_cost(const Vec3* p, std::size_t count, const Scaling& s, const Anchored& a) {
  double sum = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const AnchoredResidual r = anchored_residual(a, s.apply(p[i]));
    sum += r.z * r.z + r.e * r.e;
  }
  return sum;
}

// J^T J and J^T r over (alpha, beta, omega_t, omega_w, omega_n, dk): m moves by
// alpha w + beta n, the frame turns by the small rotation omega (frame
// coordinates), k by dk. d(x, y, z)/d omega = ((0, -z, y), (z, 0, -x), (-y, x, 0)).
void anchored_accumulate(const Vec3* p, std::size_t count, const Scaling& s, const Anchored& a,
                         NormalEquations& ne) {
  clear(ne);
  for (std::size_t i = 0; i < count; ++i) {
    const AnchoredResidual r = anchored_residual(a, s.apply(p[i]));
    Vec6 jz;
    jz << 0.0, -1.0, -r.y, r.x, 0.0, 0.0;
    Vec6 je;
    je << -r.e_y, 0.0, r.e_y * r.z, -r.e_x * r.z, r.e_x * r.y - r.e_y * r.x, r.e_k;
    ne.jtj.selfadjointView<Eigen::Lower>().rankUpdate(jz);
    ne.jtj.selfadjointView<Eigen::Lower>().rankUpdate(je);
    ne.jtr += jz * r.z + je * r.e;
    ne.cost += r.z * r.z + r.e * r.e;
  }
  ne.jtj = ne.jtj.selfadjointView<Eigen::Lower>();
}

Anchored anchored_step(const Anchored& a, const Vec6& delta) {
  Anchored b;
  b.m = a.m + delta(0) * a.frame.col(1) + delta(1) * a.frame.col(2);
  const Mat3 turned = so3_exp(a.frame * delta.segment<3>(2)) * a.frame;
  const Vec3 t = turned.col(0).normalized();
  const Vec3 w = (turned.col(1) - t.dot(turned.col(1)) * t).normalized();
  b.frame << t, w, t.cross(w);
  b.k = a.k + delta(5);
  return b;
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

// J^T J and J^T r of the 2n residuals over (c, a, b, r), the normal's tangent
// parameters along (u, v): dn/da = u, dn/db = v.
void accumulate(const Vec3* p, std::size_t count, const Scaling& s, const Circle& x, const Vec3& u, const Vec3& v,
                NormalEquations& ne) {
  clear(ne);
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

double arc_span_deg(const Vec3* p, std::size_t count, const CircleFit& fit, double* phase) {
  for (std::size_t i = 0; i < count; ++i) phase[i] = circle_phase_rad(fit, p[i]);
  std::sort(phase, phase + count);
  double gap = phase[0] + 2.0 * kPi - phase[count - 1];
  for (std::size_t i = 1; i < count; ++i) gap = std::max(gap, phase[i] - phase[i - 1]);
  return std::max(0.0, 360.0 - rad_to_deg(gap));
}

// Functions marked noinline hold a solver's or a factorisation's temporaries
// (0.2-0.4 kB each): on the stack only while they run, not in fit_circle's
// frame under every call it makes (docs/FIGURES.md "Stack"). [[gnu::noinline]] is
// ignored by compilers that do not know it.

// Initial guess: the scatter matrix's plane (normal equations suffice: the
// refinement fixes what they lose), then the Kasa circle in it; false when
// the points are collinear.
[[gnu::noinline]] bool initial_anchor(const Vec3* p, std::size_t count, const Scaling& s, Anchored& a) {
  Mat3 scatter = Mat3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 q = s.apply(p[i]);
    scatter += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(scatter);
  const Vec3 lambda = es.eigenvalues();  // ascending
  if (!(lambda(1) >= kCircleCollinearRatio * kCircleCollinearRatio * lambda(2))) return false;
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
  const Vec3 centre0 = ab(0) * e1 + ab(1) * e2;
  const double radius0 = std::sqrt(z_mean + ab.squaredNorm());
  // Anchor where the points are: towards the centroid (the origin) from the
  // initial centre, or towards the first point when the points surround it.
  Vec3 out = -centre0;
  if (out.norm() < 1e-3 * radius0) out = s.apply(p[0]) - centre0;
  out -= out.dot(e1.cross(e2)) * e1.cross(e2);
  out.normalize();
  a.m = centre0 + radius0 * out;
  a.frame << (-out).cross(e1.cross(e2)), -out, e1.cross(e2);
  a.k = 1.0 / radius0;
  return true;
}

// a^-1 b by Eigen's LDLT.
[[gnu::noinline]] Vec6 ldlt_solve(const Mat6& a, const Vec6& b) { return a.ldlt().solve(b); }

// a^-1 by Eigen's LLT, column by column: a matrix right-hand side takes
// Eigen's blocked triangular solver, whose workspace may come from the heap
// (the target link refuses it). False when a is not positive definite.
[[gnu::noinline]] bool llt_inverse(const Mat6& a, Mat6& inverse) {
  const Eigen::LLT<Mat6> llt(a);
  if (llt.info() != Eigen::Success) return false;
  for (int k = 0; k < 6; ++k) inverse.col(k) = llt.solve(Vec6::Unit(k));
  return true;
}

// The largest eigenvalue of a symmetric 3 x 3 matrix.
[[gnu::noinline]] double largest_eigenvalue(const Mat3& a) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(a, Eigen::EigenvaluesOnly);
  return es.eigenvalues()(2);
}

// The fit into work.fit.
Status solve(const Vec3* points_mm, std::size_t count, const CircleFitOptions& options, CircleFitWork& work) {
  CircleFit& fit = work.fit;
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

  Anchored a;
  if (!initial_anchor(p, count, s, a)) return Status::kPointsCollinear;

  NormalEquations& ne = work.normal;
  anchored_accumulate(p, count, s, a, ne);
  double damping = 1e-3;
  bool converged = false;
  int iterations = 0;
  double last_basin_step = std::numeric_limits<double>::infinity();
  while (!converged && iterations < kCircleMaxIterations) {
    ++iterations;
    // Near the minimum the cost's decrease falls below its rounding before the
    // parameters stop moving along a short arc's weak directions; there the
    // undamped Gauss-Newton step is taken without a cost test.
    const Vec6 gauss_newton = ldlt_solve(ne.jtj, -ne.jtr);
    const double step = gauss_newton.norm();
    if (step < kBasinStep) {
      a = anchored_step(a, gauss_newton);
      anchored_accumulate(p, count, s, a, ne);
      // Converged when the step is negligible, or when it has stopped shrinking
      // at the rounding floor.
      converged = step < kStepTol || (step < kFloorStep && step > 0.9 * last_basin_step);
      last_basin_step = step;
      continue;
    }
    Mat6& damped = work.matrix;
    damped = ne.jtj;
    for (int k = 0; k < 6; ++k) damped(k, k) += damping * std::max(ne.jtj(k, k), 1e-30);
    const Vec6 delta = ldlt_solve(damped, -ne.jtr);
    const Anchored trial = anchored_step(a, delta);
    if (anchored_cost(p, count, s, trial) <= ne.cost) {
      a = trial;
      damping = std::max(damping * 0.1, 1e-12);
      anchored_accumulate(p, count, s, a, ne);
    } else {
      damping *= 10.0;
      if (damping > kMaxLambda) break;
    }
  }
  if (!all_finite(a.m) || !all_finite(a.frame) || !std::isfinite(a.k)) return Status::kNoConvergence;
  // A straight line fits at least as well as any circle: no arc to speak of.
  if (!(std::abs(a.k) * kArcTooShortRadius > 1.0)) return Status::kArcTooShort;
  Circle x;
  x.c = a.m + a.frame.col(1) / a.k;
  x.n = a.frame.col(2);
  x.r = 1.0 / std::abs(a.k);

  if (orientation_evidence(p, count, s, x, options.angles_deg) < 0.0) x.n = -x.n;

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
  NormalEquations& final_ne = work.normal;
  accumulate(p, count, s, x, fit.axis_u, fit.axis_v, final_ne);
  Mat6& cov = work.matrix;
  if (!llt_inverse(final_ne.jtj, cov)) return converged ? Status::kPointsCollinear : Status::kArcTooShort;
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
  fit.centre_sigma_mm = std::sqrt(std::max(0.0, largest_eigenvalue(fit.centre_covariance_mm2())));

  double max_sq = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const PointResidual e = residual(x, s.apply(p[i]), fit.axis_u);
    max_sq = std::max(max_sq, e.h * e.h + e.radial * e.radial);
  }
  fit.max_distance_mm = s.scale * std::sqrt(max_sq);
  fit.rms_distance_mm = std::sqrt(ssr_mm2 / static_cast<double>(count));
  fit.arc_deg = arc_span_deg(p, count, fit, work.phase_rad);

  if (fit.arc_deg < options.min_arc_deg) return Status::kArcTooShort;
  // The iteration crawls where the data hardly determine a circle (an arc whose
  // sagitta is within a few sigma of the noise); such a circle is refused as short.
  if (!converged) return fit.centre_sigma_mm > fit.radius_mm ? Status::kArcTooShort : Status::kNoConvergence;
  if (options.max_centre_sigma_mm > 0.0) {
    if (sigma_from_data && fit.dof == 0) return Status::kTooFewPoints;
    if (fit.centre_sigma_mm > options.max_centre_sigma_mm) return Status::kArcTooShort;
  }
  return Status::kOk;
}

}  // namespace

Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count) {
  return fit_circle(points_mm, count, CircleFitOptions{});
}

Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count, const CircleFitOptions& options) {
  CircleFitWork work;
  const Status status = solve(points_mm, count, options, work);
  if (status != Status::kOk) return status;
  return work.fit;
}

Status fit_circle(const Vec3* points_mm, std::size_t count, const CircleFitOptions& options, CircleFitWork& work,
                  CircleFit& out) {
  const Status status = solve(points_mm, count, options, work);
  if (status == Status::kOk) out = work.fit;
  return status;
}

}  // namespace trueaxis::core
