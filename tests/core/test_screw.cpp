// Plucker lines and the screw error against independent computations in long
// double: pairs built from a known common perpendicular (feet, axis, offset and
// angle chosen first, the lines made from them), axis-aligned pairs whose feet
// have a closed form, Kahan's angle 2 atan(|a - b| / |a + b|), and points moved
// and turned one by one.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/screw.hpp"
#include "trueaxis/core/so3.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::PluckerLine;
using core::Vec3;
using t::Vec3L;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

Vec3L ld(const Vec3& v) { return v.cast<long double>(); }
Vec3 dbl(const Vec3L& v) { return v.cast<double>(); }
double dbl(long double x) { return static_cast<double>(x); }

PluckerLine line_through(const Vec3& p, const Vec3& d) {
  const auto r = core::plucker_from_point(p, d);
  REQUIRE(r.ok());
  return r.value();
}

// Kahan's angle 2 atan(|a |b| - b |a|| / |a |b| + b |a||) between two directions
// given in double, in long double, accurate relative to the angle even at 1e-11:
// a - b is exact, and |b| - |a| = (a - b) . (a + b) / (|a| + |b|) keeps its
// cancellation out of the rounding of the norms.
long double kahan_angle_l(const Vec3& a, const Vec3& b) {
  const Vec3L al = ld(a), bl = ld(b);
  const Vec3L diff = al - bl;
  const long double na = al.norm(), nb = bl.norm();
  const long double na_minus_nb = diff.dot(al + bl) / (na + nb);
  return 2.0L * std::atan2((diff * nb - bl * na_minus_nb).norm(), (al * nb + bl * na).norm());
}

Vec3 random_point(t::Rng& rng, double span) {
  return {rng.uniform(-span, span), rng.uniform(-span, span), rng.uniform(-span, span)};
}

core::Rigid3 random_motion(t::Rng& rng, double span) {
  return {core::so3_exp(rng.uniform(0.0, 3.1) * rng.unit_vector()), random_point(rng, span)};
}

// A pair made from its screw: foot f1 and unit u1 of the ideal line, the axis n
// perpendicular to u1, the actual line through f2 = f1 + offset n along u2 = u1
// turned by theta about n. Each line is given through a point away from its foot.
struct Built {
  PluckerLine ideal, actual;
  long double theta = 0, offset = 0;
  Vec3L axis, f1, f2;
  long double size = 0;  // the coordinates' size, mm
};

Built build(t::Rng& rng, long double theta, long double offset, double span) {
  Built b;
  const Vec3L u1 = ld(rng.unit_vector());
  b.axis = u1.cross(ld(rng.unit_vector())).normalized();
  const Vec3L u2 = std::cos(theta) * u1 + std::sin(theta) * b.axis.cross(u1);
  b.f1 = ld(random_point(rng, span));
  b.f2 = b.f1 + offset * b.axis;
  const long double a = rng.uniform(-span, span);
  const long double c = rng.uniform(-span, span);
  b.ideal = line_through(dbl(Vec3L(b.f1 + a * u1)), dbl(u1));
  b.actual = line_through(dbl(Vec3L(b.f2 + c * u2)), dbl(u2));
  b.theta = theta;
  b.offset = offset;
  b.size = b.f1.norm() + std::abs(a) + std::abs(c) + std::abs(offset);
  return b;
}

long double log_uniform(t::Rng& rng, double lo, double hi) {
  return std::exp(static_cast<long double>(rng.uniform(std::log(lo), std::log(hi))));
}

}  // namespace

