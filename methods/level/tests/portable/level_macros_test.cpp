// M1 through the module, as a controller drives it (docs/INTERFACE.md macros
// 9810..9814): three probed points in G57..G59, the point list of 9811, the
// streaming session; every refusal with its code, leaving the results and the
// stored bytes as they were; the configuration's ranges.
#include <cmath>
#include <cstdint>

#include "fixtures.hpp"
#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "split_mix64.hpp"
#include "trueaxis/core/plane_fit.hpp"
#include "trueaxis/core/sphere_fit.hpp"
#include "trueaxis/macros/module.hpp"

TA_METHOD_TESTED("level");

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
using F = trueaxis::macros::AccessFault;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;

constexpr double kRadToDeg = 180.0 / trueaxis::core::kPi;

// A face tilted by atan(0.2) about Y (rising towards +X), probed at the table's zero.
void put_inclined_face(ModuleRig& rig) {
  rig.set3(v::kG57, Vec3(0, 0, 10));
  rig.set3(v::kG58, Vec3(100, 0, 30));
  rig.set3(v::kG59, Vec3(0, 100, 10));
}

// Writes the three points, the probe pose and the hint, and runs 9810: its #9001.
double run_9810(ModuleRig& rig, const Vec3 (&points)[3], double a_deg, double c_deg, const Vec3& hint) {
  rig.set3(v::kG57, points[0]);
  rig.set3(v::kG58, points[1]);
  rig.set3(v::kG59, points[2]);
  rig.set(v::kArgA, a_deg);
  rig.set(v::kArgC, c_deg);
  rig.set3(v::kArgI, hint);
  return rig.run(9810);
}

// Axis signs, and a perfect probe: exactness is the property the random faces
// check (under probe noise a face tilted less than the noise is left at A = 0).
void set_signs(ModuleRig& rig, double a_sign, double c_sign) {
  rig.unlock();
  rig.set(v::kASign, a_sign);
  rig.set(v::kCSign, c_sign);
  rig.set(v::kProbeSigma, 0.0);
  rig.lock();
}

// Points 1..n of the point list, 30 variables per write.
void put_point_list(ModuleRig& rig, const double* xyz, std::size_t n) {
  for (std::size_t at = 0; at < 3 * n; at += 30) {
    const std::size_t count = 3 * n - at < 30 ? 3 * n - at : 30;
    rig.set(static_cast<std::uint16_t>(v::kPointList + at), static_cast<std::uint16_t>(count), xyz + at);
  }
}

bool point_list_cleared(ModuleRig& rig) {
  for (std::uint16_t k = 0; k < v::kPointListCount; ++k) {
    if (rig.get(static_cast<std::uint16_t>(v::kPointList + k)) != 0.0) return false;
  }
  return true;
}

// Adds one point to the leveling session: 9813's #9001.
double add(ModuleRig& rig, const Vec3& p) {
  rig.set3(v::kArgX, p);
  return rig.run(9813);
}

}  // namespace

TA_TEST("macro 9810 levels a face tilted atan(0.2) and completes the handshake") {
  ModuleRig rig;
  put_inclined_face(rig);
  TA_CHECK_EQ(rig.run(9810), kDone);
  TA_CHECK_EQ(rig.get(v::kError), 0.0);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 1.0);
  TA_CHECK_EQ(rig.get(v::kRunTime), 7.0);  // one tick of the fake clock
  const double tilt = std::atan(0.2) * kRadToDeg;
  TA_CHECK_NEAR(rig.get(v::kLevelTilt), tilt, 1e-12);
  // The normal (-0.2, 0, 1)/|.| needs C = -90 and A = tilt, or C = 90 and A = -tilt.
  // From the table at zero both cost 90 + tilt degrees of travel: the tie goes to
  // solution 1 (C = atan2(nx, ny) = -90).
  TA_CHECK_NEAR(rig.get(v::kLevelC), -90.0, 1e-12);
  TA_CHECK_NEAR(rig.get(v::kLevelA), tilt, 1e-12);
  TA_CHECK_NEAR(rig.get(v::kLevelOtherC), 90.0, 1e-12);
  TA_CHECK_NEAR(rig.get(v::kLevelOtherA), -tilt, 1e-12);
  TA_CHECK_EQ(rig.get(v::kLevelPointCount), 3.0);
  TA_CHECK_EQ(rig.get(v::kLevelOtherReachable), 1.0);
  TA_CHECK_EQ(rig.get(v::kLevelAxesUsed), 0.0);
  TA_CHECK(rig.get(v::kLevelTiltSigma) > 0.0);
}

