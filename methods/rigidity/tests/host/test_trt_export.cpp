// trt_export.hpp: M3's table as xyzac-trt-kins' pivot, held against the
// virtual cradle's truth and against xyzac-trt-kins' equations written again
// here (LinuxCNC's own module agrees with them in tests/linuxcnc's trt scenario).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/tools/trt_export.hpp"

namespace {

using trueaxis::core::Vec3;
namespace core = trueaxis::core;
namespace sim = trueaxis::sim;

constexpr double kPi = 3.14159265358979323846;

// xyzac-trt-kins' inverse (trtfuncs.c), tool offset 0: the joints of world w.
Vec3 trt_inverse(const sim::TrtParameters& p, const Vec3& w, double a_deg, double c_deg) {
  const double a = a_deg * kPi / 180.0, c = c_deg * kPi / 180.0;
  const Vec3 q = w - p.rot_point_mm;
  const double dy = p.y_offset_mm, dz = p.z_offset_mm;
  return Vec3(std::cos(c) * q.x() - std::sin(c) * q.y() + p.rot_point_mm.x(),
              std::sin(c) * std::cos(a) * q.x() + std::cos(c) * std::cos(a) * q.y() - std::sin(a) * q.z() -
                  std::cos(a) * dy + std::sin(a) * dz + dy + p.rot_point_mm.y(),
              std::sin(c) * std::sin(a) * q.x() + std::cos(c) * std::sin(a) * q.y() + std::cos(a) * q.z() -
                  std::sin(a) * dy - std::cos(a) * dz + dz + p.rot_point_mm.z());
}

// The M3 table of `machine` from noise-free ball centres (A -40..40 every 20, C every 45).
std::unique_ptr<core::RigidityBuilder> table_of(const sim::CradleMachine& machine, const Vec3& ball) {
  std::vector<core::RigiditySample> samples;
  for (double a = -40.0; a <= 40.0; a += 20.0) {
    for (double c = 0.0; c < 360.0; c += 45.0) samples.push_back({a, c, machine.machine_T_table(a, c).apply(ball)});
  }
  auto builder = std::make_unique<core::RigidityBuilder>();
  core::RigidityOptions options;
  REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), options, *builder) == core::Status::kOk);
  return builder;
}

sim::CradlePivot moved_pivot() {
  sim::CradlePivot pivot;
  pivot.c_point_mm = Vec3(35.0, -25.0, 0.0);
  pivot.a_offset_y_mm = 3.0;
  pivot.a_offset_z_mm = -80.0;
  return pivot;
}

}  // namespace

