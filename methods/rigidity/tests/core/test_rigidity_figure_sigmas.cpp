// The two figures issue 17 gave a sigma: the A positioning error's (the
// builder's propagation, rigidity_table.hpp convention 7) against a
// propagation written independently, sample by sample through the whole
// build; the C-circle RMS's noise floor and sigma (residual_noise.hpp)
// against the chi distribution of pure noise, a sample-by-sample propagation
// where form dominates, and a Monte Carlo of circle fits from no form at all
// to form far above the noise.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/circle_fit.hpp"
#include "trueaxis/core/residual_noise.hpp"
#include "trueaxis/core/rigidity_table.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

// ---- the A positioning error -----------------------------------------------------------

// Each sample coordinate moved by +-h, the table built again: the derivative of
// every pose's A error; the variance sum_k s_k^2 (d e / d x_k)^2 with s_k the
// per-axis noise of the sample's pose as its own circle fit estimates it
// (rms^2 n / (2n - 6), circle_fit.hpp convention 5), the figure the builder's
// sigmas rest on.
std::vector<double> a_error_sigma_by_samples(const std::vector<core::RigiditySample>& samples,
                                             const core::RigidityTable& nominal, core::RigidityBuilder& builder) {
  const std::size_t m = nominal.pose_count;
  std::vector<double> variance(m, 0.0);
  std::vector<core::RigiditySample> moved = samples;
  constexpr double kH = 1e-5;  // mm: 1 % of the noise, far above rounding
  for (std::size_t k = 0; k < samples.size(); ++k) {
    std::size_t pose = 0;
    while (std::abs(nominal.poses[pose].a_deg - samples[k].a_deg) > core::kPoseAToleranceDeg) ++pose;
    const core::RigidityPose& p = nominal.poses[pose];
    const double n = static_cast<double>(p.c_count);
    const double s2 = p.c_circle_rms_mm * p.c_circle_rms_mm * n / (2.0 * n - 6.0);
    for (int axis = 0; axis < 3; ++axis) {
      double side[2][core::kMaxAPoses];
      for (int sign = 0; sign < 2; ++sign) {
        moved[k].p_mm(axis) = samples[k].p_mm(axis) + (sign == 0 ? kH : -kH);
        REQUIRE(core::build_rigidity_table(moved.data(), moved.size(), {}, builder) == core::Status::kOk);
        for (std::size_t i = 0; i < m; ++i) side[sign][i] = builder.table().poses[i].a_error_rad;
      }
      moved[k].p_mm(axis) = samples[k].p_mm(axis);
      for (std::size_t i = 0; i < m; ++i) {
        const double d = (side[0][i] - side[1][i]) / (2.0 * kH);
        variance[i] += s2 * d * d;
      }
    }
  }
  std::vector<double> sigma(m);
  for (std::size_t i = 0; i < m; ++i) sigma[i] = std::sqrt(variance[i]);
  return sigma;
}

// The builder neglects the phase offset's correlation with the centre
// (rigidity_table.hpp convention 7), which the A error does not depend on, and
// takes its differences over a whole sigma; nothing else differs.
constexpr double kAgreement = 0.03;

struct ACase {
  const char* what;
  std::vector<double> a_deg;
  double ball_below_a_axis_mm;  // the C centres' distance from the A axis, nearly
  int c_per_pose;
  double c_step_deg;
};

}  // namespace