TA_TEST("macro 9810 levels random faces written into G57..G59") {
  ModuleRig rig;
  t::SplitMix64 rng(0x5EED'0002);
  for (int i = 0; i < 40; ++i) {
    TA_CASE_INDEX(i);
    const t::Face f = t::random_face(rng);
    set_signs(rig, f.a_sign, f.c_sign);
    const double done_before = rig.get(v::kDoneCount);
    TA_CHECK_EQ(run_9810(rig, f.points_machine, f.probe_a_deg, f.probe_c_deg, f.hint_machine), kDone);
    TA_CHECK_EQ(rig.get(v::kError), 0.0);
    TA_CHECK_EQ(rig.get(v::kDoneCount), done_before + 1.0);
    const double c = rig.get(v::kLevelC);
    const double a = rig.get(v::kLevelA);
    TA_CHECK(t::leveling_error_rad(f.normal_table, a, c, f.a_sign, f.c_sign) <= 1e-12);
    TA_CHECK(t::leveling_error_rad(f.normal_table, rig.get(v::kLevelOtherA), rig.get(v::kLevelOtherC), f.a_sign,
                                   f.c_sign) <= 1e-12);
    TA_CHECK(a >= -120.0 && a <= 120.0);
    TA_CHECK_NEAR(rig.get(v::kLevelNormalX), f.normal_table.x(), 1e-12);
    TA_CHECK_NEAR(rig.get(v::kLevelNormalY), f.normal_table.y(), 1e-12);
    TA_CHECK_NEAR(rig.get(v::kLevelNormalZ), f.normal_table.z(), 1e-12);
    TA_CHECK_NEAR(rig.get(v::kLevelTilt), trueaxis::core::rad_to_deg(f.tilt_rad), 1e-10);
    TA_CHECK_EQ(rig.get(v::kLevelPointCount), 3.0);
    TA_CHECK_EQ(rig.get(v::kArgA), 0.0);  // arguments are cleared after every macro
  }
}

TA_TEST("9810's #117 is the face's tilt in the machine frame where it was probed, #118 its sigma; at table zero #107, #108") {
  ModuleRig rig;
  put_inclined_face(rig);  // probed at the table's zero, the default probe repeatability
  TA_CHECK_EQ(rig.run(9810), kDone);
  TA_CHECK_EQ(rig.get(v::kLevelMachineTilt), rig.get(v::kLevelTilt));
  TA_CHECK_EQ(rig.get(v::kLevelMachineTiltSigma), rig.get(v::kLevelTiltSigma));
  TA_CHECK(rig.get(v::kLevelMachineTiltSigma) > 0.0);
  t::SplitMix64 rng(0x5EED'0117);
  for (int i = 0; i < 40; ++i) {
    TA_CASE_INDEX(i);
    const t::Face f = t::random_face(rng);
    set_signs(rig, f.a_sign, f.c_sign);
    TA_CHECK_EQ(run_9810(rig, f.points_machine, f.probe_a_deg, f.probe_c_deg, f.hint_machine), kDone);
    // The outward normal as the probe saw it, against machine +Z: no table angle enters.
    const Vec3& n = f.hint_machine;
    const double want_deg = std::atan2(std::hypot(n.x(), n.y()), n.z()) * kRadToDeg;
    TA_CHECK_NEAR(rig.get(v::kLevelMachineTilt), want_deg, 1e-10);
    TA_CHECK_NEAR(rig.get(v::kLevelTilt), trueaxis::core::rad_to_deg(f.tilt_rad), 1e-10);
    TA_CHECK_EQ(rig.get(v::kLevelMachineTiltSigma), 0.0);  // a perfect probe
  }
  // The same points in the machine frame, probed at another table pose: the
  // machine-frame tilt and its sigma do not move (an elongated triangle, so the
  // fit's two in-plane spreads differ and its axes matter).
  rig.unlock();
  rig.set(v::kProbeSigma, 0.0005);
  rig.lock();
  const Vec3 elongated[3] = {Vec3(0, 0, 5), Vec3(200, 0, 25), Vec3(0, 20, 7)};
  TA_CHECK_EQ(run_9810(rig, elongated, 0.0, 0.0, Vec3::Zero()), kDone);
  const double tilt_deg = rig.get(v::kLevelMachineTilt);
  const double sigma_arcsec = rig.get(v::kLevelMachineTiltSigma);
  TA_CHECK(sigma_arcsec > 0.0);
  TA_CHECK_EQ(run_9810(rig, elongated, 30.0, 50.0, Vec3::Zero()), kDone);
  TA_CHECK_NEAR(rig.get(v::kLevelMachineTilt), tilt_deg, 1e-12);
  TA_CHECK_NEAR(rig.get(v::kLevelMachineTiltSigma), sigma_arcsec, 1e-9 * sigma_arcsec);
  TA_CHECK(std::abs(rig.get(v::kLevelTilt) - tilt_deg) > 1.0);  // #107 is the tilt at table zero
}

TA_TEST("macro 9810 chooses the solution nearest the table's present position") {
  ModuleRig rig;
  put_inclined_face(rig);   // probed with the table at zero
  rig.set(v::kArgC, 80.0);  // ...but say it was at C = 80
  // The points are the same, so the face normal at table zero is Rz(80)^T (-0.2, 0, 1):
  // C1 = -90 + 80 = -10 or C2 = 170; from C = 80 solution 1 is nearer.
  TA_REQUIRE(rig.done(9810));
  TA_CHECK_NEAR(rig.get(v::kLevelC), -10.0, 1e-9);
  TA_CHECK_NEAR(rig.get(v::kLevelA), std::atan(0.2) * kRadToDeg, 1e-12);
  TA_CHECK_NEAR(rig.get(v::kLevelOtherC), 170.0, 1e-9);
}

namespace {

// After a 9810 that succeeded, `bad` makes the next macro fail: with status 3,
// `expected`, one more completion, and every result and stored byte as before.
template <typename Bad>
void refused_keeps_results(Bad bad, double macro, Status expected) {
  ModuleRig rig;
  put_inclined_face(rig);
  TA_REQUIRE(rig.done(9810));
  const ModuleRig::Results before = rig.results();
  bad(rig);
  rig.snapshot();
  TA_CHECK_EQ(rig.run(macro), kError);
  TA_CHECK_EQ(rig.code(), expected);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 2.0);
  TA_CHECK(rig.results() == before);
  TA_CHECK(rig.unchanged());
}

}  // namespace

TA_TEST("9810 with collinear points fails with 201 and keeps every result") {
  refused_keeps_results([](ModuleRig& rig) { rig.set3(v::kG59, Vec3(50, 0, 20)); }, 9810, Status::kPointsCollinear);
}

TA_TEST("9810 with coincident points fails with 200 and keeps every result") {
  refused_keeps_results(
      [](ModuleRig& rig) {
        rig.set3(v::kG58, Vec3(0, 0, 10));
        rig.set3(v::kG59, Vec3(0, 0, 10));
      },
      9810, Status::kPointsCoincident);
}

TA_TEST("9810 outside the A travel fails with 204 and keeps every result") {
  refused_keeps_results(
      [](ModuleRig& rig) {
        rig.unlock();
        rig.set(v::kAMin, -1.0);
        rig.set(v::kAMax, 1.0);
      },
      9810, Status::kUnreachable);
}

TA_TEST("9810 with A limits the wrong way round fails with 300 and keeps every result") {
  refused_keeps_results(
      [](ModuleRig& rig) {
        rig.unlock();
        rig.set(v::kAMin, 50.0);
        rig.set(v::kAMax, 10.0);
      },
      9810, Status::kConfigInvalid);
}

TA_TEST("9811 with a point count out of range fails with argument_out_of_range and keeps every result") {
  refused_keeps_results([](ModuleRig& rig) { rig.set(v::kArgQ, 2.0); }, 9811, Status::kArgumentOutOfRange);
}

TA_TEST("level's configuration takes only the values of its ranges") {
  ModuleRig rig;
  TA_REQUIRE(rig.unlock());
  TA_CHECK_EQ(rig.put(v::kASign, 0.5), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kASign, -1.0), F::kNone);
  TA_CHECK_EQ(rig.put(v::kProbeSigma, -0.001), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kAMin, -361.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kLevelAxes, 0.5), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kLevelAxes, 2.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.get(v::kASign), -1.0);
  TA_CHECK_EQ(rig.get(v::kProbeSigma), 0.0005);
  TA_CHECK_EQ(rig.get(v::kAMin), -120.0);
}

