// The LinuxCNC cradle kinematics (integrations/linuxcnc/kins/cradle_kinematics.hpp)
// on a table measured on the realistic virtual cradle and stored through the
// user's command (trueaxis-calibrate rigidity --store --linuxcnc-kins, against
// a simulator served in this process): forward and inverse invert each other
// to 1e-9 mm everywhere; inside the measured range the joints are macro
// 9835's answer for the theory point bit for bit; at A = C = 0 the world is
// the machine; the ideal kinematics are Rx(A) Rz(C); the calibrated ones put
// the ball where the true cradle has it and the ideal ones miss it; no call
// allocates; a damaged, truncated, foreign or missing file is refused with its
// reason and changes nothing.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "cradle_kinematics.hpp"
#include "in_process_sim.hpp"
#include "kins_api.h"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"

namespace {

namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
namespace t = trueaxis::test;
namespace v = trueaxis::macros::var;
using core::Vec3;

constexpr double kArcsec = 206264.80624709636;

// The ball on the realistic cradle at A -90..90 every 30, C every 10, read to
// sigma_mm: the samples file of docs/INTERFACE.md "M3 rigidity".
std::string ball_csv(const sim::CradleMachine& machine, double sigma_mm, std::uint64_t seed) {
  sim::CalibrationBall ball;
  ball.sigma_mm = sigma_mm;
  sim::SimRng rng(seed);
  std::string csv = "a_deg,c_deg,x_mm,y_mm,z_mm\n";
  for (int a = -90; a <= 90; a += 30) {
    for (int c = 0; c < 360; c += 10) {
      const sim::RigidTransform pose = machine.machine_T_table(a, c);
      const Vec3 p = sigma_mm > 0.0 ? ball.measure(pose, rng) : ball.centre_mm(pose);
      char line[160];
      std::snprintf(line, sizeof line, "%d,%d,%.12f,%.12f,%.12f\n", a, c, p.x(), p.y(), p.z());
      csv += line;
    }
  }
  return csv;
}

// The table file of a calibration on the simulator `sim` (the user's command).
std::vector<std::uint8_t> stored_table_file(t::InProcessSim& sim, const t::Workspace& w, const std::string& csv) {
  const t::Run r = t::run({TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", w.write("ball.csv", csv), "--json",
                           w.file("out.json"), "--store", "--linuxcnc-kins", w.file("m3.table"), "--port",
                           std::to_string(sim.port())},
                          w.file("stderr"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string bytes = t::slurp(w.file("m3.table"));
  return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

// Macro 9835 (R = 0, Q = 3: theory to actual, the not-a-knot blend) of a point.
Vec3 convert(sim::VariableClient& client, double a, double c, const Vec3& p) {
  const double ac[3] = {a, 0.0, c};
  const double xyz[3] = {p.x(), p.y(), p.z()};
  const double qr[2] = {3.0, 0.0};
  REQUIRE(client.write(v::kArgA, 3, ac));
  REQUIRE(client.write(v::kArgX, 3, xyz));
  REQUIRE(client.write(v::kArgQ, 2, qr));
  REQUIRE(client.run_macro(9835).status == 2);
  double out[3];
  REQUIRE(client.read(v::kConvertPointX, 3, out));
  return Vec3(out[0], out[1], out[2]);
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }

// The C interface's units back to mm when a case ends, a failed REQUIRE too:
// the module's state is global, as LinuxCNC loads one kinematics module.
struct MmAtExit {
  ~MmAtExit() {
    const char* why = "";
    trueaxis_kins_set_linear_units("mm", &why);
  }
};

// The spindle measured, calibrated and stored through the user's command, its
// model written as the kinematics' file w/m4.model.
void store_spindle_model(t::InProcessSim& sim, const t::Workspace& w) {
  const t::SpindleFiles f = t::measure_spindle(w, "s", 3, 3);
  const t::Run r = t::run({TRUEAXIS_CALIBRATE_BINARY, "spindle", "--in", f.samples, "--machine", f.machine, "--json",
                           w.file("s.json"), "--store", "--linuxcnc-kins", w.file("m4.model"), "--port",
                           std::to_string(sim.port())},
                          w.file("stderr"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
}

}  // namespace

TEST_CASE("kins: the table file of the stored calibration; forward and inverse invert each other; 9835 bit for bit",
          "[kins]") {
  t::InProcessSim sim;
  t::Workspace w("trueaxis-kins");
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  const std::vector<std::uint8_t> file = stored_table_file(sim, w, ball_csv(machine, 0.001, 7));
  trueaxis::linuxcnc::CradleKinematics kins;
  const trueaxis::linuxcnc::LoadResult loaded = kins.load_table(file.data(), file.size());
  INFO(loaded.why);
  REQUIRE(loaded.ok);
  CHECK(kins.poses() == 7);
  CHECK(kins.a_min_deg() == -90.0);
  CHECK(kins.a_max_deg() == 90.0);
  // The stored table exported on its own (an operator program's store) is the same file.
  const t::Run exported = t::run({TRUEAXIS_CALIBRATE_BINARY, "linuxcnc-kins", "rigidity", "--out", w.file("exported.table"),
                                  "--port", std::to_string(sim.port())},
                                 w.file("stderr"));
  INFO(exported.err);
  REQUIRE(exported.exit_code == 0);
  CHECK(t::slurp(w.file("exported.table")) == std::string(file.begin(), file.end()));

  sim::SimRng rng(2027);
  double worst = 0.0;
  int bit_for_bit = 0;
  for (int i = 0; i < 400; ++i) {
    // A over the measured range and 30 deg beyond it, at the poses too.
    const double a = i % 20 == 0 ? -90.0 + 30.0 * (i / 20 % 7) : -120.0 + 240.0 * rng.uniform01();
    const double c = -720.0 + 1440.0 * rng.uniform01();
    const Vec3 world(600.0 * rng.uniform01() - 300.0, 600.0 * rng.uniform01() - 300.0, 400.0 * rng.uniform01() - 100.0);
    Vec3 joint, back;
    REQUIRE(kins.inverse(world, a, c, joint));
    REQUIRE(kins.forward(joint, a, c, back));
    worst = std::max(worst, (back - world).norm());
    if (i % 10 == 0 && a >= -90.0 && a <= 90.0) {
      Vec3 p;
      REQUIRE(kins.theory_point(world, a, c, p));
      INFO("A " << a << " C " << c);
      CHECK(same_bits(convert(sim.client(), a, c, p), joint));
      ++bit_for_bit;
    }
  }
  INFO("round trip worst " << worst << " mm");
  CHECK(worst < 1e-9);
  CHECK(bit_for_bit >= 20);

  // At A = 0, C = 0 the world is the machine (convention 1).
  for (const Vec3& world : {Vec3(0, 0, 0), Vec3(200, 0, 50), Vec3(-150, 80, 120)}) {
    Vec3 joint;
    REQUIRE(kins.inverse(world, 0.0, 0.0, joint));
    CHECK((joint - world).norm() < 1e-9);
  }
  // Nothing allocates, calibrated or ideal; a non-finite input is refused.
  {
    t::AllocationScope scope;
    Vec3 joint, back;
    for (int i = 0; i < 50; ++i) {
      REQUIRE(kins.inverse(Vec3(10.0 * i, 5, 3), -95.0 + 4.0 * i, 7.0 * i, joint));
      REQUIRE(kins.forward(joint, -95.0 + 4.0 * i, 7.0 * i, back));
    }
    CHECK(scope.count() == 0);
  }
  Vec3 kept(1, 2, 3);
  CHECK_FALSE(kins.inverse(Vec3(NAN, 0, 0), 10.0, 0.0, kept));
  CHECK_FALSE(kins.forward(Vec3(0, 0, 0), INFINITY, 0.0, kept));
  CHECK(kept == Vec3(1, 2, 3));
}

TEST_CASE("kins: the ideal cradle is Rx(A) Rz(C); the calibrated one puts the ball where the true cradle has it",
          "[kins]") {
  trueaxis::linuxcnc::CradleKinematics ideal;
  sim::SimRng rng(11);
  for (int i = 0; i < 100; ++i) {
    const double a = -120.0 + 240.0 * rng.uniform01();
    const double c = -400.0 + 800.0 * rng.uniform01();
    const Vec3 world(300.0 * rng.uniform01(), -200.0 * rng.uniform01(), 100.0 * rng.uniform01());
    const core::Mat3 r = (Eigen::AngleAxisd(a * M_PI / 180.0, Vec3::UnitX()) *
                          Eigen::AngleAxisd(c * M_PI / 180.0, Vec3::UnitZ()))
                             .toRotationMatrix();
    Vec3 joint, back;
    REQUIRE(ideal.inverse(world, a, c, joint));
    CHECK((joint - r * world).norm() < 1e-9);
    REQUIRE(ideal.forward(joint, a, c, back));
    CHECK((back - world).norm() < 1e-9);
  }

  // The ball: its world position is where the true cradle has it at A = C = 0;
  // at each measured A and any C the calibrated kinematics send the probe to
  // where the true cradle has it then. Noise-free, exactly (the table's frames
  // are the ball's own circles); measured to 1 um, within 3 sigma of the table
  // at that pose (its rotation vector's and A error's sigmas over the ball's
  // 206 mm from the A axis, and the C centre's); the ideal kinematics miss by
  // the cradle's errors.
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  const sim::CalibrationBall ball;
  // The ball, and two points of a workpiece elsewhere on the table (table
  // coordinates): the table's frames carry the whole table, not the ball alone.
  const Vec3 on_table[3] = {ball.centre_table_mm, Vec3(-150.0, 80.0, 120.0), Vec3(60.0, -170.0, 10.0)};
  for (const double sigma : {0.0, 0.001}) {
    t::InProcessSim sim;
    t::Workspace w("trueaxis-kins");
    const std::vector<std::uint8_t> file = stored_table_file(sim, w, ball_csv(machine, sigma, 31));
    trueaxis::linuxcnc::CradleKinematics kins;
    REQUIRE(kins.load_table(file.data(), file.size()).ok);
    for (const double a : {-60.0, -30.0, 30.0, 60.0}) {
      // The table's sigmas at this pose (9834, R = 1).
      const double q = (a + 90.0) / 30.0 + 1.0;
      const double args[2] = {q, 1.0};
      REQUIRE(sim.client().write(v::kArgQ, 2, args));
      REQUIRE(sim.client().run_macro(9834).status == 2);
      double pose[21];
      REQUIRE(sim.client().read(v::kPoseA, 21, pose));
      REQUIRE(pose[0] == a);
      const double rotation = std::hypot(std::hypot(pose[4], pose[5]), std::hypot(pose[6], pose[18])) / kArcsec;
      const double centre = ball.sigma_mm / std::sqrt(36.0 / 2.0);
      for (std::size_t k = 0; k < 3; ++k) {
      const Vec3 world = machine.machine_T_table(0.0, 0.0).apply(on_table[k]);
      // The point's lever about the C centre at the ball's height, where the table's frames sit.
      const double lever = (on_table[k] - Vec3(0.0, 0.0, ball.centre_table_mm.z())).norm();
      const double sigma_mm = std::hypot(rotation * lever, centre);
      for (const double c : {0.0, 95.0, 200.0, 315.0}) {
        const Vec3 truth = machine.machine_T_table(a, c).apply(on_table[k]);
        Vec3 calibrated, uncompensated;
        REQUIRE(kins.inverse(world, a, c, calibrated));
        REQUIRE(ideal.inverse(world, a, c, uncompensated));
        const double error = (calibrated - truth).norm();
        const double miss = (uncompensated - truth).norm();
        INFO("point " << k << ", noise " << sigma << " mm, A " << a << " C " << c << ": calibrated " << error * 1000.0
                      << " um (sigma " << sigma_mm * 1000.0 << " um), ideal " << miss * 1000.0 << " um");
        if (sigma == 0.0) {
          CHECK(error < 1e-6);
        } else {
          CHECK(error < 3.0 * sigma_mm);
        }
        CHECK(miss > 10.0 * std::max(error, 1e-3));
        if (std::getenv("TRUEAXIS_FIGURES") != nullptr && c == 95.0) {
          std::printf("point %zu, noise %.3f mm, A %+5.1f C %5.1f: calibrated %.2f um (3 sigma %.2f um), ideal "
                      "kinematics %.1f um\n",
                      k, sigma, a, c, error * 1000.0, 3.0 * sigma_mm * 1000.0, miss * 1000.0);
        }
      }
      }
    }
  }
}

// LinuxCNC's own xyzac-trt-kins (trtfuncs.c of 2.9, its xyzac inverse and
// forward) with its rot-point, y-offset, z-offset and tool-offset pins, written
// here from its equations: the machine trueaxis_kins must agree with where the
// geometry is the same.
struct Trt {
  Vec3 rot_point = Vec3::Zero();
  double dy = 0.0, dz = 0.0, tool = 0.0;
  Vec3 inverse(const Vec3& w, double a_deg, double c_deg) const {
    const double a = a_deg * M_PI / 180.0, c = c_deg * M_PI / 180.0;
    const double z_off = dz + tool;
    const Vec3 p = w - rot_point;
    return Vec3(std::cos(c) * p.x() - std::sin(c) * p.y() + rot_point.x(),
                std::sin(c) * std::cos(a) * p.x() + std::cos(c) * std::cos(a) * p.y() - std::sin(a) * p.z() -
                    std::cos(a) * dy + std::sin(a) * z_off + dy + rot_point.y(),
                std::sin(c) * std::sin(a) * p.x() + std::cos(c) * std::sin(a) * p.y() + std::cos(a) * p.z() -
                    std::sin(a) * dy - std::cos(a) * z_off + z_off + rot_point.z());
  }
};

TEST_CASE("kins: the tool offset (motion.tooloffset.z, G43) along the tool at every A, C, as xyzac-trt-kins' "
          "tool-offset; G49 the gauge line; identity LinuxCNC's own",
          "[kins]") {
  trueaxis::linuxcnc::CradleKinematics ideal;
  sim::SimRng rng(23);
  for (int i = 0; i < 200; ++i) {
    const double a = -120.0 + 240.0 * rng.uniform01();
    const double c = -400.0 + 800.0 * rng.uniform01();
    const double tool = i % 4 == 0 ? 0.0 : 250.0 * rng.uniform01();
    const Vec3 world(300.0 * rng.uniform01() - 150.0, 200.0 * rng.uniform01() - 100.0, 100.0 * rng.uniform01());
    INFO("A " << a << " C " << c << " tool " << tool);
    Vec3 joint, back;
    REQUIRE(ideal.to_joints(true, world, a, c, tool, false, 0.0, joint));
    Trt trt;
    trt.tool = tool;
    CHECK((joint - trt.inverse(world, a, c)).norm() < 1e-9);
    // The tip, tool below the gauge line the joints hold, is the table's point
    // world - tool z turned with the table: G43 puts the tip where the program says.
    const core::Mat3 r = (Eigen::AngleAxisd(a * M_PI / 180.0, Vec3::UnitX()) *
                          Eigen::AngleAxisd(c * M_PI / 180.0, Vec3::UnitZ()))
                             .toRotationMatrix();
    CHECK(((joint - tool * Vec3::UnitZ()) - r * (world - tool * Vec3::UnitZ())).norm() < 1e-9);
    REQUIRE(ideal.to_world(true, joint, a, c, tool, false, 0.0, back));
    CHECK((back - world).norm() < 1e-9);
    // The identity leaves LinuxCNC's world as it is, the offset in it already.
    REQUIRE(ideal.to_joints(false, world, a, c, tool, false, 0.0, joint));
    CHECK(joint == world);
    REQUIRE(ideal.to_world(false, world, a, c, tool, false, 0.0, back));
    CHECK(back == world);
  }
  // G49: no offset, the gauge line is the controlled point: the cradle alone.
  Vec3 j0, j1;
  REQUIRE(ideal.to_joints(true, Vec3(10.0, 20.0, 30.0), 30.0, 40.0, 0.0, false, 0.0, j0));
  REQUIRE(ideal.inverse(Vec3(10.0, 20.0, 30.0), 30.0, 40.0, j1));
  CHECK(j0 == j1);
  // A 100 mm tool whose tip is at the pivot (world Z 100 with G43): its gauge line
  // straight above it at any A, where the kinematics without the offset turned the
  // point to 100 (0, -sin 30, cos 30): the tip 51.8 mm off, into the table.
  REQUIRE(ideal.to_joints(true, Vec3(0.0, 0.0, 100.0), 30.0, 0.0, 100.0, false, 0.0, j0));
  CHECK((j0 - Vec3(0.0, 0.0, 100.0)).norm() < 1e-12);
  REQUIRE(ideal.to_joints(true, Vec3(0.0, 0.0, 0.0), 30.0, 0.0, 0.0, false, 0.0, j1));
  CHECK((j1 - Vec3::Zero()).norm() < 1e-12);
  // Not finite: refused, untouched.
  Vec3 kept(1.0, 2.0, 3.0);
  CHECK_FALSE(ideal.to_joints(true, Vec3(0.0, 0.0, 0.0), 30.0, 0.0, NAN, false, 0.0, kept));
  CHECK_FALSE(ideal.to_world(true, Vec3(0.0, 0.0, 0.0), 30.0, 0.0, INFINITY, false, 0.0, kept));
  CHECK(kept == Vec3(1.0, 2.0, 3.0));
}

TEST_CASE("kins: a damaged, truncated, foreign or missing table file is refused with its reason; nothing changes",
          "[kins]") {
  t::InProcessSim sim;
  t::Workspace w("trueaxis-kins");
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  const std::vector<std::uint8_t> good = stored_table_file(sim, w, ball_csv(machine, 0.001, 5));
  trueaxis::linuxcnc::CradleKinematics kins;
  REQUIRE(kins.load_table(good.data(), good.size()).ok);
  Vec3 before;
  REQUIRE(kins.inverse(Vec3(100, 20, 30), 45.0, 30.0, before));
  const auto refused = [&](const std::vector<std::uint8_t>& file, const char* says) {
    const trueaxis::linuxcnc::LoadResult r = kins.load_table(file.data(), file.size());
    INFO(r.why);
    CHECK_FALSE(r.ok);
    CHECK(std::string(r.why).find(says) != std::string::npos);
    Vec3 after;
    REQUIRE(kins.inverse(Vec3(100, 20, 30), 45.0, 30.0, after));
    CHECK(same_bits(after, before));
  };
  for (const std::size_t at : {0u, 9u, 17u, 400u}) {
    std::vector<std::uint8_t> flipped = good;
    flipped[at] ^= 0x10;
    refused(flipped, at == 0 ? "not a trueaxis record file" : at == 9 ? "layout" : "damaged");
  }
  refused(std::vector<std::uint8_t>(good.begin(), good.end() - 1), "truncated");
  refused({}, "not a trueaxis record file");
  // A spindle record's file, and a good CRC around bytes that are no table.
  std::vector<std::uint8_t> foreign(good.size());
  const std::size_t payload = good.size() - trueaxis::macros::kRecordFileOverhead;
  foreign.resize(trueaxis::macros::encode_record_file(5, good.data() + 16, payload, foreign.data(), foreign.size()));
  refused(foreign, "another record");
  std::vector<std::uint8_t> garbage(good.size());
  const std::vector<std::uint8_t> noise(payload, 0x5A);
  garbage.resize(trueaxis::macros::encode_record_file(3, noise.data(), noise.size(), garbage.data(), garbage.size()));
  refused(garbage, "does not decode");

  // Nothing stored: the export says so and writes nothing.
  {
    t::InProcessSim empty;
    const t::Run none = t::run({TRUEAXIS_CALIBRATE_BINARY, "linuxcnc-kins", "rigidity", "--out", w.file("none.table"), "--port",
                                std::to_string(empty.port())},
                               w.file("stderr"));
    CHECK(none.exit_code == 1);
    CHECK(none.err.find("module error 404 no_table") != std::string::npos);
    CHECK_FALSE(t::exists(w.file("none.table")));
  }
  // The C interface the real-time module calls: a missing file says so.
  const char* why = "";
  CHECK(trueaxis_kins_load(w.file("absent.table").c_str(), &why) == -1);
  CHECK(std::string(why) == "No such file or directory");
  CHECK(trueaxis_kins_poses() == 0);
  CHECK(trueaxis_kins_load(w.file("m3.table").c_str(), &why) == 0);
  CHECK(trueaxis_kins_poses() == 7);
}

TEST_CASE("kins: a table measured under another home of the axes (#904, home=) is refused with both identities; "
          "the export carries the home either way",
          "[kins]") {
  t::InProcessSim sim;
  t::Workspace w("trueaxis-kins");
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  const double unlock[1] = {2718.0};
  const double home[1] = {7.0};
  REQUIRE(sim.client().write(v::kUnlock, 1, unlock));
  REQUIRE(sim.client().write(v::kHomeIdentity, 1, home));
  const double lock[1] = {0.0};
  REQUIRE(sim.client().write(v::kUnlock, 1, lock));
  const std::vector<std::uint8_t> file = stored_table_file(sim, w, ball_csv(machine, 0.001, 9));
  // The same bytes through the export of what is stored (9837's #129 carries the home).
  const t::Run exported = t::run({TRUEAXIS_CALIBRATE_BINARY, "linuxcnc-kins", "rigidity", "--out",
                                  w.file("again.table"), "--port", std::to_string(sim.port())},
                                 w.file("stderr"));
  REQUIRE(exported.exit_code == 0);
  const std::string again = t::slurp(w.file("again.table"));
  CHECK(std::vector<std::uint8_t>(again.begin(), again.end()) == file);

  trueaxis::linuxcnc::CradleKinematics kins;
  const trueaxis::linuxcnc::LoadResult at_zero = kins.load_table(file.data(), file.size());
  CHECK_FALSE(at_zero.ok);
  CHECK(std::string(at_zero.why).find("another home") != std::string::npos);
  CHECK(kins.file_home() == 7);
  CHECK_FALSE(kins.calibrated());
  kins.set_home(8);
  CHECK_FALSE(kins.load_table(file.data(), file.size()).ok);
  kins.set_home(7);
  CHECK(kins.load_table(file.data(), file.size()).ok);
  CHECK(kins.calibrated());
  // The C interface: home= a whole number 0..65535.
  const char* why = "";
  for (const char* bad : {"-1", "65536", "1.5", "seven", "7,8"}) {
    INFO(bad);
    CHECK(trueaxis_kins_set_home(bad, &why) == -1);
    CHECK(std::string(why).find("home takes a whole number") != std::string::npos);
  }
  REQUIRE(trueaxis_kins_set_home("8", &why) == 0);
  CHECK(trueaxis_kins_home() == 8);
  CHECK(trueaxis_kins_load(w.file("m3.table").c_str(), &why) == -1);
  CHECK(trueaxis_kins_file_home() == 7);
  REQUIRE(trueaxis_kins_set_home("7", &why) == 0);
  CHECK(trueaxis_kins_load(w.file("m3.table").c_str(), &why) == 0);
  REQUIRE(trueaxis_kins_set_home("", &why) == 0);  // absent: 0
  CHECK(trueaxis_kins_home() == 0);
}

TEST_CASE("kins: the tool tip (M4): the stored model's file, its error 9843's bit for bit, taken off the joints",
          "[kins]") {
  t::InProcessSim sim;
  t::Workspace w("trueaxis-kins");
  store_spindle_model(sim, w);
  const std::string bytes = t::slurp(w.file("m4.model"));
  const std::vector<std::uint8_t> file(bytes.begin(), bytes.end());
  const t::Run exported = t::run({TRUEAXIS_CALIBRATE_BINARY, "linuxcnc-kins", "spindle", "--out", w.file("x.model"),
                                  "--port", std::to_string(sim.port())},
                                 w.file("stderr"));
  REQUIRE(exported.exit_code == 0);
  CHECK(t::slurp(w.file("x.model")) == bytes);

  trueaxis::linuxcnc::CradleKinematics kins;
  Vec3 none;
  CHECK_FALSE(kins.tip_error(0.0, 100.0, none));  // no model yet
  REQUIRE(kins.load_spindle(file.data(), file.size()).ok);
  for (const double phi : {0.0, 37.5, 359.9, 360.0, 725.25, -90.0, -1000.0}) {
    for (const double tool : {0.0, 100.0, 250.0}) {
      INFO("phi " << phi << " tool " << tool);
      Vec3 error;
      REQUIRE(kins.tip_error(phi, tool, error));
      const double st[2] = {phi, tool};
      REQUIRE(sim.client().write_one(v::kArgS, st[0]));
      REQUIRE(sim.client().write_one(v::kArgZ, st[1]));
      REQUIRE(sim.client().run_macro(9843).status == 2);
      double out[3];
      REQUIRE(sim.client().read(v::kSpindleTipX, 3, out));
      CHECK(same_bits(error, Vec3(out[0], out[1], out[2])));
    }
  }
  Vec3 kept(1, 2, 3);
  CHECK_FALSE(kins.tip_error(0.0, -0.001, kept));
  CHECK_FALSE(kins.tip_error(0.0, 1e5 + 1.0, kept));
  CHECK_FALSE(kins.tip_error(NAN, 100.0, kept));
  CHECK(kept == Vec3(1, 2, 3));
  // A rigidity table is not a spindle model, and a damaged model file is refused.
  std::vector<std::uint8_t> damaged = file;
  damaged[100] ^= 0x02;
  const trueaxis::linuxcnc::LoadResult refused = kins.load_spindle(damaged.data(), damaged.size());
  CHECK_FALSE(refused.ok);
  CHECK(std::string(refused.why).find("damaged") != std::string::npos);
  CHECK(kins.spindle_loaded());

  // The C interface the module calls: the correction asked for before any
  // model is loaded is an error, not an uncorrected move; then off the joints and back.
  {
    const double at[3] = {1.0, 2.0, 3.0};
    double out[3] = {9.0, 9.0, 9.0};
    CHECK(trueaxis_kins_to_joints(0, at, 0.0, 0.0, 100.0, 1, 0.0, out) == -1);
    CHECK(trueaxis_kins_to_world(0, at, 0.0, 0.0, 100.0, 1, 0.0, out) == -1);
    CHECK(out[0] == 9.0);
  }
  const char* why = "";
  CHECK(trueaxis_kins_load_spindle(w.file("absent.model").c_str(), &why) == -1);
  REQUIRE(trueaxis_kins_load_spindle(w.file("m4.model").c_str(), &why) == 0);
  CHECK(trueaxis_kins_spindle_loaded() == 1);
  double e[3];
  REQUIRE(trueaxis_kins_tip_error(37.5, 100.0, e) == 0);
  Vec3 error;
  REQUIRE(kins.tip_error(37.5, 100.0, error));
  CHECK(same_bits(Vec3(e[0], e[1], e[2]), error));
  CHECK(trueaxis_kins_tip_error(37.5, -1.0, e) == -1);

  // What the module's kinematicsInverse and kinematicsForward run (kins_api.h):
  // identity or cradle, the tip's error taken off the joints while it is on,
  // and back; a tool length the model refuses is an error, not an uncorrected move.
  REQUIRE(trueaxis_kins_load(w.file("absent.table").c_str(), &why) == -1);  // the ideal cradle stays
  sim::SimRng rng(99);
  for (int i = 0; i < 50; ++i) {
    const int type = i % 2;
    const double a = -100.0 + 200.0 * rng.uniform01();
    const double c = 720.0 * rng.uniform01();
    const double phi = 360.0 * rng.uniform01();
    const double world[3] = {200.0 * rng.uniform01(), -100.0 * rng.uniform01(), 50.0 * rng.uniform01()};
    double plain[3], corrected[3], back[3];
    REQUIRE(trueaxis_kins_to_joints(type, world, a, c, 120.0, 0, phi, plain) == 0);
    REQUIRE(trueaxis_kins_to_joints(type, world, a, c, 120.0, 1, phi, corrected) == 0);
    REQUIRE(trueaxis_kins_tip_error(phi, 120.0, e) == 0);
    for (int k = 0; k < 3; ++k) CHECK(corrected[k] == plain[k] - e[k]);
    REQUIRE(trueaxis_kins_to_world(type, corrected, a, c, 120.0, 1, phi, back) == 0);
    CHECK(std::hypot(std::hypot(back[0] - world[0], back[1] - world[1]), back[2] - world[2]) < 1e-9);
    if (type == 0) CHECK((plain[0] == world[0] && plain[1] == world[1] && plain[2] == world[2]));
  }
  const double world[3] = {10.0, 20.0, 30.0};
  double joints[3] = {7.0, 7.0, 7.0};
  CHECK(trueaxis_kins_to_joints(1, world, 30.0, 0.0, -5.0, 1, 10.0, joints) == -1);
  CHECK(trueaxis_kins_to_world(1, world, 30.0, 0.0, -5.0, 1, 10.0, joints) == -1);
  CHECK((joints[0] == 7.0 && joints[1] == 7.0 && joints[2] == 7.0));
  const double bad[3] = {NAN, 0.0, 0.0};
  CHECK(trueaxis_kins_to_joints(0, bad, 0.0, 0.0, 0.0, 0, 0.0, joints) == -1);
}

TEST_CASE("kins: an inch machine (linear_units=inch): world, joints and tool offset converted, the table in mm; "
          "anything but LinuxCNC's unit names refused",
          "[kins]") {
  // On whatever table the module holds (the ideal cradle, or an earlier case's).
  const MmAtExit mm;
  const char* why = "";
  sim::SimRng rng(5);
  for (int i = 0; i < 50; ++i) {
    const double a = -100.0 + 200.0 * rng.uniform01();
    const double c = 720.0 * rng.uniform01();
    const double tool_in = 8.0 * rng.uniform01();
    const double world_in[3] = {8.0 * rng.uniform01(), -4.0 * rng.uniform01(), 3.0 * rng.uniform01()};
    const double world_mm[3] = {25.4 * world_in[0], 25.4 * world_in[1], 25.4 * world_in[2]};
    double joint_mm[3], joint_in[3], back_in[3];
    REQUIRE(trueaxis_kins_set_linear_units("mm", &why) == 0);
    REQUIRE(trueaxis_kins_to_joints(1, world_mm, a, c, 25.4 * tool_in, 0, 0.0, joint_mm) == 0);
    REQUIRE(trueaxis_kins_set_linear_units(i % 2 == 0 ? "inch" : "imperial", &why) == 0);
    REQUIRE(trueaxis_kins_to_joints(1, world_in, a, c, tool_in, 0, 0.0, joint_in) == 0);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(25.4 * joint_in[k] - joint_mm[k]) < 1e-9);
    REQUIRE(trueaxis_kins_to_world(1, joint_in, a, c, tool_in, 0, 0.0, back_in) == 0);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(back_in[k] - world_in[k]) < 1e-12);
    // The identity, LinuxCNC's world as it is, in any unit.
    REQUIRE(trueaxis_kins_to_joints(0, world_in, a, c, tool_in, 0, 0.0, joint_in) == 0);
    for (int k = 0; k < 3; ++k) CHECK(joint_in[k] == world_in[k]);
  }
  // A 4 in tool at A 30: where 101.6 mm puts it (read as mm, 4 in would be a 4 mm tool).
  const double world_in[3] = {1.0, 2.0, 4.0};
  const double world_mm[3] = {25.4, 50.8, 101.6};
  double joint_in[3], joint_mm[3];
  REQUIRE(trueaxis_kins_set_linear_units("metric", &why) == 0);
  REQUIRE(trueaxis_kins_to_joints(1, world_mm, 30.0, 0.0, 101.6, 0, 0.0, joint_mm) == 0);
  REQUIRE(trueaxis_kins_set_linear_units("in", &why) == 0);
  REQUIRE(trueaxis_kins_to_joints(1, world_in, 30.0, 0.0, 4.0, 0, 0.0, joint_in) == 0);
  for (int k = 0; k < 3; ++k) CHECK(std::abs(25.4 * joint_in[k] - joint_mm[k]) < 1e-9);
  for (const char* bad : {"", "MM", "inches", "cm", "m"}) {
    INFO(bad);
    why = "";
    CHECK(trueaxis_kins_set_linear_units(bad, &why) == -1);
    CHECK(std::string(why).find("LINEAR_UNITS") != std::string::npos);
  }
  REQUIRE(trueaxis_kins_to_joints(1, world_in, 30.0, 0.0, 4.0, 0, 0.0, joint_in) == 0);  // still inch
  for (int k = 0; k < 3; ++k) CHECK(std::abs(25.4 * joint_in[k] - joint_mm[k]) < 1e-9);
}

TEST_CASE("kins: the servo thread's tip correction: a ramp of at most tip-ramp a period, by length, arriving "
          "exactly; the mean over a revolution 9844's bit for bit; the kinematics with the error given as with the "
          "pins",
          "[kins]") {
  // The ramp (cradle_kinematics.hpp convention 7), at its exact boundaries.
  {
    const Vec3 target(0.00285, -0.0038, 0.0);  // 4.75 um
    Vec3 applied = Vec3::Zero();
    int periods = 0;
    while (!trueaxis::linuxcnc::tip_ramp_step(target, 0.0005, applied)) {
      ++periods;
      REQUIRE(periods < 100);
      CHECK(std::abs(applied.norm() - 0.0005 * periods) < 1e-15);  // 0.5 um a period, along the way to the target
      CHECK(applied.cross(target).norm() < 1e-18);
    }
    CHECK(periods == 9);  // 4.5 um after 9 periods; the 10th arrives (0.25 um left)
    CHECK(applied == target);
    // A step exactly the ramp arrives; one a hair longer does not.
    Vec3 at = Vec3::Zero();
    CHECK(trueaxis::linuxcnc::tip_ramp_step(Vec3(0.0005, 0.0, 0.0), 0.0005, at));
    at = Vec3::Zero();
    CHECK_FALSE(trueaxis::linuxcnc::tip_ramp_step(Vec3(std::nextafter(0.0005, 1.0), 0.0, 0.0), 0.0005, at));
    // A ramp not above 0 or not finite (a pin netted to a signal nobody sets): the default, never at once.
    for (const double ramp : {0.0, -1.0, static_cast<double>(NAN), static_cast<double>(INFINITY)}) {
      Vec3 a = Vec3::Zero();
      CHECK_FALSE(trueaxis::linuxcnc::tip_ramp_step(target, ramp, a));
      CHECK(std::abs(a.norm() - trueaxis::linuxcnc::kDefaultTipRampMm) < 1e-15);
    }
  }

  // The mean over a revolution: 9844's (#110..#112) bit for bit, through the C interface.
  t::InProcessSim sim;
  t::Workspace w("trueaxis-kins-mean");
  store_spindle_model(sim, w);
  const char* why = "";
  REQUIRE(trueaxis_kins_load_spindle(w.file("m4.model").c_str(), &why) == 0);
  REQUIRE(trueaxis_kins_set_linear_units("mm", &why) == 0);
  for (const double tool : {0.0, 100.0, 250.0}) {
    double mean[3];
    REQUIRE(trueaxis_kins_tip_target(2, 0.0, tool, mean) == 0);
    const double rs[2] = {1.0, 0.0};  // R = 1: the stored model, S = 0
    REQUIRE(sim.client().write(v::kArgR, 2, rs));
    REQUIRE(sim.client().write_one(v::kArgZ, tool));
    REQUIRE(sim.client().run_macro(9844).status == 2);
    double out[3];
    REQUIRE(sim.client().read(v::kSpindleMeanTipX, 3, out));
    CHECK(same_bits(Vec3(mean[0], mean[1], mean[2]), Vec3(out[0], out[1], out[2])));
    // At an angle: 9843's, as tip_error; off: zero.
    double at[3], e[3], none[3] = {9.0, 9.0, 9.0};
    REQUIRE(trueaxis_kins_tip_target(1, 37.5, tool, at) == 0);
    REQUIRE(trueaxis_kins_tip_error(37.5, tool, e) == 0);
    CHECK(same_bits(Vec3(at[0], at[1], at[2]), Vec3(e[0], e[1], e[2])));
    REQUIRE(trueaxis_kins_tip_target(0, 37.5, tool, none) == 0);
    CHECK((none[0] == 0.0 && none[1] == 0.0 && none[2] == 0.0));
    // The kinematics with that error given are the kinematics with the pins, bit for bit.
    const double world[3] = {12.0, -34.0, 56.0};
    double by_pins[3], given[3], back[3];
    for (const int type : {0, 1}) {
      REQUIRE(trueaxis_kins_to_joints(type, world, 30.0, 75.0, tool, 1, 37.5, by_pins) == 0);
      REQUIRE(trueaxis_kins_to_joints_with(type, world, 30.0, 75.0, tool, at, given) == 0);
      CHECK(same_bits(Vec3(by_pins[0], by_pins[1], by_pins[2]), Vec3(given[0], given[1], given[2])));
      REQUIRE(trueaxis_kins_to_world_with(type, given, 30.0, 75.0, tool, at, back) == 0);
      CHECK(std::hypot(std::hypot(back[0] - world[0], back[1] - world[1]), back[2] - world[2]) < 1e-9);
    }
  }
  // An inch machine with the tip's error on: the error (mm) in the machine's units.
  {
    const MmAtExit mm;
    const double world_mm[3] = {25.4, -50.8, 76.2};
    const double world_in[3] = {1.0, -2.0, 3.0};
    for (const int type : {0, 1}) {
      double jm[3], ji[3];
      REQUIRE(trueaxis_kins_set_linear_units("mm", &why) == 0);
      REQUIRE(trueaxis_kins_to_joints(type, world_mm, 30.0, 75.0, 101.6, 1, 37.5, jm) == 0);
      REQUIRE(trueaxis_kins_set_linear_units("inch", &why) == 0);
      REQUIRE(trueaxis_kins_to_joints(type, world_in, 30.0, 75.0, 4.0, 1, 37.5, ji) == 0);
      for (int k = 0; k < 3; ++k) CHECK(std::abs(25.4 * ji[k] - jm[k]) < 1e-9);
    }
  }
  double kept[3] = {7.0, 7.0, 7.0};
  CHECK(trueaxis_kins_tip_target(2, 0.0, -1.0, kept) == -1);  // a length the model refuses
  CHECK(trueaxis_kins_tip_target(3, 0.0, 10.0, kept) == -1);  // no such mode
  CHECK(kept[0] == 7.0);
  const double bad[3] = {NAN, 0.0, 0.0};
  const double world[3] = {1.0, 2.0, 3.0};
  double joint[3];
  CHECK(trueaxis_kins_to_joints_with(1, world, 0.0, 0.0, 0.0, bad, joint) == -1);  // a non-finite error
}

TEST_CASE("kins: the ideal cradle about a nominal pivot off the origin (pivot=, a_offset=) is xyzac-trt-kins with "
          "the same rot-point and offsets; refused when not numbers",
          "[kins]") {
  sim::SimRng rng(41);
  for (int i = 0; i < 200; ++i) {
    Trt trt;
    trt.rot_point = Vec3(400.0 * rng.uniform01() - 200.0, 400.0 * rng.uniform01() - 200.0, 200.0 * rng.uniform01());
    trt.dy = 100.0 * rng.uniform01() - 50.0;
    trt.dz = 100.0 * rng.uniform01() - 50.0;
    trt.tool = i % 3 == 0 ? 0.0 : 200.0 * rng.uniform01();
    trueaxis::linuxcnc::CradleKinematics ideal;
    REQUIRE(ideal.set_nominal_pivot(trt.rot_point, trt.dy, trt.dz));
    const double a = -120.0 + 240.0 * rng.uniform01();
    const double c = -400.0 + 800.0 * rng.uniform01();
    const Vec3 world(300.0 * rng.uniform01() - 150.0, 200.0 * rng.uniform01() - 100.0, 100.0 * rng.uniform01());
    INFO("A " << a << " C " << c << " pivot " << trt.rot_point.x() << "," << trt.rot_point.y() << "," << trt.rot_point.z()
                << " dy " << trt.dy << " dz " << trt.dz);
    Vec3 joint, back;
    REQUIRE(ideal.to_joints(true, world, a, c, trt.tool, false, 0.0, joint));
    CHECK((joint - trt.inverse(world, a, c)).norm() < 1e-9);
    REQUIRE(ideal.to_world(true, joint, a, c, trt.tool, false, 0.0, back));
    CHECK((back - world).norm() < 1e-9);
    // The C axis through the pivot, the A axis through pivot + (0, dy, dz): points on them stay.
    REQUIRE(ideal.inverse(trt.rot_point + Vec3(0.0, 0.0, 37.0), 0.0, c, joint));
    CHECK((joint - (trt.rot_point + Vec3(0.0, 0.0, 37.0))).norm() < 1e-9);
    const Vec3 on_a = trt.rot_point + Vec3(55.0, trt.dy, trt.dz);
    REQUIRE(ideal.inverse(on_a, a, 0.0, joint));
    CHECK((joint - on_a).norm() < 1e-9);
  }
  // Through the module's parameters (the machine's units), and what they refuse.
  const char* why = "";
  REQUIRE(trueaxis_kins_set_linear_units("mm", &why) == 0);
  for (const char* bad : {"1,2", "1,2,3,4", "a,b,c", "1;2;3", "1,2,nan", "1,,3", "1,2,3,"}) {
    INFO(bad);
    why = "";
    CHECK(trueaxis_kins_set_pivot(bad, "", &why) == -1);
    CHECK(std::string(why).find("pivot takes X,Y,Z") != std::string::npos);
  }
  for (const char* bad : {"1", "1,2,3", "x,2"}) {
    INFO(bad);
    CHECK(trueaxis_kins_set_pivot("", bad, &why) == -1);
    CHECK(std::string(why).find("a_offset takes DY,DZ") != std::string::npos);
  }
  CHECK(trueaxis_kins_set_pivot("12.5,-30,0.25", "40,-2", &why) == 0);
  CHECK(trueaxis_kins_set_pivot(nullptr, nullptr, &why) == 0);  // absent: the origin again
}
