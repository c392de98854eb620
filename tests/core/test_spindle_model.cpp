// M4's 9-parameter tool-axis model (spindle_model.hpp): exact recovery from
// noise-free data, honest 1-sigma figures on a Monte Carlo at an analyser's
// noise (15 nm per axis, 72 angles, balls 50 and 150 mm below the gauge plane),
// a prediction at a tool length not used in the fit within its propagated
// uncertainty, and each refusal. The data come from the model's own formula
// written out again here (M = o + R(phi) (G a + e + b (a + w)), R by Rodrigues),
// not from spindle_ball_mm.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "reference.hpp"
#include "trueaxis/core/spindle_model.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

constexpr double kArcsec = core::kPi / (180.0 * 3600.0);
const core::SpindleGeometry kGeometry{350.0, {50.0, 150.0}};

core::SpindleParams truth() {
  core::SpindleParams p;
  p << 0.0123, -0.0087, 399.998, -20 * kArcsec, 35 * kArcsec, 0.0023, 0.0014, -19.9 * kArcsec, 11.2 * kArcsec;
  return p;
}

// The model written out independently: Rodrigues about a, then the offsets.
Vec3 ball(const core::SpindleParams& p, double depth_mm, double phi_rad) {
  const double ax = p(3), ay = p(4), az = -std::sqrt(1 - ax * ax - ay * ay);
  const Vec3 a(ax, ay, az);
  const Vec3 e(p(5), p(6), -(ax * p(5) + ay * p(6)) / az);
  const Vec3 w(p(7), p(8), -(ax * p(7) + ay * p(8)) / az);
  const Vec3 q = kGeometry.gauge_mm * a + e + depth_mm * (a + w);
  const Vec3 rotated = q * std::cos(phi_rad) + a.cross(q) * std::sin(phi_rad) + a * a.dot(q) * (1 - std::cos(phi_rad));
  return p.head<3>() + rotated;
}

std::vector<core::SpindleSample> samples(const core::SpindleParams& p, double sigma, t::Rng& rng, int balls = 2) {
  std::vector<core::SpindleSample> s;
  for (int k = 1; k <= balls; ++k) {
    for (int i = 0; i < 72; ++i) {
      const double phi = 5.0 * i;
      const Vec3 n(rng.normal(), rng.normal(), rng.normal());
      s.push_back({phi, k, ball(p, kGeometry.ball_mm[k - 1], core::deg_to_rad(phi)) + sigma * n});
    }
  }
  return s;
}

}  // namespace

TEST_CASE("noise-free data give the parameters back", "[spindle]") {
  t::Rng rng(71);
  const core::SpindleParams p = truth();
  const auto s = samples(p, 0.0, rng);
  const auto start = core::spindle_start(s.data(), s.size(), kGeometry);
  REQUIRE(start.ok());
  CHECK((start.value() - p).cwiseAbs().maxCoeff() < 1e-9);  // whole revolution at even steps: the start is exact
  core::SpindleFit fit;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
  CHECK((fit.params - p).cwiseAbs().maxCoeff() < 1e-10);
  CHECK(fit.rms_mm < 1e-10);
  CHECK(fit.evaluations <= 4);
}

TEST_CASE("the 1-sigma figures are honest on 300 fits at 15 nm", "[spindle][mc]") {
  t::Rng rng(72);
  const core::SpindleParams p = truth();
  constexpr int kRuns = 300;
  const double sigma = 15e-6;
  Eigen::Matrix<double, 9, 1> sq = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 9, 1> reported = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 9, 1> within2 = Eigen::Matrix<double, 9, 1>::Zero();
  int tip_within3 = 0;
  for (int run = 0; run < kRuns; ++run) {
    const auto s = samples(p, sigma, rng);
    core::SpindleFit fit;
    REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
    for (int k = 0; k < 9; ++k) {
      const double e = fit.params(k) - p(k);
      const double sd = std::sqrt(fit.covariance(k, k));
      sq(k) += e * e / kRuns;
      reported(k) += fit.covariance(k, k) / kRuns;
      within2(k) += std::fabs(e) <= 2 * sd ? 1.0 / kRuns : 0.0;
    }
    // The tool line at 250 mm (no ball there), phi = 30 deg: error against the
    // truth within 3 sigma of its propagated uncertainty, per axis.
    const double depth = 250.0;
    const double phi = core::deg_to_rad(30.0);
    Eigen::Matrix<double, 3, 9> j;
    for (int k = 0; k < 9; ++k) {
      core::SpindleParams plus = fit.params, minus = fit.params;
      const double h = k < 3 ? 1e-6 : 1e-8;
      plus(k) += h;
      minus(k) -= h;
      j.col(k) = (ball(plus, depth, phi) - ball(minus, depth, phi)) / (2 * h);
    }
    const Eigen::Matrix3d cov = j * fit.covariance * j.transpose();
    const Vec3 err = ball(fit.params, depth, phi) - ball(p, depth, phi);
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && std::fabs(err(k)) <= 3 * std::sqrt(cov(k, k));
    tip_within3 += ok ? 1 : 0;
  }
  const char* names[9] = {"o_x", "o_y", "o_z", "a_x", "a_y", "e_x", "e_y", "w_x", "w_y"};
  for (int k = 0; k < 9; ++k) {
    const double ratio = std::sqrt(reported(k) / sq(k));
    INFO(names[k] << ": reported sigma / MC RMS " << ratio << ", within 2 sigma " << within2(k));
    CHECK(ratio > 1 / 1.5);
    CHECK(ratio < 1.5);
    CHECK(within2(k) >= 0.9);
  }
  INFO("tool line at 250 mm within 3 sigma in " << tip_within3 << " of " << kRuns);
  CHECK(tip_within3 >= kRuns * 95 / 100);
}

TEST_CASE("what the data cannot support is refused", "[spindle]") {
  t::Rng rng(73);
  const core::SpindleParams p = truth();
  core::SpindleFit fit;
  SECTION("one ball height: missing_group") {
    const auto s = samples(p, 15e-6, rng, 1);
    CHECK(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kMissingGroup);
  }
  SECTION("7 samples of ball 2 (8 needed): too_few_samples; 8 are enough") {
    auto s = samples(p, 15e-6, rng);
    std::vector<core::SpindleSample> few;
    for (const auto& x : s) {
      if (x.ball == 1 || static_cast<int>(x.phi_deg) % 45 == 0) few.push_back(x);
    }
    REQUIRE(few.size() == 72 + 8);
    CHECK(core::fit_spindle(few.data(), few.size(), kGeometry, fit) == Status::kOk);
    few.pop_back();
    CHECK(core::fit_spindle(few.data(), few.size(), kGeometry, fit) == Status::kTooFewSamples);
  }
  SECTION("a ball numbered 3, or the balls in the wrong order: argument_out_of_range") {
    auto s = samples(p, 15e-6, rng);
    s[5].ball = 3;
    CHECK(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kArgumentOutOfRange);
    const core::SpindleGeometry swapped{350.0, {150.0, 50.0}};
    const auto good = samples(p, 15e-6, rng);
    CHECK(core::fit_spindle(good.data(), good.size(), swapped, fit) == Status::kArgumentOutOfRange);
  }
  SECTION("a non-finite coordinate: not_finite") {
    auto s = samples(p, 15e-6, rng);
    s[3].p_mm.y() = NAN;
    CHECK(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kNotFinite);
  }
}
