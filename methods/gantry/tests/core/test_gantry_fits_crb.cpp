// M2's plane and axis fits against the Cramer-Rao bound, on 5,000 Monte-Carlo
// runs each (the circle fit's bound is tested in test_circle_fit_stats.cpp).
//
// The bounds, for points p_i = q_i + e_i with e_i ~ N(0, sigma^2 I), i = 1..n:
//  - Plane through the true points q_i, written h = d + alpha x + beta y in the
//    true frame (centroid c, in-plane principal axes u, v, normal w), x_i =
//    (q_i - c).u, y_i = (q_i - c).v with sum x_i y_i = 0. Only the heights'
//    noise carries information on (d, alpha, beta) to first order, and that
//    model is linear in them, so the Fisher information is diagonal:
//        CRB(d) = sigma^2 / n,  CRB(alpha) = sigma^2 / Sxx,  CRB(beta) = sigma^2 / Syy,
//    Sxx = sum x_i^2, Syy = sum y_i^2. The fitted normal's error along u is
//    -alpha, along v -beta; the fitted plane's offset at c is d.
//  - Axis from K passes, each of n points at positions t_i along the true unit
//    direction a (sum t_i = 0 per pass): each perpendicular slope of one pass
//    has CRB sigma^2 / Stt, Stt = sum t_i^2; the K passes are independent and
//    share a, so for the averaged direction
//        CRB(each perpendicular component) = sigma^2 / (K Stt).
// The test: the RMS error of each parameter over the runs is within 10 % of the
// square root of its bound, and the fit's reported covariance (the module's own
// 1-sigma figure, from a known point noise) is within 10 % of the bound too.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "reference.hpp"
#include "trueaxis/core/gantry_fits.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

constexpr int kRuns = 5000;

Vec3 noisy(const Vec3& q, double sigma, t::Rng& rng) {
  return q + sigma * Vec3(rng.normal(), rng.normal(), rng.normal());
}

}  // namespace

TEST_CASE("the plane fit reaches the Cramer-Rao bound on 5,000 runs", "[gantry][crb]") {
  t::Rng rng(5001);
  const double sigma = 0.0075;  // an AT960's distance term read as 1 sigma
  // Four pads of a bed, 5 x 5 points each, tilted and far from the origin.
  const Vec3 w = Vec3(0.02, -0.01, 1.0).normalized();
  const Vec3 u0 = w.unitOrthogonal();
  const Vec3 v0 = w.cross(u0);
  const Vec3 origin(2500, -1800, -600);
  std::vector<Vec3> q;
  const double pads[4][2] = {{60, 60}, {5860, 60}, {5860, 2860}, {60, 2860}};
  for (const auto& pad : pads) {
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) q.push_back(origin + (pad[0] + 20 * i) * u0 + (pad[1] + 20 * j) * v0);
    }
  }
  // The true frame: centroid and in-plane principal axes.
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : q) c += p;
  c /= static_cast<double>(q.size());
  core::Mat2 s2 = core::Mat2::Zero();
  for (const Vec3& p : q) {
    const core::Vec2 xy((p - c).dot(u0), (p - c).dot(v0));
    s2 += xy * xy.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<core::Mat2> es(s2);
  const Vec3 u = es.eigenvectors()(0, 1) * u0 + es.eigenvectors()(1, 1) * v0;  // the larger spread
  const Vec3 v = w.cross(u);
  double sxx = 0, syy = 0;
  for (const Vec3& p : q) {
    sxx += std::pow((p - c).dot(u), 2);
    syy += std::pow((p - c).dot(v), 2);
  }
  const double n = static_cast<double>(q.size());
  const double crb[3] = {sigma * sigma / n, sigma * sigma / sxx, sigma * sigma / syy};

  core::PointNoise noise;
  noise.distance_sigma_mm = sigma;
  std::vector<Vec3> p(q.size());
  double sq[3] = {0, 0, 0};
  double reported[3] = {0, 0, 0};
  for (int run = 0; run < kRuns; ++run) {
    for (std::size_t i = 0; i < q.size(); ++i) p[i] = noisy(q[i], sigma, rng);
    const auto fit = core::fit_plane_group({p.data(), p.size()}, noise);
    REQUIRE(fit.ok());
    const core::PlaneEstimate e = core::orient_plane(fit.value(), w);
    const Vec3 dn = e.normal - w;
    const double err[3] = {(e.centroid_mm - c).dot(w), -dn.dot(u), -dn.dot(v)};
    for (int k = 0; k < 3; ++k) sq[k] += err[k] * err[k];
    for (int k = 0; k < 3; ++k) reported[k] += e.covariance(k, k) / kRuns;
  }
  const char* names[3] = {"offset d", "tilt alpha", "tilt beta"};
  for (int k = 0; k < 3; ++k) {
    const double rms_over_bound = std::sqrt(sq[k] / kRuns / crb[k]);
    const double reported_over_bound = std::sqrt(reported[k] / crb[k]);
    INFO(names[k] << ": RMS / sqrt(CRB) = " << rms_over_bound << ", reported / sqrt(CRB) = " << reported_over_bound);
    CHECK(rms_over_bound == Approx(1.0).margin(0.1));
    CHECK(reported_over_bound == Approx(1.0).margin(0.1));
  }
}

