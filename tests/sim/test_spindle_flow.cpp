// M4 through the register interface, in process: the analyser's samples
// streamed with 9841, the model identified with 9842 (several steps), stored
// through the keyed store, and queried with 9843 (docs/INTERFACE.md), 9844 and 9845;
// each answer held against the core's own functions bit for bit, each refusal
// checked to leave the outputs, the session and the stored bytes as they were.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "flow_rig.hpp"
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

// The method's session in the module's shared session arena (it must hold it).
const trueaxis::core::SpindleBins& session_of(const trueaxis::macros::Module& module) {
  const auto* s = module.session<trueaxis::macros::spindle::Method>();
  REQUIRE(s != nullptr);
  return *s;
}


constexpr double kDone = 2.0;
constexpr double kError = 3.0;
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

struct Rig : t::FlowRig {
  double add(const core::SpindleSample& s) {
    put(v::kArgS, s.phi_deg);
    put(v::kArgT, s.ball);
    const double xyz[3] = {s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
    REQUIRE(module.write(v::kArgX, 3, xyz) == F::kNone);
    return run(9841);
  }
  void stream(const std::vector<core::SpindleSample>& s) {
    REQUIRE(run(9840) == kDone);
    for (const auto& x : s) REQUIRE(add(x) == kDone);
  }
  // Arguments are cleared after every macro: each call sets all of its own.
  void arguments(double r, const core::SpindleGeometry& g = kGeometry) {
    put(v::kArgR, r);
    put(v::kArgD, g.gauge_mm);
    put(v::kArgU, g.ball_mm[0]);
    put(v::kArgV, g.ball_mm[1]);
  }
  double build(bool store, const core::SpindleGeometry& g = kGeometry) {
    if (store) put(v::kUnlock, m::kUnlockCode);
    arguments(store ? 1.0 : 0.0, g);
    return run(9842);
  }
  double report(double r, double phi_deg, double tool_mm) {
    put(v::kArgR, r);
    put(v::kArgS, phi_deg);
    put(v::kArgZ, tool_mm);
    return run(9844);
  }
  double correction(double phi_deg, double tool_mm) {
    put(v::kArgS, phi_deg);
    put(v::kArgZ, tool_mm);
    return run(9843);
  }
  // #100..#104: 9843's outputs.
  std::vector<double> results() const {
    std::vector<double> r;
    for (std::uint16_t n = v::kSpindleThetaE; n <= v::kSpindleTipX + 2; ++n) r.push_back(get(n));
    return r;
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
  CHECK(rig.get(v::kSpindleSessionCapacity) == 360);

  // Nothing stored yet: 9843 says so and keeps its outputs.
  CHECK(rig.correction(30, 100) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));

  REQUIRE(rig.build(false) == kDone);
  const core::SpindleFit fit = direct_fit(s);
  CHECK(rig.get(v::kSpindleEvaluations) == fit.evaluations);
  CHECK(rig.get(v::kSpindleNoiseSigma) == fit.noise_sigma_mm);
  CHECK(rig.get(v::kSpindleSynchronousRms) == fit.synchronous_rms_mm);
  CHECK(rig.get(v::kSpindleNoiseFromRepeats) == 1.0);
  CHECK(rig.get(v::kSpindleSamplesUsed) == 288);
  for (int q = 1; q <= 9; ++q) {
    rig.put(v::kArgQ, q);
    rig.put(v::kArgR, 0);
    REQUIRE(rig.run(9845) == kDone);
    CHECK(rig.get(v::kSpindleParamValue) == fit.params(q - 1));
    CHECK(rig.get(v::kSpindleParamSigma) == std::sqrt(fit.covariance(q - 1, q - 1)));
  }
  CHECK(rig.get(v::kSpindleModelGauge) == 350.0);
  CHECK(rig.get(v::kSpindleModelBall2) == 150.0);
  // R = 0 computed only: still nothing stored.
  CHECK(rig.correction(30, 100) == kError);
  rig.put(v::kArgR, 1);
  rig.put(v::kArgQ, 1);
  CHECK(rig.refuse(9845) == Status::kNoTable);

  // Storing while locked: table_locked, nothing written.
  const std::vector<std::uint8_t> before = rig.nv;
  rig.arguments(1.0);
  CHECK(rig.refuse(9842) == Status::kTableLocked);
  CHECK(rig.nv == before);

  REQUIRE(rig.build(true) == kDone);
  const core::SpindleModel model = core::make_spindle_model(fit, kGeometry);
  for (double phi : {0.0, 5.0, 123.4, 359.9, 720.0 + 30.0, -30.0}) {
    for (double tool : {0.0, 100.0, 250.0}) {
      REQUIRE(rig.correction(phi, tool) == kDone);
      const auto c = core::spindle_correction(model.axes, 350.0, tool, core::deg_to_rad(std::fmod(phi, 360.0)));
      REQUIRE(c.ok());
      CHECK(rig.get(v::kSpindleThetaE) == c.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
      CHECK(rig.get(v::kSpindleDE) == c.value().d_e_mm);
      CHECK(rig.out3(v::kSpindleTipX) == c.value().tip_error_mm);
      const auto direct = sp::tool_tip_correction(rig.module.state<m::spindle::Method>(), phi, tool);
      REQUIRE(direct.ok());
      CHECK(direct.value().tip_error_mm == c.value().tip_error_mm);
      // 9844 on the stored model and on the last identification: the same values, with sigmas.
      for (double r : {0.0, 1.0}) {
        REQUIRE(rig.report(r, phi, tool) == kDone);
        CHECK(rig.out3(v::kSpindleTipX) == c.value().tip_error_mm);
        const auto sigma = core::spindle_correction_sigma(fit.params, fit.covariance, 350.0, tool,
                                                          core::deg_to_rad(std::fmod(phi, 360.0)));
        CHECK(rig.out3(v::kSpindleTipSigmaX) == sigma.value().tip_error_mm);
        CHECK(rig.out3(v::kSpindleMeanTipX) == core::spindle_mean_tip_error_mm(model.axes, 350.0, tool));
        CHECK(rig.get(v::kSpindleThetaE) == c.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
        CHECK(rig.get(v::kSpindleDE) == c.value().d_e_mm);
        CHECK(rig.get(v::kSpindleThetaESigma) == sigma.value().theta_e_rad * (180.0 * 3600.0 / core::kPi));
        CHECK(rig.get(v::kSpindleDESigma) == sigma.value().d_e_mm);
        CHECK(rig.out3(v::kSpindleMeanTipSigmaX) == sigma.value().mean_tip_error_mm);
      }
    }
  }
  // The tip error at 250 mm against the truth, within 3 sigma per axis.
  for (int i = 0; i < 36; ++i) {
    const double phi = 10.0 * i;
    REQUIRE(rig.report(1, phi, 250.0) == kDone);
    const auto tc = core::spindle_correction(core::spindle_axes(truth()), 350.0, 250.0, core::deg_to_rad(phi));
    const Vec3 err = rig.out3(v::kSpindleTipX) - tc.value().tip_error_mm;
    const Vec3 sd = rig.out3(v::kSpindleTipSigmaX);
    for (int k = 0; k < 3; ++k) CHECK(std::fabs(err(k)) <= 3 * sd(k));
  }

  SECTION("the stored model survives a restart, bit for bit") {
    Rig second;
    second.nv = rig.nv;
    REQUIRE(second.module.start() == Status::kOk);
    REQUIRE(rig.correction(77.7, 120) == kDone);
    REQUIRE(second.correction(77.7, 120) == kDone);
    CHECK(second.results() == rig.results());
  }
  SECTION("a refused query keeps every output") {
    REQUIRE(rig.correction(10, 100) == kDone);
    const auto kept = rig.results();
    CHECK(rig.correction(10, -0.001) == kError);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kArgumentOutOfRange));
    const double too_long = 1e5 * (1 + 1e-15);
    CHECK(rig.module.write(v::kArgZ, 1, &too_long) != F::kNone);  // refused at the write
    CHECK(rig.results() == kept);
    CHECK(sp::tool_tip_correction(rig.module.state<m::spindle::Method>(), 10, too_long).status() == Status::kArgumentOutOfRange);
    CHECK(sp::tool_tip_correction(rig.module.state<m::spindle::Method>(), 10, 1e5).ok());
    CHECK(sp::tool_tip_correction(rig.module.state<m::spindle::Method>(), 10, -0.0).ok());
    CHECK(sp::tool_tip_correction(rig.module.state<m::spindle::Method>(), NAN, 1).status() == Status::kNotFinite);
  }
}

TEST_CASE("every refusal of 9841 and 9842 keeps the outputs, the session and the stored model", "[spindle][flow][errors]") {
  const auto s = samples(92);
  Rig rig;
  rig.stream(s);
  REQUIRE(rig.build(true) == kDone);
  REQUIRE(rig.correction(45, 100) == kDone);
  const auto answer = rig.results();
  const std::vector<std::uint8_t> stored = rig.nv;
  auto unchanged = [&] {
    REQUIRE(rig.correction(45, 100) == kDone);
    CHECK(rig.results() == answer);
    CHECK(rig.nv == stored);
  };

  SECTION("9841: ball 0 or 3, half a ball") {
    for (double ball : {0.0, 3.0, 1.5}) {
      rig.put(v::kArgT, ball);
      CHECK(rig.refuse(9841) == Status::kArgumentOutOfRange);
    }
    CHECK(session_of(rig.module).samples() == 288);
    unchanged();
  }
  SECTION("9841: a non-finite coordinate is refused at the write") {
    const double bad = NAN;
    CHECK(rig.module.write(v::kArgX, 1, &bad) != F::kNone);
  }
  SECTION("9841: the 361st distinct angle of a ball is session_full") {
    REQUIRE(rig.run(9840) == kDone);
    for (int i = 0; i < 360; ++i) REQUIRE(rig.add({i * 1.0, 2, Vec3(0, 0, 400)}) == kDone);
    CHECK(rig.get(v::kSpindleSessionAngles2) == 360);
    rig.put(v::kArgS, 0.5);
    rig.put(v::kArgT, 2);
    CHECK(rig.refuse(9841) == Status::kSessionFull);
    CHECK(rig.get(v::kSpindleSessionSamples) == 360);
  }
  SECTION("9842: geometry out of range") {
    rig.stream(s);
    CHECK(rig.build(true, core::SpindleGeometry{0.0, {50, 150}}) == kError);
    CHECK(rig.build(true, core::SpindleGeometry{350.0, {150, 150}}) == kError);
    CHECK(rig.build(true, core::SpindleGeometry{350.0, {-1, 150}}) == kError);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kArgumentOutOfRange));
    // U = 0 is allowed (a ball at the gauge line): the same data with every depth 50 mm less.
    CHECK(rig.build(false, core::SpindleGeometry{350.0, {0.0, 100.0}}) == kDone);
    rig.arguments(2.0);
    CHECK(rig.refuse(9842) == Status::kArgumentOutOfRange);
    unchanged();
  }
  SECTION("9842: one ball height, 7 angles, less than a revolution") {
    std::vector<core::SpindleSample> one;
    for (const auto& x : s) {
      if (x.ball == 1) one.push_back(x);
    }
    rig.stream(one);
    CHECK(rig.build(true) == kError);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kMissingGroup));
    unchanged();

    std::vector<core::SpindleSample> few;
    for (const auto& x : s) {
      if (x.ball == 1 || (std::fmod(x.phi_deg, 45.0) == 0.0 && x.phi_deg < 315.0)) few.push_back(x);
    }
    rig.stream(few);
    CHECK(rig.build(true) == kError);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooFewSamples));
    unchanged();

    // 0..315 deg at 5 deg: the gap 315 -> 360 is 45 deg, a revolution; 0..310 leaves 50.
    for (double last : {315.0, 310.0}) {
      std::vector<core::SpindleSample> part;
      for (const auto& x : s) {
        if (std::fmod(x.phi_deg, 360.0) <= last) part.push_back(x);
      }
      rig.stream(part);
      if (last == 315.0) {
        REQUIRE(rig.build(false) == kDone);
      } else {
        CHECK(rig.build(true) == kError);
        CHECK(rig.get(v::kError) == static_cast<double>(Status::kRevolutionIncomplete));
      }
    }
    unchanged();
    // The configured limit moves the boundary: 50 deg allowed.
    rig.put(v::kSpindleMaxGap, 50.0);
    CHECK(rig.build(false) == kDone);
    rig.put(v::kSpindleMaxGap, 49.999);
    CHECK(rig.build(false) == kError);
  }
}

