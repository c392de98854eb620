// M4's 9-parameter tool-axis model (spindle_model.hpp): exact recovery from
// noise-free data, honest 1-sigma figures on a Monte Carlo at an analyser's
// noise (15 nm per axis, 72 angles, balls 50 and 150 mm below the gauge plane),
// a prediction at a tool length not used in the fit within its propagated
// uncertainty, and each refusal. The data come from the model's own formula
// written out again here (M = o + R(phi) (G a + e + b (a + w)), R by Rodrigues),
// not from spindle_ball_mm.
#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <memory>
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

std::unique_ptr<core::SpindleBins> bins_of(const std::vector<core::SpindleSample>& s) {
  auto bins = std::make_unique<core::SpindleBins>();
  bins->clear();
  for (const auto& x : s) REQUIRE(bins->add(x) == Status::kOk);
  return bins;
}

// Steps `builder` until it is done: the number of steps, the last one in `last`.
int step_to_end(core::SpindleBuilder& builder, core::SpindleStep& last) {
  int steps = 0;
  do {
    last = builder.step();
    ++steps;
  } while (last.more);
  return steps;
}

}  // namespace

TEST_CASE("noise-free data give the parameters back", "[spindle]") {
  t::Rng rng(71);
  const core::SpindleParams p = truth();
  const auto s = samples(p, 0.0, rng);
  const auto bins = bins_of(s);
  const auto start = core::spindle_start(*bins, kGeometry);
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
  SECTION("7 samples of ball 2 (8 needed): a gap first (revolution_incomplete), too_few_samples when the gap is allowed; 8 are enough") {
    auto s = samples(p, 15e-6, rng);
    std::vector<core::SpindleSample> few;
    for (const auto& x : s) {
      if (x.ball == 1 || static_cast<int>(x.phi_deg) % 45 == 0) few.push_back(x);
    }
    REQUIRE(few.size() == 72 + 8);
    CHECK(core::fit_spindle(few.data(), few.size(), kGeometry, fit) == Status::kOk);
    few.pop_back();
    CHECK(core::fit_spindle(few.data(), few.size(), kGeometry, fit) == Status::kRevolutionIncomplete);
    const auto bins = bins_of(few);
    core::SpindleBuilder builder;
    builder.start(*bins, kGeometry, 90.0);  // a gap of 90 deg allowed: the count decides
    CHECK(builder.step().status == Status::kTooFewSamples);
  }
  SECTION("angles in radians: a revolution spans 6.3 deg, revolution_incomplete") {
    auto s = samples(p, 15e-6, rng);
    for (auto& x : s) x.phi_deg = core::deg_to_rad(x.phi_deg);
    CHECK(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kRevolutionIncomplete);
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

TEST_CASE("the analytic Jacobian agrees with central differences", "[spindle]") {
  t::Rng rng(74);
  for (int trial = 0; trial < 200; ++trial) {
    core::SpindleParams p = truth();
    // Far from the study's sizes too: tilts up to 0.3 rad, offsets up to 1 mm.
    const double scale = trial < 100 ? 1.0 : 1000.0;
    p(3) *= scale * rng.uniform(-1, 1);
    p(4) *= scale * rng.uniform(-1, 1);
    for (int k = 5; k < 9; ++k) p(k) *= scale * rng.uniform(-1, 1);
    const int which = 1 + trial % 2;
    const double depth = kGeometry.ball_mm[which - 1];
    const double phi = rng.uniform(-7, 7);
    core::SpindleJacobian j;
    const Vec3 m = core::spindle_ball_jacobian(p, kGeometry, which, phi, j);
    CHECK((m - core::spindle_ball_mm(p, kGeometry, which, phi)).norm() < 1e-12);
    for (int k = 0; k < 9; ++k) {
      const double h = k < 3 ? 1e-4 : 1e-7;
      core::SpindleParams plus = p, minus = p;
      plus(k) += h;
      minus(k) -= h;
      const Vec3 numeric = (ball(plus, depth, phi) - ball(minus, depth, phi)) / (2 * h);
      INFO("trial " << trial << " parameter " << k);
      CHECK((j.col(k) - numeric).norm() <= 2e-6 * (1.0 + numeric.norm()));
    }
  }
}

TEST_CASE("angle bins: repeats merge, bins hold any angles, coverage at its limits", "[spindle]") {
  auto bins = std::make_unique<core::SpindleBins>();
  bins->clear();
  SECTION("repeats of an angle (mod 360) share a bin with the right mean and scatter") {
    const Vec3 p1(1, 2, 3), p2(1.5, 2, 3), p3(1, 2.5, 3);
    REQUIRE(bins->add({10.0, 1, p1}) == Status::kOk);
    REQUIRE(bins->add({370.0, 1, p2}) == Status::kOk);
    REQUIRE(bins->add({-350.0, 1, p3}) == Status::kOk);
    REQUIRE(bins->add({12.0, 1, p3}) == Status::kOk);  // the next bin (2 deg wide, from 10)
    CHECK(bins->angles(1) == 2);
    CHECK(bins->samples(1) == 4);
    const core::SpindleBin& b = bins->bin(1, 5);
    CHECK(b.count == 3);
    CHECK(b.phi_deg == 10.0);
    CHECK(b.angle_deg() == 10.0);
    const Vec3 mean = (p1 + p2 + p3) / 3;
    CHECK((b.mean_offset_mm - (mean - p1)).norm() < 1e-15);
    const double scatter = (p1 - mean).squaredNorm() + (p2 - mean).squaredNorm() + (p3 - mean).squaredNorm();
    CHECK(b.scatter_mm2 == Approx(scatter).epsilon(1e-14));
    // Repeats of one angle: the noise about their mean, count - 1 degrees of freedom.
    const core::SpindleNoise n = core::spindle_bin_noise(b);
    CHECK(n.dof == 2);
    CHECK(n.ssr_mm2 == b.scatter_mm2);
    CHECK(bins->bin(1, 6).count == 1);
  }
  SECTION("an angle just below 360 lies in the last bin, 0 in the first: the gap across 0 is their distance") {
    REQUIRE(bins->add({359.9999995, 2, Vec3::Zero()}) == Status::kOk);
    REQUIRE(bins->add({-0.5e-6, 2, Vec3::Ones()}) == Status::kOk);  // the same angle written below 0
    REQUIRE(bins->add({0.0, 2, Vec3::Ones()}) == Status::kOk);
    REQUIRE(bins->add({180.0, 2, Vec3::Ones()}) == Status::kOk);
    REQUIRE(bins->add({90.0, 2, Vec3::Ones()}) == Status::kOk);
    CHECK(bins->angles(2) == 4);
    CHECK(bins->bin(2, 0).phi_deg == 0.0);
    CHECK(bins->bin(2, 45).phi_deg == 90.0);
    CHECK(bins->bin(2, 90).phi_deg == 180.0);
    CHECK(bins->bin(2, core::kSpindleBins - 1).count == 2);
    CHECK(bins->largest_gap_deg(2) == Approx(180.0 - 0.5e-6).epsilon(1e-15));
  }
  SECTION("any number of distinct angles: 4,096 a revolution over 3 revolutions fill every bin") {
    for (int rev = 0; rev < 3; ++rev) {
      for (int i = 0; i < 4096; ++i) {
        REQUIRE(bins->add({360.0 * rev + 360.0 * i / 4096, 1, Vec3(1e-6 * (rev * 4096 + i), 0, 0)}) == Status::kOk);
      }
    }
    CHECK(bins->angles(1) == core::kSpindleBins);
    CHECK(bins->samples(1) == 3 * 4096);
    CHECK(bins->largest_gap_deg(1) < 2 * core::kSpindleBinDeg);  // convention 7: bins' mean angles
  }
  SECTION("bad samples change nothing") {
    CHECK(bins->add({NAN, 1, Vec3::Zero()}) == Status::kNotFinite);
    CHECK(bins->add({0.0, 0, Vec3::Zero()}) == Status::kArgumentOutOfRange);
    CHECK(bins->add({0.0, 1, Vec3(0, 1e5 * 1.0000001, 0)}) == Status::kArgumentOutOfRange);
    CHECK(bins->add({1e6 * 1.0000001, 1, Vec3::Zero()}) == Status::kArgumentOutOfRange);
    CHECK(bins->samples() == 0);
  }
  SECTION("coverage: a 45 deg gap is a revolution, 45 deg plus a hair is not") {
    const core::SpindleParams p = truth();
    auto at = [&](double phi, int k) {
      return core::SpindleSample{phi, k, ball(p, kGeometry.ball_mm[k - 1], core::deg_to_rad(phi))};
    };
    core::SpindleBins& b = *bins;
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < 8; ++i) REQUIRE(b.add(at(45.0 * i, k)) == Status::kOk);
    }
    core::SpindleBuilder builder;
    core::SpindleStep step;
    builder.start(b, kGeometry);
    do step = builder.step(); while (step.more);
    CHECK(step.status == Status::kOk);
    auto shifted = std::make_unique<core::SpindleBins>();
    shifted->clear();
    // 9 angles per ball: 0, 40, ..., 280 and then 325 + 1e-9: the gap 280 -> 325 is
    // 45 + 1e-9 > 45 (ball 2 only).
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i <= 7; ++i) REQUIRE(shifted->add(at(40.0 * i, k)) == Status::kOk);
      REQUIRE(shifted->add(at(k == 1 ? 320.0 : 325.0 + 1e-9, k)) == Status::kOk);
    }
    CHECK(shifted->largest_gap_deg(1) == 40.0);
    CHECK(shifted->largest_gap_deg(2) > 45.0);
    builder.start(*shifted, kGeometry);
    step = builder.step();
    CHECK(step.status == Status::kRevolutionIncomplete);
    CHECK_FALSE(step.more);
  }
}

