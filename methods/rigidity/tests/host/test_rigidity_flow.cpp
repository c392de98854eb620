// M3 end to end on the virtual cradle with true errors (cradle_errors.hpp
// realistic set): ball positions measured with 1 um noise, streamed into the
// module (9830, 9831), the table built and stored (9832), then checked against
// the machine's truth: rotation vectors within 3 sigma, compensation accuracy
// over the whole A range, the live table through the direct call and 9833, and
// leveling on the calibrated axes against leveling on the ideal ones. The
// register contracts (the session, the build's refusals, the stored table, the
// queries on a closed-form cradle) are portable tests:
// methods/rigidity/tests/portable/rigidity_macros_test.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "module_rig.hpp"
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



constexpr double kArcsec = sim::kArcsecPerRad;
const std::vector<double> kPosesDeg = {-90, -60, -30, 0, 30, 60, 90};

using Rig = trueaxis::test::ModuleRig;

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
      REQUIRE(rig.module().write(v::kArgA, 3, ac) == F::kNone);
      REQUIRE(rig.module().write(v::kArgX, 3, xyz) == F::kNone);
      REQUIRE(rig.run(9831) == 2.0);
    }
  }
  if (store) rig.set(v::kUnlock, m::kUnlockCode);
  rig.set(v::kArgR, store ? 1.0 : 0.0);
  const double status = rig.run(9832);
  if (store) rig.set(v::kUnlock, 0.0);
  return status;
}

struct PoseReading {
  Vec3 rotvec_arcsec, sigma_arcsec;
};

