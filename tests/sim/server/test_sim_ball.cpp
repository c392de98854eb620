// The calibration ball and the machine's errors over the simulator's variables
// (#12020..#12062, simulator.hpp contracts 4-5 and 7), without a socket.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <vector>

#include "fakes.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/server/simulator.hpp"

namespace {

using trueaxis::core::Vec3;
using trueaxis::macros::AccessFault;
using trueaxis::sim::CradleMachine;
using trueaxis::sim::FaceConfig;
namespace simvar = trueaxis::sim::simvar;

constexpr double kArcsecPerRad = trueaxis::sim::kArcsecPerRad;

struct Bench {
  explicit Bench(std::uint64_t seed = 1, bool errors_on = false) : simulator{module, FaceConfig{}, seed, errors_on} {}

  trueaxis::test::ModuleRig rig;
  trueaxis::macros::Module& module = rig.module();
  trueaxis::sim::Simulator simulator;

  AccessFault write(std::uint16_t first, std::initializer_list<double> values) {
    const std::vector<double> v(values);
    return simulator.write(first, static_cast<std::uint16_t>(v.size()), v.data());
  }

  Vec3 last_ball() const {
    return Vec3(simulator.value(simvar::kLastBallX), simulator.value(simvar::kLastBallY),
                simulator.value(simvar::kLastBallZ));
  }

  Vec3 measure_at(double a_deg, double c_deg) {
    REQUIRE(write(simvar::kAxisA, {a_deg, c_deg}) == AccessFault::kNone);
    REQUIRE(write(simvar::kBallMeasure, {1.0}) == AccessFault::kNone);
    return last_ball();
  }

  std::vector<double> all_values() const {
    std::vector<double> v;
    for (std::uint16_t n = simvar::kFirst; n <= simvar::kLast; ++n) v.push_back(simulator.value(n));
    return v;
  }
};

}  // namespace

TEST_CASE("the map's ball defaults are CalibrationBall's") {
  Bench b;
  CHECK(b.simulator.value(simvar::kBallX) == trueaxis::sim::kDefaultBallXMm);
  CHECK(b.simulator.value(simvar::kBallY) == trueaxis::sim::kDefaultBallYMm);
  CHECK(b.simulator.value(simvar::kBallZ) == trueaxis::sim::kDefaultBallZMm);
  CHECK(b.simulator.value(simvar::kBallSigma) == trueaxis::sim::kDefaultBallSigmaMm);
  CHECK(b.simulator.value(simvar::kErrors) == 0.0);
}

TEST_CASE("sim_ball_measure measures the ball at the commanded axes") {
  Bench b;
  REQUIRE(b.write(simvar::kBallX, {150.0, 20.0, 60.0, 0.0}) == AccessFault::kNone);  // sigma 0
  const Vec3 p = b.measure_at(30.0, 45.0);
  CHECK(p == CradleMachine::table_rotation(30.0, 45.0) * Vec3(150.0, 20.0, 60.0));
  SECTION("with noise, within a few sigma of the truth") {
    REQUIRE(b.write(simvar::kBallSigma, {0.001}) == AccessFault::kNone);
    CHECK((b.measure_at(30.0, 45.0) - p).cwiseAbs().maxCoeff() < 0.006);
  }
  SECTION("writing 0 measures nothing") {
    REQUIRE(b.write(simvar::kAxisA, {-60.0}) == AccessFault::kNone);
    REQUIRE(b.write(simvar::kBallMeasure, {0.0}) == AccessFault::kNone);
    CHECK(b.last_ball() == p);
  }
  SECTION("one write switching the errors and moving the ball measures after both") {
    REQUIRE(b.write(simvar::kAxisA, {90.0, 0.0}) == AccessFault::kNone);
    REQUIRE(b.write(simvar::kErrors, {1.0, 100.0, 0.0, 10.0, 0.0, 1.0}) == AccessFault::kNone);
    trueaxis::sim::CalibrationBall ball;
    ball.centre_table_mm = Vec3(100.0, 0.0, 10.0);
    const CradleMachine real(FaceConfig{}, trueaxis::sim::realistic_errors());
    CHECK(b.last_ball() == ball.centre_mm(real.machine_T_table(90.0, 0.0)));
  }
}

TEST_CASE("the same seed gives the same measurements, another seed others") {
  Bench one(7);
  Bench two(7);
  Bench other(8);
  for (double c : {0.0, 90.0, 180.0}) {
    const Vec3 p = one.measure_at(20.0, c);
    CHECK(two.measure_at(20.0, c) == p);
    CHECK(other.measure_at(20.0, c) != p);
  }
}