// A ball's form error (harmonics 2..15 of phi, the same every revolution) plus
// white probe noise, 4 revolutions: the covariance from the repeats stays
// honest while the residuals' RMS is several times the noise; with one
// revolution the figures are conservative and say so.
TEST_CASE("noise from the repeats: a synchronous form error does not inflate the intervals", "[spindle][mc]") {
  t::Rng rng(76);
  const core::SpindleParams p = truth();
  const double sigma = 15e-6;
  const double form = 50e-6;
  constexpr int kRuns = 200;
  Eigen::Matrix<double, 9, 1> sq = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 9, 1> reported = Eigen::Matrix<double, 9, 1>::Zero();
  double noise = 0, sync = 0;
  for (int run = 0; run < kRuns; ++run) {
    // Form error per ball: radial and axial harmonics 2..15 with random phases.
    double amp[2][16][3], phase[2][16][3];
    for (auto& b : amp) for (auto& h : b) for (double& x : h) x = rng.normal();
    for (auto& b : phase) for (auto& h : b) for (double& x : h) x = rng.uniform(0, 2 * core::kPi);
    double norm = 0;
    for (int h = 2; h <= 15; ++h) for (int c = 0; c < 3; ++c) norm += amp[0][h][c] * amp[0][h][c] / 2;
    const double scale = form / std::sqrt(norm);
    std::vector<core::SpindleSample> s;
    for (int rev = 0; rev < 4; ++rev) {
      for (int k = 1; k <= 2; ++k) {
        for (int i = 0; i < 72; ++i) {
          const double phi = core::deg_to_rad(5.0 * i);
          Vec3 f = Vec3::Zero();
          for (int h = 2; h <= 15; ++h) {
            for (int c = 0; c < 3; ++c) f(c) += scale * amp[k - 1][h][c] * std::cos(h * phi + phase[k - 1][h][c]);
          }
          const Vec3 n(rng.normal(), rng.normal(), rng.normal());
          s.push_back({360.0 * rev + 5.0 * i, k, ball(p, kGeometry.ball_mm[k - 1], phi) + f + sigma * n});
        }
      }
    }
    core::SpindleFit fit;
    REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
    REQUIRE(fit.noise_from_repeats);
    REQUIRE(fit.samples == 576);
    noise += fit.noise_sigma_mm / kRuns;
    sync += fit.synchronous_rms_mm / kRuns;
    for (int k = 0; k < 9; ++k) {
      const double e = fit.params(k) - p(k);
      sq(k) += e * e / kRuns;
      reported(k) += fit.covariance(k, k) / kRuns;
    }
  }
  INFO("mean noise sigma " << noise * 1e6 << " nm, synchronous RMS " << sync * 1e6 << " nm");
  CHECK(noise == Approx(sigma).epsilon(0.05));
  CHECK(sync > 2 * sigma * std::sqrt(3.0));  // the form error is there, in the means
  for (int k = 0; k < 9; ++k) {
    const double ratio = std::sqrt(reported(k) / sq(k));
    INFO("parameter " << k << ": reported sigma / MC RMS " << ratio);
    CHECK(ratio > 1 / 1.5);
    CHECK(ratio < 1.5);
  }
}