TEST_CASE("a damaged or undecodable spindle record says so at 9843", "[spindle][flow][errors]") {
  const auto s = samples(93);
  Rig rig;
  rig.stream(s);
  REQUIRE(rig.build(true) == kDone);
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != m::spindle::ModelRecord::kRecord.key) ++index;
  const std::size_t slot = m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);
  SECTION("a bit lost: table_damaged, until a model is stored again") {
    rig.nv[slot + m::KeyedStore::kHeaderBytes + 100] ^= 0x04;
    Rig second;
    second.nv = rig.nv;
    REQUIRE(second.module.start() == Status::kOk);
    CHECK(second.correction(0, 100) == kError);
    CHECK(second.get(v::kError) == static_cast<double>(Status::kTableDamaged));
    second.stream(s);
    REQUIRE(second.build(true) == kDone);
    CHECK(second.correction(0, 100) == kDone);
  }
  SECTION("a good CRC over bytes that do not decode: table_invalid") {
    Rig second;
    std::uint8_t scratch[m::kStoreScratchBytes];
    m::KeyedStore store(second.storage, m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
    REQUIRE(store.mount() == Status::kOk);
    const std::uint8_t garbage[core::kSpindleModelBytes] = {1, 0, 1};
    REQUIRE(store.save(m::spindle::ModelRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
    REQUIRE(second.module.start() == Status::kOk);
    CHECK(second.correction(0, 100) == kError);
    CHECK(second.get(v::kError) == static_cast<double>(Status::kTableInvalid));
  }
}

TEST_CASE("9844 and 9845: a bad R or Q is refused, and R = 0 has no model before an identification",
          "[spindle][flow][errors]") {
  Rig rig;
  CHECK(rig.report(0, 30, 100) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));
  rig.put(v::kArgQ, 1);
  rig.put(v::kArgR, 0);
  CHECK(rig.refuse(9845) == Status::kNoTable);

  rig.stream(samples(94));
  REQUIRE(rig.build(true) == kDone);
  for (double r : {2.0, 0.5, -1.0}) {
    CAPTURE(r);
    CHECK(rig.report(r, 30, 100) == kError);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kArgumentOutOfRange));
    rig.put(v::kArgQ, 1);
    rig.put(v::kArgR, r);
    CHECK(rig.refuse(9845) == Status::kArgumentOutOfRange);
  }
  for (double q : {0.0, 10.0, 1.5}) {
    CAPTURE(q);
    rig.put(v::kArgQ, q);
    rig.put(v::kArgR, 0);
    CHECK(rig.refuse(9845) == Status::kArgumentOutOfRange);
  }
}
