// core::level_face (docs/METHODS.md M1): random faces against a ground truth built
// with Eigen::AngleAxisd (TRUEAXIS_LEVEL_CASES of them), and every documented
// error. methods/level/tests/core/test_leveling.cpp holds it to long-double oracles.
#include <cmath>
#include <limits>

#include "fixtures.hpp"
#include "portable_test.hpp"
#include "trueaxis/core/leveling.hpp"

#ifndef TRUEAXIS_LEVEL_CASES
#define TRUEAXIS_LEVEL_CASES 2000
#endif

namespace {

using trueaxis::core::LevelConfig;
using trueaxis::core::LevelInput;
using trueaxis::core::LevelResult;
using trueaxis::core::LevelSolution;
using trueaxis::core::Status;
using trueaxis::core::Vec3;
using trueaxis::test::Face;
using trueaxis::test::leveling_error_rad;
using trueaxis::test::SplitMix64;

constexpr int kLevelCases = TRUEAXIS_LEVEL_CASES;
constexpr double kLevelTolerance_rad = 1e-12;

double move_cost_deg(const LevelSolution& s, double a_deg, double c_deg) {
  return std::fabs(s.a_deg - a_deg) + std::fabs(s.c_deg - c_deg);
}

LevelInput input_for(const Face& f, double current_a_deg, double current_c_deg) {
  LevelInput in;
  in.points_mm = f.points_machine;
  in.count = 3;
  in.probe_pose = {f.probe_a_deg, f.probe_c_deg};
  in.current_pose = {current_a_deg, current_c_deg};
  in.outward_hint_machine = f.hint_machine;
  return in;
}

// A face tilted 30 deg about X, probed at table zero, with its outward hint.
struct TiltedFace {
  Vec3 points[3] = {Vec3(0.0, 0.0, 0.0), Vec3(100.0, 0.0, 0.0),
                    Vec3(0.0, 100.0 * std::cos(trueaxis::core::deg_to_rad(30.0)),
                         100.0 * std::sin(trueaxis::core::deg_to_rad(30.0)))};
  LevelInput input() const {
    LevelInput in;
    in.points_mm = points;
    in.count = 3;
    return in;
  }
};

TA_TEST("level_face levels random faces with both solutions, the chosen one within the A limits and not costlier") {
  SplitMix64 rng(0x5EED'0001);
  for (int i = 0; i < kLevelCases; ++i) {
    TA_CASE_INDEX(i);
    const Face f = trueaxis::test::random_face(rng);
    LevelConfig cfg;
    cfg.a_sign = f.a_sign;
    cfg.c_sign = f.c_sign;
    cfg.probe_sigma_mm = 0.0;  // a perfect probe: exactness is the property here
    // Every third face gets one-sided A travel, so only one solution is reachable.
    if (i % 3 == 1) cfg.a_min_deg = 0.0;
    if (i % 3 == 2) cfg.a_max_deg = 0.0;
    const double current_a = rng.uniform(cfg.a_min_deg, cfg.a_max_deg);
    const double current_c = rng.uniform(-720.0, 720.0);
    const auto r = trueaxis::core::level_face(input_for(f, current_a, current_c), cfg);
    if (!TA_CHECK(r.ok())) continue;
    const LevelResult& out = r.value();

    TA_CHECK(leveling_error_rad(f.normal_table, out.chosen.a_deg, out.chosen.c_deg, f.a_sign, f.c_sign) <=
             kLevelTolerance_rad);
    TA_CHECK(leveling_error_rad(f.normal_table, out.other.a_deg, out.other.c_deg, f.a_sign, f.c_sign) <=
             kLevelTolerance_rad);
    TA_CHECK(std::atan2(out.normal_table.cross(f.normal_table).norm(), out.normal_table.dot(f.normal_table)) <=
             kLevelTolerance_rad);
    TA_CHECK_NEAR(out.tilt_deg, trueaxis::core::rad_to_deg(f.tilt_rad), 1e-10);

    // The two solutions are A and -A exactly (leveling.hpp item 4), |A| the tilt.
    TA_CHECK_NEAR(std::fabs(out.chosen.a_deg), trueaxis::core::rad_to_deg(f.tilt_rad), 1e-10);
    TA_CHECK_EQ(out.other.a_deg, -out.chosen.a_deg);
    TA_CHECK(std::fabs(out.chosen.c_deg - current_c) <= 180.0 + 1e-9);
    TA_CHECK(std::fabs(out.other.c_deg - current_c) <= 180.0 + 1e-9);
    // With one-sided A travel exactly the solution on the allowed side is
    // reachable; with +-120 deg both are, and the chosen one is not costlier.
    if (i % 3 == 1) {
      TA_CHECK(out.chosen.a_deg > 0.0);
      TA_CHECK(!out.other.reachable);
    } else if (i % 3 == 2) {
      TA_CHECK(out.chosen.a_deg < 0.0);
      TA_CHECK(!out.other.reachable);
    } else {
      TA_CHECK(out.other.reachable);
      TA_CHECK(move_cost_deg(out.chosen, current_a, current_c) <=
               move_cost_deg(out.other, current_a, current_c) + 1e-9);
    }
    // A perfect probe: every uncertainty is exactly zero.
    TA_CHECK_EQ(out.tilt_sigma_arcsec, 0.0);
    TA_CHECK_EQ(out.c_sigma_arcsec, 0.0);
    TA_CHECK_EQ(out.direction_sigma_arcsec, 0.0);
  }
}

TA_TEST("level_face rejects three collinear points") {
  const Vec3 points[3] = {Vec3(0.0, 0.0, 0.0), Vec3(50.0, 10.0, 5.0), Vec3(100.0, 20.0, 10.0)};
  LevelInput in;
  in.points_mm = points;
  in.count = 3;
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kPointsCollinear);
}

TA_TEST("level_face rejects three coincident points") {
  const Vec3 points[3] = {Vec3(12.0, 34.0, 56.0), Vec3(12.0, 34.0, 56.0), Vec3(12.0, 34.0, 56.0)};
  LevelInput in;
  in.points_mm = points;
  in.count = 3;
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kPointsCoincident);
}

