// Circle fit: exactness, orientation, phases, degenerate inputs, allocation.
// The statistics (stationarity, reference minimiser, Cramer-Rao) are in
// test_circle_fit_stats.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <limits>

#include "alloc_counter.hpp"
#include "circle_reference.hpp"
#include "trueaxis/core/circle_fit.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

using Phases = std::array<long double, core::kMaxCirclePoints + 1>;
using Points = std::array<Vec3, core::kMaxCirclePoints + 1>;

void sample(const t::TrueCircle& tc, const Phases& ph, std::size_t n, Points& p, t::Rng* rng = nullptr,
            double sigma = 0.0) {
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = tc.sample(ph[i]).cast<double>();
    if (rng != nullptr) p[i] += sigma * Vec3(rng->normal(), rng->normal(), rng->normal());
  }
}

double centre_error(const core::CircleFit& f, const t::TrueCircle& tc) {
  return static_cast<double>((f.centre_mm.cast<long double>() - tc.c).norm());
}
double normal_error_rad(const core::CircleFit& f, const t::Vec3L& n) {
  return static_cast<double>(t::angle_l(f.normal.cast<long double>(), n));
}

// A noiseless arc of `arc_deg` with n points on a fixed circle (radius 100 mm).
struct Arc {
  t::TrueCircle tc;
  Phases ph;
  Points p;
};
Arc make_arc(double arc_deg, std::size_t n, std::uint64_t seed = 5) {
  t::Rng rng(seed);
  Arc a;
  a.tc = t::random_circle(rng, 100.0L, 300.0);
  t::even_phases(a.ph, n, arc_deg, 0.3L);
  sample(a.tc, a.ph, n, a.p);
  return a;
}

}  // namespace

TEST_CASE("recovers noiseless circles in any orientation, size and arc", "[circle]") {
  t::Rng rng(2024);
  const double arcs[] = {360.0, 270.0, 180.0, 90.0, 60.0, 30.0, 20.0, 10.0};
  double worst_c = 0, worst_n = 0, worst_r = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const long double radius = std::pow(10.0L, static_cast<long double>(rng.uniform(0.0, 3.0)));
    const t::TrueCircle tc = t::random_circle(rng, radius, 5000.0);
    const double arc = arcs[static_cast<std::size_t>(trial) % 8];
    const std::size_t n = 3 + rng.next() % (core::kMaxCirclePoints - 2);
    Phases ph;
    t::even_phases(ph, n, arc, rng.uniform(-4.0, 4.0));
    Points p;
    sample(tc, ph, n, p);
    const auto fit = core::fit_circle(p.data(), n);
    REQUIRE(fit.ok());
    const double r = static_cast<double>(radius);
    worst_c = std::max(worst_c, centre_error(fit.value(), tc) / r);
    worst_n = std::max(worst_n, normal_error_rad(fit.value(), tc.n));  // also checks the orientation
    worst_r = std::max(worst_r, std::abs(fit.value().radius_mm - r) / r);
    // 360 deg minus the largest gap: a step between samples or the unsampled rest.
    const double step = arc >= 360.0 ? 360.0 / static_cast<double>(n) : arc / static_cast<double>(n - 1);
    const double expected_arc = 360.0 - std::max(step, 360.0 - arc);
    CHECK(fit.value().arc_deg == Approx(expected_arc).margin(1e-6));
    CHECK(fit.value().max_distance_mm < 1e-9 * r);
    CHECK(fit.value().count == n);
  }
  INFO("worst relative centre " << worst_c << ", normal " << worst_n << " rad, radius " << worst_r);
  CHECK(worst_c < 1e-9);
  CHECK(worst_n < 1e-9);
  CHECK(worst_r < 1e-9);
}

TEST_CASE("the in-plane basis and phases follow the stated conventions", "[circle]") {
  const Arc a = make_arc(360.0, 12);
  const auto fit = core::fit_circle(a.p.data(), 12);
  REQUIRE(fit.ok());
  const core::CircleFit& f = fit.value();
  SECTION("axis_u points at the first sample and (u, v, n) is right-handed") {
    CHECK((f.axis_u - (a.p[0] - f.centre_mm).normalized()).norm() < 1e-12);
    CHECK((f.axis_u.cross(f.axis_v) - f.normal).norm() < 1e-14);
  }
  SECTION("phases grow by the sample step, and circle_point_mm inverts them") {
    for (std::size_t i = 0; i < 12; ++i) {
      const double phase_deg = core::rad_to_deg(core::circle_phase_rad(f, a.p[i]));
      CHECK(phase_deg > -180.0);
      CHECK(phase_deg <= 180.0);
      CHECK(core::wrap_deg_180(phase_deg - 30.0 * static_cast<double>(i)) == Approx(0.0).margin(1e-9));
      CHECK((core::circle_point_mm(f, core::circle_phase_rad(f, a.p[i])) - a.p[i]).norm() < 1e-9);
    }
  }
}

