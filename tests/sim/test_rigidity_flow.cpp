// M3 end to end on the virtual cradle with true errors (cradle_errors.hpp
// realistic set): ball positions measured with 1 um noise, streamed into the
// module (9830, 9831), the table built and stored (9832), then checked against
// the machine's truth: rotation vectors within 3 sigma, compensation accuracy
// over the whole A range, the live table through the direct call and 9833, and
// leveling on the calibrated axes against leveling on the ideal ones.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "flow_rig.hpp"
#include "trueaxis/core/rigidity_compensation.hpp"
#include "trueaxis/core/so3.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/instruments/touch_probe.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
using core::Status;
using core::Vec3;
using F = m::AccessFault;

// The method's session in the module's shared session arena (it must hold it).
const trueaxis::macros::rigidity::RigiditySession& session_of(const trueaxis::macros::Module& module) {
  const auto* s = module.session<trueaxis::macros::rigidity::Method>();
  REQUIRE(s != nullptr);
  return *s;
}


constexpr double kArcsec = sim::kArcsecPerRad;
const std::vector<double> kPosesDeg = {-90, -60, -30, 0, 30, 60, 90};

using Rig = trueaxis::test::FlowRig;

// The realistic machine, with or without its stiffness term (see the note in
// "recovered rotation vectors").
sim::CradleMachine machine(bool stiffness) {
  sim::CradleErrors e = sim::realistic_errors();
  if (!stiffness) e.k_stiffness_arcsec = 0.0;
  return sim::CradleMachine(sim::FaceConfig{}, e);
}

// Measures the ball at every pose and C every 10 deg (36 positions, the most a
// pose takes), streams it, builds (and
// with `store` stores) the table; the build's #9001.
double measure_and_build(Rig& rig, const sim::CradleMachine& mc, double sigma_mm, std::uint64_t seed, bool store) {
  sim::CalibrationBall ball;
  ball.sigma_mm = sigma_mm;
  sim::SimRng rng(seed);
  REQUIRE(rig.run(9830) == 2.0);
  for (double a : kPosesDeg) {
    for (int k = 0; k < 36; ++k) {
      const double c = 10.0 * k;
      const Vec3 p = ball.measure(mc.machine_T_table(a, c), rng);
      const double ac[3] = {a, 0.0, c};
      const double xyz[3] = {p.x(), p.y(), p.z()};
      REQUIRE(rig.module.write(v::kArgA, 3, ac) == F::kNone);
      REQUIRE(rig.module.write(v::kArgX, 3, xyz) == F::kNone);
      REQUIRE(rig.run(9831) == 2.0);
    }
  }
  if (store) rig.put(v::kUnlock, m::kUnlockCode);
  rig.put(v::kArgR, store ? 1.0 : 0.0);
  const double status = rig.run(9832);
  if (store) rig.put(v::kUnlock, 0.0);
  return status;
}

struct PoseReading {
  Vec3 rotvec_arcsec, sigma_arcsec;
};

PoseReading pose(Rig& rig, int q, bool stored) {
  rig.put(v::kArgQ, q);
  rig.put(v::kArgR, stored ? 1.0 : 0.0);
  REQUIRE(rig.run(9834) == 2.0);
  return {rig.out3(v::kPoseRotvecX), rig.out3(v::kPoseRotvecSigmaX)};
}

}  // namespace