TEST_CASE("one revolution: the noise comes from every residual", "[spindle]") {
  t::Rng rng(77);
  const auto s = samples(truth(), 15e-6, rng);
  core::SpindleFit fit;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
  CHECK_FALSE(fit.noise_from_repeats);
  // (2F + 0) / (3 n - 9) against the 3-D RMS: s^2 = rms^2 n / (3 n - 9).
  CHECK(fit.noise_sigma_mm == Approx(fit.rms_mm * std::sqrt(144.0 / (3 * 144.0 - 9))).epsilon(1e-12));
  CHECK(fit.synchronous_rms_mm == Approx(fit.rms_mm).epsilon(1e-12));
  // 8 repeats are not enough to use (kMinNoiseRepeats = 9); 9 are.
  auto more = s;
  const auto again = [&](std::size_t i) {  // a revolution on, the same centre
    more.push_back(s[i]);
    more.back().phi_deg += 360.0;
  };
  for (std::size_t i = 0; i < 8; ++i) again(i);
  REQUIRE(core::fit_spindle(more.data(), more.size(), kGeometry, fit) == Status::kOk);
  CHECK_FALSE(fit.noise_from_repeats);
  again(8);
  REQUIRE(core::fit_spindle(more.data(), more.size(), kGeometry, fit) == Status::kOk);
  CHECK(fit.noise_from_repeats);
  CHECK(fit.noise_sigma_mm == 0.0);  // exact repeats: no scatter
}