TEST_CASE("the axis fit from 3 passes reaches the Cramer-Rao bound on 5,000 runs", "[gantry][crb]") {
  t::Rng rng(5002);
  const double sigma = 0.0075;
  const Vec3 a = Vec3(0.999, 0.03, -0.02).normalized();
  const Vec3 start(1200, 3400, 2100);
  constexpr std::size_t k_passes = 3;
  const int n = 15;
  const double stroke = 2800.0;
  std::vector<Vec3> q;
  for (int i = 0; i < n; ++i) q.push_back(start + (stroke * i / (n - 1)) * a);
  double stt = 0;
  for (int i = 0; i < n; ++i) stt += std::pow(stroke * i / (n - 1) - stroke / 2, 2);
  const double crb = sigma * sigma / (static_cast<double>(k_passes) * stt);
  const Vec3 e1 = a.unitOrthogonal();
  const Vec3 e2 = a.cross(e1);

  core::PointNoise noise;
  noise.distance_sigma_mm = sigma;
  std::vector<std::vector<Vec3>> passes(k_passes, std::vector<Vec3>(q.size()));
  double sq[2] = {0, 0};
  double reported[2] = {0, 0};
  for (int run = 0; run < kRuns; ++run) {
    core::PointSpan spans[k_passes];
    for (std::size_t k = 0; k < k_passes; ++k) {
      for (std::size_t i = 0; i < q.size(); ++i) passes[k][i] = noisy(q[i], sigma, rng);
      spans[k] = {passes[k].data(), passes[k].size()};
    }
    const auto fit = core::fit_axis_passes(spans, k_passes, noise);
    REQUIRE(fit.ok());
    const Vec3 d = fit.value().direction - a;
    sq[0] += std::pow(d.dot(e1), 2);
    sq[1] += std::pow(d.dot(e2), 2);
    reported[0] += e1.dot(fit.value().covariance * e1) / kRuns;
    reported[1] += e2.dot(fit.value().covariance * e2) / kRuns;
  }
  for (int k = 0; k < 2; ++k) {
    const double rms_over_bound = std::sqrt(sq[k] / kRuns / crb);
    const double reported_over_bound = std::sqrt(reported[k] / crb);
    INFO("perpendicular component " << k + 1 << ": RMS / sqrt(CRB) = " << rms_over_bound
                                    << ", reported / sqrt(CRB) = " << reported_over_bound);
    CHECK(rms_over_bound == Approx(1.0).margin(0.1));
    CHECK(reported_over_bound == Approx(1.0).margin(0.1));
  }
}

