// The virtual gantry's truth (gantry_machine.hpp): self-consistency of the frames
// and each error term alone against a closed form or an independent construction
// (circumcentres of three points, the lines' 2x2 normal equations, an eigenvector
// line fit).
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>

#include "gantry_geometry.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"

namespace {

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;
using trueaxis::sim::GantryConfig;
using trueaxis::sim::GantryMachine;
using trueaxis::sim::MasterAxis;
using trueaxis::sim::SubMachineTruth;

using namespace trueaxis::test::gantry;  // NOLINT: the closed forms these tests check against

void check_orthonormal_right_handed(const Mat3& r) {
  CHECK((r.transpose() * r - Mat3::Identity()).norm() < 1e-14);
  CHECK(r.determinant() == Approx(1.0).epsilon(1e-14));
}

GantryMachine with_sub_errors(void (*set)(trueaxis::sim::SubMachineConfig&)) {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  for (auto& s : c.sub_machines) set(s);
  return GantryMachine(c);
}

}  // namespace

TEST_CASE("the truth's frames are orthonormal, right-handed and follow the gantry") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const Mat3 g = m.machine_T_global().rotation;
  check_orthonormal_right_handed(g);
  CHECK((g.col(0) - m.gantry_direction()).norm() == 0.0);
  CHECK(std::abs(g.col(1).dot(Vec3::UnitZ())) < 1e-15);  // y = z0 x x is in the bed plane
  CHECK(g.col(2).z() > 0.0);
  REQUIRE(m.sub_machine_count() == 4);
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    check_orthonormal_right_handed(t.axes);
    check_orthonormal_right_handed(t.axes_global);
    CHECK((t.global_T_sub.bottomRows<1>() - Eigen::RowVector4d(0, 0, 0, 1)).norm() == 0.0);
    // Xsp agrees with the gantry's positive X.
    CHECK(t.axes_global(0, 0) > 0.999);
  }
}

TEST_CASE("the global origin is the common point of the bed and side planes") {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  c.side_1_offset_mm = 0.5;
  c.side_2_offset_mm = -0.25;
  CHECK((GantryMachine(c).machine_T_global().translation_mm - Vec3(0.5, -0.25, 0.0)).norm() < 1e-15);
  c.side_1_yaw_arcsec = 40.0;
  c.side_1_tilt_arcsec = -30.0;
  c.side_2_yaw_arcsec = -25.0;
  c.side_2_tilt_arcsec = 35.0;
  const GantryMachine m(c);
  const Vec3 o = m.machine_T_global().translation_mm;
  CHECK(std::abs(o.z()) < 1e-15);
  for (int k = 1; k <= 2; ++k) {
    const auto& plane = m.side_plane(k);
    CHECK(std::abs(plane.normal.dot(o - plane.point_mm)) < 1e-12);
    CHECK(plane.normal.norm() == Approx(1.0).epsilon(1e-15));
    for (double z : {-10.0, -50.0}) {
      const Vec3 p = m.side_point(k, 70.0, z);
      CHECK(std::abs(plane.normal.dot(p - plane.point_mm)) < 1e-12);
    }
  }
  // The faces' tilts move the face points by tens of nanometres per arc-second over 50 mm.
  CHECK(angle_arcsec(m.side_plane(1).normal, -Vec3::UnitX()) == Approx(50.0).epsilon(1e-6));
  CHECK(std::abs(m.side_point(1, 70.0, -50.0).x() - 0.5) > 0.005);
  // The tilts turn the faces; the corner they share with the bed moves by the
  // other face's offset times the angle (0.25 mm x 40" = 48 nm).
  CHECK((o - Vec3(0.5, -0.25, 0.0)).norm() < 1e-4);
}

TEST_CASE("the gantry's yaw turns x in the bed plane and leaves z on the bed normal") {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  c.gantry_yaw_arcsec = 6.0;
  const GantryMachine m(c);
  const double y = 6.0 * kRadPerArcsec;
  CHECK((m.gantry_direction() - Vec3(std::cos(y), std::sin(y), 0.0)).norm() < 1e-16);
  const Mat3 r = m.machine_T_global().rotation;
  CHECK((r.col(2) - Vec3::UnitZ()).norm() < 1e-16);
  CHECK(angle_arcsec(r.col(1), Vec3::UnitY()) == Approx(6.0).epsilon(1e-6));
}

TEST_CASE("the gantry's pitch lifts x and the global z is corrected by the same angle") {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  c.gantry_pitch_arcsec = -4.0;
  const GantryMachine m(c);
  const double p = -4.0 * kRadPerArcsec;
  CHECK((m.gantry_direction() - Vec3(std::cos(p), 0.0, std::sin(p))).norm() < 1e-16);
  const Mat3 r = m.machine_T_global().rotation;
  CHECK((r.col(1) - Vec3::UnitY()).norm() < 1e-16);
  CHECK(angle_arcsec(r.col(2), Vec3::UnitZ()) == Approx(4.0).epsilon(1e-6));
  CHECK(r.col(2).x() > 0.0);  // x dips, so z leans forward
}

