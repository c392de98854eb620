// M4 through the module, as a controller drives it (docs/INTERFACE.md macros
// 9840..9845), on the closed-form spindle of spindle_fixture.hpp: the session
// and its capacity, the identification in steps with and without storing, the
// model, the correction and its report against the closed form, every refusal
// with its code leaving the outputs, the session and the stored model as they
// were, and the shared arenas (session_closed, result_replaced).
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "spindle_fixture.hpp"
#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

TA_METHOD_TESTED("spindle");

namespace {

namespace m = trueaxis::macros;
namespace sp = trueaxis::macros::spindle;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
namespace sf = trueaxis::test::spindle;
using F = trueaxis::macros::AccessFault;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;

// Exact samples: what is left is the solver's convergence and rounding.
constexpr double kMmTolerance = 1e-9;
constexpr double kArcsecTolerance = 1e-5;

bool near3(const Vec3& a, const Vec3& b, double tolerance) { return (a - b).cwiseAbs().maxCoeff() <= tolerance; }

double report(ModuleRig& rig, double r, double phi_deg, double tool_mm) {
  rig.set(v::kArgR, r);
  rig.set(v::kArgS, phi_deg);
  rig.set(v::kArgZ, tool_mm);
  return rig.run(9844);
}

double model(ModuleRig& rig, double r, double q) {
  rig.set(v::kArgR, r);
  rig.set(v::kArgQ, q);
  return rig.run(9845);
}

// 9843's outputs, #100..#104.
struct Correction {
  double v[5];
  bool operator==(const Correction& o) const {
    for (int i = 0; i < 5; ++i) {
      if (!(v[i] == o.v[i])) return false;
    }
    return true;
  }
};
Correction correction_outputs(const ModuleRig& rig) {
  Correction c{};
  for (std::uint16_t i = 0; i < 5; ++i) c.v[i] = rig.get(static_cast<std::uint16_t>(v::kSpindleThetaE + i));
  return c;
}

}  // namespace

TA_TEST("9840 opens an empty session of 180 angle bins per ball; 9841 counts samples and the bins holding them") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9840));
  TA_CHECK_EQ(rig.get(v::kSpindleSessionSamples), 0.0);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionCapacity), 180.0);
  TA_CHECK_EQ(sf::add(rig, 10.0, 1, sf::ball(1, 10.0)), kDone);
  TA_CHECK_EQ(sf::add(rig, 370.0, 1, sf::ball(1, 10.0)), kDone);  // the same angle a revolution on: its bin
  TA_CHECK_EQ(sf::add(rig, 20.0, 2, sf::ball(2, 20.0)), kDone);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionSamples), 3.0);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionAngles1), 1.0);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionAngles2), 1.0);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionCapacity), 180.0);
  TA_REQUIRE(rig.done(9840));
  TA_CHECK_EQ(rig.get(v::kSpindleSessionSamples), 0.0);
}

TA_TEST("9841 refuses a ball other than 1 or 2 and keeps the session; any number of distinct angles is taken") {
  ModuleRig rig;
  sf::stream(rig);
  const ModuleRig::Results kept = rig.results();
  for (const double k : {0.0, 3.0, 1.5}) {
    TA_CHECK_EQ(sf::add(rig, 5.0, k, sf::ball(1, 5.0)), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  const double bad = std::numeric_limits<double>::quiet_NaN();
  TA_CHECK(rig.put(v::kArgX, bad) != F::kNone);  // refused at the write
  TA_CHECK(rig.results() == kept);
  const trueaxis::core::SpindleBins* bins = rig.module().session<sp::Method>();
  TA_REQUIRE(bins != nullptr);
  TA_CHECK_EQ(bins->samples(), std::size_t{2 * sf::kAngles});
  TA_REQUIRE(rig.done(9840));
  // 720 distinct angles (the session held 360 before issue 18), then 360 more
  // that never repeat them: every one taken, all 180 bins hold samples.
  for (int i = 0; i < 720; ++i) TA_REQUIRE(sf::add(rig, 0.5 * i, 2, Vec3(0, 0, 400 + 1e-6 * i)) == kDone);
  for (int i = 0; i < 360; ++i) TA_REQUIRE(sf::add(rig, 360.25 + i, 2, Vec3(0, 0, 401 + 1e-6 * i)) == kDone);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionAngles2), 180.0);
  TA_CHECK_EQ(rig.get(v::kSpindleSessionSamples), 1080.0);
  TA_CHECK_EQ(sf::add(rig, 0.5, 1, Vec3(0, 0, 400)), kDone);
}

