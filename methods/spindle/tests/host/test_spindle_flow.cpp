// M4 through the register interface against oracles only the host has: the
// analyser's samples of a seeded, noisy spindle streamed with 9841, the model
// identified with 9842 (several steps) and stored, and queried with 9843
// (docs/INTERFACE.md), 9844 and 9845; each answer held against the core's own
// functions bit for bit, the tip error against the truth within 3 sigma. The
// register contracts (the session, every refusal, the stored model, the
// queries on a closed-form spindle) are portable tests:
// methods/spindle/tests/portable/spindle_macros_test.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "module_rig.hpp"
#include "reference.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace sp = trueaxis::macros::spindle;
namespace v = trueaxis::macros::var;
namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;
using F = m::AccessFault;



using t::kDone;
constexpr double kArcsec = core::kPi / (180.0 * 3600.0);
const core::SpindleGeometry kGeometry{350.0, {50.0, 150.0}};

core::SpindleParams truth() {
  core::SpindleParams p;
  p << 0.0123, -0.0087, 399.998, -20 * kArcsec, 35 * kArcsec, 0.0023, 0.0014, -19.9 * kArcsec, 11.2 * kArcsec;
  return p;
}

// Two revolutions at 5 deg, both balls, 15 nm noise.
std::vector<core::SpindleSample> samples(std::uint64_t seed) {
  t::Rng rng(seed);
  std::vector<core::SpindleSample> s;
  for (int rev = 0; rev < 2; ++rev) {
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < 72; ++i) {
        const double phi = 360.0 * rev + 5.0 * i;
        const Vec3 n(rng.normal(), rng.normal(), rng.normal());
        s.push_back({phi, k, core::spindle_ball_mm(truth(), kGeometry, k, core::deg_to_rad(phi)) + 15e-6 * n});
      }
    }
  }
  return s;
}

struct Rig : t::ModuleRig {
  double add(const core::SpindleSample& s) {
    set(v::kArgS, s.phi_deg);
    set(v::kArgT, s.ball);
    const double xyz[3] = {s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
    REQUIRE(module().write(v::kArgX, 3, xyz) == F::kNone);
    return run(9841);
  }
  void stream(const std::vector<core::SpindleSample>& s) {
    REQUIRE(run(9840) == kDone);
    for (const auto& x : s) REQUIRE(add(x) == kDone);
  }
  // Arguments are cleared after every macro: each call sets all of its own.
  void arguments(double r, const core::SpindleGeometry& g = kGeometry) {
    set(v::kArgR, r);
    set(v::kArgD, g.gauge_mm);
    set(v::kArgU, g.ball_mm[0]);
    set(v::kArgV, g.ball_mm[1]);
  }
  double build(bool store, const core::SpindleGeometry& g = kGeometry) {
    if (store) set(v::kUnlock, m::kUnlockCode);
    arguments(store ? 1.0 : 0.0, g);
    return run(9842);
  }
  double report(double r, double phi_deg, double tool_mm) {
    set(v::kArgR, r);
    set(v::kArgS, phi_deg);
    set(v::kArgZ, tool_mm);
    return run(9844);
  }
  double correction(double phi_deg, double tool_mm) {
    set(v::kArgS, phi_deg);
    set(v::kArgZ, tool_mm);
    return run(9843);
  }
};

core::SpindleFit direct_fit(const std::vector<core::SpindleSample>& s) {
  core::SpindleFit fit;
  REQUIRE(core::fit_spindle(s.data(), s.size(), kGeometry, fit) == Status::kOk);
  return fit;
}

}  // namespace