TEST_CASE("the gantry's bow leaves its direction and bends its path by the bow") {
  GantryConfig c = trueaxis::sim::ideal_gantry();
  c.gantry_bow_h_mm = 0.003;
  c.gantry_bow_v_mm = 0.004;
  const GantryMachine m(c);
  CHECK((m.gantry_direction() - Vec3::UnitX()).norm() == 0.0);
  const Vec3 home = m.gantry_target(0.0);
  CHECK((m.gantry_target(3600.0) - (home + 3600.0 * Vec3::UnitX())).norm() < 1e-12);
  CHECK((m.gantry_target(1800.0) - (home + Vec3(1800.0, 0.003, 0.004))).norm() < 1e-12);
  // Straightness from an eigenvector line fit of the true path at 15 stops.
  std::vector<double> stops;
  for (int i = 0; i < 15; ++i) stops.push_back(3600.0 * i / 14.0);
  Vec3 mean = Vec3::Zero();
  for (double u : stops) mean += m.gantry_target(u) / 15.0;
  Mat3 scatter = Mat3::Zero();
  for (double u : stops) scatter += (m.gantry_target(u) - mean) * (m.gantry_target(u) - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  const Vec3 dir = eig.eigenvectors().col(2);
  CHECK(angle_arcsec(dir, Vec3::UnitX()) < 1e-3);
  double worst = 0.0;
  for (double u : stops) worst = std::max(worst, distance_to_line(m.gantry_target(u), mean, dir));
  CHECK(m.gantry_straightness_mm(stops) == Approx(2.0 * worst).epsilon(1e-6));
  CHECK(m.gantry_straightness_mm(stops) > 0.005);
  CHECK(m.gantry_straightness_mm(stops) < 0.010);
}

TEST_CASE("O_sp lies on the C axis at the swing length, where C turning leaves it") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    const double swing = m.config().sub_machines[i].swing_mm;
    CHECK((t.origin_mm - t.wrist_mm).norm() == Approx(swing).epsilon(1e-14));
    CHECK((t.origin_mm - t.wrist_mm).normalized().dot(t.c_dir) == Approx(1.0).epsilon(1e-15));
    CHECK((m.head_point(i, Vec3::Zero(), 0.0, 0.0, t.origin_mm) - t.origin_mm).norm() == 0.0);
    CHECK((m.head_point(i, Vec3::Zero(), 0.0, 137.0, t.origin_mm) - t.origin_mm).norm() < 1e-10);
    // The SMR's C circle: centre on the C line, normal c for increasing C.
    Vec3 n;
    const Vec3 centre = circumcentre(m.smr(i, Vec3::Zero(), 0.0, 0.0), m.smr(i, Vec3::Zero(), 0.0, 100.0),
                                     m.smr(i, Vec3::Zero(), 0.0, 230.0), n);
    CHECK(distance_to_line(centre, t.wrist_mm, t.c_dir) < 1e-9);
    CHECK((n - t.c_dir).norm() < 1e-12);
    // The tool tip swings about A at the swing length from it (A and C nearly meet).
    const Vec3 tip = m.head_point(i, Vec3::Zero(), 60.0, 0.0, t.origin_mm);
    CHECK(distance_to_line(tip, t.a_point_mm, t.a_dir) == Approx(swing).margin(0.05));
  }
}

TEST_CASE("global_T_sub maps the sub-machine's origin to O_sp and its axes to the S4 axes") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  // global_T_machine by Eigen's Isometry inverse: another route than R^T, -R^T t.
  Eigen::Isometry3d machine_T_global = Eigen::Isometry3d::Identity();
  machine_T_global.linear() = m.machine_T_global().rotation;
  machine_T_global.translation() = m.machine_T_global().translation_mm;
  const Eigen::Isometry3d global_T_machine = machine_T_global.inverse(Eigen::Isometry);
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    const Eigen::Vector4d o = t.global_T_sub * Eigen::Vector4d(0, 0, 0, 1);
    CHECK((o.head<3>() - global_T_machine * t.origin_mm).norm() < 1e-11);
    CHECK((t.origin_global_mm - global_T_machine * t.origin_mm).norm() < 1e-11);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector4d unit = Eigen::Vector4d::Zero();
      unit[k] = 1.0;
      unit[3] = 1.0;
      const Vec3 moved = (t.global_T_sub * unit).head<3>() - o.head<3>();
      CHECK((moved - global_T_machine.linear() * t.axes.col(k)).norm() < 1e-12);  // 1e3 mm rounding
    }
  }
}