TEST_CASE("linuxcnc-trt: on a cradle whose axes are only out of place, xyzac-trt-kins with the exported pivot puts "
          "every table point where the machine has it",
          "[trt]") {
  sim::CradleErrors e;  // locations only: the A axis 150 um, 120 um out, C 80 um across it
  e.a_point_mm = Vec3(0.0, 0.150, -0.120);
  e.c_offset_mm = 0.080;
  const sim::CradleMachine machine(sim::FaceConfig{}, e, moved_pivot());
  const Vec3 ball(200.0, 0.0, 50.0);
  const auto builder = table_of(machine, ball);
  sim::TrtParameters p;
  std::string why;
  REQUIRE(sim::trt_parameters(builder->table(), p, why));
  // The C axis at A = 0 at the ball's height; the A axis' line at X = r.x.
  CHECK((p.rot_point_mm - machine.c_centre_at(0.0, ball.z())).norm() < 1e-9);
  const sim::Line a = machine.a_axis();
  const Vec3 on_a = a.point_mm + (p.rot_point_mm.x() - a.point_mm.x()) / a.direction.x() * a.direction;
  CHECK(p.y_offset_mm == Approx(on_a.y() - p.rot_point_mm.y()).margin(1e-9));
  CHECK(p.z_offset_mm == Approx(on_a.z() - p.rot_point_mm.z()).margin(1e-9));
  // The numbers themselves: the A axis 150 um and -120 um out, C 80 um across
  // it (the table moves with A's error, cradle_errors.hpp model 3); the pivot
  // at the ball's height, 50 mm above the table's origin, 130 above A.
  CHECK(p.rot_point_mm.x() == Approx(35.0).margin(1e-9));
  CHECK(p.rot_point_mm.y() == Approx(-25.0 + 3.0 + 0.150 - (3.0 - 0.080)).margin(1e-9));
  CHECK(p.rot_point_mm.z() == Approx(0.0 - 0.120 + 50.0).margin(1e-9));
  CHECK(p.y_offset_mm == Approx(3.0 - 0.080).margin(1e-9));
  CHECK(p.z_offset_mm == Approx(-130.0).margin(1e-9));
  CHECK(p.not_held_arcsec() < 1e-3);  // no orientation to hold
  // Every table point, at every pose (also outside the measured A range).
  sim::SimRng rng(5);
  const sim::RigidTransform world_T_table = machine.machine_T_table(0.0, 0.0);
  for (int i = 0; i < 200; ++i) {
    const double a_deg = -90.0 + 180.0 * rng.uniform01();
    const double c_deg = 720.0 * rng.uniform01() - 360.0;
    const Vec3 point(400.0 * rng.uniform01() - 200.0, 400.0 * rng.uniform01() - 200.0, 100.0 * rng.uniform01());
    INFO("A " << a_deg << " C " << c_deg);
    const Vec3 world = world_T_table.apply(point);
    CHECK((trt_inverse(p, world, a_deg, c_deg) - machine.machine_T_table(a_deg, c_deg).apply(point)).norm() < 1e-7);
  }
  // The nominal pivot alone misses by the location errors.
  sim::TrtParameters nominal;
  nominal.rot_point_mm = moved_pivot().c_point_mm;
  nominal.y_offset_mm = 3.0;
  nominal.z_offset_mm = -80.0;
  CHECK((trt_inverse(nominal, world_T_table.apply(ball), 40.0, 90.0) - machine.machine_T_table(40.0, 90.0).apply(ball))
            .norm() > 0.05);
}

TEST_CASE("linuxcnc-trt: on the realistic cradle what it cannot hold is stated, and bounds its miss", "[trt]") {
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors(), moved_pivot());
  const Vec3 ball(200.0, 0.0, 50.0);
  const auto builder = table_of(machine, ball);
  sim::TrtParameters p;
  std::string why;
  REQUIRE(sim::trt_parameters(builder->table(), p, why));
  // The stated angles are the table's (M3's A axis is the one its C centres
  // turn about, the deflection's share included: not the error model's a_dir):
  // +X turned by them as cradle_errors.hpp model 1 is the table's A axis.
  const core::RigidityTable& t = builder->table();
  const double y = p.a_direction_y_arcsec / 206264.806, z = p.a_direction_z_arcsec / 206264.806;
  CHECK((Vec3(std::cos(z) * std::cos(y), std::cos(z) * std::sin(y), std::sin(z)) - t.a_axis_direction).norm() < 1e-12);
  CHECK(p.c_tilt_arcsec == Approx(std::acos(t.poses[t.reference].c_direction.z()) * 206264.806).margin(1e-3));
  double rigidity = 0.0, a_error = 0.0;
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    rigidity = std::max(rigidity, t.poses[i].rotvec_rad.norm() * 206264.806);
    a_error = std::max(a_error, std::fabs(t.poses[i].a_error_rad) * 206264.806);
  }
  CHECK(p.rigidity_arcsec == Approx(rigidity).margin(1e-6));
  CHECK(p.a_error_arcsec == Approx(a_error).margin(1e-9));
  CHECK(p.a_direction_y_arcsec > 10.0);
  CHECK(p.a_error_arcsec > 1.0);
  // The A axis' line is taken at X = r.x (the table's own A point is the C
  // centres' circle's, elsewhere along a tilted axis).
  // The same line from another of its points, 150 mm along the tilted axis: the same offsets.
  core::RigidityTable along = t;
  along.a_axis_point_mm += 150.0 * t.a_axis_direction;
  sim::TrtParameters same;
  REQUIRE(sim::trt_parameters(along, same, why));
  CHECK(same.y_offset_mm == Approx(p.y_offset_mm).margin(1e-9));
  CHECK(same.z_offset_mm == Approx(p.z_offset_mm).margin(1e-9));
  CHECK(std::hypot(t.a_axis_direction.y(), t.a_axis_direction.z()) * 150.0 > 1e-3);  // 150 mm of it: > 1 um
  // The A error's size whatever its sign.
  core::RigidityTable negative = t;
  negative.poses[0].a_error_rad = -1000.0 / 206264.806;
  sim::TrtParameters q;
  REQUIRE(sim::trt_parameters(negative, q, why));
  CHECK(q.a_error_arcsec == Approx(1000.0).margin(1e-6));
  // The ball, at the measured poses: the miss within the ball's lever (from
  // the A axis) times what is not held, and not within a tenth of it.
  const sim::RigidTransform world_T_table = machine.machine_T_table(0.0, 0.0);
  const double lever_mm = std::hypot(200.0, 50.0 + 80.0) + 10.0;
  double worst = 0.0;
  for (double a = -40.0; a <= 40.0; a += 20.0) {
    for (double c = 0.0; c < 360.0; c += 45.0) {
      const double miss = (trt_inverse(p, world_T_table.apply(ball), a, c) - machine.machine_T_table(a, c).apply(ball)).norm();
      worst = std::max(worst, miss);
    }
  }
  const double bound = lever_mm * p.not_held_arcsec() / 206264.806;
  INFO("worst " << worst * 1000.0 << " um, bound " << bound * 1000.0 << " um");
  CHECK(worst <= bound);
  CHECK(worst > 0.1 * bound);
  const std::string hal = sim::trt_hal_text(p);
  CHECK(hal.find("setp xyzac-trt-kins.x-rot-point ") != std::string::npos);
  CHECK(hal.find("setp xyzac-trt-kins.z-offset ") != std::string::npos);
  CHECK(hal.find("the A positioning error: up to") != std::string::npos);
}