TEST_CASE("recovered rotation vectors are within 3 sigma of the truth by the module's own figure",
          "[rigidity][flow]") {
  // The truth is docs/INTERFACE.md's definition applied to the true machine: the
  // same build on noise-free ball positions (the definition's A axis is the
  // circle through the C centres). Without the stiffness term that equals the
  // simulator's own truth about its true A axis (checked below to 0.1"); with it
  // the C centres leave the circle and the two definitions differ by up to 20"
  // (the simulator's note), so the noise-free build is the truth there.
  for (const bool stiffness : {false, true}) {
    CAPTURE(stiffness);
    const sim::CradleMachine mc = machine(stiffness);
    Rig truth;
    REQUIRE(measure_and_build(truth, mc, 0.0, 1, false) == 2.0);
    if (!stiffness) {
      for (std::size_t i = 0; i < kPosesDeg.size(); ++i) {
        const Vec3 sim_truth = mc.rotation_vector_rad(kPosesDeg[i], sim::kDefaultBallZMm) * kArcsec;
        CHECK((pose(truth, static_cast<int>(i) + 1, false).rotvec_arcsec - sim_truth).norm() < 0.1);
      }
    }
    int within = 0, total = 0;
    double worst_ratio = 0.0;
    for (std::uint64_t seed = 10; seed < 30; ++seed) {
      Rig rig;
      REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, seed, false) == 2.0);
      for (std::size_t i = 0; i < kPosesDeg.size(); ++i) {
        if (kPosesDeg[i] == 0.0) continue;
        const PoseReading got = pose(rig, static_cast<int>(i) + 1, false);
        const Vec3 want = pose(truth, static_cast<int>(i) + 1, false).rotvec_arcsec;
        for (int k = 0; k < 3; ++k) {
          const double ratio = std::fabs(got.rotvec_arcsec[k] - want[k]) / got.sigma_arcsec[k];
          worst_ratio = std::fmax(worst_ratio, ratio);
          within += ratio <= 3.0 ? 1 : 0;
          ++total;
        }
      }
    }
    INFO("components within 3 sigma: " << within << " of " << total << ", worst " << worst_ratio << " sigma");
    CHECK(within >= total * 99 / 100);  // a Gaussian puts 99.73 % there
    CHECK(worst_ratio < 4.5);
  }
}

TEST_CASE("compensation brings the table's orientation error under 5 % and a point 200 mm out under 2 um",
          "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  double worst_ratio = 0.0, worst_position_um = 0.0;
  for (std::uint64_t seed = 100; seed < 110; ++seed) {  // ten calibrations, each measured anew
    Rig rig;
    REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, seed, true) == 2.0);
    const m::rigidity::State& state = rig.module.state<m::rigidity::Method>();
    core::RigidityTable table;
    REQUIRE(state.table.read([&](const core::RigidityTable& t) { table = t; }));
    const auto frames_at = [&](double a, double c) {
      const auto f = core::rigidity_frames(table, a, c, core::Blend::kCubicNotAKnot, false);
      REQUIRE(f.ok());
      return f.value();
    };
    // Physical table points 200 mm from the C axis, in the product's table frame
    // (defined by the measurement): where the truth puts them at A = 0, C = 0.
    const core::RigidityFrames f0 = frames_at(0.0, 0.0);
    const sim::RigidTransform t0 = mc.machine_T_table(0.0, 0.0);
    std::vector<Vec3> q_true, q_product;
    for (int k = 0; k < 8; ++k) {
      const double phi = core::kPi / 4 * k;
      const Vec3 q(200.0 * std::cos(phi), 200.0 * std::sin(phi), 25.0 * (k % 3));
      q_true.push_back(q);
      q_product.push_back(f0.machine_T_table_actual.inverse().point(t0.apply(q)));
    }
    double uncompensated = 0.0, compensated = 0.0, position_um = 0.0;
    for (double a = -90.0; a <= 90.0; a += 2.5) {
      for (double c = 0.0; c < 360.0; c += 45.0) {
        const core::RigidityFrames f = frames_at(a, c);
        const sim::RigidTransform t = mc.machine_T_table(a, c);
        const core::Mat3 r_true = t.rotation * t0.rotation.transpose();
        const core::Mat3 r_theory =
            f.machine_T_table_theory.rotation * f0.machine_T_table_theory.rotation.transpose();
        const core::Mat3 r_actual =
            f.machine_T_table_actual.rotation * f0.machine_T_table_actual.rotation.transpose();
        uncompensated = std::fmax(uncompensated, core::so3_log(r_true * r_theory.transpose()).norm());
        compensated = std::fmax(compensated, core::so3_log(r_true * r_actual.transpose()).norm());
        for (std::size_t k = 0; k < q_true.size(); ++k) {
          const double err = (t.apply(q_true[k]) - f.machine_T_table_actual.point(q_product[k])).norm();
          position_um = std::fmax(position_um, 1000.0 * err);
        }
      }
    }
    UNSCOPED_INFO("seed " << seed << ": orientation error uncompensated " << uncompensated * kArcsec
                          << "\", compensated " << compensated * kArcsec << "\"; position " << position_um
                          << " um");
    CHECK(uncompensated * kArcsec > 20.0);  // the machine really has errors to compensate
    worst_ratio = std::fmax(worst_ratio, compensated / uncompensated);
    worst_position_um = std::fmax(worst_position_um, position_um);
  }
  CHECK(worst_ratio < 0.05);
  CHECK(worst_position_um < 2.0);
}