TEST_CASE("recovers theta, offset, axis and feet of 100,000 pairs built from their screw", "[screw]") {
  t::Rng rng(7001);
  double worst_theta = 0, worst_angle = 0, worst_offset = 0, worst_axis = 0, worst_feet = 0, worst_recip = 0;
  double worst_offset_10m_mm = 0, worst_perpendicular = 0;
  int refused = 0, parallel = 0, distance_not_abs = 0;
  for (int i = 0; i < 100000; ++i) {
    const int kind = i % 20;
    long double theta = rng.uniform(1e-300, core::kPi);
    if (kind >= 14 && kind < 17) theta = log_uniform(rng, 1e-11, 1e-2);
    if (kind >= 17) theta = t::kPiL - log_uniform(rng, 1e-11, 1e-2);
    const long double offset = kind == 0 ? 0.0L : rng.sign() * log_uniform(rng, 1e-6, 1e2);
    const double span = i % 2 == 0 ? 1e3 : 1e4;
    const Built b = build(rng, theta, offset, span);
    const auto r = core::screw_error(b.ideal, b.actual);
    if (!r.ok()) {
      ++refused;
      continue;
    }
    const core::ScrewError& e = r.value();
    parallel += e.parallel ? 1 : 0;
    distance_not_abs += e.distance_mm == std::abs(e.offset_mm) ? 0 : 1;
    const double unit_mm = kEps * dbl(b.size);
    const double s = dbl(std::sin(theta));
    worst_theta = std::max(worst_theta, dbl(std::abs(e.theta_rad - theta)) / kEps);
    worst_angle = std::max(
        worst_angle,
        dbl(std::abs(e.theta_rad - kahan_angle_l(b.ideal.direction, b.actual.direction)) / (kEps * theta)));
    const double offset_error_mm = dbl(std::abs(e.offset_mm - offset));
    // Rounding the directions turns the axis by eps / sin(theta), which changes
    // the offset of the rounded lines by offset (eps / sin(theta))^2 / 2.
    const double turn = kEps / s;
    worst_offset = std::max(worst_offset, offset_error_mm / (unit_mm + dbl(std::abs(offset)) * turn * turn));
    if (span == 1e4 && std::abs(offset) <= 1e-2L) {
      worst_offset_10m_mm = std::max(worst_offset_10m_mm, offset_error_mm);
    }
    worst_axis = std::max(worst_axis, dbl((ld(e.axis) - b.axis).norm()) * s / kEps);
    // Perpendicular to both directions as given, to the ulp (a plain u1 x u2 is
    // off by eps / sin(theta) here).
    const long double off_1 = std::abs(ld(e.axis).dot(ld(b.ideal.direction)));
    const long double off_2 = std::abs(ld(e.axis).dot(ld(b.actual.direction)));
    worst_perpendicular = std::max(worst_perpendicular, dbl(std::max(off_1, off_2)) / kEps);
    const double feet_tol = unit_mm / s + kEps * dbl(std::abs(offset)) / (s * s);
    worst_feet = std::max(worst_feet, dbl(std::max((ld(e.foot_1_mm) - b.f1).norm(), (ld(e.foot_2_mm) - b.f2).norm())) /
                                          feet_tol);
    // The reciprocal product of the lines as given, against -offset sin(theta).
    const long double recip = ld(b.ideal.direction).dot(ld(b.actual.moment_mm)) +
                              ld(b.actual.direction).dot(ld(b.ideal.moment_mm));
    const double m_size = b.ideal.moment_mm.norm() + b.actual.moment_mm.norm() + 1.0;
    worst_recip = std::max(worst_recip,
                           dbl(std::abs(recip + e.offset_mm * std::sin(static_cast<long double>(e.theta_rad)))) /
                               (kEps * m_size));
  }
  INFO("theta " << worst_theta << " eps, against Kahan " << worst_angle << " eps theta, offset " << worst_offset
                << " of tolerance (10 m, up to 10 um: " << worst_offset_10m_mm << " mm), axis " << worst_axis
                << " eps / sin (perpendicular to " << worst_perpendicular << " eps), feet " << worst_feet
                << " of tolerance, reciprocal " << worst_recip << " eps |m|");
  CHECK(refused == 0);
  CHECK(parallel == 0);
  CHECK(distance_not_abs == 0);
  CHECK(worst_theta < 4.0);
  CHECK(worst_angle < 4.0);
  CHECK(worst_offset < 6.0);
  CHECK(worst_offset_10m_mm < 3e-11);
  CHECK(worst_axis < 4.0);
  CHECK(worst_perpendicular < 2.5);
  CHECK(worst_feet < 6.0);
  CHECK(worst_recip < 4.0);
}

