// The virtual machine itself: its geometry must be what cradle_machine.hpp says,
// or every ground-truth comparison in the other tests means nothing.
#include <catch2/catch.hpp>

#include <cmath>

#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/instruments/touch_probe.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"

namespace {

using trueaxis::core::Vec3;
using trueaxis::sim::CradleMachine;
using trueaxis::sim::FaceConfig;
using trueaxis::sim::SimRng;
using trueaxis::sim::TouchProbe;

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("the face normal at table zero follows tilt and azimuth") {
  const CradleMachine m(FaceConfig{12.5, 30.0, 40.0});
  const Vec3 n = m.normal_table();
  CHECK(n.norm() == Approx(1.0).epsilon(1e-15));
  CHECK(std::acos(n.z()) * 180.0 / kPi == Approx(12.5).epsilon(1e-12));
  CHECK(std::atan2(n.y(), n.x()) * 180.0 / kPi == Approx(30.0).epsilon(1e-12));
  CHECK(m.tilt_deg_at(0.0, 0.0) == Approx(12.5).epsilon(1e-12));
}

TEST_CASE("turning the table to the docs/METHODS.md M1 angles makes the face level") {
  for (double azimuth : {-170.0, -90.0, 0.0, 30.0, 135.0}) {
    const CradleMachine m(FaceConfig{20.0, azimuth, 40.0});
    const Vec3 n = m.normal_table();
    const double c1 = std::atan2(n.x(), n.y()) * 180.0 / kPi;
    const double a1 = std::atan2(std::hypot(n.x(), n.y()), n.z()) * 180.0 / kPi;
    CHECK(m.tilt_deg_at(a1, c1) < 1e-9);
    CHECK(m.tilt_deg_at(-a1, c1 + 180.0) < 1e-9);
  }
}

TEST_CASE("rotations are right-handed: +A turns +Y towards +Z, +C turns +X towards +Y") {
  const Vec3 y = CradleMachine::table_rotation(90.0, 0.0) * Vec3::UnitY();
  CHECK(y.z() == Approx(1.0));
  const Vec3 x = CradleMachine::table_rotation(0.0, 90.0) * Vec3::UnitX();
  CHECK(x.y() == Approx(1.0));
}

TEST_CASE("a touch point lies on the face and below the probe") {
  const CradleMachine m(FaceConfig{12.5, 30.0, 40.0});
  for (double a : {0.0, 10.0, -30.0}) {
    Vec3 p;
    REQUIRE(TouchProbe::touch(m.face_at(a, 45.0), 25.0, -10.0, p));
    CHECK(p.x() == 25.0);
    CHECK(p.y() == -10.0);
    const auto R = CradleMachine::table_rotation(a, 45.0);
    const Vec3 p_table = R.transpose() * p;
    CHECK(m.normal_table().dot(p_table - Vec3(0.0, 0.0, 40.0)) == Approx(0.0).margin(1e-12));
  }
}

TEST_CASE("the probe refuses a face too steep to touch from above") {
  const CradleMachine m(FaceConfig{12.5, 90.0, 40.0});
  Vec3 p(1.0, 2.0, 3.0);
  CHECK_FALSE(TouchProbe::touch(m.face_at(-70.0, 0.0), 0.0, 0.0, p));  // 82.5 deg
  CHECK(p == Vec3(1.0, 2.0, 3.0));
  CHECK(TouchProbe::touch(m.face_at(-60.0, 0.0), 0.0, 0.0, p));  // 72.5 deg
}

TEST_CASE("the noise generator is deterministic and has unit variance") {
  SimRng a(7);
  SimRng b(7);
  double sum = 0.0;
  double sum_sq = 0.0;
  constexpr int kN = 200000;
  for (int i = 0; i < kN; ++i) {
    const double x = a.normal();
    REQUIRE(x == b.normal());
    sum += x;
    sum_sq += x * x;
  }
  CHECK(std::abs(sum / kN) < 0.01);
  CHECK(sum_sq / kN == Approx(1.0).epsilon(0.02));
}

TEST_CASE("with no errors the true machine is Rx(A) Rz(C) about the origin, bit for bit") {
  const CradleMachine m(FaceConfig{12.5, 30.0, 40.0});
  SimRng rng(11);
  for (int i = 0; i < 200; ++i) {
    const double a = i < 4 ? 90.0 * i - 120.0 : 240.0 * rng.uniform01() - 120.0;
    const double c = 720.0 * rng.uniform01() - 360.0;
    const auto machine_T = m.machine_T_table(a, c);
    INFO("A " << a << " C " << c);
    REQUIRE((machine_T.rotation == CradleMachine::table_rotation(a, c)));
    REQUIRE(machine_T.translation_mm == Vec3::Zero());
    // Against an independent closed form in long double: Rx(A) Rz(C) p expanded.
    const long double ar = static_cast<long double>(a) * 3.14159265358979323846264338327950288L / 180.0L;
    const long double cr = static_cast<long double>(c) * 3.14159265358979323846264338327950288L / 180.0L;
    const long double px = 200.0L, py = -30.0L, pz = 50.0L;
    const long double x = std::cos(cr) * px - std::sin(cr) * py;
    const long double y = std::sin(cr) * px + std::cos(cr) * py;
    const Vec3 expected(static_cast<double>(x), static_cast<double>(std::cos(ar) * y - std::sin(ar) * pz),
                        static_cast<double>(std::sin(ar) * y + std::cos(ar) * pz));
    trueaxis::sim::CalibrationBall ball;
    ball.centre_table_mm = Vec3(200.0, -30.0, 50.0);
    CHECK((ball.centre_mm(m.machine_T_table(a, c)) - expected).norm() < 1e-12);
    CHECK(m.actual_a_deg(a) == a);
  }
  CHECK(m.a_axis().point_mm == Vec3::Zero());
  CHECK(m.a_axis().direction == Vec3::UnitX());
  CHECK(m.c_to_a_offset_mm() == 0.0);
  CHECK(m.c_to_a_squareness_arcsec() == Approx(0.0).margin(1e-9));
  for (double a : {-90.0, -30.0, 45.0, 120.0}) {
    CHECK(m.rotation_vector_rad(a, 50.0).norm() < 1e-15);
    CHECK(m.a_positioning_error_arcsec(a, 50.0) == Approx(0.0).margin(1e-9));
  }
}