TA_TEST("9811 fits the point list and flags an outlier") {
  ModuleRig rig;
  double pts[3 * 8];
  for (std::size_t k = 0; k < 8; ++k) {
    const double x = 20.0 * static_cast<double>(k % 4);
    const double y = 30.0 * static_cast<double>(k / 4) + 5.0 * static_cast<double>(k % 3);
    pts[3 * k] = x;
    pts[3 * k + 1] = y;
    pts[3 * k + 2] = 0.1 * x + ((k % 2) != 0 ? 0.0004 : -0.0004);
  }
  pts[3 * 5 + 2] += 0.05;
  put_point_list(rig, pts, 8);
  rig.set(v::kArgQ, 8.0);
  TA_REQUIRE(rig.done(9811));
  TA_CHECK_EQ(rig.get(v::kLevelPointCount), 8.0);
  TA_CHECK_EQ(rig.get(v::kLevelOutlierPoint), 6.0);
  // The module publishes the core fit's flatness of the same points (wiring, not math: test_plane_fit.cpp).
  Vec3 p[8];
  for (std::size_t k = 0; k < 8; ++k) p[k] = Vec3(pts[3 * k], pts[3 * k + 1], pts[3 * k + 2]);
  const auto fit = trueaxis::core::fit_plane(p, 8);
  TA_REQUIRE(fit.ok());
  TA_CHECK_EQ(rig.get(v::kLevelFlatness), fit.value().flatness_mm);
  TA_CHECK(rig.get(v::kLevelFlatness) > 0.04);
}

