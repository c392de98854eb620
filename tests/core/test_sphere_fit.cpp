#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/sphere_fit.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

// Reference: the centre by variable projection in long double (the radius
// eliminated as the mean distance, Gauss-Newton on d_i - mean d with the
// Jacobian -u_i + mean u), a different formulation from the core's, started
// from the true centre.
t::Vec3L reference_centre(const std::vector<Vec3>& p, const t::Vec3L& start) {
  t::Vec3L c = start;
  const auto n = static_cast<long double>(p.size());
  for (int it = 0; it < 100; ++it) {
    std::vector<t::Vec3L> u(p.size());
    std::vector<long double> d(p.size());
    long double mean_d = 0;
    t::Vec3L mean_u = t::Vec3L::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const t::Vec3L v = p[i].cast<long double>() - c;
      d[i] = v.norm();
      u[i] = v / d[i];
      mean_d += d[i] / n;
      mean_u += u[i] / n;
    }
    t::Mat3L jtj = t::Mat3L::Zero();
    t::Vec3L jte = t::Vec3L::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const t::Vec3L j = -u[i] + mean_u;
      jtj += j * j.transpose();
      jte += j * (d[i] - mean_d);
    }
    const t::Vec3L step = -jtj.ldlt().solve(jte);
    c += step;
    if (step.norm() < 1e-16L) break;
  }
  return c;
}

// count touches of a ball (centre, radius) on a cap up to `cap_deg` from its
// pole `axis`.
std::vector<Vec3> touches(t::Rng& rng, const Vec3& centre, double radius, std::size_t count, double cap_deg,
                          const Vec3& axis) {
  const Vec3 u = axis.unitOrthogonal();
  const Vec3 v = axis.cross(u);
  const double cos_cap = std::cos(cap_deg * M_PI / 180.0);
  std::vector<Vec3> p;
  while (p.size() < count) {
    const double z = rng.uniform(cos_cap, 1.0);
    const double phi = rng.uniform(0.0, 2.0 * M_PI);
    const double s = std::sqrt(1.0 - z * z);
    p.push_back(centre + radius * (z * axis + s * std::cos(phi) * u + s * std::sin(phi) * v));
  }
  return p;
}

}  // namespace

TEST_CASE("recovers the exact sphere through touches on any cap", "[sphere]") {
  t::Rng rng(51);
  double worst_centre = 0.0;
  double worst_radius = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 centre(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-200, 200));
    const double radius = rng.uniform(1.0, 60.0);
    const auto count = static_cast<std::size_t>(rng.uniform(4.0, 32.999));
    const auto p = touches(rng, centre, radius, count, rng.uniform(60.0, 180.0), rng.unit_vector());
    const bool fixed = i % 3 == 0;
    const auto fit = core::fit_sphere(p.data(), p.size(), fixed ? radius : 0.0, 0.0005);
    REQUIRE(fit.ok());
    worst_centre = std::max(worst_centre, (fit.value().centre_mm - centre).norm() / radius);
    worst_radius = std::max(worst_radius, std::fabs(fit.value().radius_mm - radius) / radius);
  }
  CHECK(worst_centre < 1e-10);
  CHECK(worst_radius < 1e-10);
}

TEST_CASE("the noisy fit agrees with a long-double variable-projection fit", "[sphere]") {
  t::Rng rng(52);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 centre(rng.uniform(-300, 300), rng.uniform(-300, 300), rng.uniform(0, 200));
    const double radius = rng.uniform(5.0, 30.0);
    auto p = touches(rng, centre, radius, static_cast<std::size_t>(rng.uniform(5.0, 32.999)), rng.uniform(80.0, 180.0),
                     rng.unit_vector());
    for (auto& q : p) q += 0.002 * Vec3(rng.normal(), rng.normal(), rng.normal());
    const auto fit = core::fit_sphere(p.data(), p.size(), 0.0, 0.002);
    REQUIRE(fit.ok());
    const t::Vec3L ref = reference_centre(p, centre.cast<long double>());
    CHECK(static_cast<double>((fit.value().centre_mm.cast<long double>() - ref).norm()) < 1e-9);
  }
}