TEST_CASE("9833 and the direct call read the stored table, across a restart", "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  Rig rig;
  rig.put(v::kArgA, 45.0);
  CHECK(rig.run(9833) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));
  REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 3, true) == 2.0);

  for (const double blend : {0.0, 1.0, 2.0, 3.0}) {
    rig.put(v::kArgA, 45.0);
    rig.put(v::kArgQ, blend);
    REQUIRE(rig.run(9833) == 2.0);
    const auto direct = m::rigidity::compensation_rad(rig.module.state<m::rigidity::Method>(), 45.0,
                                                      static_cast<core::Blend>(static_cast<int>(blend)), false);
    REQUIRE(direct.ok());
    CHECK(rig.out3(v::kRigidityRotvecX) == direct.value() * kArcsec);
    CHECK(rig.get(v::kRigidityRotvecNorm) == direct.value().norm() * kArcsec);
  }
  // Exactly at the first and the last pose: inside the range, that pose's own
  // rotation vector bit for bit, whatever the blend.
  for (const double blend : {0.0, 1.0, 2.0, 3.0}) {
    for (const auto& [a, q] : {std::pair{-90.0, 1}, std::pair{90.0, 7}}) {
      rig.put(v::kArgA, a);
      rig.put(v::kArgQ, blend);
      rig.put(v::kArgR, 0.0);
      REQUIRE(rig.run(9833) == 2.0);
      const Vec3 at_pose = rig.out3(v::kRigidityRotvecX);
      CHECK(at_pose == pose(rig, q, true).rotvec_arcsec);
    }
  }
  // Outside the measured range, one ulp or more: refused with its own code,
  // the outputs of the last query kept; clamped to the end pose on request.
  rig.put(v::kArgA, 45.0);
  rig.put(v::kArgQ, 0.0);
  rig.put(v::kArgR, 0.0);
  REQUIRE(rig.run(9833) == 2.0);
  const Vec3 kept = rig.out3(v::kRigidityRotvecX);
  for (const double a : {std::nextafter(90.0, 100.0), std::nextafter(-90.0, -100.0), 95.0}) {
    rig.put(v::kArgA, a);
    rig.put(v::kArgR, 0.0);
    CHECK(rig.run(9833) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kOutsideMeasuredRange));
    CHECK(rig.out3(v::kRigidityRotvecX) == kept);
  }
  rig.put(v::kArgA, 95.0);
  rig.put(v::kArgR, 1.0);
  REQUIRE(rig.run(9833) == 2.0);
  const Vec3 clamped = rig.out3(v::kRigidityRotvecX);
  CHECK(clamped == pose(rig, 7, true).rotvec_arcsec);
  rig.put(v::kArgQ, 4.0);
  CHECK(rig.run(9833) == 3.0);  // no such blend

  // The same storage after a restart: the stored table is live again.
  m::Module second(rig.storage, rig.clock);
  REQUIRE(second.start() == Status::kOk);
  const auto again = m::rigidity::compensation_rad(second.state<m::rigidity::Method>(), 90.0, core::Blend::kLinear, false);
  REQUIRE(again.ok());
  CHECK(again.value() * kArcsec == clamped);
}