TEST_CASE("the builder's steps are bounded and give fit_spindle's result bit for bit", "[spindle]") {
  t::Rng rng(78);
  std::vector<core::SpindleSample> s;
  for (int k = 1; k <= 2; ++k) {
    for (int i = 0; i < 360; ++i) {
      const Vec3 n(rng.normal(), rng.normal(), rng.normal());
      s.push_back({i * 1.0, k, ball(truth(), kGeometry.ball_mm[k - 1], core::deg_to_rad(i)) + 15e-6 * n});
    }
  }
  const auto bins = bins_of(s);
  core::SpindleBuilder builder;
  builder.start(*bins, kGeometry);
  core::SpindleStep step;
  const int steps = step_to_end(builder, step);
  REQUIRE(step.status == Status::kOk);
  core::SpindleFit direct;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, direct) == Status::kOk);
  CHECK(bool(builder.fit().params == direct.params));
  CHECK(bool(builder.fit().covariance == direct.covariance));
  const int evaluations = builder.fit().evaluations;
  // start + the bins' noise + per evaluation (the sums, then its decision) + the finish
  CHECK(steps == 2 + evaluations * 2 + 1);
  // The builder runs again from start() with the same result; a step after the end repeats it.
  builder.start(*bins, kGeometry);
  do step = builder.step(); while (step.more);
  CHECK(bool(builder.fit().params == direct.params));
  CHECK(builder.step().status == Status::kOk);
  CHECK_FALSE(builder.step().more);
}