TA_TEST("9841 refuses a sample given twice bit for bit (duplicate_sample); a revolution on is a repeat; the samples given twice change no figure") {
  ModuleRig rig;
  // The fixture's revolution, computed once: the samples sent again are the same bits.
  Vec3 file[2][sf::kAngles];
  const auto phi_of = [](int i) { return 360.0 / sf::kAngles * i; };
  TA_REQUIRE(rig.done(9840));
  for (int k = 1; k <= 2; ++k) {
    for (int i = 0; i < sf::kAngles; ++i) {
      file[k - 1][i] = sf::ball(k, phi_of(i));
      TA_REQUIRE(sf::add(rig, phi_of(i), k, file[k - 1][i]) == kDone);
    }
  }
  sf::arguments(rig, 0.0);
  TA_REQUIRE(rig.run(9842) == kDone);
  const ModuleRig::Results built = rig.results();
  const trueaxis::core::SpindleBins* bins = rig.module().session<sp::Method>();
  TA_REQUIRE(bins != nullptr);
  // The file again: every sample refused (each is its bin's first).
  for (int k = 1; k <= 2; ++k) {
    for (int i = 0; i < sf::kAngles; ++i) {
      TA_CASE_INDEX(k * 100 + i);
      TA_CHECK_EQ(sf::add(rig, phi_of(i), k, file[k - 1][i]), kError);
      TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
    }
  }
  TA_CHECK_EQ(bins->samples(), std::size_t{2 * sf::kAngles});
  sf::arguments(rig, 0.0);
  TA_REQUIRE(rig.run(9842) == kDone);
  TA_CHECK(rig.results() == built);
  // A revolution on (phi + 360), the same centre: a repeat of the measurement, taken.
  TA_CHECK_EQ(sf::add(rig, 375.0, 1, file[0][1]), kDone);
  // That row twice in a row: its bin's latest sample.
  TA_CHECK_EQ(sf::add(rig, 375.0, 1, file[0][1]), kError);
  TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
  // One ulp off in any one field: a sample of its own.
  const Vec3 p = file[1][2];
  const double phi = phi_of(2);
  const double up = 1e300;
  TA_CHECK_EQ(sf::add(rig, std::nextafter(phi, up), 2, p), kDone);
  TA_CHECK_EQ(sf::add(rig, phi, 2, Vec3(std::nextafter(p.x(), up), p.y(), p.z())), kDone);
  TA_CHECK_EQ(sf::add(rig, phi, 2, Vec3(p.x(), std::nextafter(p.y(), up), p.z())), kDone);
  TA_CHECK_EQ(sf::add(rig, phi, 2, Vec3(p.x(), p.y(), std::nextafter(p.z(), up))), kDone);
  TA_CHECK_EQ(bins->samples(), std::size_t{2 * sf::kAngles + 5});
  TA_CHECK_EQ(sf::add(rig, phi, 2, p), kError);  // the bin's first sample again, after four others
  TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
}

