// The virtual gantry's sub-machine heads and linear axes (gantry_machine.hpp
// conventions 5-7): each error term alone, against closed forms, circumcentres of
// three points and the lines' 2x2 normal equations; and the realistic set's sizes.
#include <catch2/catch.hpp>

#include <cmath>

#include "gantry_geometry.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"

namespace {

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;
using trueaxis::sim::GantryConfig;
using trueaxis::sim::GantryMachine;
using trueaxis::sim::SubMachineConfig;
using trueaxis::sim::SubMachineTruth;

using namespace trueaxis::test::gantry;  // NOLINT: the closed forms these tests check against

GantryMachine with_sub_errors(void (*set)(SubMachineConfig&)) {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  for (auto& s : c.sub_machines) set(s);
  return GantryMachine(c);
}

Mat3 turn(const Vec3& rotation_arcsec) {
  const Vec3 w = rotation_arcsec * kRadPerArcsec;
  return Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
}

}  // namespace

TEST_CASE("the head rotation turns C and A but not the linear axes") {
  const GantryMachine m = with_sub_errors([](SubMachineConfig& s) { s.head_rotation_arcsec = Vec3(10.0, -14.0, 6.0); });
  const Mat3 r = turn(Vec3(10.0, -14.0, 6.0));
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    const SubMachineConfig& s = m.config().sub_machines[i];
    CHECK((t.c_dir - r * s.tool_nominal).norm() < 1e-15);
    CHECK((t.a_dir - r * s.a_nominal).norm() < 1e-15);
    CHECK((t.axes - Mat3::Identity()).norm() == 0.0);
    CHECK(angle_arcsec(t.c_dir, s.tool_nominal) > 10.0);
    CHECK(t.a_c_angle_deg == Approx(90.0).epsilon(1e-14));
  }
}

TEST_CASE("the A-to-C angle error tilts A towards C by that angle, A still through the wrist") {
  const GantryMachine m = with_sub_errors([](SubMachineConfig& s) { s.a_c_angle_error_arcsec = 25.0; });
  const double delta = 25.0 * kRadPerArcsec;
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    CHECK(t.a_dir.dot(t.c_dir) == Approx(-std::sin(delta)).epsilon(1e-9));
    CHECK(t.a_c_angle_deg == Approx(90.0 + 25.0 / 3600.0).epsilon(1e-14));
    CHECK(t.a_c_offset_mm == 0.0);
    // The SMR's A circle: centre on the A line through the wrist, normal a for increasing A.
    Vec3 n;
    const Vec3 centre = circumcentre(m.smr(i, Vec3::Zero(), -60.0, 0.0), m.smr(i, Vec3::Zero(), 10.0, 0.0),
                                     m.smr(i, Vec3::Zero(), 70.0, 0.0), n);
    CHECK(distance_to_line(centre, t.wrist_mm, t.a_dir) < 1e-9);
    CHECK((n - t.a_dir).norm() < 1e-12);
  }
}

TEST_CASE("the A-to-C offset is the common perpendicular's length, its foot on C the wrist") {
  const GantryMachine ideal(trueaxis::sim::ideal_gantry());
  const GantryMachine m = with_sub_errors([](SubMachineConfig& s) {
    s.a_c_offset_mm = -0.031;
    s.a_c_angle_error_arcsec = 18.0;
    s.head_rotation_arcsec = Vec3(5.0, 0.0, -13.0);
  });
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    // Closest points of the two lines from the 2x2 normal equations.
    const Vec3 w = t.wrist_mm - t.a_point_mm;
    const double b = t.a_dir.dot(t.c_dir);
    const double d = t.a_dir.dot(w);
    const double f = t.c_dir.dot(w);
    const double s = (d - b * f) / (1.0 - b * b);  // along A from a_point
    const double u = (b * d - f) / (1.0 - b * b);  // along C from the wrist
    const Vec3 gap = (t.wrist_mm + u * t.c_dir) - (t.a_point_mm + s * t.a_dir);
    CHECK(gap.norm() == Approx(0.031).epsilon(1e-9));
    CHECK(t.a_c_offset_mm == Approx(0.031).epsilon(1e-15));
    CHECK(std::abs(u) < 1e-12);
    // O_sp is the swing length down C from the wrist, whatever A does.
    CHECK((t.origin_mm - (ideal.truth(i).wrist_mm + m.config().sub_machines[i].swing_mm * t.c_dir)).norm() < 1e-12);
    Vec3 n;
    const Vec3 centre = circumcentre(m.smr(i, Vec3::Zero(), -90.0, 0.0), m.smr(i, Vec3::Zero(), 0.0, 0.0),
                                     m.smr(i, Vec3::Zero(), 45.0, 0.0), n);
    CHECK(distance_to_line(centre, t.a_point_mm, t.a_dir) < 1e-9);
    CHECK(distance_to_line(centre, t.wrist_mm, t.a_dir) == Approx(0.031).epsilon(1e-6));
  }
}