TEST_CASE("axis-aligned pairs match their closed form on both sides of the parallel threshold", "[screw]") {
  // Ideal: along +x through p1. Actual: along (sigma, s, 0) through p2. Exact in
  // double up to s = 1e-8, so the code's |u1 x u2| is s itself and the branch is
  // chosen to the ulp. Non-parallel: axis +z, offset z2 - z1, feet where the
  // projections on z = 0 cross; parallel: foot_1 = (0, y1, z1), the point of the
  // ideal line nearest the origin, foot_2 the point of the actual line nearest it.
  const double below = std::nextafter(core::kParallelSin, 0.0);
  const double above = std::nextafter(core::kParallelSin, 1.0);
  const double sins[] = {0.0,   1e-15, below, core::kParallelSin, above, 1e-12 * (1 - 1e-3), 1e-12 * (1 + 1e-3),
                         1e-9,  1e-6,  1e-3};
  struct Geometry {
    Vec3 p1, p2;
  };
  const Geometry geometries[] = {
      {{5.0, 0.0, 0.0}, {0.0, 0.001, 0.002}},                                  // near the origin, 1-2 um apart
      {{1e4, 1e4, -3e3}, {-2e3, 1e4 + 0.001, -3e3 + 0.0005}},                  // 10 m out, 1 um and 0.5 um
      {{-7e3, 2.5e3, 8e3}, {4e3, 2.5e3, 8e3}},                                 // parallel: coincident
  };
  for (const Geometry& g : geometries) {
    for (const double s : sins) {
      for (const double sigma : {1.0, -1.0}) {
        CAPTURE(g.p1.transpose(), g.p2.transpose(), s, sigma);
        const PluckerLine l1 = line_through(g.p1, Vec3::UnitX());
        const PluckerLine l2 = line_through(g.p2, Vec3(sigma, s, 0.0));
        const auto r = core::screw_error(l1, l2);
        REQUIRE(r.ok());
        const core::ScrewError& e = r.value();
        const Vec3L p1 = ld(g.p1), p2 = ld(g.p2);
        const Vec3L u2 = Vec3L(sigma, s, 0).normalized();
        const long double theta = std::atan2(static_cast<long double>(s), static_cast<long double>(sigma));
        const double size = g.p1.norm() + g.p2.norm();
        CHECK(std::abs(e.theta_rad - theta) <= 4 * kEps * theta);
        CHECK(e.parallel == (s < core::kParallelSin));
        CHECK(e.distance_mm == std::abs(e.offset_mm));
        Vec3L f1, f2;
        if (e.parallel) {
          f1 = Vec3L(0, p1.y(), p1.z());
          f2 = p2 + (f1 - p2).dot(u2) * u2;
          const long double d = (f2 - f1).norm();
          CHECK(std::abs(e.distance_mm - d) <= 8 * kEps * size);
          CHECK(e.offset_mm >= 0.0);
          if (d > 0) CHECK(dbl((ld(e.axis) - (f2 - f1) / d).norm()) <= 8 * kEps * size / dbl(d));
        } else {
          const long double x = p2.x() + sigma * (p1.y() - p2.y()) / s;
          f1 = Vec3L(x, p1.y(), p1.z());
          f2 = Vec3L(x, p1.y(), p2.z());
          CHECK(e.axis == Vec3::UnitZ());
          CHECK(std::abs(e.offset_mm - (p2.z() - p1.z())) <= 8 * kEps * size);
        }
        CHECK(std::abs(e.axis.norm() - 1.0) <= 2 * kEps);
        // Parallel branch: perpendicular to u2, so off u1 by up to s.
        CHECK(std::abs(e.axis.dot(l1.direction)) <= 2 * kEps + s);
        const double feet_tol = 8 * kEps * size * (1.0 + (e.parallel ? 0.0 : 1.0 / s));
        CHECK(dbl((ld(e.foot_1_mm) - f1).norm()) <= feet_tol);
        CHECK(dbl((ld(e.foot_2_mm) - f2).norm()) <= feet_tol);
      }
    }
  }
  SECTION("the threshold's two sides give the two distances, 10 m out") {
    const PluckerLine l1 = line_through(geometries[1].p1, Vec3::UnitX());
    const auto at = [&](double s) { return core::screw_error(l1, line_through(geometries[1].p2, Vec3(1, s, 0))); };
    const Vec3 gap = geometries[1].p2 - geometries[1].p1;
    CHECK(at(below).value().parallel);
    // The actual line's point nearest foot_1 = (0, y1, z1) is at x = 0, s x 2 m further along y.
    CHECK(at(below).value().distance_mm == Approx(std::hypot(gap.y() + below * 2e3, gap.z())).epsilon(1e-9));
    CHECK_FALSE(at(core::kParallelSin).value().parallel);
    CHECK(at(core::kParallelSin).value().distance_mm == Approx(gap.z()).epsilon(1e-9));
    CHECK(at(core::kParallelSin).value().foot_1_mm.x() ==
          Approx(geometries[1].p2.x() - gap.y() / core::kParallelSin).epsilon(1e-8));
  }
}