TA_TEST("9842 identifies the closed-form model in several steps; R = 0 stores nothing, R = 1 stores it") {
  ModuleRig rig;
  sf::stream(rig);
  rig.snapshot();
  TA_REQUIRE(sf::build(rig, false) == kDone);
  TA_CHECK(rig.get(v::kStepCount) > 1.0);
  TA_CHECK(rig.unchanged_but_log());
  TA_CHECK_EQ(rig.get(v::kSpindleSamplesUsed), 48.0);
  TA_CHECK_NEAR(rig.get(v::kSpindleSynchronousRms), 0.0, kMmTolerance);
  TA_CHECK_EQ(rig.get(v::kSpindleNoiseFromRepeats), 0.0);  // one revolution: no repeats
  TA_CHECK_EQ(sf::correction(rig, 30.0, 100.0), kError);   // identified, not stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_CHECK_EQ(model(rig, 1.0, 1.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_REQUIRE(sf::build(rig, true) == kDone);  // the session is kept after an identification
  TA_CHECK(!rig.unchanged());
  for (const double r : {0.0, 1.0}) {
    for (int q = 1; q <= 9; ++q) {
      TA_CASE_INDEX(10 * static_cast<int>(r) + q);
      TA_REQUIRE(model(rig, r, q) == kDone);
      TA_CHECK_NEAR(rig.get(v::kSpindleParamValue), sf::kParams[q - 1], kMmTolerance);
      TA_CHECK_EQ(rig.get(v::kSpindleModelGauge), sf::kGaugeMm);
      TA_CHECK_EQ(rig.get(v::kSpindleModelBall1), sf::kBallMm[0]);
      TA_CHECK_EQ(rig.get(v::kSpindleModelBall2), sf::kBallMm[1]);
      TA_CHECK_EQ(rig.get(v::kSpindleModelSamples), 48.0);
    }
  }
}

TA_TEST("9843 gives the closed-form screw and tool-tip errors at any angle and tool length, as 9844 and the direct call") {
  ModuleRig rig;
  sf::stored(rig);
  for (const double phi : {0.0, 15.0, 123.4, 359.9, 765.0, -30.0}) {
    for (const double tool : {0.0, 100.0, 250.0}) {
      TA_CASE_INDEX(1000 * static_cast<int>(phi) + static_cast<int>(tool));
      TA_REQUIRE(sf::correction(rig, phi, tool) == kDone);
      TA_CHECK_NEAR(rig.get(v::kSpindleThetaE), sf::theta_e_arcsec(), kArcsecTolerance);
      TA_CHECK_NEAR(rig.get(v::kSpindleDE), sf::d_e_mm(), kMmTolerance);
      TA_CHECK(near3(rig.get3(v::kSpindleTipX), sf::tip_error_mm(phi, tool), kMmTolerance));
      const auto direct = sp::tool_tip_correction(rig.module().state<sp::Method>(), phi, tool);
      TA_REQUIRE(direct.ok());
      TA_CHECK(direct.value().tip_error_mm == rig.get3(v::kSpindleTipX));
      const Correction answer = correction_outputs(rig);
      for (const double r : {0.0, 1.0}) {
        TA_REQUIRE(report(rig, r, phi, tool) == kDone);
        TA_CHECK(correction_outputs(rig) == answer);
        // Over a revolution R(phi) averages to zero, and a = -Z: no mean tip error.
        TA_CHECK(near3(rig.get3(v::kSpindleMeanTipX), Vec3::Zero(), kMmTolerance));
      }
    }
  }
  // The stored model survives a restart, bit for bit.
  TA_REQUIRE(sf::correction(rig, 77.7, 120) == kDone);
  const Correction before = correction_outputs(rig);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_REQUIRE(sf::correction(rig, 77.7, 120) == kDone);
  TA_CHECK(correction_outputs(rig) == before);
}