TEST_CASE("orients the normal by sample order or by the commanded angles", "[circle]") {
  const std::size_t n = 8;
  Arc a = make_arc(140.0, n);
  SECTION("samples in increasing phase give the true normal, reversed the opposite one") {
    const auto fwd = core::fit_circle(a.p.data(), n);
    std::reverse(a.p.begin(), a.p.begin() + n);
    const auto rev = core::fit_circle(a.p.data(), n);
    REQUIRE(fwd.ok());
    REQUIRE(rev.ok());
    CHECK(normal_error_rad(fwd.value(), a.tc.n) < 1e-12);
    CHECK(normal_error_rad(rev.value(), -a.tc.n) < 1e-12);
  }
  SECTION("shuffled samples follow their angles, whichever way the angles run") {
    const std::size_t order[n] = {5, 2, 7, 0, 3, 6, 1, 4};
    Points shuffled;
    std::array<double, n> up;
    std::array<double, n> down;
    for (std::size_t k = 0; k < n; ++k) {
      shuffled[k] = a.p[order[k]];
      up[k] = 20.0 * static_cast<double>(order[k]) + 1000.0;  // 20 deg per step, any offset
      down[k] = -up[k];
    }
    core::CircleFitOptions o;
    o.angles_deg = up.data();
    const auto with_up = core::fit_circle(shuffled.data(), n, o);
    o.angles_deg = down.data();
    const auto with_down = core::fit_circle(shuffled.data(), n, o);
    REQUIRE(with_up.ok());
    REQUIRE(with_down.ok());
    CHECK(normal_error_rad(with_up.value(), a.tc.n) < 1e-12);
    CHECK(normal_error_rad(with_down.value(), -a.tc.n) < 1e-12);
  }
}

TEST_CASE("the phase offset points at the circle's commanded zero even when zero was not sampled", "[circle]") {
  t::Rng rng(77);
  for (int trial = 0; trial < 50; ++trial) {
    const t::TrueCircle tc = t::random_circle(rng, rng.uniform(20.0, 400.0), 500.0);
    const long double phase_at_zero = rng.uniform(-3.0, 3.0);
    // Commanded C at 30 + 60 k deg, shuffled, with 1 um of noise.
    const std::array<double, 6> angles{270.0, 30.0, 210.0, 90.0, 330.0, 150.0};
    Points p;
    for (std::size_t k = 0; k < angles.size(); ++k) {
      p[k] = tc.sample(phase_at_zero + t::deg_l(angles[k])).cast<double>() +
             0.001 * Vec3(rng.normal(), rng.normal(), rng.normal());
    }
    core::CircleFitOptions o;
    o.angles_deg = angles.data();
    const auto fit = core::fit_circle(p.data(), angles.size(), o);
    REQUIRE(fit.ok());
    const auto offset = core::circle_phase_offset_rad(fit.value(), p.data(), angles.data(), angles.size());
    REQUIRE(offset.ok());
    const Vec3 x_dir = core::circle_direction(fit.value(), offset.value().mean_rad);
    const t::Vec3L truth = std::cos(phase_at_zero) * tc.u + std::sin(phase_at_zero) * tc.v;
    CHECK(static_cast<double>(t::angle_l(x_dir.cast<long double>(), truth)) < 1e-4);
    CHECK(offset.value().resultant_length > 0.999999);
    CHECK(offset.value().standard_error_rad < 1e-4);
  }
}