TEST_CASE("a stored table that fails its CRC or does not decode says so, not no_table", "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  Rig rig;
  REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 4, true) == 2.0);
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != m::RigidityTableRecord::kRecord.key) ++index;
  // The first save of the table went to slot 0, its only copy.
  const std::size_t slot = m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);
  const auto expect_everywhere = [](Rig& r, Status status) {
    r.put(v::kArgA, 10.0);
    CHECK(r.run(9833) == 3.0);
    CHECK(r.get(v::kError) == static_cast<double>(status));
    r.put(v::kArgQ, 1.0);
    r.put(v::kArgR, 1.0);
    CHECK(r.run(9834) == 3.0);
    CHECK(r.get(v::kError) == static_cast<double>(status));
    r.put(v::kArgA, 10.0);
    CHECK(r.run(9835) == 3.0);
    CHECK(r.get(v::kError) == static_cast<double>(status));
    CHECK(m::rigidity::compensation_rad(r.module.state<m::rigidity::Method>(), 10.0, core::Blend::kLinear, false).status() ==
          status);
  };

  SECTION("a bit lost in the stored table: table_damaged until a table is stored again") {
    rig.nv[slot + m::KeyedStore::kHeaderBytes + 100] ^= 0x04;
    Rig second;
    second.nv = rig.nv;
    REQUIRE(second.module.start() == Status::kOk);
    expect_everywhere(second, Status::kTableDamaged);
    REQUIRE(measure_and_build(second, mc, sim::kDefaultBallSigmaMm, 4, true) == 2.0);
    second.put(v::kArgA, 10.0);
    CHECK(second.run(9833) == 2.0);
  }
  SECTION("a record with a good CRC whose table does not decode: table_invalid") {
    Rig second;
    std::uint8_t scratch[m::kStoreScratchBytes];
    m::KeyedStore store(second.storage, m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
    REQUIRE(store.mount() == Status::kOk);
    const std::uint8_t garbage[64] = {1, 2, 3};
    REQUIRE(store.save(m::RigidityTableRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
    REQUIRE(second.module.start() == Status::kOk);
    expect_everywhere(second, Status::kTableInvalid);
  }
  SECTION("never stored: no_table") {
    Rig second;
    expect_everywhere(second, Status::kNoTable);
  }
}

TEST_CASE("a failed build stores nothing and keeps the live table", "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  Rig rig;
  REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 5, true) == 2.0);
  const auto before = rig.nv;
  const auto live_before = m::rigidity::compensation_rad(rig.module.state<m::rigidity::Method>(), 30.0, core::Blend::kLinear, false);
  REQUIRE(live_before.ok());

  SECTION("two poses only") {
    REQUIRE(rig.run(9830) == 2.0);
    for (double a : {0.0, 30.0}) {
      for (int k = 0; k < 6; ++k) {
        const double ac[3] = {a, 0.0, 60.0 * k};
        const Vec3 p = sim::CalibrationBall{}.centre_mm(mc.machine_T_table(a, 60.0 * k));
        const double xyz[3] = {p.x(), p.y(), p.z()};
        REQUIRE(rig.module.write(v::kArgA, 3, ac) == F::kNone);
        REQUIRE(rig.module.write(v::kArgX, 3, xyz) == F::kNone);
        REQUIRE(rig.run(9831) == 2.0);
      }
    }
    rig.put(v::kUnlock, m::kUnlockCode);
    rig.put(v::kArgR, 1.0);
    CHECK(rig.run(9832) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooFewPoses));
  }
  SECTION("locked") {
    rig.put(v::kArgR, 1.0);
    CHECK(rig.run(9832) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTableLocked));
  }
  CHECK(rig.nv == before);
  const auto live_after = m::rigidity::compensation_rad(rig.module.state<m::rigidity::Method>(), 30.0, core::Blend::kLinear, false);
  REQUIRE(live_after.ok());
  CHECK(live_after.value() == live_before.value());
}