TEST_CASE("parallel and antiparallel lines in any orientation: theta exactly 0 or pi, their distance", "[screw]") {
  t::Rng rng(7002);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 u = rng.unit_vector();
    const double sigma = i % 2 == 0 ? 1.0 : -1.0;
    const double span = i % 4 < 2 ? 1e3 : 1e4;
    const Vec3L n = ld(u).cross(ld(rng.unit_vector())).normalized();
    const long double d = i % 10 == 0 ? 0.0L : log_uniform(rng, 1e-6, 1e2);
    const Vec3 p1 = random_point(rng, span);
    const Vec3 p2 = dbl(Vec3L(ld(p1) + d * n + rng.uniform(-span, span) * ld(u)));
    const PluckerLine l1 = line_through(p1, u);
    const PluckerLine l2 = line_through(p2, sigma * u);
    const auto r = core::screw_error(l1, l2);
    REQUIRE(r.ok());
    const core::ScrewError& e = r.value();
    const double size = 4 * span;
    CHECK(e.parallel);
    CHECK(e.theta_rad == (sigma > 0 ? 0.0 : core::kPi));
    CHECK(std::abs(e.distance_mm - dbl(d)) <= 8 * kEps * size);
    CHECK(e.offset_mm == e.distance_mm);
    // foot_1 is the ideal line's point nearest the origin; the feet are d apart along the axis.
    const Vec3L u_l = ld(u).normalized();
    CHECK(dbl((ld(e.foot_1_mm) - (ld(p1) - ld(p1).dot(u_l) * u_l)).norm()) <= 8 * kEps * size);
    CHECK(dbl((ld(e.foot_2_mm - e.foot_1_mm) - ld(e.axis) * static_cast<long double>(e.distance_mm)).norm()) <=
          8 * kEps * size);
    CHECK(core::line_distance_mm(l2, e.foot_2_mm) <= 8 * kEps * size);
    CHECK(std::abs(e.axis.norm() - 1.0) <= 2 * kEps);
    if (d > 1e-3) CHECK(std::abs(e.axis.dot(u)) <= 8 * kEps * size / dbl(d));
  }
}

TEST_CASE("coincident lines have distance 0, one foot and an axis perpendicular to them", "[screw]") {
  t::Rng rng(7003);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 u = rng.unit_vector();
    const Vec3 p = random_point(rng, 1e4);
    const PluckerLine l1 = line_through(p, u);
    const PluckerLine reversed{-l1.direction, -l1.moment_mm};
    const PluckerLine elsewhere = line_through(Vec3(p + rng.uniform(-1e4, 1e4) * u), u);
    for (const PluckerLine& l2 : {l1, reversed, elsewhere}) {
      const auto r = core::screw_error(l1, l2);
      REQUIRE(r.ok());
      const core::ScrewError& e = r.value();
      CHECK(e.parallel);
      CHECK(std::abs(e.axis.norm() - 1.0) <= 2 * kEps);
      CHECK(std::abs(e.axis.dot(u)) <= 8 * kEps);
      CHECK(e.distance_mm <= 16 * kEps * 3e4);
      CHECK((e.foot_2_mm - e.foot_1_mm).norm() <= 16 * kEps * 3e4);
    }
    const core::ScrewError same = core::screw_error(l1, l1).value();
    CHECK(same.distance_mm == 0.0);
    CHECK(same.theta_rad == 0.0);
    CHECK(core::screw_error(l1, reversed).value().distance_mm == 0.0);
    CHECK(core::screw_error(l1, reversed).value().theta_rad == core::kPi);
  }
}