TEST_CASE("the circular mean wraps at pi and reports its spread", "[circle]") {
  SECTION("angles either side of pi average to pi") {
    const std::array<double, 2> a{core::kPi - 0.1, -core::kPi + 0.1};
    const auto m = core::circular_mean_rad(a.data(), 2);
    REQUIRE(m.ok());
    CHECK(std::cos(m.value().mean_rad) == Approx(-1.0).margin(1e-15));
    CHECK(m.value().resultant_length == Approx(std::cos(0.1)).epsilon(1e-14));
  }
  SECTION("small offsets give the linear mean and its standard error") {
    const std::array<double, 5> a{0.001, -0.002, 0.0005, 0.003, 0.0};
    const auto m = core::circular_mean_rad(a.data(), a.size());
    REQUIRE(m.ok());
    double mean = 0, ss = 0;
    for (double x : a) mean += x / 5.0;
    for (double x : a) ss += (x - mean) * (x - mean);
    CHECK(m.value().mean_rad == Approx(mean).margin(1e-9));
    CHECK(m.value().standard_error_rad == Approx(std::sqrt(ss / 20.0)).epsilon(1e-5));
  }
  SECTION("opposed angles have no resultant") {
    const std::array<double, 4> a{0.0, 0.5 * core::kPi, core::kPi, 1.5 * core::kPi};
    const auto m = core::circular_mean_rad(a.data(), a.size());
    REQUIRE(m.ok());
    CHECK(m.value().resultant_length < 1e-15);
  }
  SECTION("rejects no angles and NaN") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(core::circular_mean_rad(&nan, 0).status() == Status::kTooFewPoints);
    CHECK(core::circular_mean_rad(&nan, 1).status() == Status::kNotFinite);
  }
}

TEST_CASE("three points give the exact circle and no residual scatter", "[circle]") {
  const Arc a = make_arc(120.0, 3);
  SECTION("from the data: dof 0, sigma 0, zero covariance") {
    const auto fit = core::fit_circle(a.p.data(), 3);
    REQUIRE(fit.ok());
    CHECK(fit.value().dof == 0);
    CHECK(fit.value().sigma_mm == 0.0);
    CHECK(fit.value().covariance.norm() == 0.0);
    CHECK(centre_error(fit.value(), a.tc) < 1e-10);
  }
  SECTION("with a known sigma: a real covariance") {
    core::CircleFitOptions o;
    o.point_sigma_mm = 0.01;
    const auto fit = core::fit_circle(a.p.data(), 3, o);
    REQUIRE(fit.ok());
    CHECK(fit.value().centre_sigma_mm > 0.001);
  }
  SECTION("a centre-sigma limit cannot be judged from three points") {
    core::CircleFitOptions o;
    o.max_centre_sigma_mm = 1.0;
    CHECK(core::fit_circle(a.p.data(), 3, o).status() == Status::kTooFewPoints);
  }
}

TEST_CASE("rejects point counts outside 3 to the capacity", "[circle]") {
  Arc a = make_arc(360.0, core::kMaxCirclePoints + 1);
  CHECK(core::fit_circle(a.p.data(), 0).status() == Status::kTooFewPoints);
  CHECK(core::fit_circle(a.p.data(), 2).status() == Status::kTooFewPoints);
  CHECK(core::fit_circle(a.p.data(), core::kMaxCirclePoints + 1).status() == Status::kTooManyPoints);
  CHECK(core::fit_circle(a.p.data(), core::kMaxCirclePoints).ok());
}

TEST_CASE("rejects non-finite inputs and negative options", "[circle]") {
  const Arc a = make_arc(90.0, 5);
  const double bad_values[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()};
  for (double bad : bad_values) {
    for (std::size_t k = 0; k < 15; ++k) {
      Points copy = a.p;
      copy[k / 3](static_cast<Eigen::Index>(k % 3)) = bad;
      CHECK(core::fit_circle(copy.data(), 5).status() == Status::kNotFinite);
    }
    std::array<double, 5> angles{0, 10, 20, 30, bad};
    core::CircleFitOptions o;
    o.angles_deg = angles.data();
    CHECK(core::fit_circle(a.p.data(), 5, o).status() == Status::kNotFinite);
    core::CircleFitOptions s;
    s.point_sigma_mm = bad;
    CHECK(core::fit_circle(a.p.data(), 5, s).status() == Status::kNotFinite);
  }
  core::CircleFitOptions neg;
  neg.max_centre_sigma_mm = -1.0;
  CHECK(core::fit_circle(a.p.data(), 5, neg).status() == Status::kArgumentOutOfRange);
}

