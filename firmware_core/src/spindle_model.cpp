#include "trueaxis/core/spindle_model.hpp"

#include <cmath>

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
  for (int ball = 1; ball <= 2; ++ball) {
    if (bins.angles(ball) < kMinSpindleSamples) return Status::kTooFewSamples;
  }
  for (int ball = 1; ball <= 2; ++ball) {
    if (!(bins.largest_gap_deg(ball) <= max_gap_deg)) return Status::kRevolutionIncomplete;
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

Vec3 spindle_ball_jacobian(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad,
                           SpindleJacobian& j) {
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
  const double c = std::cos(phi_rad);
  const double s = std::sin(phi_rad);
  const double depth = g.gauge_mm + b;
  // M = o + depth a + c v + s (a x v); v's own parameters enter through
  // d v / d e_x = d a-normal unit (1, 0, -a_x / a_z) = da_x, likewise the rest.
  j.leftCols<3>().setIdentity();
  j.col(3) = depth * da_x + c * dv_x + s * (da_x.cross(v) + a.cross(dv_x));
  j.col(4) = depth * da_y + c * dv_y + s * (da_y.cross(v) + a.cross(dv_y));
  const Vec3 de_x = c * da_x + s * a.cross(da_x);
  const Vec3 de_y = c * da_y + s * a.cross(da_y);
  j.col(5) = de_x;
  j.col(6) = de_y;
  j.col(7) = b * de_x;
  j.col(8) = b * de_y;
  return p.head<3>() + depth * a + c * v + s * a.cross(v);
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
  angles_[0] = angles_[1] = 0;
  samples_[0] = samples_[1] = 0;
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
  SpindleBin* bins = bins_[k];
  std::size_t& n = angles_[k];
  // The first bin at or above phi - tolerance (bins sorted by angle).
  std::size_t lo = 0;
  std::size_t hi = n;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (bins[mid].phi_deg < phi - kSameAngleDeg) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  SpindleBin* same = nullptr;
  if (lo < n && bins[lo].phi_deg <= phi + kSameAngleDeg) same = &bins[lo];
  // Across 0 / 360.
  if (same == nullptr && n > 0 && phi < kSameAngleDeg && bins[n - 1].phi_deg - 360.0 >= phi - kSameAngleDeg) {
    same = &bins[n - 1];
  }
  if (same == nullptr && n > 0 && phi > 360.0 - kSameAngleDeg && bins[0].phi_deg + 360.0 <= phi + kSameAngleDeg) {
    same = &bins[0];
  }
  const std::uint32_t fingerprint = spindle_fingerprint(s);
  if (same != nullptr) {
    if (fingerprint == same->first_fingerprint || fingerprint == same->last_fingerprint) {
      return Status::kDuplicateSample;
    }
    if (same->count >= kMaxBinCount) return Status::kSessionFull;
    same->last_fingerprint = fingerprint;
    ++same->count;
    const Vec3 delta = s.p_mm - same->mean_mm;
    same->mean_mm += delta / static_cast<double>(same->count);
    same->scatter_mm2 += delta.dot(s.p_mm - same->mean_mm);
  } else {
    if (n == kMaxSpindleAngles) return Status::kSessionFull;
    for (std::size_t i = n; i > lo; --i) bins[i] = bins[i - 1];
    bins[lo].phi_deg = phi;
    bins[lo].count = 1;
    bins[lo].mean_mm = s.p_mm;
    bins[lo].scatter_mm2 = 0.0;
    bins[lo].first_fingerprint = bins[lo].last_fingerprint = fingerprint;
    ++n;
  }
  ++samples_[k];
  return Status::kOk;
}

double SpindleBins::largest_gap_deg(int ball) const {
  const std::size_t k = index(ball);
  const std::size_t n = angles_[k];
  if (n < 2) return 360.0;
  double gap = bins_[k][0].phi_deg + 360.0 - bins_[k][n - 1].phi_deg;
  for (std::size_t i = 1; i < n; ++i) gap = std::fmax(gap, bins_[k][i].phi_deg - bins_[k][i - 1].phi_deg);
  return gap;
}

double SpindleBins::scatter_mm2() const {
  double sum = 0.0;
  for (std::size_t k = 0; k < 2; ++k) {
    for (std::size_t i = 0; i < angles_[k]; ++i) sum += bins_[k][i].scatter_mm2;
  }
  return sum;
}

Result<SpindleParams> spindle_start(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg) {
  const Status status = check_bins(bins, g, max_gap_deg);
  if (status != Status::kOk) return status;
  Vec3 mean[2];
  Vec3 v[2];
  for (int k = 0; k < 2; ++k) {
    const std::size_t n = bins.angles(k + 1);
    mean[k].setZero();
    for (std::size_t i = 0; i < n; ++i) mean[k] += bins.bin(k + 1, i).mean_mm;
    mean[k] /= static_cast<double>(n);
    v[k].setZero();
    for (std::size_t i = 0; i < n; ++i) {
      const SpindleBin& b = bins.bin(k + 1, i);
      v[k] += (2.0 / static_cast<double>(n)) * std::cos(deg_to_rad(b.phi_deg)) * (b.mean_mm - mean[k]);
    }
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
  phase_ = Phase::kStart;
  status_ = Status::kOk;
  cursor_ = 0;
}

SpindleStep SpindleBuilder::fail(Status s) {
  phase_ = Phase::kDone;
  status_ = s;
  return {s, false};
}

SpindleStep SpindleBuilder::step() {
  switch (phase_) {
    case Phase::kStart: {
      const Result<SpindleParams> p0 = spindle_start(*bins_, geometry_, max_gap_deg_);
      if (!p0.ok()) return fail(p0.status());
      lm_.start(p0.value(), options_);
      lm_.begin_evaluation();
      cursor_ = 0;
      phase_ = Phase::kEvaluate;
      return {Status::kOk, true};
    }
    case Phase::kEvaluate: {
      const std::size_t n1 = bins_->angles(1);
      const std::size_t total = n1 + bins_->angles(2);
      const SpindleParams p = lm_.point();
      SpindleJacobian j;
      for (std::size_t done = 0; done < kBinsPerStep && cursor_ < total; ++done, ++cursor_) {
        const int ball = cursor_ < n1 ? 1 : 2;
        const SpindleBin& b = bins_->bin(ball, cursor_ < n1 ? cursor_ : cursor_ - n1);
        const Vec3 m = spindle_ball_jacobian(p, geometry_, ball, deg_to_rad(b.phi_deg), j);
        const double root = std::sqrt(static_cast<double>(b.count));
        const Vec3 r = root * (m - b.mean_mm);
        j *= root;
        lm_.add(r, j);
      }
      if (cursor_ == total) phase_ = Phase::kDecide;
      return {Status::kOk, true};
    }
    case Phase::kDecide: {
      const LmStep s = lm_.finish_evaluation();
      if (s.more) {
        lm_.begin_evaluation();
        cursor_ = 0;
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
      const double bins = static_cast<double>(bins_->angles(1) + bins_->angles(2));
      const double scatter = bins_->scatter_mm2();
      const double means = 2.0 * lm_.cost();  // sum of count x |mean residual|^2
      const std::size_t repeats = bins_->samples() - (bins_->angles(1) + bins_->angles(2));
      fit_.noise_from_repeats = repeats >= kMinNoiseRepeats;
      const double s2 = fit_.noise_from_repeats ? scatter / (3.0 * (n - bins))
                                                : (means + scatter) / (3.0 * n - kSpindleParams);
      fit_.params = lm_.solution();
      if (!(std::hypot(fit_.params(3), fit_.params(4)) <= kMaxSpindleTilt)) return fail(Status::kArgumentOutOfRange);
      lm_.covariance(s2 > 0.0 ? s2 : 1e-300, fit_.covariance, factor_);
      fit_.noise_sigma_mm = std::sqrt(s2);
      fit_.rms_mm = std::sqrt((means + scatter) / n);
      fit_.synchronous_rms_mm = std::sqrt(means / n);
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