TEST_CASE("intersecting lines have distance 0 and meet at the feet", "[screw]") {
  t::Rng rng(7004);
  for (const long double theta : {1e-9L, 1e-6L, 0.3L, 1.5L, 3.0L, t::kPiL - 1e-6L, t::kPiL - 1e-9L}) {
    for (int i = 0; i < 1000; ++i) {
      const Built b = build(rng, theta, 0.0L, 1e4);
      const core::ScrewError e = core::screw_error(b.ideal, b.actual).value();
      const double s = dbl(std::sin(theta));
      CAPTURE(dbl(theta));
      CHECK_FALSE(e.parallel);
      CHECK(e.distance_mm <= 8 * kEps * dbl(b.size));
      CHECK(dbl((ld(e.foot_1_mm) - b.f1).norm()) <= 8 * kEps * dbl(b.size) / s);
      CHECK(dbl((ld(e.foot_2_mm) - b.f1).norm()) <= 8 * kEps * dbl(b.size) / s);
    }
  }
}

TEST_CASE("the screw error turns and moves with the lines, swaps and reverses as stated", "[screw]") {
  t::Rng rng(7005);
  for (int i = 0; i < 10000; ++i) {
    const Built b = build(rng, rng.uniform(0.01, 3.13), rng.sign() * log_uniform(rng, 1e-6, 1e2), 1e3);
    const core::Rigid3 a_T_b = random_motion(rng, 1e4);
    const core::ScrewError e = core::screw_error(b.ideal, b.actual).value();
    const core::ScrewError moved =
        core::screw_error(core::transform_line(a_T_b, b.ideal), core::transform_line(a_T_b, b.actual)).value();
    const double tol = 64 * kEps * (dbl(b.size) + 1e4) / std::sin(e.theta_rad);
    CHECK(moved.theta_rad == Approx(e.theta_rad).margin(16 * kEps));
    CHECK(moved.offset_mm == Approx(e.offset_mm).margin(64 * kEps * (dbl(b.size) + 1e4)));
    CHECK((moved.axis - a_T_b.R * e.axis).norm() <= 16 * kEps / std::sin(e.theta_rad));
    CHECK((moved.foot_1_mm - core::apply_point(a_T_b, e.foot_1_mm)).norm() <= tol);
    CHECK((moved.foot_2_mm - core::apply_point(a_T_b, e.foot_2_mm)).norm() <= tol);
    // From the actual line to the ideal one: the same angle and offset about -axis.
    const core::ScrewError swapped = core::screw_error(b.actual, b.ideal).value();
    CHECK(swapped.theta_rad == Approx(e.theta_rad).margin(2 * kEps));
    CHECK(swapped.offset_mm == Approx(e.offset_mm).margin(8 * kEps * dbl(b.size)));
    CHECK((swapped.axis + e.axis).norm() <= 4 * kEps / std::sin(e.theta_rad));
    CHECK((swapped.foot_1_mm - e.foot_2_mm).norm() <= tol);
    // The actual line the other way round: pi - theta about -axis, offset negated.
    const PluckerLine reversed{-b.actual.direction, -b.actual.moment_mm};
    const core::ScrewError flipped = core::screw_error(b.ideal, reversed).value();
    CHECK(flipped.theta_rad == Approx(core::kPi - e.theta_rad).margin(4 * kEps));
    CHECK(flipped.offset_mm == Approx(-e.offset_mm).margin(8 * kEps * dbl(b.size)));
    CHECK((flipped.axis + e.axis).norm() <= 4 * kEps / std::sin(e.theta_rad));
  }
}