TEST_CASE("leveling on the calibrated axes is within 3 sigma where the ideal axes are not", "[rigidity][flow][level]") {
  struct Face {
    double tilt_deg, azimuth_deg;
  };
  for (const Face face : {Face{40.0, 30.0}, Face{35.0, 200.0}, Face{45.0, 120.0}, Face{30.0, 300.0}}) {
    CAPTURE(face.tilt_deg, face.azimuth_deg);
    sim::CradleErrors e = sim::realistic_errors();
    const sim::CradleMachine mc(sim::FaceConfig{face.tilt_deg, face.azimuth_deg, 40.0}, e);
    Rig rig;
    REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 21, true) == 2.0);
    sim::SimRng rng(77);
    const auto level = [&](double axes, double& true_tilt_arcsec, double& sigma_arcsec) {
      rig.put(v::kUnlock, m::kUnlockCode);
      rig.put(v::kLevelAxes, axes);
      rig.put(v::kUnlock, 0.0);
      const std::uint16_t targets[3] = {v::kG57, v::kG58, v::kG59};
      for (int i = 0; i < 3; ++i) {  // an equilateral triangle of side 100 mm, table at zero
        const double angle = core::kPi / 2 + 2 * core::kPi * i / 3;
        Vec3 p;
        REQUIRE(sim::TouchProbe::touch(mc.face_at(0.0, 0.0), 57.735 * std::cos(angle), 57.735 * std::sin(angle), p));
        const double noisy[3] = {p.x() + 0.0005 * rng.normal(), p.y() + 0.0005 * rng.normal(), p.z() + 0.0005 * rng.normal()};
        REQUIRE(rig.module.write(targets[i], 3, noisy) == F::kNone);
      }
      REQUIRE(rig.run(9810) == 2.0);
      CHECK(rig.get(v::kLevelAxesUsed) == axes);
      true_tilt_arcsec = mc.tilt_deg_at(rig.get(v::kLevelA), rig.get(v::kLevelC)) * 3600.0;
      sigma_arcsec = rig.get(v::kLevelTiltSigma);
    };
    double ideal = 0, ideal_sigma = 0, calibrated = 0, calibrated_sigma = 0;
    level(0.0, ideal, ideal_sigma);
    level(1.0, calibrated, calibrated_sigma);
    INFO("true residual tilt: ideal axes " << ideal << "\", calibrated " << calibrated << "\" (1 sigma "
                                          << calibrated_sigma << "\")");
    CHECK(calibrated <= 3.0 * calibrated_sigma);
    CHECK(ideal > 3.0 * ideal_sigma);
  }
}

TEST_CASE("9834 R = 0 reports only a table whose 9832 succeeded", "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  Rig rig;
  REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 9, false) == 2.0);
  REQUIRE(pose(rig, 7, false).rotvec_arcsec.norm() > 0.0);
  rig.put(v::kArgR, 1.0);  // store while locked: built, then refused
  CHECK(rig.run(9832) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kTableLocked));
  rig.put(v::kArgQ, 7.0);
  rig.put(v::kArgR, 0.0);
  CHECK(rig.run(9834) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));
}

TEST_CASE("the rigidity session takes exactly its capacity and refuses the next sample", "[rigidity][flow]") {
  Rig rig;
  REQUIRE(rig.run(9830) == 2.0);
  CHECK(rig.get(v::kRigiditySessionCount) == 0.0);
  CHECK(rig.get(v::kRigiditySessionCapacity) == static_cast<double>(m::rigidity::kSessionCapacity));
  const auto add = [&](std::size_t k) {
    const double ac[3] = {static_cast<double>(k / 32), 0.0, 10.0 * static_cast<double>(k % 32)};
    const double xyz[3] = {200.0, static_cast<double>(k), 50.0};
    REQUIRE(rig.module.write(v::kArgA, 3, ac) == F::kNone);
    REQUIRE(rig.module.write(v::kArgX, 3, xyz) == F::kNone);
    return rig.run(9831);
  };
  for (std::size_t k = 0; k < m::rigidity::kSessionCapacity; ++k) REQUIRE(add(k) == 2.0);
  CHECK(rig.get(v::kRigiditySessionCount) == 512.0);
  CHECK(add(512) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kSessionFull));
  CHECK(rig.get(v::kRigiditySessionCount) == 512.0);  // the outputs of the last success
  CHECK(session_of(rig.module).size() == m::rigidity::kSessionCapacity);
  REQUIRE(rig.run(9830) == 2.0);
  CHECK(rig.get(v::kRigiditySessionCount) == 0.0);
  CHECK(add(0) == 2.0);
  CHECK(rig.get(v::kRigiditySessionCount) == 1.0);
}
