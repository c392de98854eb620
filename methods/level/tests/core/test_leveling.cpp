// core::level_face against long-double oracles (leveling_fixtures.hpp): 100,000
// random faces, the quadrants, the limits to the ulp, the uncertainties in
// closed form. Its refusals are portable tests (methods/level/tests/portable/level_face_test.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "leveling_fixtures.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;
using namespace trueaxis::test::leveling;  // NOLINT: the fixtures of this file's tests


TEST_CASE("levels 100000 random faces to +Z within 1e-12 rad by a long-double oracle, both solutions", "[level]") {
  t::Rng rng(2026);
  std::size_t second_chosen = 0;
  long double worst = 0;
  for (int i = 0; i < 100000; ++i) {
    core::LevelConfig cfg;
    // A perfect probe: the exactness of the angles is the property here; how
    // noise makes a nearly level face level is tested below.
    cfg.probe_sigma_mm = 0.0;
    cfg.a_sign = (rng.next() & 1) ? 1.0 : -1.0;
    cfg.c_sign = (rng.next() & 1) ? 1.0 : -1.0;
    if (rng.next() & 1) {
      cfg.a_min_deg = -30.0;
      cfg.a_max_deg = 110.0;
    }
    const double tilt = std::exp(rng.uniform(std::log(1e-9), std::log(core::kPi / 2)));
    const double azimuth = rng.uniform(-core::kPi, core::kPi);
    const core::TablePose pose{rng.uniform(cfg.a_min_deg, cfg.a_max_deg), rng.uniform(-720, 720)};
    const Face f = make_face(tilt, azimuth, pose, cfg, rng);
    const auto r = core::level_face(input_for(f, pose), cfg);
    REQUIRE(r.ok());
    const core::LevelResult& out = r.value();
    const long double e1 = residual_rad(f.n_table, out.chosen.c_deg, out.chosen.a_deg, cfg);
    const long double e2 = residual_rad(f.n_table, out.other.c_deg, out.other.a_deg, cfg);
    worst = std::max({worst, e1, e2});
    CHECK(e1 < 1e-12L);
    CHECK(e2 < 1e-12L);
    // The limits, reachability, the cheaper choice and C's representative are
    // the portable test's (methods/level/tests/portable/level_face_test.cpp, on the host and
    // the Cortex-M7); here only what needs the long-double oracle.
    CHECK(std::abs(static_cast<double>(t::angle_l(out.normal_table.cast<long double>(), f.n_table))) < 1e-12);
    CHECK(out.tilt_deg == Approx(tilt * 180.0 / core::kPi).epsilon(1e-9).margin(1e-12));
    if (out.chosen.a_deg * cfg.a_sign < 0) ++second_chosen;
  }
  WARN("worst residual over 100000 faces, both solutions: " << static_cast<double>(worst) << " rad");
  CHECK(worst < 1e-12L);
  CHECK(second_chosen > 1000);  // the choice really goes both ways
}

TEST_CASE("uses atan2: faces in every quadrant get C = 90 deg - azimuth or its opposite", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.0;
  t::Rng rng(7);
  const double tilt_deg = 0.4 * 180.0 / core::kPi;
  // Away from the ties (azimuth 0, 180) and the wrap of C2 (azimuth -90, 90).
  for (double az_deg : {-170.0, -135.0, -100.0, -45.0, -10.0, 10.0, 45.0, 80.0, 100.0, 135.0, 170.0}) {
    INFO("azimuth " << az_deg);
    const Face f = make_face(0.4, az_deg * core::kPi / 180.0, {}, cfg, rng);
    const auto r = core::level_face(input_for(f, {}), cfg);
    REQUIRE(r.ok());
    const core::LevelResult& out = r.value();
    // n = (sin t cos az, sin t sin az, cos t): C1 = atan2(nx, ny) = 90 - az, A1 = t;
    // C2 = C1 + 180, A2 = -t. From C = 0 the cheaper one has |C| <= 90; on a tie, 1.
    const double c1 = core::wrap_deg_180(90.0 - az_deg);
    const double c2 = core::wrap_deg_180(270.0 - az_deg);
    const bool first = std::abs(c1) <= std::abs(c2);
    CHECK(out.chosen.c_deg == Approx(first ? c1 : c2).margin(1e-10));
    CHECK(out.chosen.a_deg == Approx(first ? tilt_deg : -tilt_deg).margin(1e-10));
    CHECK(out.other.c_deg == Approx(first ? c2 : c1).margin(1e-10));
    CHECK(out.other.a_deg == -out.chosen.a_deg);
    CHECK(residual_rad(f.n_table, out.chosen.c_deg, out.chosen.a_deg, cfg) < 1e-12L);
    CHECK(residual_rad(f.n_table, out.other.c_deg, out.other.a_deg, cfg) < 1e-12L);
  }
}