TEST_CASE("plucker_from_point gives the unit direction, the moment p x u and the line's points", "[screw]") {
  t::Rng rng(7006);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 p = random_point(rng, 1e4);
    const Vec3 d = std::exp(rng.uniform(-20.0, 20.0)) * rng.unit_vector();
    const PluckerLine l = line_through(p, d);
    const Vec3L u = ld(d).normalized();
    const Vec3L m = ld(p).cross(u);
    CHECK(dbl((ld(l.direction) - u).norm()) <= 2 * kEps);
    CHECK(dbl((ld(l.moment_mm) - m).norm()) <= 4 * kEps * p.norm());
    CHECK(std::abs(l.direction.dot(l.moment_mm)) <= 2 * kEps * l.moment_mm.norm());
    // Nearest point to the origin: the foot of the perpendicular from it.
    const Vec3L nearest = ld(p) - ld(p).dot(u) * u;
    CHECK(dbl((ld(core::closest_point_to_origin(l)) - nearest).norm()) <= 4 * kEps * p.norm());
    const Vec3 q = random_point(rng, 1e4);
    CHECK(core::line_distance_mm(l, q) ==
          Approx(dbl((ld(q) - ld(p)).cross(u).norm())).margin(8 * kEps * (p.norm() + q.norm())));
    CHECK(core::line_distance_mm(l, dbl(Vec3L(ld(p) + 1234.5L * u))) <= 8 * kEps * (p.norm() + 1234.5));
  }
}

TEST_CASE("plucker_from_point and screw_error refuse what is not a line", "[screw]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(core::plucker_from_point(Vec3(nan, 0, 0), Vec3::UnitX()).status() == core::Status::kNotFinite);
  CHECK(core::plucker_from_point(Vec3::Zero(), Vec3(0, inf, 0)).status() == core::Status::kNotFinite);
  CHECK(core::plucker_from_point(Vec3::Zero(), Vec3::Zero()).status() == core::Status::kArgumentOutOfRange);
  CHECK(core::plucker_from_point(Vec3(1.5e308, -1.5e308, 0), Vec3(1, 1, 0)).status() ==
        core::Status::kArgumentOutOfRange);
  // Directions too short or too long for a plain norm.
  const auto tiny = core::plucker_from_point(Vec3(1, 2, 3), Vec3(1e-300, 0, -1e-300));
  const auto huge_direction = core::plucker_from_point(Vec3(1, 2, 3), Vec3(3e300, 3e300, 3e300));
  REQUIRE(tiny.ok());
  REQUIRE(huge_direction.ok());
  CHECK((tiny.value().direction - Vec3(1, 0, -1) / std::sqrt(2.0)).norm() <= 2 * kEps);
  CHECK((huge_direction.value().direction - Vec3(1, 1, 1) / std::sqrt(3.0)).norm() <= 2 * kEps);

  const PluckerLine good = line_through(Vec3(1, 2, 3), Vec3(0, 1, 1));
  const PluckerLine not_finite{good.direction, Vec3(0, nan, 0)};
  const PluckerLine not_unit{2.0 * good.direction, good.moment_mm};
  const PluckerLine zero{Vec3::Zero(), Vec3::Zero()};
  const PluckerLine slightly_long{Vec3(1, 1e-6, 0), Vec3::Zero()};  // |u|^2 - 1 = 1e-12
  CHECK(core::screw_error(not_finite, good).status() == core::Status::kNotFinite);
  CHECK(core::screw_error(good, not_finite).status() == core::Status::kNotFinite);
  CHECK(core::screw_error(not_unit, good).status() == core::Status::kArgumentOutOfRange);
  CHECK(core::screw_error(good, zero).status() == core::Status::kArgumentOutOfRange);
  CHECK(core::screw_error(good, slightly_long).status() == core::Status::kArgumentOutOfRange);
  CHECK(core::screw_error(good, line_through(Vec3::Zero(), slightly_long.direction)).ok());
  const PluckerLine huge = line_through(Vec3(0, 1e305, 0), Vec3::UnitX());
  CHECK(core::screw_error(huge, line_through(Vec3(0, -1e305, 1), Vec3(1, 1e-6, 0))).status() ==
        core::Status::kArgumentOutOfRange);
}