TEST_CASE("the A positioning error's sigma agrees with a propagation sample by sample, near singular set-ups too",
          "[rigidity][sigma]") {
  const ACase cases[] = {
      {"a usual set-up", {-60.0, -30.0, 0.0, 30.0, 60.0}, 100.0, 8, 45.0},
      {"C over 120 deg", {-90.0, -45.0, 0.0, 45.0}, 100.0, 9, 15.0},
      // The A error is the angle of a C centre about the A axis: 1 mm from it,
      // a micrometre of centre is 200"; the sigma must follow.
      {"C centres 1 mm from the A axis", {-60.0, -20.0, 0.0, 20.0, 60.0}, 1.0, 8, 45.0},
      // The A axis from an arc of 6 deg (just above the 5 deg minimum).
      {"an A arc of 6 deg", {0.0, 3.0, 6.0}, 100.0, 10, 36.0},
  };
  t::Rng rng(1707);
  auto builder = std::make_unique<core::RigidityBuilder>();
  auto probe = std::make_unique<core::RigidityBuilder>();
  double worst = 0.0;
  for (const ACase& c : cases) {
    for (int draw = 0; draw < 3; ++draw) {  // random C phases, noise and ball place
      t::Cradle cradle;
      cradle.ball_at_zero = cradle.a_point + t::Vec3L(7.0L + static_cast<long double>(rng.uniform(60.0, 140.0)),
                                                      static_cast<long double>(rng.uniform(-60.0, 60.0)),
                                                      -static_cast<long double>(c.ball_below_a_axis_mm));
      t::Plan plan;
      plan.a_deg = c.a_deg;
      plan.c_per_pose = c.c_per_pose;
      plan.c_step_deg = c.c_step_deg;
      plan.noise_mm = rng.uniform(0.0005, 0.002);
      const std::vector<core::RigiditySample> samples = t::measure(cradle, plan, rng);
      REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), {}, *builder) == core::Status::kOk);
      const core::RigidityTable& table = builder->table();
      const std::vector<double> oracle = a_error_sigma_by_samples(samples, table, *probe);
      for (std::size_t i = 0; i < table.pose_count; ++i) {
        INFO(c.what << ", draw " << draw << ", A = " << table.poses[i].a_deg << ": builder "
                    << table.poses[i].a_error_sigma_rad * core::kArcsecPerRad << "\", by samples "
                    << oracle[i] * core::kArcsecPerRad << "\"");
        if (i == table.reference) {
          CHECK(table.poses[i].a_error_sigma_rad == 0.0);  // by definition (convention 5)
          continue;
        }
        REQUIRE(oracle[i] > 0.0);
        const double ratio = table.poses[i].a_error_sigma_rad / oracle[i];
        worst = std::max(worst, std::abs(ratio - 1.0));
        CHECK(std::abs(ratio - 1.0) < kAgreement);
      }
    }
  }
  WARN("A positioning error sigma: builder against the sample-by-sample propagation, worst relative difference "
       << worst);
}

// ---- the C-circle RMS --------------------------------------------------------------------

namespace {

// A C circle with form the circle cannot follow: a three-lobe radial and a
// two-lobe axial wave of `form_mm` each, n points spread over a turn, each
// with per-axis Gaussian noise of `noise_mm` (0: none).
std::vector<Vec3> lobed_circle(std::size_t n, double form_mm, double noise_mm, t::Rng& rng) {
  const Vec3 centre(12.0, -3.0, 40.0);
  const Vec3 normal = Vec3(0.1, -0.2, 1.0).normalized();
  const Vec3 u = normal.cross(Vec3::UnitX()).normalized();
  const Vec3 v = normal.cross(u);
  const double phase = rng.uniform(0.0, 2.0 * core::kPi);
  std::vector<Vec3> points;
  for (std::size_t k = 0; k < n; ++k) {
    const double phi = phase + 2.0 * core::kPi * static_cast<double>(k) / static_cast<double>(n);
    const double radius = 150.0 + form_mm * std::cos(3.0 * phi + 0.4);
    Vec3 p = centre + radius * (std::cos(phi) * u + std::sin(phi) * v) + form_mm * std::cos(2.0 * phi + 1.1) * normal;
    if (noise_mm > 0.0) p += noise_mm * Vec3(rng.normal(), rng.normal(), rng.normal());
    points.push_back(p);
  }
  return points;
}

double rms_of_fit(const std::vector<Vec3>& points) {
  const core::Result<core::CircleFit> fit = core::fit_circle(points.data(), points.size());
  REQUIRE(fit.ok());
  return fit.value().rms_distance_mm;
}

core::ResidualNoise noise_of(double rms_mm, std::size_t n, double noise_mm) {
  return core::residual_rms_noise(rms_mm, n, core::circle_residual_dof(n), noise_mm);
}

}  // namespace

TEST_CASE("pure noise: the C-circle RMS's sigma is the spread of the chi distribution, its floor the RMS noise gives",
          "[rigidity][sigma]") {
  // SSR / s^2 of pure noise is chi-square with k = 2n - 6 degrees of freedom,
  // so RMS = s chi_k / sqrt(n): its spread is s sqrt(k - mu_k^2) / sqrt(n),
  // mu_k = sqrt(2) Gamma((k + 1) / 2) / Gamma(k / 2), and E[RMS^2] = k s^2 / n.
  // The sigma is first order about the expected RMS: 8 % wide of the exact
  // spread at 4 points (k = 2), within 1 % from 10 on.
  t::Rng rng(17);
  for (std::size_t n = 4; n <= core::kMaxCirclePoints; ++n) {
    const double s = rng.uniform(1e-4, 1e-2);
    const double k = static_cast<double>(core::circle_residual_dof(n));
    const double mu = std::sqrt(2.0) * std::exp(std::lgamma((k + 1.0) / 2.0) - std::lgamma(k / 2.0));
    const double exact_sigma = s * std::sqrt(k - mu * mu) / std::sqrt(static_cast<double>(n));
    const double floor = s * std::sqrt(k / static_cast<double>(n));
    const core::ResidualNoise got = noise_of(floor, n, s);
    INFO(n << " points: sigma " << got.sigma_mm << ", chi's spread " << exact_sigma);
    CHECK(got.floor_mm == Approx(floor).epsilon(1e-12));
    CHECK(got.sigma_mm == Approx(exact_sigma).epsilon(n < 10 ? 0.09 : 0.01));
    // An RMS below the floor (a lucky draw) keeps the sigma of the floor; an RMS of 0 gives no NaN.
    CHECK(noise_of(0.5 * floor, n, s).sigma_mm == Approx(got.sigma_mm).epsilon(1e-9));
    CHECK(noise_of(0.0, n, s).sigma_mm == Approx(got.sigma_mm).epsilon(1e-9));
  }
  // No stated noise: nothing to say, and never NaN.
  const core::ResidualNoise none = noise_of(0.003, 20, 0.0);
  CHECK(none.floor_mm == 0.0);
  CHECK(none.sigma_mm == 0.0);
  CHECK(noise_of(0.0, 0, 0.001).sigma_mm == 0.0);
}

