#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/leveling.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

// A face with outward normal n_table (table at zero), probed at `pose`: three
// well-spread points, built and rotated in long double.
struct Face {
  t::Vec3L n_table;
  std::array<Vec3, 3> machine_points;
  Vec3 n_machine;
};

t::Mat3L table_rotation_l(const core::TablePose& pose, const core::LevelConfig& cfg) {
  return t::rot_x_l(cfg.a_sign * t::deg_l(pose.a_deg)) * t::rot_z_l(cfg.c_sign * t::deg_l(pose.c_deg));
}

Face make_face(double tilt_rad, double azimuth_rad, const core::TablePose& pose, const core::LevelConfig& cfg,
               t::Rng& rng) {
  Face f;
  const long double tl = tilt_rad;
  const long double al = azimuth_rad;
  f.n_table = t::Vec3L(std::sin(tl) * std::cos(al), std::sin(tl) * std::sin(al), std::cos(tl));
  t::Vec3L u = f.n_table.cross(t::Vec3L::UnitX());
  if (u.norm() < 0.5L) u = f.n_table.cross(t::Vec3L::UnitY());
  u.normalize();
  const t::Vec3L v = f.n_table.cross(u);
  const t::Vec3L centre(rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(0, 150));
  const t::Mat3L r = table_rotation_l(pose, cfg);
  const long double angles[3] = {0.0L, 2.0L * t::kPiL / 3.0L, 4.0L * t::kPiL / 3.0L};
  const long double phase = rng.uniform(0, 6.28);
  const long double radius = rng.uniform(30, 150);
  for (int k = 0; k < 3; ++k) {
    const long double a = angles[k] + phase + rng.uniform(-0.3, 0.3);
    const t::Vec3L p = centre + radius * (std::cos(a) * u + std::sin(a) * v);
    f.machine_points[static_cast<std::size_t>(k)] = (r * p).cast<double>();
  }
  f.n_machine = (r * f.n_table).cast<double>();
  return f;
}

// Angle between +Z and the face normal turned by the commanded (C, A), long double.
long double residual_rad(const t::Vec3L& n_table, double c_deg, double a_deg, const core::LevelConfig& cfg) {
  const t::Vec3L turned = table_rotation_l({a_deg, c_deg}, cfg) * n_table;
  return t::angle_l(turned, t::Vec3L::UnitZ());
}

core::LevelInput input_for(const Face& f, const core::TablePose& pose) {
  core::LevelInput in;
  in.points_mm = f.machine_points.data();
  in.count = 3;
  in.probe_pose = pose;
  in.current_pose = pose;
  in.outward_hint_machine = f.n_machine;
  return in;
}

// Root mean square spread of `value(result)` about its value for the noise-free
// face, over `trials` probings with isotropic Gaussian noise of cfg.probe_sigma_mm.
template <typename Value>
double monte_carlo_sd(const Face& f, const core::LevelConfig& cfg, t::Rng& rng, int trials, Value value) {
  const auto nominal = core::level_face(input_for(f, {}), cfg);
  REQUIRE(nominal.ok());
  const double centre = value(nominal.value());
  double sum_sq = 0;
  for (int k = 0; k < trials; ++k) {
    Face noisy = f;
    for (auto& p : noisy.machine_points) p += cfg.probe_sigma_mm * Vec3(rng.normal(), rng.normal(), rng.normal());
    const auto r = core::level_face(input_for(noisy, {}), cfg);
    REQUIRE(r.ok());
    const double d = value(r.value()) - centre;
    sum_sq += d * d;
  }
  return std::sqrt(sum_sq / trials);
}

}  // namespace