PoseReading pose(Rig& rig, int q, bool stored) {
  rig.set(v::kArgQ, q);
  rig.set(v::kArgR, stored ? 1.0 : 0.0);
  REQUIRE(rig.run(9834) == 2.0);
  return {rig.get3(v::kPoseRotvecX), rig.get3(v::kPoseRotvecSigmaX)};
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

TEST_CASE("the A positioning error's and the C-circle RMS's sigmas match their Monte-Carlo spread on the simulator",
          "[rigidity][flow][montecarlo]") {
  // The realistic machine measured with the simulator's ball (1 um per axis)
  // kRuns times, each calibration built in the module and read back by 9834:
  // the A positioning error's spread about the noise-free build (the
  // definition's truth, as above) against its reported sigma, and the C-circle
  // RMS's spread about its mean against its sigma under the default ball noise
  // #601. The virtual C circles are exact circles, so every C-circle RMS is the
  // ball's noise: it must sit at its noise floor, within 3 sigma.
  // TRUEAXIS_FIGURES=1 prints the figures per pose.
  constexpr int kRuns = 60;
  const std::size_t m = kPosesDeg.size();
  const sim::CradleMachine mc = machine(true);
  Rig truth;
  REQUIRE(measure_and_build(truth, mc, 0.0, 1, false) == 2.0);
  std::vector<double> a_error_truth(m);
  for (std::size_t i = 0; i < m; ++i) {
    truth.set(v::kArgQ, static_cast<double>(i + 1));
    truth.set(v::kArgR, 0.0);
    REQUIRE(truth.run(9834) == 2.0);
    a_error_truth[i] = truth.get(v::kPoseAError);
  }
  struct Spread {
    double error2 = 0.0, sigma2 = 0.0, sum = 0.0, floor = 0.0;
    int at_floor = 0;
  };
  std::vector<Spread> a_error(m), rms(m);
  for (int run = 0; run < kRuns; ++run) {
    Rig rig;
    REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, 5000 + static_cast<std::uint64_t>(run), false) ==
            2.0);
    for (std::size_t i = 0; i < m; ++i) {
      rig.set(v::kArgQ, static_cast<double>(i + 1));
      rig.set(v::kArgR, 0.0);
      REQUIRE(rig.run(9834) == 2.0);
      const double e = rig.get(v::kPoseAError) - a_error_truth[i];
      a_error[i].error2 += e * e;
      a_error[i].sigma2 += std::pow(rig.get(v::kPoseAErrorSigma), 2);
      const double q = rig.get(v::kPoseCCircleRms), q_sigma = rig.get(v::kPoseCCircleRmsSigma);
      const double q_floor = rig.get(v::kPoseCCircleRmsFloor);
      rms[i].sum += q;
      rms[i].error2 += q * q;
      rms[i].sigma2 += q_sigma * q_sigma;
      rms[i].floor = q_floor;
      rms[i].at_floor += q <= q_floor + 3.0 * q_sigma ? 1 : 0;
    }
  }
  double worst = 1.0;
  for (std::size_t i = 0; i < m; ++i) {
    CAPTURE(kPosesDeg[i]);
    const double rms_mean = rms[i].sum / kRuns;
    const double rms_observed = std::sqrt(std::max(0.0, rms[i].error2 / kRuns - rms_mean * rms_mean));
    const double rms_predicted = std::sqrt(rms[i].sigma2 / kRuns);
    const double rms_ratio = rms_predicted / rms_observed;
    INFO("C-circle RMS " << rms_mean * 1000 << " um, floor " << rms[i].floor * 1000 << " um; sigma predicted "
                         << rms_predicted * 1000 << " um, observed " << rms_observed * 1000 << " um");
    CHECK(rms_ratio < 1.5);
    CHECK(rms_ratio > 1.0 / 1.5);
    CHECK(rms[i].at_floor >= kRuns - 1);  // noise, reported as such
    CHECK(std::fabs(rms_mean / rms[i].floor - 1.0) < 0.05);
    worst = std::max({worst, rms_ratio, 1.0 / rms_ratio});
    double a_ratio = 1.0, a_predicted = 0.0, a_observed = 0.0;
    if (kPosesDeg[i] != 0.0) {
      a_predicted = std::sqrt(a_error[i].sigma2 / kRuns);
      a_observed = std::sqrt(a_error[i].error2 / kRuns);
      a_ratio = a_predicted / a_observed;
      INFO("A positioning error sigma predicted " << a_predicted << "\", observed " << a_observed << "\"");
      CHECK(a_ratio < 1.5);
      CHECK(a_ratio > 1.0 / 1.5);
      worst = std::max({worst, a_ratio, 1.0 / a_ratio});
    } else {
      CHECK(a_error[i].sigma2 == 0.0);  // the reference, by definition
    }
    if (std::getenv("TRUEAXIS_FIGURES") != nullptr) {
      std::printf("A %6.1f: A error sigma %.3f\" predicted, %.3f\" observed (%.2f); C rms %.4f um, floor %.4f um, "
                  "sigma %.4f um predicted, %.4f um observed (%.2f); at the floor %d of %d\n",
                  kPosesDeg[i], a_predicted, a_observed, a_ratio, rms_mean * 1000, rms[i].floor * 1000,
                  rms_predicted * 1000, rms_observed * 1000, rms_ratio, rms[i].at_floor, kRuns);
    }
  }
  WARN("A positioning error and C-circle RMS sigmas over " << kRuns << " simulator calibrations: worst ratio "
                                                           << worst);
}

TEST_CASE("compensation brings the table's orientation error under 5 % and a point 200 mm out under 2 um",
          "[rigidity][flow]") {
  const sim::CradleMachine mc = machine(true);
  double worst_ratio = 0.0, worst_position_um = 0.0;
  for (std::uint64_t seed = 100; seed < 110; ++seed) {  // ten calibrations, each measured anew
    Rig rig;
    REQUIRE(measure_and_build(rig, mc, sim::kDefaultBallSigmaMm, seed, true) == 2.0);
    const m::rigidity::State& state = rig.module().state<m::rigidity::Method>();
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
      rig.set(v::kUnlock, m::kUnlockCode);
      rig.set(v::kLevelAxes, axes);
      rig.set(v::kUnlock, 0.0);
      const std::uint16_t targets[3] = {v::kG57, v::kG58, v::kG59};
      for (int i = 0; i < 3; ++i) {  // an equilateral triangle of side 100 mm, table at zero
        const double angle = core::kPi / 2 + 2 * core::kPi * i / 3;
        Vec3 p;
        REQUIRE(sim::TouchProbe::touch(mc.face_at(0.0, 0.0), 57.735 * std::cos(angle), 57.735 * std::sin(angle), p));
        const double noisy[3] = {p.x() + 0.0005 * rng.normal(), p.y() + 0.0005 * rng.normal(), p.z() + 0.0005 * rng.normal()};
        REQUIRE(rig.module().write(targets[i], 3, noisy) == F::kNone);
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