TEST_CASE("linuxcnc-trt: a table whose A is not about +X, or C not about +Z, is refused", "[trt]") {
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::CradleErrors{}, moved_pivot());
  const auto builder = table_of(machine, Vec3(200.0, 0.0, 50.0));
  core::RigidityTable table = builder->table();
  sim::TrtParameters p;
  std::string why;
  REQUIRE(sim::trt_parameters(table, p, why));
  CHECK(p.not_held_arcsec() < 1e-3);
  CHECK((p.rot_point_mm - Vec3(35.0, -25.0, 50.0)).norm() < 1e-9);
  CHECK(p.y_offset_mm == Approx(3.0).margin(1e-9));
  CHECK(p.z_offset_mm == Approx(-130.0).margin(1e-9));  // the A axis 80 below r, 130 below the ball's height
  for (const double deg : {1.01, 0.99}) {  // the A axis near 1 deg off +X, towards +Z
    core::RigidityTable tilted = table;
    const double a = deg * kPi / 180.0;
    tilted.a_axis_direction = Vec3(std::cos(a), 0.0, std::sin(a));
    INFO(deg);
    CHECK(sim::trt_parameters(tilted, p, why) == (deg < 1.0));
  }
  core::RigidityTable flipped = table;
  flipped.a_axis_direction = -flipped.a_axis_direction;
  CHECK_FALSE(sim::trt_parameters(flipped, p, why));
  CHECK(why.find("+X") != std::string::npos);
  core::RigidityTable tilted = table;
  const double t = 1.01 * kPi / 180.0;
  tilted.poses[tilted.reference].c_direction = Vec3(std::sin(t), 0.0, std::cos(t));
  CHECK_FALSE(sim::trt_parameters(tilted, p, why));
  CHECK(why.find("+Z") != std::string::npos);
  tilted.poses[tilted.reference].c_direction = Vec3(std::sin(0.99 * kPi / 180.0), 0.0, std::cos(0.99 * kPi / 180.0));
  CHECK(sim::trt_parameters(tilted, p, why));
}