TEST_CASE("a face already level keeps C and sets A to zero", "[level]") {
  const std::array<Vec3, 3> pts{Vec3(0, 0, 5), Vec3(100, 0, 5), Vec3(0, 80, 5)};
  core::LevelInput in;
  in.points_mm = pts.data();
  in.count = 3;
  in.probe_pose = {0.0, 37.5};
  in.current_pose = {0.0, 37.5};
  // Probed at C = 37.5 with A = 0: the normal is still exactly +Z.
  const auto r = core::level_face(in, core::LevelConfig{});
  REQUIRE(r.ok());
  CHECK(r.value().chosen.a_deg == 0.0);
  CHECK(r.value().chosen.c_deg == 37.5);
  CHECK(r.value().tilt_deg == 0.0);
  CHECK(r.value().other.c_deg == 37.5);
  CHECK(r.value().other.a_deg == 0.0);
  // At zero tilt the tilt's uncertainty is sigma / s_v and C's is unbounded, capped
  // at 180 deg (leveling.hpp item 7). s_v: the smaller singular value of the
  // centred points, in closed form for this triangle (x, y in mm).
  const long double sxx = 2.0L * (100.0L / 3) * (100.0L / 3) + (200.0L / 3) * (200.0L / 3);
  const long double syy = 2.0L * (80.0L / 3) * (80.0L / 3) + (160.0L / 3) * (160.0L / 3);
  const long double sxy = (100.0L / 3) * (80.0L / 3) - (200.0L / 3) * (80.0L / 3) - (100.0L / 3) * (160.0L / 3);
  const long double s_v = std::sqrt((sxx + syy) / 2 - std::sqrt((sxx - syy) * (sxx - syy) / 4 + sxy * sxy));
  const double expected_arcsec =
      static_cast<double>(0.0005L / s_v * 180.0L / t::kPiL * 3600.0L);  // default probe sigma 0.5 um
  CHECK(r.value().direction_sigma_arcsec == Approx(expected_arcsec).epsilon(1e-12));
  CHECK(r.value().tilt_sigma_arcsec == r.value().direction_sigma_arcsec);
  CHECK(r.value().c_sigma_arcsec == Approx(180.0 * 3600.0).epsilon(1e-15));
  // A perfect probe knows C and the tilt exactly.
  core::LevelConfig perfect;
  perfect.probe_sigma_mm = 0.0;
  const auto p = core::level_face(in, perfect);
  REQUIRE(p.ok());
  CHECK(p.value().tilt_sigma_arcsec == 0.0);
  CHECK(p.value().c_sigma_arcsec == 0.0);
}

TEST_CASE("a vertical face levels with A at plus or minus 90 degrees", "[level]") {
  // Face x = 10, outward -X... given by the hint.
  const std::array<Vec3, 3> pts{Vec3(10, 0, 0), Vec3(10, 100, 0), Vec3(10, 0, 80)};
  core::LevelInput in;
  in.points_mm = pts.data();
  in.count = 3;
  in.outward_hint_machine = Vec3(-1, 0, 0);
  const auto r = core::level_face(in, core::LevelConfig{});
  REQUIRE(r.ok());
  CHECK(std::abs(r.value().chosen.a_deg) == Approx(90.0).margin(1e-12));
  CHECK(r.value().tilt_deg == Approx(90.0).margin(1e-12));
  CHECK(r.value().normal_table.x() == Approx(-1.0).margin(1e-15));
  // Without a hint, the default (+Z) is perpendicular to this face.
  in.outward_hint_machine = Vec3::Zero();
  CHECK(core::level_face(in, core::LevelConfig{}).status() == core::Status::kOrientationAmbiguous);
}

TEST_CASE("the outward normal follows the hint, not the point order", "[level]") {
  const std::array<Vec3, 3> a{Vec3(0, 0, 0), Vec3(100, 0, 10), Vec3(0, 100, 0)};
  const std::array<Vec3, 3> b{a[0], a[2], a[1]};
  for (const auto* pts : {&a, &b}) {
    core::LevelInput in;
    in.points_mm = pts->data();
    in.count = 3;
    const auto r = core::level_face(in, core::LevelConfig{});
    REQUIRE(r.ok());
    CHECK(r.value().normal_table.z() > 0.0);
  }
}

