#include "trueaxis/core/spindle_model.hpp"

#include <cmath>

namespace trueaxis::core {

namespace {

// a, e, w of convention 1.
struct Axes {
  Vec3 a, e, w;
};

Axes axes_of(const SpindleParams& p) {
  const double ax = p(3);
  const double ay = p(4);
  const double az = -std::sqrt(std::fmax(0.0, 1.0 - ax * ax - ay * ay));
  Axes r;
  r.a = Vec3(ax, ay, az);
  r.e = Vec3(p(5), p(6), -(ax * p(5) + ay * p(6)) / az);
  r.w = Vec3(p(7), p(8), -(ax * p(7) + ay * p(8)) / az);
  return r;
}

Status check(const SpindleSample* s, std::size_t count, const SpindleGeometry& g, std::size_t per_ball[2]) {
  if (!std::isfinite(g.gauge_mm) || !std::isfinite(g.ball_mm[0]) || !std::isfinite(g.ball_mm[1])) {
    return Status::kNotFinite;
  }
  if (!(g.ball_mm[1] > g.ball_mm[0])) return Status::kArgumentOutOfRange;
  per_ball[0] = per_ball[1] = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(s[i].phi_deg) || !s[i].p_mm.allFinite()) return Status::kNotFinite;
    if (s[i].ball != 1 && s[i].ball != 2) return Status::kArgumentOutOfRange;
    ++per_ball[s[i].ball - 1];
  }
  if (per_ball[0] == 0 || per_ball[1] == 0) return Status::kMissingGroup;
  if (per_ball[0] < kMinSpindleSamples || per_ball[1] < kMinSpindleSamples) return Status::kTooFewSamples;
  return Status::kOk;
}

}  // namespace

Vec3 spindle_ball_mm(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad) {
  const Axes x = axes_of(p);
  const double b = g.ball_mm[ball == 2 ? 1 : 0];
  const Vec3 v = x.e + b * x.w;
  return p.head<3>() + (g.gauge_mm + b) * x.a + std::cos(phi_rad) * v + std::sin(phi_rad) * x.a.cross(v);
}

Result<SpindleParams> spindle_start(const SpindleSample* s, std::size_t count, const SpindleGeometry& g) {
  std::size_t n[2];
  const Status status = check(s, count, g, n);
  if (status != Status::kOk) return status;
  Vec3 mean[2] = {Vec3::Zero(), Vec3::Zero()};
  for (std::size_t i = 0; i < count; ++i) mean[s[i].ball - 1] += s[i].p_mm;
  for (int k = 0; k < 2; ++k) mean[k] /= static_cast<double>(n[k]);
  Vec3 v[2] = {Vec3::Zero(), Vec3::Zero()};
  for (std::size_t i = 0; i < count; ++i) {
    const int k = s[i].ball - 1;
    v[k] += (2.0 / static_cast<double>(n[k])) * std::cos(deg_to_rad(s[i].phi_deg)) * (s[i].p_mm - mean[k]);
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

Status fit_spindle(const SpindleSample* s, std::size_t count, const SpindleGeometry& g, SpindleFit& out) {
  SpindleParams p0;
  const Result<SpindleParams> start = spindle_start(s, count, g);
  if (!start.ok()) return start.status();
  p0 = start.value();
  LevenbergMarquardt<kSpindleParams> lm;
  lm.start(p0);
  LmStep step;
  constexpr double kStep = 1e-7;
  do {
    const SpindleParams p = lm.point();
    lm.begin_evaluation();
    for (std::size_t i = 0; i < count; ++i) {
      const double phi = deg_to_rad(s[i].phi_deg);
      Eigen::Matrix<double, 3, kSpindleParams> j;
      j.leftCols<3>().setIdentity();
      for (int k = 3; k < kSpindleParams; ++k) {
        SpindleParams plus = p;
        SpindleParams minus = p;
        plus(k) += kStep;
        minus(k) -= kStep;
        j.col(k) = (spindle_ball_mm(plus, g, s[i].ball, phi) - spindle_ball_mm(minus, g, s[i].ball, phi)) / (2 * kStep);
      }
      const Vec3 r = spindle_ball_mm(p, g, s[i].ball, phi) - s[i].p_mm;
      lm.add(r, j);
    }
    step = lm.finish_evaluation();
  } while (step.more);
  if (lm.status() != Status::kOk) return lm.status();
  out.params = lm.solution();
  out.covariance = lm.covariance();
  out.rms_mm = std::sqrt(2.0 * lm.cost() / static_cast<double>(count));
  out.evaluations = lm.evaluations();
  return Status::kOk;
}

}  // namespace trueaxis::core