TEST_CASE("the mount rotation turns the axes and the head together, square") {
  const GantryMachine m = with_sub_errors([](trueaxis::sim::SubMachineConfig& s) {
    s.mount_rotation_arcsec = Vec3(12.0, -8.0, 20.0);
  });
  const Vec3 w = Vec3(12.0, -8.0, 20.0) * kRadPerArcsec;
  const Mat3 r = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    CHECK((t.d_x - r.col(0)).norm() < 1e-15);
    CHECK((t.d_y - r.col(1)).norm() < 1e-15);
    CHECK((t.d_z - r.col(2)).norm() < 1e-15);
    CHECK((t.axes - r).norm() < 1e-15);
    CHECK((t.c_dir - r * m.config().sub_machines[i].tool_nominal).norm() < 1e-15);
    CHECK(std::abs(t.squareness_xy_arcsec) + std::abs(t.squareness_yz_arcsec) + std::abs(t.squareness_zx_arcsec) <
          1e-9);
    CHECK(t.a_c_angle_deg == Approx(90.0).epsilon(1e-14));
    CHECK(angle_arcsec(t.d_x, Vec3::UnitX()) > 10.0);
  }
}

TEST_CASE("the squareness errors are the axes' angles minus 90 degrees and S4 keeps the master") {
  const GantryMachine m = with_sub_errors([](trueaxis::sim::SubMachineConfig& s) {
    s.mount_rotation_arcsec = Vec3(-15.0, 10.0, 8.0);
    s.squareness_xy_arcsec = 15.0;
    s.squareness_yz_arcsec = -22.0;
    s.squareness_zx_arcsec = 30.0;
  });
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const SubMachineTruth& t = m.truth(i);
    CHECK(angle_arcsec(t.d_x, t.d_y) - 90.0 * 3600.0 == Approx(15.0).margin(2e-4));
    CHECK(angle_arcsec(t.d_y, t.d_z) - 90.0 * 3600.0 == Approx(-22.0).margin(2e-4));
    CHECK(angle_arcsec(t.d_z, t.d_x) - 90.0 * 3600.0 == Approx(30.0).margin(2e-4));
    CHECK(t.squareness_xy_arcsec == Approx(15.0).epsilon(1e-9));
    CHECK(t.squareness_yz_arcsec == Approx(-22.0).epsilon(1e-9));
    CHECK(t.squareness_zx_arcsec == Approx(30.0).epsilon(1e-9));
    const Vec3 d[3] = {t.d_x, t.d_y, t.d_z};
    const int master = static_cast<int>(t.master);
    CHECK((t.axes.col(master) - d[master]).norm() < 1e-15);
    for (int k = 0; k < 3; ++k) CHECK(angle_arcsec(t.axes.col(k), d[k]) < 40.0);
  }
  CHECK(m.truth(0).master == MasterAxis::kY);
  CHECK(m.truth(1).master == MasterAxis::kZ);
  CHECK(m.truth(2).master == MasterAxis::kZ);
  CHECK(m.truth(3).master == MasterAxis::kY);
}

TEST_CASE("S4 rebuilds the other axes by the cross products docs/METHODS.md gives") {
  const Vec3 x = Vec3(1.0, 2e-4, -1e-4).normalized();
  const Vec3 y = Vec3(-1e-4, 1.0, 3e-4).normalized();
  const Vec3 z = Vec3(2e-4, -1e-4, 1.0).normalized();
  const Mat3 ax = trueaxis::sim::orthonormalise(x, y, z, MasterAxis::kX);
  const Mat3 ay = trueaxis::sim::orthonormalise(x, y, z, MasterAxis::kY);
  const Mat3 az = trueaxis::sim::orthonormalise(x, y, z, MasterAxis::kZ);
  for (const Mat3* a : {&ax, &ay, &az}) check_orthonormal_right_handed(*a);
  // X master: y' normal to x and z; Y master: x' normal to y and z; Z master likewise.
  CHECK((ax.col(0) - x).norm() < 1e-15);
  CHECK(std::abs(ax.col(1).dot(z)) < 1e-15);
  CHECK((ay.col(1) - y).norm() < 1e-15);
  CHECK(std::abs(ay.col(0).dot(z)) < 1e-15);
  CHECK((az.col(2) - z).norm() < 1e-15);
  CHECK(std::abs(az.col(0).dot(y)) < 1e-15);
  // A longest X stroke makes X the master; a tie goes to the first.
  GantryConfig c = trueaxis::sim::ideal_gantry();
  c.sub_machines[0].stroke_min_mm = Vec3(-1000.0, -500.0, -500.0);
  c.sub_machines[0].stroke_max_mm = Vec3(1000.0, 500.0, 500.0);
  c.sub_machines[1].stroke_min_mm = Vec3(-400.0, -400.0, -400.0);
  c.sub_machines[1].stroke_max_mm = Vec3(400.0, 400.0, 100.0);
  const GantryMachine m(c);
  CHECK(m.truth(0).master == MasterAxis::kX);
  CHECK(m.truth(1).master == MasterAxis::kX);
}