TEST_CASE("transform_line and its 6x6 matrix move a line as they move its points", "[screw]") {
  t::Rng rng(7007);
  for (int i = 0; i < 10000; ++i) {
    const Vec3 p = random_point(rng, 1e4);
    const PluckerLine l = line_through(p, rng.unit_vector());
    const core::Rigid3 a_T_b = random_motion(rng, 1e4);
    // Two points of the line, moved in long double, and the line through them.
    const t::Mat3L R = a_T_b.R.cast<long double>();
    const Vec3L q0 = R * ld(p) + ld(a_T_b.t);
    const Vec3L q1 = R * (ld(p) + 100.0L * ld(l.direction)) + ld(a_T_b.t);
    const Vec3L u = (q1 - q0).normalized();
    const Vec3L m = q0.cross(u);
    const PluckerLine moved = core::transform_line(a_T_b, l);
    const double tol = 16 * kEps * (p.norm() + a_T_b.t.norm());
    CHECK(dbl((ld(moved.direction) - u).norm()) <= 4 * kEps);
    CHECK(dbl((ld(moved.moment_mm) - m).norm()) <= tol);
    const core::Vec6 v = core::line_transform_matrix(a_T_b) * core::plucker_vector(l);
    CHECK((v - core::plucker_vector(moved)).norm() <= tol);
    const core::Rigid3 b_T_c = random_motion(rng, 1e4);
    const PluckerLine twice = core::transform_line(core::compose(a_T_b, b_T_c), l);
    const PluckerLine in_turn = core::transform_line(a_T_b, core::transform_line(b_T_c, l));
    CHECK((core::plucker_vector(twice) - core::plucker_vector(in_turn)).norm() <= 4 * tol);
    // The inverse brings it back.
    const PluckerLine back = core::transform_line(core::inverse(a_T_b), moved);
    CHECK((core::plucker_vector(back) - core::plucker_vector(l)).norm() <= 4 * tol);
  }
}

TEST_CASE("rotation_about_line turns points about an axis that misses the origin", "[screw]") {
  t::Rng rng(7008);
  for (int i = 0; i < 10000; ++i) {
    const PluckerLine axis = line_through(random_point(rng, 1e3), rng.unit_vector());
    const double phi = rng.uniform(-7.0, 7.0);
    const core::Rigid3 motion = core::rotation_about_line(axis, phi);
    const Vec3L c = ld(core::closest_point_to_origin(axis));
    const t::Mat3L R = t::rodrigues_l(static_cast<long double>(phi) * ld(axis.direction));
    const Vec3 q = random_point(rng, 1e3);
    const double tol = 16 * kEps * (2e3 + q.norm());
    CHECK(dbl((ld(core::apply_point(motion, q)) - (c + R * (ld(q) - c))).norm()) <= tol);
    const Vec3 on_axis = core::closest_point_to_origin(axis) + rng.uniform(-1e3, 1e3) * axis.direction;
    CHECK((core::apply_point(motion, on_axis) - on_axis).norm() <= tol);
    // A line parallel to the axis at radius r stays parallel and moves 2 r sin(phi / 2).
    const Vec3 off = core::closest_point_to_origin(axis) + 5.0 * axis.direction.unitOrthogonal();
    const PluckerLine tool = line_through(off, axis.direction);
    const core::ScrewError e = core::screw_error(tool, core::transform_line(motion, tool)).value();
    CHECK(e.parallel);
    CHECK(e.distance_mm == Approx(10.0 * std::abs(std::sin(phi / 2))).margin(tol));
  }
}

TEST_CASE("the Plucker functions and screw_error do not allocate", "[screw][alloc]") {
  const PluckerLine l1 = line_through(Vec3(1e4, 2, 3), Vec3(0, 1, 1));
  const PluckerLine l2 = line_through(Vec3(-1, 2e3, 3), Vec3(1, 1e-3, 0));
  const core::Rigid3 a_T_b{core::so3_exp(Vec3(0.1, 0.2, 0.3)), Vec3(10, 20, 30)};
  t::AllocationScope scope;
  const auto made = core::plucker_from_point(Vec3(1, 2, 3), Vec3(3, 2, 1));
  const auto skew = core::screw_error(l1, l2);
  const auto parallel = core::screw_error(l1, l1);
  const PluckerLine moved = core::transform_line(a_T_b, l1);
  const core::Mat6 m = core::line_transform_matrix(a_T_b);
  const core::Rigid3 turn = core::rotation_about_line(l2, 0.5);
  const double d = core::line_distance_mm(l1, Vec3(0, 0, 0)) + core::closest_point_to_origin(l2).norm();
  CHECK(scope.count() == 0);
  CHECK(made.ok());
  CHECK(skew.ok());
  CHECK(parallel.ok());
  CHECK(core::all_finite(moved.moment_mm));
  CHECK(core::all_finite(m));
  CHECK(core::all_finite(turn.t));
  CHECK(std::isfinite(d));
}