TA_TEST("9811 takes Q = 32, its documented maximum, refuses 33, and clears the whole point list after each") {
  ModuleRig rig;
  double pts[v::kPointListCount];
  for (std::size_t k = 0; k < 32; ++k) {
    const double y = 10.0 * static_cast<double>(k / 8) + static_cast<double>(k % 3);
    pts[3 * k] = 10.0 * static_cast<double>(k % 8);
    pts[3 * k + 1] = y;
    pts[3 * k + 2] = 5.0 + 0.1 * y;  // tilted about X, atan(0.1)
  }
  put_point_list(rig, pts, 32);
  rig.set(v::kArgQ, 32.0);
  TA_REQUIRE(rig.done(9811));
  TA_CHECK_EQ(rig.get(v::kLevelPointCount), 32.0);
  TA_CHECK_NEAR(rig.get(v::kLevelTilt), std::atan(0.1) * kRadToDeg, 1e-12);
  TA_CHECK(point_list_cleared(rig));
  TA_CHECK_EQ(rig.get(v::kArgQ), 0.0);
  const ModuleRig::Results r = rig.results();
  put_point_list(rig, pts, 32);
  rig.set(v::kArgQ, 33.0);
  TA_CHECK_EQ(rig.refuse(9811), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == r);
  TA_CHECK(point_list_cleared(rig));
}