TA_TEST("level_face rejects a NaN or an infinity in a point, the pose or the hint") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 3; ++k) {
    TiltedFace face;
    face.points[k].y() = nan;
    TA_CHECK_EQ(trueaxis::core::level_face(face.input(), LevelConfig{}).status(), Status::kNotFinite);
  }
  const TiltedFace face;
  LevelInput in = face.input();
  in.probe_pose.a_deg = nan;
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kNotFinite);
  in = face.input();
  in.current_pose.c_deg = std::numeric_limits<double>::infinity();
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kNotFinite);
  in = face.input();
  in.outward_hint_machine = Vec3(0.0, nan, 1.0);
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kNotFinite);
  in = face.input();
  in.outward_hint_machine = Vec3(std::numeric_limits<double>::infinity(), 0.0, 1.0);
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kNotFinite);
}

TA_TEST("level_face reports unreachable when A travel excludes both solutions") {
  const TiltedFace face;
  LevelConfig cfg;
  cfg.a_min_deg = -10.0;
  cfg.a_max_deg = 10.0;
  TA_CHECK_EQ(trueaxis::core::level_face(face.input(), cfg).status(), Status::kUnreachable);
  cfg.a_min_deg = -30.5;  // now -30 deg (the second solution) is inside
  const auto r = trueaxis::core::level_face(face.input(), cfg);
  TA_REQUIRE(r.ok());
  TA_CHECK_NEAR(r.value().chosen.a_deg, -30.0, 1e-12);
  TA_CHECK(!r.value().other.reachable);
}

TA_TEST("level_face rejects a face perpendicular to the orientation hint") {
  const TiltedFace face;
  LevelInput in = face.input();
  // The face's normal is (0, -sin 30, cos 30); (0, cos 30, sin 30) lies in the face.
  in.outward_hint_machine =
      Vec3(0.0, std::cos(trueaxis::core::deg_to_rad(30.0)), std::sin(trueaxis::core::deg_to_rad(30.0)));
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kOrientationAmbiguous);
  in.outward_hint_machine = Vec3(1.0, 0.0, 0.0);
  TA_CHECK_EQ(trueaxis::core::level_face(in, LevelConfig{}).status(), Status::kOrientationAmbiguous);
}

TA_TEST("level_face flips the fitted normal to agree with the hint") {
  const TiltedFace face;
  LevelInput in = face.input();
  in.outward_hint_machine = Vec3(0.0, 0.0, -1.0);
  LevelConfig cfg;
  cfg.a_min_deg = -180.0;
  cfg.a_max_deg = 180.0;
  const auto r = trueaxis::core::level_face(in, cfg);
  TA_REQUIRE(r.ok());
  TA_CHECK(r.value().normal_table.z() < 0.0);
  TA_CHECK_NEAR(r.value().tilt_deg, 150.0, 1e-12);
}

TA_TEST("level_face rejects an inconsistent or non-finite configuration") {
  const TiltedFace face;
  LevelConfig cfg;
  cfg.a_min_deg = 10.0;
  cfg.a_max_deg = -10.0;
  TA_CHECK_EQ(trueaxis::core::level_face(face.input(), cfg).status(), Status::kConfigInvalid);
  cfg = LevelConfig{};
  cfg.c_sign = 0.5;
  TA_CHECK_EQ(trueaxis::core::level_face(face.input(), cfg).status(), Status::kConfigInvalid);
  cfg = LevelConfig{};
  cfg.a_sign = 0.5;
  TA_CHECK_EQ(trueaxis::core::level_face(face.input(), cfg).status(), Status::kConfigInvalid);
  cfg = LevelConfig{};
  cfg.probe_sigma_mm = std::numeric_limits<double>::quiet_NaN();
  TA_CHECK_EQ(trueaxis::core::level_face(face.input(), cfg).status(), Status::kConfigInvalid);
}

}  // namespace