TEST_CASE("9840..9845: the module identifies, stores and answers as the core computes", "[spindle][flow]") {
  const auto s = samples(91);
  Rig rig;
  rig.stream(s);
  CHECK(rig.get(v::kSpindleSessionSamples) == 288);
  CHECK(rig.get(v::kSpindleSessionAngles1) == 72);
  CHECK(rig.get(v::kSpindleSessionAngles2) == 72);
  CHECK(rig.get(v::kSpindleSessionCapacity) == 180);

  REQUIRE(rig.build(false) == kDone);
  const core::SpindleFit fit = direct_fit(s);
  CHECK(rig.get(v::kSpindleEvaluations) == fit.evaluations);
  CHECK(rig.get(v::kSpindleNoiseSigma) == fit.noise_sigma_mm);
  CHECK(rig.get(v::kSpindleSynchronousRms) == fit.synchronous_rms_mm);
  CHECK(rig.get(v::kSpindleNoiseFromRepeats) == 1.0);
  CHECK(rig.get(v::kSpindleSamplesUsed) == 288);
  for (int q = 1; q <= 9; ++q) {
    rig.set(v::kArgQ, q);
    rig.set(v::kArgR, 0);
    REQUIRE(rig.run(9845) == kDone);
    CHECK(rig.get(v::kSpindleParamValue) == fit.params(q - 1));
    CHECK(rig.get(v::kSpindleParamSigma) == std::sqrt(fit.covariance(q - 1, q - 1)));
  }
  CHECK(rig.get(v::kSpindleModelGauge) == 350.0);
  CHECK(rig.get(v::kSpindleModelBall2) == 150.0);

  REQUIRE(rig.build(true) == kDone);
  const core::SpindleModel model = core::make_spindle_model(fit, kGeometry);
  for (double phi : {0.0, 5.0, 123.4, 359.9, 720.0 + 30.0, -30.0}) {
    for (double tool : {0.0, 100.0, 250.0}) {
      REQUIRE(rig.correction(phi, tool) == kDone);
      const auto c = core::spindle_correction(model.axes, 350.0, tool, core::deg_to_rad(std::fmod(phi, 360.0)));
      REQUIRE(c.ok());
      CHECK(rig.get(v::kSpindleThetaE) == c.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
      CHECK(rig.get(v::kSpindleDE) == c.value().d_e_mm);
      CHECK(rig.get3(v::kSpindleTipX) == c.value().tip_error_mm);
      const auto direct = sp::tool_tip_correction(rig.module().state<m::spindle::Method>(), phi, tool);
      REQUIRE(direct.ok());
      CHECK(direct.value().tip_error_mm == c.value().tip_error_mm);
      // 9844 on the stored model and on the last identification: the same values, with sigmas.
      for (double r : {0.0, 1.0}) {
        REQUIRE(rig.report(r, phi, tool) == kDone);
        CHECK(rig.get3(v::kSpindleTipX) == c.value().tip_error_mm);
        const auto sigma = core::spindle_correction_sigma(fit.params, fit.covariance, 350.0, tool,
                                                          core::deg_to_rad(std::fmod(phi, 360.0)));
        CHECK(rig.get3(v::kSpindleTipSigmaX) == sigma.value().tip_error_mm);
        CHECK(rig.get3(v::kSpindleMeanTipX) == core::spindle_mean_tip_error_mm(model.axes, 350.0, tool));
        CHECK(rig.get(v::kSpindleThetaE) == c.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
        CHECK(rig.get(v::kSpindleDE) == c.value().d_e_mm);
        CHECK(rig.get(v::kSpindleThetaESigma) == sigma.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
        CHECK(rig.get(v::kSpindleDESigma) == sigma.value().d_e_mm);
        CHECK(rig.get3(v::kSpindleMeanTipSigmaX) == sigma.value().mean_tip_error_mm);
      }
    }
  }
  // The tip error at 250 mm against the truth, within 3 sigma per axis.
  for (int i = 0; i < 36; ++i) {
    const double phi = 10.0 * i;
    REQUIRE(rig.report(1, phi, 250.0) == kDone);
    const auto tc = core::spindle_correction(core::spindle_axes(truth()), 350.0, 250.0, core::deg_to_rad(phi));
    const Vec3 err = rig.get3(v::kSpindleTipX) - tc.value().tip_error_mm;
    const Vec3 sd = rig.get3(v::kSpindleTipSigmaX);
    for (int k = 0; k < 3; ++k) CHECK(std::fabs(err(k)) <= 3 * sd(k));
  }
}

TEST_CASE("9846: each figure's sigma holds both models' variances, and its log entry every figure, w_y the sixth",
          "[spindle][flow][check][log]") {
  // A model stored from one session and another identified (R = 0) from a
  // second session of the same spindle: similar sigmas, so a sigma that left
  // out either model's would be 1 / sqrt(2) of the right one.
  Rig rig;
  rig.stream(samples(91));
  REQUIRE(rig.build(true) == kDone);
  rig.stream(samples(92));
  REQUIRE(rig.build(false) == kDone);
  const auto parameter = [&rig](double r, int q, double& value, double& sigma) {
    rig.set(v::kArgR, r);
    rig.set(v::kArgQ, q);
    REQUIRE(rig.run(9845) == kDone);
    value = rig.get(v::kSpindleParamValue);
    sigma = rig.get(v::kSpindleParamSigma);
  };
  double deviation[6], sigma[6], tolerance[6];
  const char* names[6] = {"a_x", "a_y", "e_x", "e_y", "w_x", "w_y"};
  for (int k = 0; k < 6; ++k) {
    INFO("figure " << k + 1 << " " << names[k]);
    double stored = 0, stored_sigma = 0, built = 0, built_sigma = 0;
    parameter(1.0, k + 4, stored, stored_sigma);  // a_x .. w_y: parameters 4..9 (9845's Q)
    parameter(0.0, k + 4, built, built_sigma);
    const bool offset = k == 2 || k == 3;
    const double scale = offset ? 1.0 : core::kArcsecPerRad;
    rig.set(v::kArgQ, k + 1);
    REQUIRE(rig.run(9846) == kDone);
    CHECK(rig.get(m::var::kCheckFigureKind) == k + 1);
    CHECK(rig.get(m::var::kCheckFigureDeviation) == built * scale - stored * scale);  // in the figure's unit
    const double both = std::sqrt(stored_sigma * stored_sigma + built_sigma * built_sigma) * scale;
    CHECK(rig.get(m::var::kCheckFigureSigma) == Approx(both).epsilon(1e-12));
    CHECK(stored_sigma == Approx(built_sigma).epsilon(0.3));  // two comparable sessions: neither dominates
    deviation[k] = rig.get(m::var::kCheckFigureDeviation);
    sigma[k] = rig.get(m::var::kCheckFigureSigma);
    tolerance[k] = rig.get(m::var::kCheckFigureTolerance);
    CHECK(deviation[k] != 0.0);
  }
  // The check (Q = 0) logs one entry: per kind its worst figure, here each
  // kind's only one, all six in the window #9030..#9059.
  rig.set(v::kLogTime, 1'800'000'000.0);
  REQUIRE(rig.run(9846) == kDone);
  const double newest = rig.get(v::kLogNewest);
  rig.set(v::kLogSelect, newest);
  CHECK(rig.get(v::kLogMacro) == 9846.0);
  CHECK(rig.get(v::kLogType) == 1.0);  // a check
  REQUIRE(rig.get(v::kLogFigureCount) == 6.0);
  for (int k = 0; k < 6; ++k) {
    INFO("logged figure " << k + 1 << " " << names[k]);
    const auto field = [&rig, k](int j) { return rig.get(static_cast<std::uint16_t>(v::kLogFigureFirst + 5 * k + j)); };
    CHECK(field(0) == k + 1);  // kind
    CHECK(field(1) == 0.0);    // item: the whole
    CHECK(field(2) == static_cast<double>(static_cast<float>(deviation[k])));
    CHECK(field(3) == static_cast<double>(static_cast<float>(sigma[k])));
    CHECK(field(4) == static_cast<double>(static_cast<float>(tolerance[k])));
  }
}