TEST_CASE("an A exactly on a travel limit is reachable, one ulp beyond is not", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.0;
  t::Rng rng(81);
  for (double a_sign : {1.0, -1.0}) {
    cfg.a_sign = a_sign;
    cfg.a_min_deg = -120.0;
    cfg.a_max_deg = 120.0;
    const Face f = make_face(0.3, 1.0, {}, cfg, rng);
    const auto wide = core::level_face(input_for(f, {}), cfg);
    REQUIRE(wide.ok());
    // The two solutions' commanded A: +a and -a exactly (solution 2 negates A1).
    const double a = std::abs(wide.value().chosen.a_deg);
    REQUIRE(a > 17.0);
    REQUIRE(std::abs(wide.value().other.a_deg) == a);
    INFO("a_sign " << a_sign << ", a " << a);

    // Upper limit exactly on +a, lower limit far from -a: +a is taken.
    cfg.a_min_deg = -5.0;
    cfg.a_max_deg = a;
    auto r = core::level_face(input_for(f, {}), cfg);
    REQUIRE(r.ok());
    CHECK(r.value().chosen.a_deg == a);
    CHECK(r.value().chosen.reachable);
    CHECK_FALSE(r.value().other.reachable);
    // One ulp inside +a: neither is reachable.
    cfg.a_max_deg = std::nextafter(a, 0.0);
    CHECK(core::level_face(input_for(f, {}), cfg).status() == core::Status::kUnreachable);

    // Lower limit exactly on -a: -a is taken, also when +a is one ulp out.
    cfg.a_min_deg = -a;
    r = core::level_face(input_for(f, {}), cfg);
    REQUIRE(r.ok());
    CHECK(r.value().chosen.a_deg == -a);
    CHECK_FALSE(r.value().other.reachable);
    CHECK(r.value().other.a_deg == a);
    // One ulp inside -a as well: refused.
    cfg.a_min_deg = std::nextafter(-a, 0.0);
    CHECK(core::level_face(input_for(f, {}), cfg).status() == core::Status::kUnreachable);
    // Both limits exactly on the solutions: both reachable, the cheaper chosen.
    cfg.a_min_deg = -a;
    cfg.a_max_deg = a;
    r = core::level_face(input_for(f, {}), cfg);
    REQUIRE(r.ok());
    CHECK(r.value().chosen.reachable);
    CHECK(r.value().other.reachable);
  }
}

TEST_CASE("C limits pick a representative inside them or refuse", "[level]") {
  core::LevelConfig cfg;
  t::Rng rng(9);
  const Face f = make_face(0.3, 1.0, {}, cfg, rng);  // C1 = 90 - 57.3 deg
  cfg.c_min_deg = 400.0;
  cfg.c_max_deg = 800.0;
  const auto r = core::level_face(input_for(f, {}), cfg);
  REQUIRE(r.ok());
  // C1 = 90 - 57.2958 = 32.7042 deg, C2 = -147.2958 deg. Inside [400, 800] the
  // representatives nearest the current C = 0 are 392.70 (out) -> 752.70 for C1 and
  // 572.70 for C2; both A are reachable, so the cheaper is C2 + 720.
  const double c1 = 90.0 - 1.0 * 180.0 / core::kPi;
  CHECK(r.value().chosen.c_deg == Approx(c1 - 180.0 + 720.0).margin(1e-10));
  CHECK(r.value().chosen.a_deg == Approx(-0.3 * 180.0 / core::kPi).margin(1e-10));
  CHECK(r.value().other.c_deg == Approx(c1 + 720.0).margin(1e-10));
  CHECK(r.value().other.reachable);
  cfg.c_min_deg = 1.0;
  cfg.c_max_deg = 2.0;
  CHECK(core::level_face(input_for(f, {}), cfg).status() == core::Status::kUnreachable);
}

TEST_CASE("a tie in travel goes to solution 1 within kLevelTieDeg, and only within it", "[level]") {
  // Both reachable, from the table at A = 0, C = 0: solution 1 costs 100 deg of
  // travel, solution 2 100 deg less `d`.
  const core::TablePose at_zero{};
  core::LevelSolution s1;
  s1.a_deg = 10.0;
  s1.c_deg = 90.0;
  s1.reachable = true;
  for (const double d : {0.0, 0.5 * core::kLevelTieDeg, 0.99 * core::kLevelTieDeg, 1.01 * core::kLevelTieDeg,
                         2.0 * core::kLevelTieDeg, -2.0 * core::kLevelTieDeg}) {
    CAPTURE(d);
    core::LevelSolution s2;
    s2.a_deg = -10.0;
    s2.c_deg = -90.0 + d;
    s2.reachable = true;
    core::LevelSolution chosen, other;
    core::order_level_solutions(s1, s2, at_zero, chosen, other);
    const bool second = d > core::kLevelTieDeg;
    CHECK(chosen.c_deg == (second ? s2.c_deg : s1.c_deg));
    CHECK(other.c_deg == (second ? s1.c_deg : s2.c_deg));
  }
}