TEST_CASE("both balls at one place: not_identifiable; a solver cut short: no_convergence", "[spindle]") {
  t::Rng rng(79);
  auto s = samples(truth(), 15e-6, rng);
  SECTION("the balls' centres coincide: no axis direction") {
    for (auto& x : s) {
      if (x.ball == 2) x.p_mm = s[static_cast<std::size_t>(x.phi_deg / 5.0)].p_mm;
    }
    core::SpindleFit fit;
    CHECK(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kNotIdentifiable);
  }
  SECTION("one evaluation allowed") {
    const auto bins = bins_of(s);
    core::LmOptions options;
    options.max_iterations = 1;
    core::SpindleBuilder builder;
    builder.start(*bins, kGeometry, core::kMaxSpindleGapDeg, options);
    core::SpindleStep step;
    do step = builder.step(); while (step.more);
    CHECK(step.status == Status::kNoConvergence);
    options.max_iterations = 200;
    builder.start(*bins, kGeometry, core::kMaxSpindleGapDeg, options);
    do step = builder.step(); while (step.more);
    CHECK(step.status == Status::kOk);
  }
}

// --- proposed (review of M4): each closes a break no test caught ---

TEST_CASE("2^23 samples fit in one angle bin, the next is session_full and changes nothing", "[spindle]") {
  auto bins = std::make_unique<core::SpindleBins>();
  bins->clear();
  std::uint32_t ok = 0;
  // Each sample its own (a duplicate would be refused): the centre's x counts them, in um.
  for (std::uint32_t i = 0; i < core::kMaxBinCount; ++i) {
    ok += bins->add({10.0, 1, Vec3(1e-3 * static_cast<double>(i), 0, 0)}) == Status::kOk ? 1u : 0u;
  }
  CHECK(ok == core::kMaxBinCount);
  CHECK(bins->add({371.0, 1, Vec3(-1, 0, 0)}) == Status::kSessionFull);  // the same bin, another angle
  CHECK(bins->bin(1, 5).count == core::kMaxBinCount);
  CHECK(bins->samples(1) == core::kMaxBinCount);
  CHECK(bins->sums(1).count == core::kMaxBinCount);
  CHECK(bins->add({12.0, 1, Vec3(-1, 0, 0)}) == Status::kOk);  // the next bin still takes samples
}

// Two revolutions of exact data, the second moved by d along X: each bin's mean is
// the model moved by d / 2 (o_x takes it exactly) and each sample is d / 2 from it,
// so convention 6's figures are known in closed form.
TEST_CASE("the noise and the RMS figures are convention 6's formulas exactly", "[spindle]") {
  const double d = 1e-3;
  std::vector<core::SpindleSample> s;
  for (int rev = 0; rev < 2; ++rev) {
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < 72; ++i) {
        const double phi = 5.0 * i;
        s.push_back({360.0 * rev + phi, k,
                     ball(truth(), kGeometry.ball_mm[k - 1], core::deg_to_rad(phi)) + rev * d * Vec3::UnitX()});
      }
    }
  }
  core::SpindleFit fit;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
  REQUIRE(fit.noise_from_repeats);
  CHECK(std::fabs(fit.params(0) - (truth()(0) + d / 2)) < 1e-10);
  // s^2 = scatter / (3 (n - bins)) = 144 x 2 (d / 2)^2 / (3 x 144) = d^2 / 6
  CHECK(fit.noise_sigma_mm == Approx(d / std::sqrt(6.0)).epsilon(1e-9));
  CHECK(fit.rms_mm == Approx(d / 2).epsilon(1e-9));  // every sample, scatter included
  CHECK(fit.synchronous_rms_mm < 1e-9);              // the means lie on the model
}

TEST_CASE("an evaluation takes one step whatever the number of samples", "[spindle]") {
  // 16 samples or 20,480 a ball: the same steps per evaluation.
  for (const int per_revolution : {8, 4096}) {
    const int revolutions = per_revolution == 8 ? 1 : 5;
    auto bins = std::make_unique<core::SpindleBins>();
    bins->clear();
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < per_revolution * revolutions; ++i) {
        const double phi = 360.0 * i / per_revolution;
        REQUIRE(bins->add({phi, k, ball(truth(), kGeometry.ball_mm[k - 1], core::deg_to_rad(phi)) +
                                       Vec3(1e-9 * (i % 7), 0, 0)}) == Status::kOk);
      }
    }
    core::SpindleBuilder builder;
    builder.start(*bins, kGeometry);
    core::SpindleStep step;
    const int steps = step_to_end(builder, step);
    CAPTURE(per_revolution);
    REQUIRE(step.status == Status::kOk);
    CHECK(steps == 2 + builder.fit().evaluations * 2 + 1);
  }
}