TA_TEST("the point list is cleared after a macro that succeeds and after one that fails") {
  ModuleRig rig;
  put_inclined_face(rig);
  double pts[v::kPointListCount];
  for (std::size_t i = 0; i < v::kPointListCount; ++i) pts[i] = 1.0 + static_cast<double>(i);
  for (const double macro : {9810.0, 1234.0}) {
    TA_CASE_INDEX(static_cast<int>(macro));
    put_point_list(rig, pts, v::kPointListCount / 3);
    rig.run(macro);
    TA_CHECK(point_list_cleared(rig));
  }
  TA_CHECK_EQ(rig.get(v::kG58 + 2), 30.0);  // work offsets are kept
}

TA_TEST("the leveling session streams points one at a time and levels through them as 9810 does") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9812));
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), 0.0);
  TA_CHECK_EQ(rig.get(v::kLevelSessionCapacity), static_cast<double>(m::level::kSessionCapacity));
  TA_CHECK_EQ(add(rig, Vec3(0, 0, 10)), kDone);
  TA_CHECK_EQ(add(rig, Vec3(100, 0, 30)), kDone);
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), 2.0);
  TA_CHECK_EQ(rig.refuse(9814), Status::kTooFewSamples);
  TA_CHECK_EQ(add(rig, Vec3(0, 100, 10)), kDone);
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), 3.0);
  TA_REQUIRE(rig.done(9814));
  const ModuleRig::Results streamed = rig.results();
  put_inclined_face(rig);  // the same three points through 9810
  TA_REQUIRE(rig.done(9810));
  TA_CHECK(rig.results() == streamed);
}

TA_TEST("the leveling session refuses a point at its capacity and keeps the others; 9812 empties it") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9812));
  for (std::size_t k = 0; k < m::level::kSessionCapacity; ++k) {
    const double x = 10.0 * static_cast<double>(k % 8);
    TA_REQUIRE(add(rig, Vec3(x, 10.0 * static_cast<double>(k / 8), 0.1 * x)) == kDone);
  }
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), static_cast<double>(m::level::kSessionCapacity));
  rig.set3(v::kArgX, Vec3(1, 2, 3));
  TA_CHECK_EQ(rig.refuse(9813), Status::kSessionFull);
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), static_cast<double>(m::level::kSessionCapacity));
  TA_REQUIRE(rig.done(9814));
  TA_CHECK_EQ(rig.get(v::kLevelPointCount), static_cast<double>(m::level::kSessionCapacity));
  TA_CHECK_NEAR(rig.get(v::kLevelTilt), std::atan(0.1) * kRadToDeg, 1e-12);
  TA_REQUIRE(rig.done(9812));
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), 0.0);
  TA_CHECK_EQ(rig.refuse(9814), Status::kTooFewSamples);
}

namespace {

// Five touches of a ball of radius 13 (a 25 mm ball, a 1 mm stylus tip) at
// (120, -40, 75): the pole and four 30 deg below the equator.
void put_ball_touches(ModuleRig& rig, double radius = 13.0) {
  const Vec3 centre(120.0, -40.0, 75.0);
  const double c = std::cos(trueaxis::core::kPi / 6.0);
  const double s = std::sin(trueaxis::core::kPi / 6.0);
  const Vec3 dirs[5] = {Vec3(0, 0, 1), Vec3(c, 0, -s), Vec3(0, c, -s), Vec3(-c, 0, -s), Vec3(0, -c, -s)};
  rig.done(9812);
  for (const Vec3& d : dirs) add(rig, centre + radius * d);
}

}  // namespace