TEST_CASE("sim_errors switches the machine and the ground truth follows it") {
  Bench b;
  const Vec3 ideal = b.measure_at(90.0, 0.0);
  REQUIRE(b.write(simvar::kErrors, {1.0}) == AccessFault::kNone);
  const Vec3 real = b.measure_at(90.0, 0.0);
  // Tens of micrometres apart at 200 mm (beyond the instrument's 1 um noise).
  CHECK((real - ideal).norm() > 0.02);
  CHECK((real - ideal).norm() < 0.2);

  const CradleMachine m(FaceConfig{}, trueaxis::sim::realistic_errors());
  const Vec3 rv = m.rotation_vector_rad(90.0, 50.0) * kArcsecPerRad;
  CHECK(b.simulator.value(simvar::kTrueRotvecX) == rv.x());
  CHECK(b.simulator.value(simvar::kTrueRotvecY) == rv.y());
  CHECK(b.simulator.value(simvar::kTrueRotvecZ) == rv.z());
  CHECK(b.simulator.value(simvar::kTrueAPositioningError) == m.a_positioning_error_arcsec(90.0, 50.0));
  CHECK(b.simulator.value(simvar::kTrueADriveError) == Approx(7.0));
  CHECK(b.simulator.value(simvar::kTrueCToAOffset) == Approx(0.025).margin(1e-6));
  CHECK(b.simulator.value(simvar::kTrueCToASquareness) == Approx(15.0).margin(1e-3));
  CHECK(b.simulator.value(simvar::kTrueAPointY) == 0.010);
  CHECK(b.simulator.value(simvar::kTrueADirY) == m.a_axis().direction.y());
  CHECK(b.simulator.value(simvar::kTrueCCentreY) == m.c_centre_at(90.0, 50.0).y());
  CHECK(b.simulator.value(simvar::kTrueCDirZ) == m.c_axis_at(90.0).direction.z());
  SECTION("the truth is for a ball at sim_ball_z") {
    REQUIRE(b.write(simvar::kBallZ, {120.0}) == AccessFault::kNone);
    CHECK(b.simulator.value(simvar::kTrueRotvecX) == m.rotation_vector_rad(90.0, 120.0).x() * kArcsecPerRad);
  }
  SECTION("at the reference pose the rotation vector reads exactly zero") {
    REQUIRE(b.write(simvar::kAxisA, {0.0, 123.0}) == AccessFault::kNone);
    for (std::uint16_t n = simvar::kTrueRotvecX; n <= simvar::kTrueAPositioningError; ++n) {
      CHECK(b.simulator.value(n) == 0.0);
    }
  }
  SECTION("back to 0, the ideal machine and its truth") {
    REQUIRE(b.write(simvar::kErrors, {0.0}) == AccessFault::kNone);
    CHECK(b.simulator.value(simvar::kTrueADirX) == 1.0);
    CHECK(b.simulator.value(simvar::kTrueCToAOffset) == 0.0);
    CHECK(std::abs(b.simulator.value(simvar::kTrueRotvecX)) < 1e-9);
  }
}

TEST_CASE("a simulator started with errors on has them from the start") {
  Bench b(1, true);
  CHECK(b.simulator.value(simvar::kErrors) == 1.0);
  CHECK(b.simulator.value(simvar::kTrueADriveError) == Approx(2.0));
  CHECK(b.simulator.machine().errors().c_offset_mm == 0.025);
}

TEST_CASE("bad ball, sigma, measure and error values are refused and change nothing") {
  Bench b;
  const Vec3 first = b.measure_at(10.0, 20.0);
  const std::vector<double> before = b.all_values();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(b.write(simvar::kBallX, {nan}) == AccessFault::kNotFinite);
  CHECK(b.write(simvar::kBallZ, {-inf}) == AccessFault::kNotFinite);
  CHECK(b.write(simvar::kBallY, {1000.5}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kBallSigma, {-0.001}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kBallSigma, {1.5}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kBallMeasure, {2.0}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kBallMeasure, {0.5}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kErrors, {2.0}) == AccessFault::kOutOfRange);
  CHECK(b.write(simvar::kErrors, {-1.0}) == AccessFault::kOutOfRange);
  // A measure request beside a bad value is refused whole: nothing measured.
  CHECK(b.write(simvar::kBallSigma, {0.01, 1.0, 0.0}) == AccessFault::kReadOnly);
  CHECK(b.write(simvar::kErrors, {1.0, 5.0, 5.0, 5.0, 0.001, 1.0, 0.0}) == AccessFault::kReadOnly);
  CHECK(b.write(simvar::kBallZ, {5.0, nan, 1.0}) == AccessFault::kNotFinite);
  CHECK(b.write(simvar::kErrors, {1.0, 5.0, 5.0, 5.0, 0.001, 3.0}) == AccessFault::kOutOfRange);
  for (std::uint16_t n = simvar::kLastBallX; n <= simvar::kLastBallZ; ++n) {
    CHECK(b.write(n, {0.0}) == AccessFault::kReadOnly);
  }
  for (std::uint16_t n = simvar::kTrueRotvecX; n <= simvar::kBallMachineZ; ++n) {
    CHECK(b.write(n, {0.0}) == AccessFault::kReadOnly);
  }
  CHECK(b.write(simvar::kDriftA, {60.0, 3601.0}) == AccessFault::kOutOfRange);  // sim_drift_arcsec beyond 1 deg
  for (std::uint16_t n = simvar::kTrueTilt + 1; n < simvar::kErrors; ++n) {
    double out = 0.0;
    CHECK(b.simulator.read(n, 1, &out) == AccessFault::kUndefined);
    CHECK(b.write(n, {0.0}) == AccessFault::kUndefined);
  }
  CHECK(b.all_values() == before);
  // And no deviate was drawn: the next measurement is a fresh simulator's second.
  Bench fresh;
  (void)fresh.measure_at(10.0, 20.0);
  CHECK(b.measure_at(10.0, 20.0) == fresh.measure_at(10.0, 20.0));
  CHECK(first != b.last_ball());
}