// The fit stores only what the decoder loads again (spindle_correction.hpp
// convention 5): an axis beyond 30 deg from -Z is refused at the fit.
TEST_CASE("an axis tilted past kMaxSpindleTilt is refused at the fit, one just inside is identified", "[spindle]") {
  for (const double ax : {0.49, 0.51}) {
    core::SpindleParams p = truth();
    p(3) = ax;
    p(4) = 0.0;
    t::Rng rng(80);
    const auto s = samples(p, 0.0, rng);
    core::SpindleFit fit;
    const Status status = core::fit_spindle(s.data(), s.size(), kGeometry, fit);
    CAPTURE(ax);
    CHECK(status == (ax < core::kMaxSpindleTilt ? Status::kOk : Status::kArgumentOutOfRange));
  }
}

// ---- issue 18: any sampling, in fixed memory --------------------------------------

TEST_CASE("a bin's noise is the residual of its own local line, as a regression on its samples gives it",
          "[spindle]") {
  t::Rng rng(1801);
  for (int trial = 0; trial < 200; ++trial) {
    auto bins = std::make_unique<core::SpindleBins>();
    bins->clear();
    const int n = 2 + trial % 30;
    const double phi0 = 2.0 * static_cast<double>(trial % 180);
    // Samples at angles across the bin (or, every fourth trial, repeats of one
    // angle), each a line in delta plus noise, around a centre far from 0.
    std::vector<double> delta(static_cast<std::size_t>(n));
    std::vector<Vec3> p(static_cast<std::size_t>(n));
    const Vec3 centre(123.4, -56.7, 400.0);
    const Vec3 slope(rng.normal(), rng.normal(), rng.normal());
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      delta[k] = trial % 4 == 0 ? 0.0 : (i == 0 ? 0.0 : rng.uniform(0.0, 1.999));
      p[k] = centre + 1e-3 * delta[k] * slope + 15e-6 * Vec3(rng.normal(), rng.normal(), rng.normal());
      REQUIRE(bins->add({phi0 + delta[k] + 720.0, 1, p[k]}) == Status::kOk);
    }
    REQUIRE(bins->angles(1) == 1);
    const core::SpindleBin& b = bins->bin(1, static_cast<std::size_t>(phi0 / 2.0));
    REQUIRE(b.count == static_cast<std::uint32_t>(n));
    const core::SpindleNoise got = core::spindle_bin_noise(b);
    // Independent: per axis, least squares on (1, delta) by normal equations
    // in long double (one angle: the mean alone).
    long double sd = 0, sdd = 0;
    for (double d : delta) {
      sd += d;
      sdd += static_cast<long double>(d) * d;
    }
    const bool one_angle = trial % 4 == 0;
    long double ssr = 0;
    for (int x = 0; x < 3; ++x) {
      long double sp = 0, sdp = 0;
      for (std::size_t k = 0; k < delta.size(); ++k) {
        sp += p[k](x);
        sdp += static_cast<long double>(delta[k]) * p[k](x);
      }
      const long double det = n * sdd - sd * sd;
      const long double beta = one_angle ? 0.0L : (n * sdp - sd * sp) / det;
      const long double alpha = (sp - beta * sd) / n;
      for (std::size_t k = 0; k < delta.size(); ++k) {
        const long double r = p[k](x) - alpha - beta * delta[k];
        ssr += r * r;
      }
    }
    CAPTURE(trial, n);
    CHECK(got.dof == static_cast<std::size_t>(one_angle ? n - 1 : n - 2));
    INFO(std::setprecision(17) << got.ssr_mm2 << " " << static_cast<double>(ssr));
    CHECK(got.ssr_mm2 == Approx(static_cast<double>(ssr)).epsilon(1e-8).margin(1e-20));
  }
}