TEST_CASE("a circle refuses coincident points on either side of the threshold", "[circle]") {
  const Vec3 base(1234.5, -678.9, 10.0);
  const std::array<Vec3, 4> same{base, base, base, base};
  CHECK(core::fit_circle(same.data(), 4).status() == Status::kPointsCoincident);
  const double d = core::kCircleCoincidentSpan_mm;
  const std::array<Vec3, 4> tiny{base, base + Vec3(0.5 * d, 0, 0), base + Vec3(0, 0.5 * d, 0),
                                 base + Vec3(0.5 * d, 0.5 * d, 0)};
  CHECK(core::fit_circle(tiny.data(), 4).status() == Status::kPointsCoincident);
  const std::array<Vec3, 4> small{base + Vec3(10 * d, 0, 0), base + Vec3(0, 10 * d, 0),
                                  base + Vec3(-10 * d, 0, 0), base + Vec3(0, -10 * d, 0)};
  const auto fit = core::fit_circle(small.data(), 4);
  REQUIRE(fit.ok());
  CHECK(fit.value().radius_mm == Approx(10 * d).epsilon(1e-6));
}

TEST_CASE("a circle refuses collinear and nearly collinear points", "[circle]") {
  const Vec3 a(10, 20, 30);
  const Vec3 dir = Vec3(3, -1, 2).normalized();
  const Vec3 off = dir.unitOrthogonal();
  const double len = 200.0;
  std::array<Vec3, 5> line;
  for (std::size_t k = 0; k < 5; ++k) line[k] = a + len * 0.25 * static_cast<double>(k) * dir;
  CHECK(core::fit_circle(line.data(), 5).status() == Status::kPointsCollinear);
  // The middle point pushed aside: the ratio of the in-plane spreads is
  // sqrt(4/5) bump / (sqrt(10)/4 len) = 1.13 bump / len; a factor 2 either side.
  auto bumped = line;
  bumped[2] += 0.5 / 1.13 * core::kCircleCollinearRatio * len * off;
  CHECK(core::fit_circle(bumped.data(), 5).status() == Status::kPointsCollinear);
  bumped = line;
  bumped[2] += 2.0 / 1.13 * core::kCircleCollinearRatio * len * off;
  // No longer collinear: an arc of about 0.1 deg, refused as short.
  CHECK(core::fit_circle(bumped.data(), 5).status() == Status::kArcTooShort);
}

TEST_CASE("refuses arcs shorter than the minimum arc, on either side of it", "[circle]") {
  const double limit = core::kDefaultMinArcDeg;
  const Arc below = make_arc(0.98 * limit, 6);
  const Arc above = make_arc(1.02 * limit, 6);
  CHECK(core::fit_circle(below.p.data(), 6).status() == Status::kArcTooShort);
  CHECK(core::fit_circle(above.p.data(), 6).ok());
  core::CircleFitOptions o;
  o.min_arc_deg = 45.0;
  CHECK(core::fit_circle(make_arc(44.9, 6).p.data(), 6, o).status() == Status::kArcTooShort);
  CHECK(core::fit_circle(make_arc(45.1, 6).p.data(), 6, o).ok());
  o.min_arc_deg = 0.0;
  CHECK(core::fit_circle(make_arc(0.5, 6).p.data(), 6, o).ok());
}

TEST_CASE("refuses a centre less certain than the caller's limit, on either side of it", "[circle]") {
  const Arc a = make_arc(30.0, 8);
  core::CircleFitOptions o;
  o.point_sigma_mm = 0.002;
  const auto free_fit = core::fit_circle(a.p.data(), 8, o);
  REQUIRE(free_fit.ok());
  const double s = free_fit.value().centre_sigma_mm;
  // For a 30 deg arc of 100 mm the centre is far less certain than the points.
  CHECK(s > 10.0 * o.point_sigma_mm);
  o.max_centre_sigma_mm = 0.99 * s;
  CHECK(core::fit_circle(a.p.data(), 8, o).status() == Status::kArcTooShort);
  o.max_centre_sigma_mm = 1.01 * s;
  CHECK(core::fit_circle(a.p.data(), 8, o).ok());
}

TEST_CASE("fitting a circle does not allocate", "[circle][alloc]") {
  const Arc a = make_arc(360.0, core::kMaxCirclePoints);
  std::array<double, core::kMaxCirclePoints> angles;
  for (std::size_t k = 0; k < angles.size(); ++k) angles[k] = static_cast<double>(k);
  core::CircleFitOptions o;
  o.angles_deg = angles.data();
  const t::AllocationScope scope;
  const auto fit = core::fit_circle(a.p.data(), core::kMaxCirclePoints, o);
  const auto offset = core::circle_phase_offset_rad(fit.value(), a.p.data(), angles.data(), angles.size());
  CHECK(scope.count() == 0);
  CHECK(fit.ok());
  CHECK(offset.ok());
}