TEST_CASE("the centre's sigma follows the touches' noise (Monte Carlo)", "[sphere][sigma]") {
  // The LinuxCNC rigidity program's pattern (trueaxis_probe_ball.ngc): the pole
  // and four touches on the equator; and the pole and four 30 deg below it.
  // Noise along the normal; free and fixed radius.
  const Vec3 centre(120.0, -40.0, 75.0);
  const double radius = 13.0;  // a 25 mm ball and a 1 mm stylus tip
  const double sigma = 0.0005;
  for (const int pattern : {0, 1, 2, 3}) {
    const bool fixed = pattern % 2 == 1;
    const double below = pattern < 2 ? 0.0 : M_PI / 6;
    std::array<Vec3, 5> dirs = {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
    for (std::size_t k = 1; k < 5; ++k) dirs[k] = dirs[k] * std::cos(below) - Vec3(0, 0, std::sin(below));
    t::Rng rng(53 + static_cast<std::uint64_t>(pattern));
    const int runs = 4000;
    Vec3 sum_sq = Vec3::Zero();
    Vec3 reported = Vec3::Zero();
    for (int i = 0; i < runs; ++i) {
      std::array<Vec3, 5> p;
      for (std::size_t k = 0; k < 5; ++k) p[k] = centre + (radius + sigma * rng.normal()) * dirs[k];
      const auto fit = core::fit_sphere(p.data(), p.size(), fixed ? radius : 0.0, sigma);
      REQUIRE(fit.ok());
      const Vec3 e = fit.value().centre_mm - centre;
      sum_sq += e.cwiseProduct(e);
      reported = fit.value().centre_sigma_mm;
    }
    const Vec3 ratio = reported.cwiseQuotient((sum_sq / runs).cwiseSqrt());
    INFO("pattern " << pattern << ": reported / observed " << ratio(0) << " " << ratio(1) << " " << ratio(2));
    for (int a = 0; a < 3; ++a) {
      CHECK(ratio(a) > 0.93);
      CHECK(ratio(a) < 1.07);
    }
  }
}

TEST_CASE("degenerate touches are refused next to the boundary", "[sphere]") {
  // Four touches on one circle: no ball, whatever the radius.
  std::array<Vec3, 4> ring = {Vec3(10, 0, 5), Vec3(0, 10, 5), Vec3(-10, 0, 5), Vec3(0, -10, 5)};
  CHECK(core::fit_sphere(ring.data(), 4, 0.0, 0.001).status() == core::Status::kNotIdentifiable);
  CHECK(core::fit_sphere(ring.data(), 4, 12.0, 0.001).status() == core::Status::kNotIdentifiable);
  // Just below and above the coplanarity limit (smallest over largest singular value).
  auto lifted = [&](double ratio) {
    std::array<Vec3, 4> p = ring;
    // Singular values of the centred ring: sqrt(200) in X and Y; one point lifted by h
    // gives a smallest one of h sqrt(3) / 2.
    const double h = ratio * std::sqrt(200.0) * 2.0 / std::sqrt(3.0);
    p[0].z() += h;
    return p;
  };
  CHECK(core::fit_sphere(lifted(0.5 * core::kCollinearRatio).data(), 4, 0.0, 0.001).status() ==
        core::Status::kNotIdentifiable);
  CHECK(core::fit_sphere(lifted(20.0 * core::kCollinearRatio).data(), 4, 12.0, 0.001).ok());
  std::array<Vec3, 4> same = {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)};
  CHECK(core::fit_sphere(same.data(), 4, 0.0, 0.001).status() == core::Status::kPointsCoincident);
  CHECK(core::fit_sphere(ring.data(), 3, 0.0, 0.001).status() == core::Status::kTooFewPoints);
  std::array<Vec3, core::kMaxSpherePoints + 1> many;
  t::Rng rng(55);
  for (auto& p : many) p = 10.0 * rng.unit_vector();
  CHECK(core::fit_sphere(many.data(), many.size(), 0.0, 0.001).status() == core::Status::kTooManyPoints);
  CHECK(core::fit_sphere(many.data(), core::kMaxSpherePoints, 0.0, 0.001).ok());
  std::array<Vec3, 4> bad = {Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10),
                             Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)};
  CHECK(core::fit_sphere(bad.data(), 4, 0.0, 0.001).status() == core::Status::kNotFinite);
  std::array<Vec3, 4> tetra = {Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10), Vec3(-10, 0, 0)};
  CHECK(core::fit_sphere(tetra.data(), 4, -1.0, 0.001).status() == core::Status::kArgumentOutOfRange);
  CHECK(core::fit_sphere(tetra.data(), 4, 0.0, -0.001).status() == core::Status::kArgumentOutOfRange);
  const auto fit = core::fit_sphere(tetra.data(), 4, 0.0, 0.001);
  REQUIRE(fit.ok());
  CHECK(fit.value().centre_mm.norm() < 1e-12);
  CHECK(fit.value().radius_mm == Approx(10.0).epsilon(1e-14));
}

TEST_CASE("fitting a sphere does not allocate", "[sphere][alloc]") {
  std::array<Vec3, 6> p = {Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10), Vec3(-10, 0, 0), Vec3(0, -10, 0),
                           Vec3(7.0710678, 0, 7.0710678)};
  const trueaxis::test::AllocationScope scope;
  const auto fit = core::fit_sphere(p.data(), p.size(), 0.0, 0.001);
  CHECK(scope.count() == 0);
  CHECK(fit.ok());
}