TA_TEST("9843 refuses a tool length out of range and keeps its outputs, as the direct call") {
  ModuleRig rig;
  sf::stored(rig);
  TA_REQUIRE(sf::correction(rig, 10, 100) == kDone);
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(sf::correction(rig, 10, -0.001), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  const double too_long = 1e5 * (1 + 1e-15);
  TA_CHECK(rig.put(v::kArgZ, too_long) != F::kNone);  // refused at the write
  TA_CHECK(rig.results() == kept);
  const auto& state = rig.module().state<sp::Method>();
  TA_CHECK_EQ(sp::tool_tip_correction(state, 10, too_long).status(), Status::kArgumentOutOfRange);
  TA_CHECK(sp::tool_tip_correction(state, 10, 1e5).ok());
  TA_CHECK(sp::tool_tip_correction(state, 10, -0.0).ok());
  TA_CHECK_EQ(sp::tool_tip_correction(state, std::numeric_limits<double>::quiet_NaN(), 1).status(),
              Status::kNotFinite);
}

namespace {

// The fixture stored, then `bad` must make 9842 fail with `expected`, keeping
// the outputs, the stored model and its answer.
template <typename Bad>
void refused_identification(Bad bad, Status expected) {
  ModuleRig rig;
  sf::stored(rig);
  TA_REQUIRE(sf::correction(rig, 45, 100) == kDone);
  const ModuleRig::Results answer = rig.results();
  bad(rig);
  rig.snapshot();
  const ModuleRig::Results before = rig.results();
  TA_CHECK_EQ(rig.refuse(9842), expected);
  TA_CHECK(rig.unchanged_after(expected));
  TA_CHECK(rig.results() == before);
  TA_REQUIRE(sf::correction(rig, 45, 100) == kDone);
  TA_CHECK(rig.results() == answer);
}

// Ball 1 over the whole revolution, ball 2 at the angles `keep` accepts.
template <typename Keep>
void stream_ball_2_at(ModuleRig& rig, Keep keep) {
  rig.done(9840);
  for (int k = 1; k <= 2; ++k) {
    for (int i = 0; i < sf::kAngles; ++i) {
      const double phi = 360.0 / sf::kAngles * i;
      if (k == 1 || keep(phi)) sf::add(rig, phi, k, sf::ball(k, phi));
    }
  }
}

}  // namespace

TA_TEST("9842 with a geometry out of range or R = 2 fails with argument_out_of_range and keeps the model") {
  const double geometries[3][3] = {{0.0, 50, 150}, {350.0, 150, 150}, {350.0, -1, 150}};
  for (const auto& geometry : geometries) {
    refused_identification(
        [&](ModuleRig& rig) {
          rig.unlock();
          sf::arguments(rig, 1.0, geometry[0], geometry[1], geometry[2]);
        },
        Status::kArgumentOutOfRange);
  }
  refused_identification(
      [](ModuleRig& rig) {
        rig.unlock();
        sf::arguments(rig, 2.0);
      },
      Status::kArgumentOutOfRange);
}

TA_TEST("9842 R = 1 while locked fails with table_locked and keeps the stored model") {
  refused_identification(
      [](ModuleRig& rig) {
        rig.lock();
        sf::arguments(rig, 1.0);
      },
      Status::kTableLocked);
}

TA_TEST("9842 with one ball height fails with missing_group, with 7 angles of a ball too_few_samples (#800 at 90)") {
  refused_identification(
      [](ModuleRig& rig) {
        stream_ball_2_at(rig, [](double) { return false; });
        rig.unlock();
        sf::arguments(rig, 1.0);
      },
      Status::kMissingGroup);
  refused_identification(
      [](ModuleRig& rig) {
        stream_ball_2_at(rig, [](double phi) { return std::fmod(phi, 45.0) == 0.0 && phi < 315.0; });
        rig.unlock();
        sf::arguments(rig, 1.0);
        rig.set(v::kSpindleMaxGap, 90.0);  // the gap 270 -> 360 allowed: the count decides
      },
      Status::kTooFewSamples);
}

TA_TEST("9842 with a gap in a revolution over #800 fails with revolution_incomplete; #800 moves the limit") {
  // 0..315 deg every 15: the gap 315 -> 360 is 45 deg, allowed; 0..300 leaves 60.
  ModuleRig rig;
  stream_ball_2_at(rig, [](double phi) { return phi <= 315.0; });
  TA_CHECK_EQ(sf::build(rig, false), kDone);
  refused_identification(
      [](ModuleRig& other) {
        stream_ball_2_at(other, [](double phi) { return phi <= 300.0; });
        other.unlock();
        sf::arguments(other, 1.0);
      },
      Status::kRevolutionIncomplete);
  stream_ball_2_at(rig, [](double phi) { return phi <= 300.0; });
  rig.unlock();
  rig.set(v::kSpindleMaxGap, 60.0);
  TA_CHECK_EQ(sf::build(rig, false), kDone);
  rig.set(v::kSpindleMaxGap, 59.999);
  TA_CHECK_EQ(sf::build(rig, false), kError);
  TA_CHECK_EQ(rig.code(), Status::kRevolutionIncomplete);
}

TA_TEST("9844 and 9845 refuse a bad R or Q, and R = 0 has no model before an identification") {
  ModuleRig rig;
  TA_CHECK_EQ(report(rig, 0, 30, 100), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_CHECK_EQ(model(rig, 0, 1), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  sf::stored(rig);
  for (const double r : {2.0, 0.5, -1.0}) {
    TA_CASE_INDEX(static_cast<int>(10 * r));
    TA_CHECK_EQ(report(rig, r, 30, 100), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
    TA_CHECK_EQ(model(rig, r, 1), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  for (const double q : {0.0, 10.0, 1.5}) {
    TA_CASE_INDEX(static_cast<int>(10 * q));
    TA_CHECK_EQ(model(rig, 0, q), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
}

namespace {

std::size_t first_slot_of_model() {
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != sp::ModelRecord::kRecord.key) ++index;
  return m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);
}

}  // namespace

TA_TEST("a stored model that fails its CRC says table_damaged at 9843 until a model is stored again") {
  ModuleRig rig;
  sf::stored(rig);
  rig.storage().bytes[first_slot_of_model() + m::KeyedStore::kHeaderBytes + 100] ^= 0x04;
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(sf::correction(rig, 0, 100), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableDamaged);
  TA_CHECK_EQ(model(rig, 1, 1), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableDamaged);
  sf::stored(rig);
  TA_CHECK_EQ(sf::correction(rig, 0, 100), kDone);
}

TA_TEST("a stored model with a good CRC that does not decode says table_invalid at 9843") {
  ModuleRig rig;
  static std::uint8_t scratch[m::kStoreScratchBytes];
  m::KeyedStore store(rig.storage(), m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
  TA_REQUIRE(store.mount() == Status::kOk);
  static std::uint8_t garbage[trueaxis::core::kSpindleModelBytes] = {1, 0, 1};
  TA_REQUIRE(store.save(sp::ModelRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(sf::correction(rig, 0, 100), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableInvalid);
  TA_CHECK_EQ(sp::tool_tip_correction(rig.module().state<sp::Method>(), 0, 100).status(), Status::kTableInvalid);
}

TA_TEST("9841 and 9842 answer session_closed once another method's session replaced this one") {
  ModuleRig rig;
  sf::stream(rig);
  TA_REQUIRE(rig.open_foreign_session());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(sf::add(rig, 5.0, 1, sf::ball(1, 5.0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK_EQ(sf::build(rig, false), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK(rig.results() == kept);
  sf::stream(rig);  // 9840 opens it again
  TA_CHECK_EQ(sf::build(rig, false), kDone);
}

TA_TEST("9844 and 9845 R = 0 answer result_replaced after another method's computation; R = 1 still answers") {
  ModuleRig rig;
  sf::stored(rig);
  TA_REQUIRE(model(rig, 0, 6) == kDone);
  TA_REQUIRE(rig.open_foreign_work());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(model(rig, 0, 6), kError);
  TA_CHECK_EQ(rig.code(), Status::kResultReplaced);
  TA_CHECK_EQ(report(rig, 0, 30, 100), kError);
  TA_CHECK_EQ(rig.code(), Status::kResultReplaced);
  TA_CHECK(rig.results() == kept);
  TA_CHECK_EQ(model(rig, 1, 6), kDone);
  TA_CHECK_NEAR(rig.get(v::kSpindleParamValue), sf::kParams[5], kMmTolerance);
}

// ---- recipes (method_tests.hpp) ------------------------------------------------------------

namespace {

void one_sample(ModuleRig& rig) {
  rig.set(v::kArgS, 15.0);
  rig.set(v::kArgT, 1.0);
  rig.set3(v::kArgX, sf::ball(1, 15.0));
}
void streamed(ModuleRig& rig) { sf::stream(rig); }
void stored(ModuleRig& rig) { sf::stored(rig); }
void store_arguments(ModuleRig& rig) {
  rig.unlock();
  sf::arguments(rig, 1.0);
}
void correction_arguments(ModuleRig& rig) {
  rig.set(v::kArgS, 123.4);
  rig.set(v::kArgZ, 250.0);
}
void report_arguments(ModuleRig& rig) {
  rig.set(v::kArgR, 1.0);
  correction_arguments(rig);
}
void model_arguments(ModuleRig& rig) {
  rig.set(v::kArgR, 1.0);
  rig.set(v::kArgQ, 9.0);
}
void words_arguments(ModuleRig& rig) {
  rig.set(v::kArgR, 1.0);
  rig.set(v::kArgQ, 1.0);
}

// 9847 for part q of the last identification (R = 0) or the stored model (R = 1): its #9001.
double words(ModuleRig& rig, double q, double r) {
  rig.set(v::kArgQ, q);
  rig.set(v::kArgR, r);
  return rig.run(9847);
}

}  // namespace

TA_TEST("9847's words are the stored model's record bit for bit, from the identification and the stored model") {
  ModuleRig rig;
  sf::stored(rig);
  static std::uint8_t scratch[m::kStoreScratchBytes];
  m::KeyedStore store(rig.storage(), m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
  TA_REQUIRE(store.mount() == Status::kOk);
  static std::uint8_t record[trueaxis::core::kSpindleModelBytes];
  std::size_t length = 0;
  TA_REQUIRE(store.load(sp::ModelRecord::kRecord.key, record, sizeof record, length) == Status::kOk);
  TA_REQUIRE(length == sizeof record);
  for (const double r : {0.0, 1.0}) {
    TA_CASE_INDEX(static_cast<int>(r));
    static std::uint8_t rebuilt[trueaxis::core::kSpindleModelBytes];
    std::size_t at = 0;
    for (const double q : {0.0, 1.0}) {
      TA_REQUIRE(words(rig, q, r) == kDone);
      TA_CHECK_EQ(rig.get(v::kSpindleWordsBytes), 512.0);
      const auto n = static_cast<std::size_t>(rig.get(v::kSpindleWordsCount));
      TA_CHECK_EQ(n, q == 0.0 ? 98u : 30u);
      for (std::size_t k = 0; k < sp::kWordsPerPart; ++k) {
        const double w = rig.get(static_cast<std::uint16_t>(v::kSpindleWordsFirst + k));
        if (k >= n) {
          TA_CHECK_EQ(w, 0.0);
          continue;
        }
        TA_REQUIRE(w >= 0.0 && w <= 4294967295.0 && w == static_cast<double>(static_cast<std::uint32_t>(w)));
        trueaxis::core::put_u32(rebuilt + at, static_cast<std::uint32_t>(w));
        at += 4;
      }
    }
    TA_CHECK_EQ(at, length);
    TA_CHECK(std::memcmp(rebuilt, record, length) == 0);
  }
  const ModuleRig::Results kept = rig.results();
  for (const double q : {-1.0, 0.5, 2.0}) {
    TA_CASE_INDEX(static_cast<int>(10 * q));
    TA_CHECK_EQ(words(rig, q, 1.0), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  TA_CHECK(rig.results() == kept);
}

TA_RECIPE(9840, nullptr, nullptr);
TA_RECIPE(9841, nullptr, one_sample);
TA_RECIPE(9842, streamed, store_arguments);
TA_RECIPE(9843, stored, correction_arguments);
TA_RECIPE(9844, stored, report_arguments);
TA_RECIPE(9845, stored, model_arguments);
TA_RECIPE(9846, stored, nullptr);  // the build stored is the build checked: every figure 0, pass
TA_RECIPE(9847, stored, words_arguments);