TEST_CASE("a linear axis moves the head along its true direction, bowed by its bow") {
  const GantryMachine m = with_sub_errors([](SubMachineConfig& s) {
    s.mount_rotation_arcsec = Vec3(7.0, 18.0, -25.0);
    s.squareness_xy_arcsec = 20.0;
    s.squareness_yz_arcsec = 14.0;
    s.squareness_zx_arcsec = 27.0;
  });
  GantryConfig bowed_config = m.config();
  for (auto& s : bowed_config.sub_machines) s.bow_mm = Vec3(0.0015, 0.002, 0.001);
  const GantryMachine bowed(bowed_config);
  const Vec3 p_home(10.0, -20.0, 30.0);
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    const SubMachineConfig& s = m.config().sub_machines[i];
    const Vec3 d[3] = {t.d_x, t.d_y, t.d_z};
    for (int k = 0; k < 3; ++k) {
      Vec3 q = Vec3::Zero();
      q[k] = s.stroke_max_mm[k] - 1.0;
      // Rigidly translated, also with A and C away from zero.
      CHECK((m.head_point(i, q, 30.0, 50.0, p_home) - m.head_point(i, Vec3::Zero(), 30.0, 50.0, p_home) -
             q[k] * d[k]).norm() < 1e-10);
      // Bowed: straight between the stroke's ends, |bow| off at mid-stroke, across the axis.
      Vec3 lo = Vec3::Zero(), mid = Vec3::Zero(), hi = Vec3::Zero();
      lo[k] = s.stroke_min_mm[k];
      hi[k] = s.stroke_max_mm[k];
      mid[k] = 0.5 * (lo[k] + hi[k]);
      const Vec3 p_lo = bowed.smr(i, lo, 0.0, 0.0);
      const Vec3 p_hi = bowed.smr(i, hi, 0.0, 0.0);
      CHECK(((p_hi - p_lo) / (hi[k] - lo[k]) - d[k]).norm() < 1e-14);
      const double bow = bowed_config.sub_machines[i].bow_mm[k];
      CHECK(distance_to_line(bowed.smr(i, mid, 0.0, 0.0), p_lo, d[k]) == Approx(bow).epsilon(1e-6));
    }
    // At home the bow changes nothing.
    CHECK((bowed.smr(i, Vec3::Zero(), 0.0, 0.0) - t.smr_home_mm).norm() == 0.0);
  }
}

TEST_CASE("the realistic set is of the sizes issue 6 asks for") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const Vec3 nominal[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  double mean_off_arcsec = 0.0;  // over the 12 linear axes
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    const SubMachineConfig& s = m.config().sub_machines[i];
    INFO("sub-machine " << t.id);
    const Vec3 d[3] = {t.d_x, t.d_y, t.d_z};
    for (int k = 0; k < 3; ++k) {
      CHECK(angle_arcsec(d[k], nominal[k]) > 5.0);
      CHECK(angle_arcsec(d[k], nominal[k]) < 80.0);
      mean_off_arcsec += angle_arcsec(d[k], nominal[k]) / 12.0;
    }
    for (double sq : {t.squareness_xy_arcsec, t.squareness_yz_arcsec, t.squareness_zx_arcsec}) {
      CHECK(std::abs(sq) >= 10.0);
      CHECK(std::abs(sq) <= 40.0);
    }
    CHECK(t.a_c_offset_mm >= 0.01);
    CHECK(t.a_c_offset_mm <= 0.05);
    CHECK(std::abs(t.a_c_angle_deg - 90.0) * 3600.0 >= 10.0);
    CHECK(std::abs(t.a_c_angle_deg - 90.0) * 3600.0 <= 40.0);
    CHECK(s.swing_mm >= 200.0);
    CHECK(s.swing_mm <= 400.0);
    // The SMR draws circles of useful radius about both axes.
    CHECK(distance_to_line(t.smr_home_mm, t.wrist_mm, t.c_dir) > 100.0);
    CHECK(distance_to_line(t.smr_home_mm, t.a_point_mm, t.a_dir) > 100.0);
  }
  CHECK(mean_off_arcsec > 20.0);
  CHECK(mean_off_arcsec < 50.0);
  const double yaw_pitch = angle_arcsec(m.gantry_direction(), Vec3::UnitX());
  CHECK(yaw_pitch > 3.0);
  CHECK(yaw_pitch < 10.0);
}