TEST_CASE("with no stated noise, the axis fit's covariance follows noise that differs across the line",
          "[gantry][crb]") {
  // A tracker is noisier across its line of sight than along it: here 20 um
  // along e1, 5 um along e2 (and 9 um along the pass, which the slopes do not
  // see). Each perpendicular component's reported variance, from the
  // residuals alone (gantry_fits.hpp convention 4), must follow its own noise:
  // within 10 % of its own bound sigma_k^2 / (K Stt); pooled over both
  // components it would be sqrt((20^2 + 5^2) / 2) / 5 = 2.9 times too large on e2.
  t::Rng rng(5003);
  const double sigma[2] = {0.020, 0.005};
  const double along = 0.009;
  const Vec3 a = Vec3(0.2, 0.97, 0.1).normalized();
  const Vec3 e1 = a.unitOrthogonal();
  const Vec3 e2 = a.cross(e1);
  const Vec3 start(-800, 500, 1900);
  constexpr std::size_t k_passes = 2;
  const int n = 6;  // few points: n - 2 degrees of freedom per component matter (n would read 0.82)
  const double stroke = 1500.0;
  std::vector<Vec3> q;
  for (int i = 0; i < n; ++i) q.push_back(start + (stroke * i / (n - 1)) * a);
  double stt = 0;
  for (int i = 0; i < n; ++i) stt += std::pow(stroke * i / (n - 1) - stroke / 2, 2);

  std::vector<std::vector<Vec3>> passes(k_passes, std::vector<Vec3>(q.size()));
  double sq[2] = {0, 0};
  double reported[2] = {0, 0};
  double cross = 0;
  for (int run = 0; run < kRuns; ++run) {
    core::PointSpan spans[k_passes];
    for (std::size_t k = 0; k < k_passes; ++k) {
      for (std::size_t i = 0; i < q.size(); ++i) {
        passes[k][i] = q[i] + sigma[0] * rng.normal() * e1 + sigma[1] * rng.normal() * e2 + along * rng.normal() * a;
      }
      spans[k] = {passes[k].data(), passes[k].size()};
    }
    const auto fit = core::fit_axis_passes(spans, k_passes, core::PointNoise{});
    REQUIRE(fit.ok());
    const Vec3 d = fit.value().direction - a;
    sq[0] += std::pow(d.dot(e1), 2);
    sq[1] += std::pow(d.dot(e2), 2);
    reported[0] += e1.dot(fit.value().covariance * e1) / kRuns;
    reported[1] += e2.dot(fit.value().covariance * e2) / kRuns;
    cross += e1.dot(fit.value().covariance * e2) / kRuns;
  }
  for (int k = 0; k < 2; ++k) {
    const double crb = sigma[k] * sigma[k] / (static_cast<double>(k_passes) * stt);
    const double rms_over_bound = std::sqrt(sq[k] / kRuns / crb);
    const double reported_over_bound = std::sqrt(reported[k] / crb);
    INFO("perpendicular component " << k + 1 << ": RMS / sqrt(CRB) = " << rms_over_bound
                                    << ", reported / sqrt(CRB) = " << reported_over_bound);
    CHECK(rms_over_bound == Approx(1.0).margin(0.1));
    CHECK(reported_over_bound == Approx(1.0).margin(0.1));
  }
  // Independent noise on e1 and e2: no correlation reported on average.
  CHECK(std::fabs(cross) < 0.05 * std::sqrt(reported[0] * reported[1]));
}

TEST_CASE("with no stated noise, the plane fit's covariance takes the residuals' variance over n - 3 degrees of freedom",
          "[gantry][crb]") {
  // The same points fitted twice: with a stated constant noise sigma the
  // covariance is sigma^2 sum g g^T (gantry_fits.hpp convention 3); with none,
  // sigma^2 is estimated as the residuals' sum of squares over n - 3. So the
  // two covariances are in the ratio n rms^2 / (n - 3) / sigma^2 exactly, at
  // n = 4 (1 degree of freedom: n - 2 would halve it) and at n = 9.
  t::Rng rng(5004);
  for (const int n : {4, 9}) {
    INFO("points " << n);
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) {
      const double x = 300.0 * rng.normal();
      const double y = 200.0 * rng.normal();
      p.push_back(Vec3(x, y, 0.002 * x - 0.001 * y + 0.01 * rng.normal()) + Vec3(1500.0, -400.0, 900.0));
    }
    core::PointNoise stated;
    stated.distance_sigma_mm = 0.01;
    const auto none = core::fit_plane_group({p.data(), p.size()}, core::PointNoise{});
    const auto known = core::fit_plane_group({p.data(), p.size()}, stated);
    REQUIRE(none.ok());
    REQUIRE(known.ok());
    const double rms = none.value().rms_residual_mm;
    REQUIRE(rms > 0.0);
    const double ratio = n * rms * rms / (n - 3.0) / (0.01 * 0.01);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        const double scale = std::sqrt(none.value().covariance(r, r) * none.value().covariance(c, c));
        CHECK(none.value().covariance(r, c) ==
              Approx(ratio * known.value().covariance(r, c)).epsilon(1e-12).margin(1e-12 * scale));
      }
    }
  }
}