TA_TEST("9815 finds the ball's centre from the session's touches, with the core fit's sigmas") {
  ModuleRig rig;
  put_ball_touches(rig);
  TA_REQUIRE(rig.done(9815));
  TA_CHECK_NEAR(rig.get(v::kBallCentreX), 120.0, 1e-10);
  TA_CHECK_NEAR(rig.get(v::kBallCentreY), -40.0, 1e-10);
  TA_CHECK_NEAR(rig.get(v::kBallCentreZ), 75.0, 1e-10);
  TA_CHECK_NEAR(rig.get(v::kBallRadius), 13.0, 1e-10);
  TA_CHECK_EQ(rig.get(v::kBallPointCount), 5.0);
  TA_CHECK(rig.get(v::kBallRmsResidual) < 1e-10);
  // The sigmas are the core fit's with #506 (0.5 um by default) as the touches' noise.
  const Vec3 touches[5] = {Vec3(120, -40, 88), Vec3(120 + 13 * std::cos(trueaxis::core::kPi / 6), -40, 68.5),
                           Vec3(120, -40 + 13 * std::cos(trueaxis::core::kPi / 6), 68.5),
                           Vec3(120 - 13 * std::cos(trueaxis::core::kPi / 6), -40, 68.5),
                           Vec3(120, -40 - 13 * std::cos(trueaxis::core::kPi / 6), 68.5)};
  const auto direct = trueaxis::core::fit_sphere(touches, 5, 0.0, 0.0005);
  TA_REQUIRE(direct.ok());
  TA_CHECK_NEAR(rig.get(v::kBallCentreSigmaX), direct.value().centre_sigma_mm.x(), 1e-12);
  TA_CHECK_NEAR(rig.get(v::kBallCentreSigmaZ), direct.value().centre_sigma_mm.z(), 1e-12);
  TA_CHECK_NEAR(rig.get(v::kBallRadiusSigma), direct.value().radius_sigma_mm, 1e-12);
  TA_CHECK(rig.get(v::kBallCentreSigmaZ) > 0.0);
  // R fixes the radius: a sphere of 13.002 through touches at 13 puts the centre
  // 2 um lower along the mean touch direction's opposite, and reports R.
  put_ball_touches(rig);
  rig.set(v::kArgR, 13.002);
  TA_REQUIRE(rig.done(9815));
  TA_CHECK_EQ(rig.get(v::kBallRadius), 13.002);
  TA_CHECK_EQ(rig.get(v::kBallRadiusSigma), 0.0);
  TA_CHECK(rig.get(v::kBallRmsResidual) > 1e-4);
}

TA_TEST("9815 refuses three touches, touches on one circle and a negative R, keeping the session") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9812));
  add(rig, Vec3(10, 0, 5));
  add(rig, Vec3(0, 10, 5));
  add(rig, Vec3(-10, 0, 5));
  TA_CHECK_EQ(rig.refuse(9815), Status::kTooFewSamples);
  add(rig, Vec3(0, -10, 5));
  TA_CHECK_EQ(rig.refuse(9815), m::level::kTouchesCoplanar);
  TA_CHECK_EQ(rig.get(v::kLevelSessionCount), 4.0);  // results as they were: 9813 put the count in #100
  add(rig, Vec3(0, 0, 15));
  rig.set(v::kArgR, -1.0);
  TA_CHECK_EQ(rig.refuse(9815), Status::kArgumentOutOfRange);
  TA_REQUIRE(rig.done(9815));  // the five touches are still there
  TA_CHECK_NEAR(rig.get(v::kBallCentreZ), 5.0, 1e-10);
  TA_CHECK_NEAR(rig.get(v::kBallRadius), 10.0, 1e-10);
}

// ---- recipes (method_tests.hpp) ------------------------------------------------------------