TEST_CASE("form far above the noise: the C-circle RMS's sigma agrees with a propagation sample by sample",
          "[rigidity][sigma]") {
  // The RMS's derivative with respect to every coordinate, each moved by +-h
  // and the circle fitted again; its sigma to first order is s times that
  // gradient's length (s/sqrt(n) in theory: the residuals are orthogonal to
  // what the fit absorbs).
  t::Rng rng(29);
  double worst = 0.0;
  for (std::size_t n : {5u, 8u, 13u, 36u}) {
    const double form = rng.uniform(0.002, 0.02);
    const double s = 1e-3 * form;
    const std::vector<Vec3> points = lobed_circle(n, form, 0.0, rng);
    const double rms = rms_of_fit(points);
    std::vector<Vec3> moved = points;
    constexpr double kH = 1e-7;
    double gradient2 = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        moved[k](axis) = points[k](axis) + kH;
        const double plus = rms_of_fit(moved);
        moved[k](axis) = points[k](axis) - kH;
        const double minus = rms_of_fit(moved);
        moved[k](axis) = points[k](axis);
        const double d = (plus - minus) / (2.0 * kH);
        gradient2 += d * d;
      }
    }
    const double oracle = s * std::sqrt(gradient2);
    const core::ResidualNoise got = noise_of(rms, n, s);
    INFO(n << " points, form " << form << " mm, RMS " << rms << ": sigma " << got.sigma_mm << ", by samples "
           << oracle);
    CHECK(got.sigma_mm == Approx(oracle).epsilon(0.02));
    CHECK(got.floor_mm < 0.01 * rms);
    worst = std::max(worst, std::abs(got.sigma_mm / oracle - 1.0));
  }
  WARN("C-circle RMS sigma against the sample-by-sample propagation (form-dominated): worst relative difference "
       << worst);
}

TEST_CASE("the C-circle RMS's sigma matches the Monte-Carlo spread from no form to form far above the noise",
          "[rigidity][sigma][montecarlo]") {
  constexpr double kNoise = 0.001;
  constexpr int kRuns = 400;
  t::Rng rng(4242);
  for (std::size_t n : {8u, 36u}) {
    for (double form_in_noise : {0.0, 0.3, 1.0, 3.0, 30.0}) {
      const double form = form_in_noise * kNoise;
      double sum = 0.0, sum2 = 0.0, sigma2 = 0.0, floor = 0.0;
      int at_floor = 0;
      for (int run = 0; run < kRuns; ++run) {
        const double rms = rms_of_fit(lobed_circle(n, form, kNoise, rng));
        const core::ResidualNoise got = noise_of(rms, n, kNoise);
        sum += rms;
        sum2 += rms * rms;
        sigma2 += got.sigma_mm * got.sigma_mm;
        floor = got.floor_mm;
        at_floor += rms <= got.floor_mm + 3.0 * got.sigma_mm ? 1 : 0;
      }
      const double mean = sum / kRuns;
      const double observed = std::sqrt(std::max(0.0, sum2 / kRuns - mean * mean));
      const double predicted = std::sqrt(sigma2 / kRuns);
      INFO(n << " points, form " << form_in_noise << " x the noise: RMS " << mean << ", floor " << floor
             << ", sigma predicted " << predicted << ", observed " << observed << " (ratio " << predicted / observed
             << "), within 3 sigma of the floor " << at_floor << " of " << kRuns);
      CHECK(predicted / observed < 1.5);
      CHECK(predicted / observed > 1.0 / 1.5);
      if (form_in_noise == 0.0) {
        // Pure noise: the RMS sits at its floor and is flagged as noise.
        CHECK(mean == Approx(floor).epsilon(0.05));
        CHECK(at_floor >= kRuns * 99 / 100);
      }
      if (form_in_noise == 30.0) CHECK(at_floor == 0);  // real form is never taken for noise
      WARN(n << " points, form " << form_in_noise << " x noise: sigma predicted/observed " << predicted / observed);
    }
  }
}
