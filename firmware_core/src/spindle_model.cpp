#include "trueaxis/core/spindle_model.hpp"

#include <cmath>

#include "trueaxis/core/small_linear.hpp"

namespace trueaxis::core {

namespace {

// d a / d (a_x, a_y), and the z of a vector normal to a with given x, y and its
// derivatives (convention 1: n_z = -(a_x n_x + a_y n_y) / a_z).
struct Normal {
  Vec3 n;
  Vec3 d_ax;  // d n / d a_x (only z moves)
  Vec3 d_ay;
};

Normal normal_to(double ax, double ay, double az, double nx, double ny) {
  const double s = ax * nx + ay * ny;
  Normal r;
  r.n = Vec3(nx, ny, -s / az);
  // d a_z / d a_x = -a_x / a_z
  r.d_ax = Vec3(0.0, 0.0, -nx / az - s * ax / (az * az * az));
  r.d_ay = Vec3(0.0, 0.0, -ny / az - s * ay / (az * az * az));
  return r;
}

Status check_geometry(const SpindleGeometry& g) {
  if (!std::isfinite(g.gauge_mm) || !std::isfinite(g.ball_mm[0]) || !std::isfinite(g.ball_mm[1])) {
    return Status::kNotFinite;
  }
  if (!(g.ball_mm[1] > g.ball_mm[0])) return Status::kArgumentOutOfRange;
  return Status::kOk;
}

// Conventions 3, 7 and the counts, on complete bins.
Status check_bins(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg) {
  const Status geometry = check_geometry(g);
  if (geometry != Status::kOk) return geometry;
  for (int ball = 1; ball <= 2; ++ball) {
    if (bins.angles(ball) == 0) return Status::kMissingGroup;
  }
  // Coverage before the count: with the default gap of 45 deg, fewer than 8
  // bins always leave a wider gap, and angles given in radians (a revolution
  // spans 6.3 deg, 4 bins) are a part of a revolution, which its text names.
  for (int ball = 1; ball <= 2; ++ball) {
    if (!(bins.largest_gap_deg(ball) <= max_gap_deg)) return Status::kRevolutionIncomplete;
  }
  for (int ball = 1; ball <= 2; ++ball) {
    if (bins.angles(ball) < kMinSpindleSamples) return Status::kTooFewSamples;
  }
  return Status::kOk;
}

}  // namespace

SpindleAxes spindle_axes(const SpindleParams& p) {
  const double ax = p(3);
  const double ay = p(4);
  const double az = -std::sqrt(std::fmax(0.0, 1.0 - ax * ax - ay * ay));
  SpindleAxes r;
  r.a = Vec3(ax, ay, az);
  r.e = Vec3(p(5), p(6), -(ax * p(5) + ay * p(6)) / az);
  r.w = Vec3(p(7), p(8), -(ax * p(7) + ay * p(8)) / az);
  return r;
}

Vec3 spindle_ball_mm(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad) {
  const SpindleAxes x = spindle_axes(p);
  const double b = g.ball_mm[ball == 2 ? 1 : 0];
  const Vec3 v = x.e + b * x.w;
  return p.head<3>() + (g.gauge_mm + b) * x.a + std::cos(phi_rad) * v + std::sin(phi_rad) * x.a.cross(v);
}

void spindle_ball_terms(const SpindleParams& p, const SpindleGeometry& g, int ball, SpindleBallTerms& out) {
  const double ax = p(3);
  const double ay = p(4);
  const double az = -std::sqrt(std::fmax(0.0, 1.0 - ax * ax - ay * ay));
  const Vec3 a(ax, ay, az);
  const Vec3 da_x(1.0, 0.0, -ax / az);
  const Vec3 da_y(0.0, 1.0, -ay / az);
  const double b = g.ball_mm[ball == 2 ? 1 : 0];
  const Normal e = normal_to(ax, ay, az, p(5), p(6));
  const Normal w = normal_to(ax, ay, az, p(7), p(8));
  const Vec3 v = e.n + b * w.n;
  const Vec3 dv_x = e.d_ax + b * w.d_ax;  // d v / d a_x
  const Vec3 dv_y = e.d_ay + b * w.d_ay;
  const double depth = g.gauge_mm + b;
  out.m = p.head<3>() + depth * a;
  out.v = v;
  out.u = a.cross(v);
  // m = o + depth a; v's own parameters enter through d v / d e_x = the
  // a-normal unit (1, 0, -a_x / a_z) = da_x, likewise the rest; u = a x v.
  out.jm.setZero();
  out.jm.leftCols<3>().setIdentity();
  out.jm.col(3) = depth * da_x;
  out.jm.col(4) = depth * da_y;
  out.jv.leftCols<3>().setZero();
  out.jv.col(3) = dv_x;
  out.jv.col(4) = dv_y;
  out.jv.col(5) = da_x;
  out.jv.col(6) = da_y;
  out.jv.col(7) = b * da_x;
  out.jv.col(8) = b * da_y;
  out.ju.leftCols<3>().setZero();
  out.ju.col(3) = da_x.cross(v) + a.cross(dv_x);
  out.ju.col(4) = da_y.cross(v) + a.cross(dv_y);
  out.ju.col(5) = a.cross(da_x);
  out.ju.col(6) = a.cross(da_y);
  out.ju.col(7) = b * out.ju.col(5);
  out.ju.col(8) = b * out.ju.col(6);
}

Vec3 spindle_ball_jacobian(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad,
                           SpindleJacobian& j) {
  SpindleBallTerms t;
  spindle_ball_terms(p, g, ball, t);
  const double c = std::cos(phi_rad);
  const double s = std::sin(phi_rad);
  j = t.jm + c * t.jv + s * t.ju;
  return t.m + c * t.v + s * t.u;
}

Vec3 SpindleBallSums::mean_mm() const {
  if (count == 0) return Vec3::Zero();
  return origin_mm + d / static_cast<double>(count);
}

Status spindle_harmonics(const SpindleBallSums& sums, SpindleHarmonics& out) {
  SquareMatrix<3> h;
  h << static_cast<double>(sums.count), sums.c, sums.s, sums.c, sums.cc, sums.cs, sums.s, sums.cs, sums.ss;
  SquareMatrix<3> l;
  // Positive definite needs three angles; judged relative to the count, as
  // the sums of cos^2 and sin^2 over close angles cancel to rounding.
  if (!cholesky(h, l) || !(l(2, 2) > 1e-9 * std::sqrt(static_cast<double>(sums.count)))) {
    return Status::kNotIdentifiable;
  }
  SpindleHarmonics r;
  r.l = l.triangularView<Eigen::Lower>();
  double ssr = 0.0;
  Mat3 z;
  for (int x = 0; x < 3; ++x) {
    const Vec3 g(sums.d(x), sums.dc(x), sums.ds(x));
    const Vec3 y = r.l.triangularView<Eigen::Lower>().solve(g);
    r.y.col(x) = y;
    z.col(x) = r.l.transpose().triangularView<Eigen::Upper>().solve(y);
    ssr += std::fmax(0.0, sums.dd(x) - y.squaredNorm());
  }
  r.centre_mm = sums.origin_mm + z.row(0).transpose();
  r.v = z.row(1).transpose();
  r.u = z.row(2).transpose();
  r.ssr_mm2 = ssr;
  out = r;
  return Status::kOk;
}

SpindleNoise spindle_bin_noise(const SpindleBin& b) {
  SpindleNoise n;
  if (b.count < 2) return n;
  const double count = static_cast<double>(b.count);
  if (std::sqrt(b.delta_m2 / count) <= kSameAngleDeg) {  // repeats of one angle: the mean
    n.ssr_mm2 = b.scatter_mm2;
    n.dof = b.count - 1;
    return n;
  }
  n.ssr_mm2 = std::fmax(0.0, b.scatter_mm2 - b.cross_mm.squaredNorm() / b.delta_m2);
  n.dof = b.count - 2;
  return n;
}

std::uint32_t spindle_fingerprint(const SpindleSample& s) {
  // Each word mixed in with a multiply and a shift (splitmix64's finaliser):
  // every input bit reaches every output bit, so that a changed last digit
  // of a coordinate changes the fingerprint.
  std::uint64_t h = 0;
  const double words[4] = {s.phi_deg, s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
  for (const double w : words) {
    h ^= bits_of(w);
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
    h ^= h >> 31;
  }
  return static_cast<std::uint32_t>(h ^ (h >> 32));
}

void SpindleBins::clear() {
  for (auto& ball : bins_) {
    for (SpindleBin& b : ball) b.count = 0;
  }
  sums_[0] = sums_[1] = SpindleBallSums();
  angles_[0] = angles_[1] = 0;
}

Status SpindleBins::add(const SpindleSample& s) {
  if (!std::isfinite(s.phi_deg) || !s.p_mm.allFinite()) return Status::kNotFinite;
  if ((s.ball != 1 && s.ball != 2) || std::fabs(s.phi_deg) > kSpindleBigDeg ||
      s.p_mm.cwiseAbs().maxCoeff() > kSpindleBigMm) {
    return Status::kArgumentOutOfRange;
  }
  double phi = std::fmod(s.phi_deg, 360.0);
  if (phi < 0.0) phi += 360.0;
  if (phi >= 360.0) phi = 0.0;  // -tiny + 360 rounds to 360
  const std::size_t k = index(s.ball);
  std::size_t i = static_cast<std::size_t>(phi / kSpindleBinDeg);
  if (i >= kSpindleBins) i = kSpindleBins - 1;
  SpindleBin& b = bins_[k][i];
  const std::uint32_t fingerprint = spindle_fingerprint(s);
  if (b.count > 0) {
    if (fingerprint == b.first_fingerprint || fingerprint == b.last_fingerprint) return Status::kDuplicateSample;
    if (b.count >= kMaxBinCount) return Status::kSessionFull;
  }
  // The bin (Welford's update of the means, of sum (delta - mean)^2, of the
  // cross sums and of the scatter).
  if (b.count == 0) {
    b = SpindleBin();
    b.phi_deg = phi;
    b.first_fingerprint = fingerprint;
    ++angles_[k];
  }
  SpindleBallSums& sum = sums_[k];
  if (sum.count == 0) sum.origin_mm = s.p_mm;
  const Vec3 d = s.p_mm - sum.origin_mm;
  b.last_fingerprint = fingerprint;
  ++b.count;
  const double n = static_cast<double>(b.count);
  const double delta = phi - b.phi_deg;
  const double dd = delta - b.mean_delta_deg;
  b.mean_delta_deg += dd / n;
  const Vec3 dp = d - b.mean_offset_mm;
  b.mean_offset_mm += dp / n;
  const Vec3 dp_after = d - b.mean_offset_mm;
  b.delta_m2 += dd * (delta - b.mean_delta_deg);
  b.cross_mm += dd * dp_after;
  b.scatter_mm2 += dp.dot(dp_after);
  // The ball's sums.
  const double rad = deg_to_rad(phi);
  const double c = std::cos(rad);
  const double sn = std::sin(rad);
  ++sum.count;
  sum.c += c;
  sum.s += sn;
  sum.cc += c * c;
  sum.cs += c * sn;
  sum.ss += sn * sn;
  sum.d += d;
  sum.dc += c * d;
  sum.ds += sn * d;
  sum.dd += d.cwiseProduct(d);
  return Status::kOk;
}

double SpindleBins::largest_gap_deg(int ball) const {
  const SpindleBin* bins = bins_[index(ball)];
  if (angles(ball) < 2) return 360.0;
  double first = 0.0;
  double last = 0.0;
  double gap = 0.0;
  bool any = false;
  for (std::size_t i = 0; i < kSpindleBins; ++i) {
    if (bins[i].count == 0) continue;
    const double angle = bins[i].angle_deg();
    if (any) {
      gap = std::fmax(gap, angle - last);
    } else {
      first = angle;
      any = true;
    }
    last = angle;
  }
  return std::fmax(gap, first + 360.0 - last);
}

SpindleNoise SpindleBins::noise() const {
  SpindleNoise sum;
  for (const auto& ball : bins_) {
    for (const SpindleBin& b : ball) {
      const SpindleNoise n = spindle_bin_noise(b);
      sum.ssr_mm2 += n.ssr_mm2;
      sum.dof += n.dof;
    }
  }
  return sum;
}

Result<SpindleParams> spindle_start(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg,
                                    SpindleHarmonics* harmonics) {
  const Status status = check_bins(bins, g, max_gap_deg);
  if (status != Status::kOk) return status;
  SpindleHarmonics own[2];
  SpindleHarmonics* h = harmonics != nullptr ? harmonics : own;
  Vec3 mean[2];
  Vec3 v[2];
  for (int k = 0; k < 2; ++k) {
    const Status fitted = spindle_harmonics(bins.sums(k + 1), h[k]);
    if (fitted != Status::kOk) return fitted;
    mean[k] = h[k].centre_mm;
    v[k] = h[k].v;
  }
  const Vec3 d = mean[1] - mean[0];
  if (!(d.norm() > 0.0)) return Status::kNotIdentifiable;
  const Vec3 a = d / d.norm();
  if (!(a.z() < 0.0)) return Status::kArgumentOutOfRange;  // ball 2 must lie farther along the tool
  for (Vec3& vk : v) vk -= vk.dot(a) * a;
  const double b1 = g.ball_mm[0];
  const double b2 = g.ball_mm[1];
  const Vec3 w = (v[1] - v[0]) / (b2 - b1);
  const Vec3 e = v[0] - b1 * w;
  SpindleParams p;
  p.head<3>() = mean[0] - (g.gauge_mm + b1) * a;
  p(3) = a.x();
  p(4) = a.y();
  p(5) = e.x();
  p(6) = e.y();
  p(7) = w.x();
  p(8) = w.y();
  return p;
}

void SpindleBuilder::start(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg,
                           const LmOptions& options) {
  bins_ = &bins;
  geometry_ = g;
  max_gap_deg_ = max_gap_deg;
  options_ = options;
  fit_ = SpindleFit();
  noise_ = SpindleNoise();
  phase_ = Phase::kStart;
  status_ = Status::kOk;
}

SpindleStep SpindleBuilder::fail(Status s) {
  phase_ = Phase::kDone;
  status_ = s;
  return {s, false};
}

void SpindleBuilder::evaluate(const SpindleParams& p, bool into_solver, double ssr[2]) {
  for (int k = 0; k < 2; ++k) {
    const SpindleHarmonics& h = harmonics_[k];
    spindle_ball_terms(p, geometry_, k + 1, terms_);
    const Vec3 m = terms_.m - bins_->sums(k + 1).origin_mm;
    double sum = 0.0;
    for (int x = 0; x < 3; ++x) {
      // Convention 4: L^T z_x - y_x and its Jacobian L^T (d z_x / d p).
      const Vec3 z(m(x), terms_.v(x), terms_.u(x));
      const Vec3 r = h.l.transpose() * z - h.y.col(x);
      sum += r.squaredNorm();
      if (into_solver) {
        SpindleJacobian dz;
        dz.row(0) = terms_.jm.row(x);
        dz.row(1) = terms_.jv.row(x);
        dz.row(2) = terms_.ju.row(x);
        const SpindleJacobian j = h.l.transpose().lazyProduct(dz);
        lm_.add(r, j);
      }
    }
    ssr[k] = sum + h.ssr_mm2;
  }
}

SpindleStep SpindleBuilder::step() {
  switch (phase_) {
    case Phase::kStart: {
      const Result<SpindleParams> p0 = spindle_start(*bins_, geometry_, max_gap_deg_, harmonics_);
      if (!p0.ok()) return fail(p0.status());
      lm_.start(p0.value(), options_);
      phase_ = Phase::kNoise;
      return {Status::kOk, true};
    }
    case Phase::kNoise:
      noise_ = bins_->noise();
      phase_ = Phase::kEvaluate;
      return {Status::kOk, true};
    case Phase::kEvaluate: {
      double ssr[2];
      lm_.begin_evaluation();
      evaluate(lm_.point(), true, ssr);
      phase_ = Phase::kDecide;
      return {Status::kOk, true};
    }
    case Phase::kDecide: {
      const LmStep s = lm_.finish_evaluation();
      if (s.more) {
        phase_ = Phase::kEvaluate;
        return {Status::kOk, true};
      }
      // The samples and the geometry are finite (checked): a model value that
      // is not means the iteration left the model's domain (the axis driven
      // towards horizontal, convention 1), which is a fit that did not converge.
      if (s.status == Status::kNotFinite) return fail(Status::kNoConvergence);
      if (s.status != Status::kOk) return fail(s.status);
      phase_ = Phase::kFinish;
      return {Status::kOk, true};
    }
    case Phase::kFinish: {
      const double n = static_cast<double>(bins_->samples());
      fit_.params = lm_.solution();
      if (!(std::hypot(fit_.params(3), fit_.params(4)) <= kMaxSpindleTilt)) return fail(Status::kArgumentOutOfRange);
      evaluate(fit_.params, false, fit_.ball_ssr_mm2);
      const double ssr = fit_.ball_ssr_mm2[0] + fit_.ball_ssr_mm2[1];
      fit_.noise_from_repeats = noise_.dof >= kMinNoiseRepeats;
      const double s2 = fit_.noise_from_repeats ? noise_.ssr_mm2 / (3.0 * static_cast<double>(noise_.dof))
                                                : ssr / (3.0 * n - kSpindleParams);
      lm_.covariance(s2 > 0.0 ? s2 : 1e-300, fit_.covariance, factor_);
      fit_.noise_sigma_mm = std::sqrt(s2);
      fit_.rms_mm = std::sqrt(ssr / n);
      fit_.synchronous_rms_mm = std::sqrt(std::fmax(0.0, ssr - noise_.ssr_mm2) / n);
      fit_.samples = static_cast<std::uint32_t>(bins_->samples());
      fit_.angles[0] = static_cast<std::uint32_t>(bins_->angles(1));
      fit_.angles[1] = static_cast<std::uint32_t>(bins_->angles(2));
      fit_.smallest_eigenvalue_ratio = lm_.smallest_eigenvalue_ratio();
      fit_.evaluations = lm_.evaluations();
      if (!fit_.covariance.allFinite()) return fail(Status::kNotIdentifiable);
      phase_ = Phase::kDone;
      status_ = Status::kOk;
      return {Status::kOk, false};
    }
    case Phase::kDone:
      break;
  }
  return {status_, false};
}

Status fit_spindle(const SpindleSample* samples, std::size_t count, const SpindleGeometry& g, SpindleFit& out) {
  SpindleBins bins;
  bins.clear();
  for (std::size_t i = 0; i < count; ++i) {
    const Status s = bins.add(samples[i]);
    if (s != Status::kOk) return s;
  }
  SpindleBuilder builder;
  builder.start(bins, g);
  SpindleStep step;
  do {
    step = builder.step();
  } while (step.more);
  if (step.status != Status::kOk) return step.status;
  out = builder.fit();
  return Status::kOk;
}

}  // namespace trueaxis::core