TA_TEST("9816 judges the face probed again after leveling: level passes, 20 arcsec off fails, in between as check.hpp says") {
  // A face 100 mm square at the table's zero (A = C = 0), its tilt about Y.
  const auto face = [](ModuleRig& rig, double tilt_arcsec) {
    TA_REQUIRE(rig.done(9812));
    const double slope = std::tan(tilt_arcsec / 3600.0 / kRadToDeg);
    for (const Vec3& p : {Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(0, 100, 0), Vec3(100, 100, 0)}) {
      TA_REQUIRE(add(rig, Vec3(p.x(), p.y(), 40.0 + slope * p.x())) == kDone);
    }
  };
  ModuleRig rig;
  TA_REQUIRE(rig.done(9812));
  TA_CHECK_EQ(add(rig, Vec3(0, 0, 40)), kDone);
  TA_CHECK_EQ(rig.refuse(9816), Status::kTooFewSamples);
  face(rig, 0.0);
  TA_REQUIRE(rig.done(9816));
  TA_CHECK_EQ(rig.get(v::kCheckVerdict), 0.0);
  TA_CHECK_EQ(rig.get(v::kCheckFigures), 1.0);
  TA_CHECK_NEAR(rig.get(v::kCheckFigureDeviation), 0.0, 1e-9);
  TA_CHECK_EQ(rig.get(v::kCheckFigureTolerance), 10.0);
  face(rig, 20.0);
  TA_REQUIRE(rig.done(9816));
  TA_CHECK_EQ(rig.get(v::kCheckVerdict), 2.0);
  TA_CHECK_NEAR(rig.get(v::kCheckFigureDeviation), 20.0, 1e-6);
  TA_CHECK(rig.get(v::kCheckFigureSigma) > 0.0);
  TA_REQUIRE(rig.done(9814));  // the check's figure is 9814's #117 and #118
  const double tilt = rig.get(v::kLevelMachineTilt) * 3600.0;
  const double sigma = rig.get(v::kLevelMachineTiltSigma);
  TA_CHECK_NEAR(tilt, 20.0, 1e-6);
  // Just inside the tolerance by less than 2 sigma: warn.
  face(rig, 10.0 - sigma);
  TA_REQUIRE(rig.done(9816));
  TA_CHECK_EQ(rig.get(v::kCheckVerdict), 1.0);
  rig.set(v::kArgQ, 2.0);
  TA_CHECK_EQ(rig.refuse(9816), Status::kArgumentOutOfRange);
}

namespace {

void level_pose(ModuleRig& rig) {
  put_inclined_face(rig);
  rig.set(v::kArgA, 0.0);
  rig.set(v::kArgC, 0.0);
}
void level_point_list(ModuleRig& rig) {
  double pts[3 * 8];
  for (std::size_t k = 0; k < 8; ++k) {
    const double x = 20.0 * static_cast<double>(k % 4);
    pts[3 * k] = x;
    pts[3 * k + 1] = 30.0 * static_cast<double>(k / 4) + 5.0 * static_cast<double>(k % 3);
    pts[3 * k + 2] = 0.1 * x + ((k % 2) != 0 ? 0.0004 : -0.0004);
  }
  put_point_list(rig, pts, 8);
  rig.set(v::kArgQ, 8.0);
}
void level_session_point(ModuleRig& rig) { rig.set3(v::kArgX, Vec3(1, 2, 3)); }
void level_session_of_three(ModuleRig& rig) {
  rig.done(9812);
  add(rig, Vec3(0, 0, 10));
  add(rig, Vec3(100, 0, 30));
  add(rig, Vec3(0, 100, 10));
}

void level_ball_touches(ModuleRig& rig) { put_ball_touches(rig); }

}  // namespace

TA_RECIPE(9810, nullptr, level_pose);
TA_RECIPE(9811, nullptr, level_point_list);
TA_RECIPE(9812, nullptr, nullptr);
TA_RECIPE(9813, nullptr, level_session_point);
TA_RECIPE(9814, level_session_of_three, nullptr);
TA_RECIPE(9815, level_ball_touches, nullptr);
TA_RECIPE(9816, level_session_of_three, nullptr);  // an inclined face: the check fails, the macro succeeds