TEST_CASE("the face's plane and the ball's centre for an outside probe follow the table and the errors") {
  // #12048..#12054 (the LinuxCNC machine's virtual probe): on the ideal machine,
  // Rx(A) Rz(C) of the table-frame face and ball, computed here independently.
  Bench b;
  REQUIRE(b.write(simvar::kAxisA, {30.0, 45.0}) == AccessFault::kNone);
  const double a = 30.0 * M_PI / 180.0;
  const double c = 45.0 * M_PI / 180.0;
  auto turn = [&](const Vec3& p) {
    const Vec3 q(std::cos(c) * p.x() - std::sin(c) * p.y(), std::sin(c) * p.x() + std::cos(c) * p.y(), p.z());
    return Vec3(q.x(), std::cos(a) * q.y() - std::sin(a) * q.z(), std::sin(a) * q.y() + std::cos(a) * q.z());
  };
  const double t = 12.5 * M_PI / 180.0;
  const double az = 30.0 * M_PI / 180.0;
  const Vec3 n = turn(Vec3(std::sin(t) * std::cos(az), std::sin(t) * std::sin(az), std::cos(t)));
  CHECK(b.simulator.value(simvar::kFaceNormalX) == Approx(n.x()).margin(1e-15));
  CHECK(b.simulator.value(simvar::kFaceNormalY) == Approx(n.y()).margin(1e-15));
  CHECK(b.simulator.value(simvar::kFaceNormalZ) == Approx(n.z()).margin(1e-15));
  CHECK(b.simulator.value(simvar::kFaceOffset) == Approx(n.dot(turn(Vec3(0, 0, 40)))).margin(1e-12));
  const Vec3 ball = turn(Vec3(200, 0, 50));
  CHECK(b.simulator.value(simvar::kBallMachineX) == Approx(ball.x()).margin(1e-12));
  CHECK(b.simulator.value(simvar::kBallMachineY) == Approx(ball.y()).margin(1e-12));
  CHECK(b.simulator.value(simvar::kBallMachineZ) == Approx(ball.z()).margin(1e-12));
  // The realistic machine: the ball the instrument measures (1 um noise) and the
  // probe's face are the true machine's, tens of micrometres off the ideal.
  REQUIRE(b.write(simvar::kErrors, {1.0}) == AccessFault::kNone);
  const Vec3 real(b.simulator.value(simvar::kBallMachineX), b.simulator.value(simvar::kBallMachineY),
                  b.simulator.value(simvar::kBallMachineZ));
  CHECK((real - ball).norm() > 0.02);
  const Vec3 measured = b.measure_at(30.0, 45.0);
  CHECK((measured - real).norm() < 0.006);
  const CradleMachine m(FaceConfig{}, trueaxis::sim::realistic_errors());
  const auto face = m.face_at(30.0, 45.0);
  CHECK(b.simulator.value(simvar::kFaceOffset) == face.normal.dot(face.point_mm));
}

TEST_CASE("sim_tip_error: the realistic spindle's tool tip error at sim_spindle_angle and sim_tool_length, 0 without") {
  Bench b;
  const trueaxis::sim::VirtualSpindle spindle(trueaxis::sim::realistic_spindle());
  CHECK(b.simulator.value(simvar::kTipErrorX) == 0.0);  // sim_spindle = 0 at start: no spindle errors
  REQUIRE(b.write(simvar::kSpindle, {1.0}) == AccessFault::kNone);
  for (const double phi : {0.0, 90.0, 217.5, 725.0}) {
    for (const double tool : {0.0, 100.0, 250.0}) {
      REQUIRE(b.write(simvar::kSpindleAngle, {phi, tool}) == AccessFault::kNone);
      const trueaxis::core::Vec3 truth = spindle.tool_tip_error_mm(tool, phi);
      CHECK(b.simulator.value(simvar::kTipErrorX) == truth.x());
      CHECK(b.simulator.value(simvar::kTipErrorY) == truth.y());
      CHECK(b.simulator.value(simvar::kTipErrorZ) == truth.z());
    }
  }
  CHECK(b.write(simvar::kTipErrorX, {0.0}) != AccessFault::kNone);  // ground truth is read-only
  REQUIRE(b.write(simvar::kSpindle, {0.0}) == AccessFault::kNone);
  CHECK(b.simulator.value(simvar::kTipErrorY) == 0.0);
}