TEST_CASE("angles spread by no more than kSameAngleDeg are repeats of one angle; a little more is a line",
          "[spindle]") {
  for (const double spread : {0.99e-6, 1.01e-6}) {
    auto bins = std::make_unique<core::SpindleBins>();
    bins->clear();
    // Two angles +-spread around 31: RMS spread exactly `spread`, four samples.
    const double at[4] = {31.0 - spread, 31.0 + spread, 31.0 - spread, 31.0 + spread};
    for (int i = 0; i < 4; ++i) REQUIRE(bins->add({at[i], 1, Vec3(1e-3 * i, 0, 0)}) == Status::kOk);
    const core::SpindleNoise n = core::spindle_bin_noise(bins->bin(1, 15));
    CAPTURE(spread);
    CHECK(n.dof == (spread < core::kSameAngleDeg ? 3u : 2u));
  }
}

// The session's sums give the least-squares fit to every sample, for angles that
// never repeat (time-sampled, a drifting speed): against a Gauss-Newton written
// here on the samples themselves (the model of `ball`, numeric Jacobian).
TEST_CASE("time-sampled angles: the fit from the sums is the least-squares fit to every sample", "[spindle]") {
  t::Rng rng(1802);
  const core::SpindleParams p = truth();
  std::vector<core::SpindleSample> s;
  double phi = 17.3;
  for (int i = 0; phi < 17.3 + 3 * 360.0; ++i) {
    const double speed = 1.0 + 0.01 * (phi - 17.3) / (3 * 360.0) - 0.005;  // drifting by 1 %
    for (int k = 1; k <= 2; ++k) {
      const Vec3 n(rng.normal(), rng.normal(), rng.normal());
      const double r = core::deg_to_rad(phi);
      const Vec3 form(40e-6 * std::cos(3 * r + k), 30e-6 * std::sin(5 * r), 0.0);
      s.push_back({phi, k, ball(p, kGeometry.ball_mm[k - 1], r) + form + 15e-6 * n});
    }
    phi += 360.0 / 1024 * speed;
  }
  core::SpindleFit fit;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
  // Gauss-Newton on the samples.
  core::SpindleParams q = fit.params;
  for (int k = 0; k < 9; ++k) q(k) += 3.0 * std::sqrt(fit.covariance(k, k));  // a start off the answer
  double ssr_ball[2] = {0, 0};
  for (int iteration = 0; iteration < 6; ++iteration) {
    Eigen::Matrix<double, 9, 9> a = Eigen::Matrix<double, 9, 9>::Zero();
    Eigen::Matrix<double, 9, 1> g = Eigen::Matrix<double, 9, 1>::Zero();
    ssr_ball[0] = ssr_ball[1] = 0;
    for (const auto& x : s) {
      const double depth = kGeometry.ball_mm[x.ball - 1];
      const double r = core::deg_to_rad(std::fmod(x.phi_deg, 360.0));
      const Vec3 res = ball(q, depth, r) - x.p_mm;
      ssr_ball[x.ball - 1] += res.squaredNorm();
      Eigen::Matrix<double, 3, 9> j;
      for (int k = 0; k < 9; ++k) {
        core::SpindleParams plus = q, minus = q;
        const double h = k < 3 || k == 5 || k == 6 ? 1e-5 : 1e-7;
        plus(k) += h;
        minus(k) -= h;
        j.col(k) = (ball(plus, depth, r) - ball(minus, depth, r)) / (2 * h);
      }
      a += j.transpose() * j;
      g += j.transpose() * res;
    }
    q -= a.ldlt().solve(g);
  }
  for (int k = 0; k < 9; ++k) {
    CAPTURE(k);
    CHECK(std::fabs(fit.params(k) - q(k)) < 1e-3 * std::sqrt(fit.covariance(k, k)));
  }
  CHECK(fit.ball_ssr_mm2[0] == Approx(ssr_ball[0]).epsilon(1e-6));
  CHECK(fit.ball_ssr_mm2[1] == Approx(ssr_ball[1]).epsilon(1e-6));
  CHECK(fit.rms_mm == Approx(std::sqrt((ssr_ball[0] + ssr_ball[1]) / static_cast<double>(s.size()))).epsilon(1e-6));
  // The noise from the bins' local lines: the probes' 15 nm, not the form error.
  CHECK(fit.noise_from_repeats);
  CHECK(fit.noise_sigma_mm == Approx(15e-6).epsilon(0.05));
  CHECK(fit.synchronous_rms_mm > 30e-6);
}