TEST_CASE("levels 100000 random faces to +Z within 1e-12 rad, both solutions", "[level]") {
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
    CHECK(out.chosen.a_deg >= cfg.a_min_deg);
    CHECK(out.chosen.a_deg <= cfg.a_max_deg);
    // Independent reachability and nearest-position check.
    const bool other_in_limits = out.other.a_deg >= cfg.a_min_deg && out.other.a_deg <= cfg.a_max_deg;
    CHECK(out.other.reachable == other_in_limits);
    if (other_in_limits) {
      const double cost_chosen = std::abs(out.chosen.a_deg - pose.a_deg) + std::abs(out.chosen.c_deg - pose.c_deg);
      const double cost_other = std::abs(out.other.a_deg - pose.a_deg) + std::abs(out.other.c_deg - pose.c_deg);
      CHECK(cost_chosen <= cost_other);
    }
    // C is the representative nearest the current C.
    CHECK(std::abs(out.chosen.c_deg - pose.c_deg) <= 180.0 + 1e-9);
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

TEST_CASE("refuses when neither solution is inside the A travel limits", "[level]") {
  core::LevelConfig cfg;
  cfg.a_min_deg = -5.0;
  cfg.a_max_deg = 5.0;
  t::Rng rng(8);
  const Face f = make_face(0.3, 1.0, {}, cfg, rng);
  CHECK(core::level_face(input_for(f, {}), cfg).status() == core::Status::kUnreachable);
  cfg.a_max_deg = 20.0;  // 0.3 rad = 17.2 deg: now one is reachable
  const auto r = core::level_face(input_for(f, {}), cfg);
  REQUIRE(r.ok());
  CHECK_FALSE(r.value().other.reachable);
  CHECK(r.value().chosen.a_deg == Approx(0.3 * 180.0 / core::kPi).margin(1e-12));
  CHECK(r.value().other.a_deg == -r.value().chosen.a_deg);
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

TEST_CASE("rejects non-finite poses, hints and configuration", "[level]") {
  core::LevelConfig cfg;
  t::Rng rng(10);
  const Face f = make_face(0.2, 0.5, {}, cfg, rng);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto in = input_for(f, {});
  in.probe_pose.a_deg = nan;
  CHECK(core::level_face(in, cfg).status() == core::Status::kNotFinite);
  in = input_for(f, {});
  in.outward_hint_machine.x() = std::numeric_limits<double>::infinity();
  CHECK(core::level_face(in, cfg).status() == core::Status::kNotFinite);
  core::LevelConfig bad = cfg;
  bad.a_sign = 0.5;
  CHECK(core::level_face(input_for(f, {}), bad).status() == core::Status::kConfigInvalid);
  bad = cfg;
  bad.a_min_deg = 10;
  bad.a_max_deg = -10;
  CHECK(core::level_face(input_for(f, {}), bad).status() == core::Status::kConfigInvalid);
  bad = cfg;
  bad.probe_sigma_mm = nan;
  CHECK(core::level_face(input_for(f, {}), bad).status() == core::Status::kConfigInvalid);
}

TEST_CASE("refuses points too close for the probe repeatability", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.001;
  cfg.max_direction_sigma_deg = 0.1;  // sigma / s_v must stay below 1.745e-3 rad
  const std::array<Vec3, 3> close{Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0.01)};
  core::LevelInput in;
  in.points_mm = close.data();
  in.count = 3;
  CHECK(core::level_face(in, cfg).status() == core::Status::kPointsTooClose);
  cfg.probe_sigma_mm = 0.0;  // a perfect probe: the same points are fine
  CHECK(core::level_face(in, cfg).ok());
}

TEST_CASE("the tilt uncertainty matches a Monte Carlo of probe noise", "[level][uncertainty]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.002;
  t::Rng rng(13);
  for (double tilt : {0.05, 0.4, 1.2}) {
    const Face f = make_face(tilt, 0.7, {}, cfg, rng);
    const auto nominal = core::level_face(input_for(f, {}), cfg);
    REQUIRE(nominal.ok());
    const double sd_arcsec =
        3600.0 * monte_carlo_sd(f, cfg, rng, 4000, [](const core::LevelResult& r) { return r.tilt_deg; });
    INFO("tilt " << tilt << " MC " << sd_arcsec << " model " << nominal.value().tilt_sigma_arcsec);
    CHECK(nominal.value().tilt_sigma_arcsec == Approx(sd_arcsec).epsilon(0.06));
  }
}

TEST_CASE("more points give flatness and flag a gross outlier", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.001;
  t::Rng rng(14);
  std::vector<Vec3> pts;
  for (int k = 0; k < 12; ++k) {
    const double x = rng.uniform(-100, 100);
    const double y = rng.uniform(-100, 100);
    pts.emplace_back(x, y, 0.1 * x - 0.05 * y + 0.001 * rng.normal());
  }
  core::LevelInput in;
  in.points_mm = pts.data();
  in.count = pts.size();
  auto r = core::level_face(in, cfg);
  REQUIRE(r.ok());
  CHECK(r.value().outlier_point == 0);
  CHECK(r.value().flatness_mm > 0.0);
  CHECK(r.value().flatness_mm < 0.01);
  pts[6].z() += 0.05;  // 50 sigma
  r = core::level_face(in, cfg);
  REQUIRE(r.ok());
  CHECK(r.value().outlier_point == 7);
  CHECK(r.value().max_standardized_residual > core::kOutlierLimit);
  CHECK(r.value().flatness_mm > 0.04);
}

TEST_CASE("a table not at zero while probing gives absolute angles", "[level]") {
  core::LevelConfig cfg;
  t::Rng rng(15);
  const core::TablePose pose{-35.0, 123.0};
  const Face f = make_face(0.25, -2.0, pose, cfg, rng);
  const auto r = core::level_face(input_for(f, pose), cfg);
  REQUIRE(r.ok());
  // Probing the same face at zero gives the same absolute answer (up to C's turn).
  const Face g = make_face(0.25, -2.0, {}, cfg, rng);
  const auto r0 = core::level_face(input_for(g, {}), cfg);
  REQUIRE(r0.ok());
  CHECK(std::abs(r.value().tilt_deg - r0.value().tilt_deg) < 1e-10);
  CHECK((r.value().normal_table - r0.value().normal_table).norm() < 1e-12);
}

TEST_CASE("leveling does not allocate", "[level][alloc]") {
  core::LevelConfig cfg;
  t::Rng rng(16);
  const Face f = make_face(0.3, 0.3, {10, 20}, cfg, rng);
  const auto in = input_for(f, {10, 20});
  const trueaxis::test::AllocationScope scope;
  const auto r = core::level_face(in, cfg);
  CHECK(scope.count() == 0);
  CHECK(r.ok());
}

TEST_CASE("a nearly level face under probe noise keeps C instead of swinging it", "[level]") {
  core::LevelConfig cfg;  // 0.5 um probe
  t::Rng rng(17);
  for (double tilt : {1e-12, 1e-9, 1e-7}) {
    for (double az : {0.3, 2.0, -2.5}) {
      const Face f = make_face(tilt, az, {0.0, 37.5}, cfg, rng);
      const auto r = core::level_face(input_for(f, {0.0, 37.5}), cfg);
      REQUIRE(r.ok());
      REQUIRE(tilt * 180.0 / core::kPi * 3600.0 < r.value().direction_sigma_arcsec);
      CHECK(r.value().chosen.c_deg == 37.5);
      CHECK(r.value().chosen.a_deg == 0.0);
    }
  }
  // Above the noise the face is leveled as usual.
  const Face g = make_face(1e-3, 0.3, {0.0, 37.5}, cfg, rng);
  const auto r = core::level_face(input_for(g, {0.0, 37.5}), cfg);
  REQUIRE(r.ok());
  CHECK(r.value().chosen.a_deg != 0.0);
}

TEST_CASE("a face facing down needs A near 180 degrees, never A = 0", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.0;
  cfg.a_min_deg = -200.0;
  cfg.a_max_deg = 200.0;
  t::Rng rng(18);
  for (double tilt_deg : {100.0, 135.0, 179.0, 180.0}) {
    const Face f = make_face(tilt_deg * core::kPi / 180.0, 0.8, {}, cfg, rng);
    const auto r = core::level_face(input_for(f, {}), cfg);
    REQUIRE(r.ok());
    CHECK(r.value().tilt_deg == Approx(tilt_deg).margin(1e-9));
    CHECK(residual_rad(f.n_table, r.value().chosen.c_deg, r.value().chosen.a_deg, cfg) < 1e-12L);
    CHECK(std::abs(r.value().chosen.a_deg) == Approx(tilt_deg).margin(1e-9));
  }
  cfg.a_min_deg = -120.0;
  cfg.a_max_deg = 120.0;
  const Face down = make_face(core::kPi, 0.0, {}, cfg, rng);
  CHECK(core::level_face(input_for(down, {}), cfg).status() == core::Status::kUnreachable);
}

TEST_CASE("refuses an orientation that probe noise could flip", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.001;
  // A vertical face 20 mm wide: sigma / s_v is about 7e-5 rad; a hint 1e-5 rad
  // from the face plane could be on either side after noise.
  const std::array<Vec3, 3> pts{Vec3(10, 0, 0), Vec3(10, 20, 0), Vec3(10, 0, 20)};
  core::LevelInput in;
  in.points_mm = pts.data();
  in.count = 3;
  in.outward_hint_machine = Vec3(1e-5, 0, 1);
  CHECK(core::level_face(in, cfg).status() == core::Status::kOrientationAmbiguous);
  in.outward_hint_machine = Vec3(1e-2, 0, 1);
  CHECK(core::level_face(in, cfg).ok());
}

TEST_CASE("the C uncertainty matches a Monte Carlo of probe noise", "[level][uncertainty]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.002;
  t::Rng rng(19);
  for (double tilt : {0.05, 0.5}) {
    const Face f = make_face(tilt, 0.7, {}, cfg, rng);
    const auto nominal = core::level_face(input_for(f, {}), cfg);
    REQUIRE(nominal.ok());
    // C wrapped next to the nominal one, so a turn of 360 is no error.
    const double c0 = nominal.value().chosen.c_deg;
    const double sd_arcsec = 3600.0 * monte_carlo_sd(f, cfg, rng, 4000, [c0](const core::LevelResult& r) {
                               return c0 + core::wrap_deg_180(r.chosen.c_deg - c0);
                             });
    INFO("tilt " << tilt << " MC " << sd_arcsec << " model " << nominal.value().c_sigma_arcsec);
    CHECK(nominal.value().c_sigma_arcsec == Approx(sd_arcsec).epsilon(0.06));
  }
}

TEST_CASE("level within noise means a tilt up to 1 sigma of the normal's direction, not more", "[level]") {
  t::Rng rng(20);
  const core::TablePose pose{0.0, 37.5};
  for (double az : {0.3, 2.0, -2.5}) {
    // The direction sigma is sigma / s_v; s_v depends on the points only, so one
    // run with a known sigma gives it, and sigma is then set for the wanted ratio.
    core::LevelConfig cfg;
    const double tilt = 2e-5;
    const Face f = make_face(tilt, az, pose, cfg, rng);
    const auto probe = core::level_face(input_for(f, pose), cfg);
    REQUIRE(probe.ok());
    const double s_v_mm = cfg.probe_sigma_mm / (probe.value().direction_sigma_arcsec / 3600.0 * core::kPi / 180.0);
    for (double ratio : {0.9, 1.5, 2.5}) {
      cfg.probe_sigma_mm = tilt / ratio * s_v_mm;
      const auto r = core::level_face(input_for(f, pose), cfg);
      REQUIRE(r.ok());
      const core::LevelResult& out = r.value();
      INFO("azimuth " << az << ", tilt / direction sigma " << ratio);
      REQUIRE(out.tilt_deg * 3600.0 / out.direction_sigma_arcsec == Approx(ratio).epsilon(1e-6));
      if (ratio < 1.0) {
        CHECK(out.chosen.a_deg == 0.0);
        CHECK(out.chosen.c_deg == 37.5);
      } else {
        CHECK(std::abs(out.chosen.a_deg) == Approx(tilt * 180.0 / core::kPi).epsilon(1e-9));
        CHECK(residual_rad(f.n_table, out.chosen.c_deg, out.chosen.a_deg, cfg) < 1e-12L);
      }
    }
  }
}

TEST_CASE("the outward hint may have any length: 1e-9 to 1e9 times a unit hint give the same result", "[level]") {
  core::LevelConfig cfg;
  cfg.probe_sigma_mm = 0.001;
  cfg.a_min_deg = -180.0;
  cfg.a_max_deg = 180.0;
  t::Rng rng(21);
  for (int i = 0; i < 200; ++i) {
    const core::TablePose pose{rng.uniform(-90, 90), rng.uniform(-360, 360)};
    const Face f = make_face(rng.uniform(0.01, 1.5), rng.uniform(-core::kPi, core::kPi), pose, cfg, rng);
    // A unit hint off the normal by up to 60 deg, outward or (half the time) inward.
    Vec3 off = f.n_machine.cross(rng.unit_vector());
    off = off.normalized() * std::tan(rng.uniform(0.0, 1.0));
    const Vec3 hint = ((i % 2 == 0 ? 1.0 : -1.0) * f.n_machine + off).normalized();
    core::LevelInput in = input_for(f, pose);
    in.outward_hint_machine = hint;
    const auto unit = core::level_face(in, cfg);
    REQUIRE(unit.ok());
    for (double scale : {1e-9, 1e-3, 1e3, 1e9}) {
      INFO("face " << i << ", hint scale " << scale);
      in.outward_hint_machine = scale * hint;
      const auto r = core::level_face(in, cfg);
      REQUIRE(r.ok());
      CHECK(r.value().chosen.a_deg == unit.value().chosen.a_deg);
      CHECK(r.value().chosen.c_deg == unit.value().chosen.c_deg);
      CHECK(r.value().other.a_deg == unit.value().other.a_deg);
      CHECK(r.value().other.c_deg == unit.value().other.c_deg);
      CHECK((r.value().normal_table == unit.value().normal_table));
      CHECK(r.value().tilt_sigma_arcsec == unit.value().tilt_sigma_arcsec);
    }
    // The face is turned as the hint says: outward normal on the hint's side.
    CHECK(unit.value().normal_table.dot(f.n_table.cast<double>()) * (i % 2 == 0 ? 1.0 : -1.0) > 0.99);
  }
}
