// M3 through the module, as a controller drives it (docs/INTERFACE.md macros
// 9830..9837), on the closed-form cradle of rigidity_fixture.hpp: the session,
// the build in steps with and without storing, the queries against the closed
// form, every refusal with its code leaving the outputs and the stored table
// as they were, and the shared arenas (session_closed, result_replaced).
#include <cmath>
#include <cstdint>
#include <cstring>

#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "rigidity_fixture.hpp"
#include "split_mix64.hpp"
#include "trueaxis/core/residual_noise.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"
#if __has_include("trueaxis/macros/level/level_map.hpp")
#include "trueaxis/macros/level/level_map.hpp"
#define TRUEAXIS_WITH_LEVEL 1
#endif

TA_METHOD_TESTED("rigidity");

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
namespace rf = trueaxis::test::rigidity;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;

constexpr double kArcsecTolerance = 1e-6;  // exact samples: rounding only
constexpr double kMmTolerance = 1e-9;

bool near3(const Vec3& a, const Vec3& b, double tolerance) { return (a - b).cwiseAbs().maxCoeff() <= tolerance; }

// 9833 at A with blend Q and clamp R: its #9001.
double query(ModuleRig& rig, double a_deg, double blend, double clamp) {
  rig.set(v::kArgA, a_deg);
  rig.set(v::kArgQ, blend);
  rig.set(v::kArgR, clamp);
  return rig.run(9833);
}

// 9834 for pose q of the last built (R = 0) or the stored (R = 1) table: its #9001.
double pose(ModuleRig& rig, int q, double r) {
  rig.set(v::kArgQ, q);
  rig.set(v::kArgR, r);
  return rig.run(9834);
}

// 9835 of a point and a direction at (A, C): its #9001.
double convert(ModuleRig& rig, double a_deg, double c_deg, const Vec3& p, const Vec3& d, double inverse) {
  rig.set(v::kArgA, a_deg);
  rig.set(v::kArgC, c_deg);
  rig.set3(v::kArgX, p);
  rig.set3(v::kArgI, d);
  rig.set(v::kArgR, inverse);
  return rig.run(9835);
}

}  // namespace

TA_TEST("9830 opens an empty session of 512 samples and 9831 counts each sample") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9830));
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 0.0);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCapacity), 512.0);
  TA_CHECK_EQ(rf::add(rig, 0.0, 0.0, rf::actual_ball(0.0, 0.0)), kDone);
  TA_CHECK_EQ(rf::add(rig, 0.0, 60.0, rf::actual_ball(0.0, 60.0)), kDone);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 2.0);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCapacity), 512.0);
  TA_REQUIRE(rig.done(9830));
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 0.0);
}

TA_TEST("the rigidity session takes exactly its capacity and refuses the next sample") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9830));
  const auto add = [&](std::size_t k) {
    return rf::add(rig, static_cast<double>(k / 32), 10.0 * static_cast<double>(k % 32),
                   Vec3(200.0, static_cast<double>(k), 50.0));
  };
  for (std::size_t k = 0; k < m::rigidity::kSessionCapacity; ++k) TA_REQUIRE(add(k) == kDone);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 512.0);
  TA_CHECK_EQ(add(512), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionFull);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 512.0);  // the outputs of the last success
  TA_REQUIRE(rig.done(9830));
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 0.0);
  TA_CHECK_EQ(add(0), kDone);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 1.0);
}

TA_TEST("9831 refuses a sample given twice bit for bit (duplicate_sample); the samples given twice change no figure") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(rf::build(rig, false) == kDone);
  const ModuleRig::Results built = rig.results();
  const m::rigidity::RigiditySession* session = rig.module().session<m::rigidity::Method>();
  TA_REQUIRE(session != nullptr);
  constexpr std::size_t kCount = rf::kPoses * rf::kCPositions;
  TA_REQUIRE(session->size() == kCount);
  // The whole file again (the very bits the session holds): every sample refused, the session as it was.
  for (std::size_t i = 0; i < kCount; ++i) {
    TA_CASE_INDEX(i);
    const trueaxis::core::RigiditySample s = (*session)[i];
    TA_CHECK_EQ(rf::add(rig, s.a_deg, s.c_deg, s.p_mm), kError);
    TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
  }
  TA_CHECK_EQ(session->size(), kCount);
  TA_REQUIRE(rf::build(rig, false) == kDone);
  TA_CHECK(rig.results() == built);
  // A measurement repeated differs somewhere: one ulp in any one field is a sample of its own.
  const trueaxis::core::RigiditySample s = (*session)[7];
  const double up = 1e300;
  const Vec3 p = s.p_mm;
  TA_CHECK_EQ(rf::add(rig, std::nextafter(s.a_deg, up), s.c_deg, p), kDone);
  TA_CHECK_EQ(rf::add(rig, s.a_deg, std::nextafter(s.c_deg, up), p), kDone);
  TA_CHECK_EQ(rf::add(rig, s.a_deg, s.c_deg, Vec3(std::nextafter(p.x(), up), p.y(), p.z())), kDone);
  TA_CHECK_EQ(rf::add(rig, s.a_deg, s.c_deg, Vec3(p.x(), std::nextafter(p.y(), up), p.z())), kDone);
  TA_CHECK_EQ(rf::add(rig, s.a_deg, s.c_deg, Vec3(p.x(), p.y(), std::nextafter(p.z(), up))), kDone);
  TA_CHECK_EQ(session->size(), kCount + 5);
  TA_CHECK_EQ(rf::add(rig, s.a_deg, s.c_deg, Vec3(p.x(), p.y(), std::nextafter(p.z(), up))), kError);  // that one twice
  TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
}

TA_TEST("9832 builds the closed-form table in several steps; R = 0 stores nothing, R = 1 stores it") {
  ModuleRig rig;
  rf::stream(rig);
  rig.snapshot();
  TA_REQUIRE(rf::build(rig, false) == kDone);
  TA_CHECK(rig.get(v::kStepCount) > 1.0);
  TA_CHECK(rig.unchanged_but_log());
  TA_CHECK_EQ(rig.get(v::kRigidityPoses), 5.0);
  TA_CHECK_NEAR(rig.get(v::kRigidityWorst), 20.0, kArcsecTolerance);  // |psi(+-60)|
  TA_CHECK(near3(rig.get3(v::kRigidityAPointX), Vec3::Zero(), kMmTolerance));
  TA_CHECK(near3(rig.get3(v::kRigidityADirectionX), Vec3::UnitX(), 1e-12));
  TA_CHECK_NEAR(rig.get(v::kRigidityCToAOffset), 0.0, kMmTolerance);
  TA_CHECK_NEAR(rig.get(v::kRigidityCToASquareness), 0.0, kArcsecTolerance);
  TA_CHECK_NEAR(rig.get(v::kRigidityWorstCircleRms), 0.0, kMmTolerance);
  TA_CHECK_EQ(query(rig, 30.0, 0.0, 0.0), kError);  // built, not stored: nothing to query
  TA_CHECK_EQ(rig.code(), Status::kNoTable);

  const ModuleRig::Results built = rig.results();
  TA_REQUIRE(rf::build(rig, true) == kDone);  // the session is kept after a build
  TA_CHECK(rig.get(v::kStepCount) > 2.0);  // the build's steps, then the commit's
  TA_CHECK(!rig.unchanged());
  for (std::uint16_t n = v::kRigidityPoses; n <= v::kRigidityWorstCircleRms; ++n) {
    TA_CASE_INDEX(n);
    TA_CHECK_EQ(rig.get(n), built[n - 100]);
  }
  TA_CHECK_EQ(query(rig, 30.0, 0.0, 0.0), kDone);
}

TA_TEST("9834 reports every pose as the closed form has it, from the built and from the stored table") {
  ModuleRig rig;
  rf::stored(rig);
  for (const double r : {0.0, 1.0}) {
    for (int q = 1; q <= rf::kPoses; ++q) {
      TA_CASE_INDEX(10 * static_cast<int>(r) + q);
      const double a = rf::pose_a_deg(q - 1);
      TA_REQUIRE(pose(rig, q, r) == kDone);
      TA_CHECK_EQ(rig.get(v::kPoseA), a);
      TA_CHECK(near3(rig.get3(v::kPoseRotvecX), rf::rotvec_arcsec(a), kArcsecTolerance));
      TA_CHECK_NEAR(rig.get(v::kPoseRigidity), std::fabs(rf::psi_arcsec(a)), kArcsecTolerance);
      TA_CHECK_NEAR(rig.get(v::kPoseAError), 0.0, kArcsecTolerance);
      TA_CHECK(near3(rig.get3(v::kPoseCCentreX), rf::rot_x(a, Vec3(0, 0, 50)), kMmTolerance));
      TA_CHECK(near3(rig.get3(v::kPoseCDirectionX), rf::rot_x(a, Vec3::UnitZ()), 1e-12));
      TA_CHECK_NEAR(rig.get(v::kPoseCCircleRms), 0.0, kMmTolerance);
      TA_CHECK_EQ(rig.get(v::kPoseCount), 5.0);
    }
  }
  const ModuleRig::Results kept = rig.results();
  for (const int q : {0, 6}) {
    TA_CASE_INDEX(q);
    TA_CHECK_EQ(pose(rig, q, 1.0), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  TA_CHECK_EQ(pose(rig, 1, 2.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == kept);
}

TA_TEST("9834 reports the A error's sigma as stored and the C-circle RMS's sigma and noise floor under #601") {
  ModuleRig rig;
  // The fixture's ball positions, each moved by up to 2 um: sigmas that differ from pose to pose.
  trueaxis::test::SplitMix64 noise(1717);
  TA_REQUIRE(rig.done(9830));
  for (int i = 0; i < rf::kPoses; ++i) {
    for (int k = 0; k < rf::kCPositions; ++k) {
      const double c = 360.0 / rf::kCPositions * k;
      const Vec3 moved(noise.uniform(-0.002, 0.002), noise.uniform(-0.002, 0.002), noise.uniform(-0.002, 0.002));
      TA_REQUIRE(rf::add(rig, rf::pose_a_deg(i), c, rf::actual_ball(rf::pose_a_deg(i), c) + moved) == kDone);
    }
  }
  TA_REQUIRE(rf::build(rig, true) == kDone);
  const double worst_rms = rig.get(v::kRigidityWorstCircleRms);
  const double worst_floor = rig.get(v::kRigidityWorstCircleRmsFloor);
  const double worst_sigma = rig.get(v::kRigidityWorstCircleRmsSigma);
  trueaxis::core::RigidityTable table;
  TA_REQUIRE(rig.module().state<m::rigidity::Method>().table.read([&](const trueaxis::core::RigidityTable& t) {
    table = t;
  }));
  for (const double ball_noise : {m::rigidity::kDefaultBallNoiseMm, 0.004, 0.0}) {
    if (ball_noise != m::rigidity::kDefaultBallNoiseMm) {
      TA_REQUIRE(rig.unlock());
      TA_REQUIRE(rig.put(v::kRigidityBallNoise, ball_noise) == m::AccessFault::kNone);
      TA_REQUIRE(rig.lock());
    }
    TA_CHECK_EQ(rig.get(v::kRigidityBallNoise), ball_noise);
    int worst_seen = 0;
    for (const double r : {0.0, 1.0}) {
      for (int q = 1; q <= rf::kPoses; ++q) {
        TA_CASE_INDEX(10 * static_cast<int>(r) + q);
        const trueaxis::core::RigidityPose& p = table.poses[q - 1];
        TA_REQUIRE(pose(rig, q, r) == kDone);
        TA_CHECK_EQ(rig.get(v::kPoseAErrorSigma), p.a_error_sigma_rad * trueaxis::core::kArcsecPerRad);
        TA_CHECK(q == 3 || rig.get(v::kPoseAErrorSigma) > 0.0);  // pose 3 is the reference
        const trueaxis::core::ResidualNoise want = trueaxis::core::residual_rms_noise(
            p.c_circle_rms_mm, p.c_count, 2 * p.c_count - 6, ball_noise);
        TA_CHECK_EQ(rig.get(v::kPoseCCircleRmsSigma), want.sigma_mm);
        TA_CHECK_EQ(rig.get(v::kPoseCCircleRmsFloor), want.floor_mm);
        TA_CHECK_EQ(want.floor_mm > 0.0, ball_noise > 0.0);
        if (ball_noise == m::rigidity::kDefaultBallNoiseMm && p.c_circle_rms_mm == worst_rms) {
          ++worst_seen;  // 9832 named this pose's figures
          TA_CHECK_EQ(worst_floor, want.floor_mm);
          TA_CHECK_EQ(worst_sigma, want.sigma_mm);
        }
      }
    }
    TA_CHECK(ball_noise != m::rigidity::kDefaultBallNoiseMm || worst_seen == 2);
  }
}

namespace {

// The direct call for the controller's real-time task, in arcsec.
Vec3 direct_arcsec(const ModuleRig& rig, double a_deg, int blend) {
  const auto r = m::rigidity::compensation_rad(rig.module().state<m::rigidity::Method>(), a_deg,
                                               static_cast<trueaxis::core::Blend>(blend), false);
  return r.ok() ? Vec3(r.value() / rf::kArcsecToRad) : Vec3::Constant(-1.0);
}

}  // namespace

TA_TEST("9833 gives the closed form at every pose with every blend, and the linear blend between poses") {
  ModuleRig rig;
  rf::stored(rig);
  for (int blend = 0; blend <= 3; ++blend) {
    for (int i = 0; i < rf::kPoses; ++i) {
      TA_CASE_INDEX(10 * blend + i);
      const double a = rf::pose_a_deg(i);
      TA_REQUIRE(query(rig, a, blend, 0.0) == kDone);
      TA_CHECK(near3(rig.get3(v::kRigidityRotvecX), rf::rotvec_arcsec(a), kArcsecTolerance));
      TA_CHECK_NEAR(rig.get(v::kRigidityRotvecNorm), std::fabs(rf::psi_arcsec(a)), kArcsecTolerance);
      TA_CHECK(near3(direct_arcsec(rig, a, blend), rig.get3(v::kRigidityRotvecX), 1e-9));
    }
  }
  // Between poses the linear blend is the mean of the bracketing poses' vectors
  // (rigidity_compensation.hpp convention 3).
  TA_REQUIRE(query(rig, 45.0, 0.0, 0.0) == kDone);
  const Vec3 mid = 0.5 * (rf::rotvec_arcsec(30.0) + rf::rotvec_arcsec(60.0));
  TA_CHECK(near3(rig.get3(v::kRigidityRotvecX), mid, kArcsecTolerance));
  TA_CHECK_NEAR(rig.get(v::kRigidityRotvecNorm), mid.norm(), kArcsecTolerance);
  TA_CHECK(near3(direct_arcsec(rig, 45.0, 0), mid, kArcsecTolerance));
  // The stored table is live again after a restart.
  TA_REQUIRE(rig.start() == trueaxis::core::Status::kOk);
  TA_CHECK(near3(direct_arcsec(rig, 45.0, 0), mid, kArcsecTolerance));
  TA_REQUIRE(query(rig, 45.0, 0.0, 0.0) == kDone);
  // Outside the measured range, by one ulp or more: refused with its own code,
  // the last outputs kept; clamped to the end pose on request.
  const ModuleRig::Results kept = rig.results();
  for (const double a : {std::nextafter(60.0, 100.0), std::nextafter(-60.0, -100.0), 95.0}) {
    TA_CHECK_EQ(query(rig, a, 0.0, 0.0), kError);
    TA_CHECK_EQ(rig.code(), Status::kOutsideMeasuredRange);
    TA_CHECK(rig.results() == kept);
  }
  TA_REQUIRE(query(rig, 95.0, 0.0, 1.0) == kDone);
  TA_CHECK(near3(rig.get3(v::kRigidityRotvecX), rf::rotvec_arcsec(60.0), kArcsecTolerance));
  const ModuleRig::Results clamped = rig.results();
  TA_CHECK_EQ(query(rig, 30.0, 4.0, 0.0), kError);  // no such blend
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(query(rig, 30.0, 0.0, 2.0), kError);  // no such R
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == clamped);
}

TA_TEST("9835 moves where the ideal machine puts the ball to where the real one does, and R = 1 back") {
  ModuleRig rig;
  rf::stored(rig);
  for (int i = 0; i < rf::kPoses; ++i) {
    for (const double c : {0.0, 60.0, 135.0}) {
      TA_CASE_INDEX(1000 * i + static_cast<int>(c));
      const double a = rf::pose_a_deg(i);
      const Vec3 dir = rf::rot_x(a, rf::rot_z(c, Vec3::UnitX()));
      TA_REQUIRE(convert(rig, a, c, rf::theory_ball(a, c), dir, 0.0) == kDone);
      TA_CHECK(near3(rig.get3(v::kConvertPointX), rf::actual_ball(a, c), kMmTolerance));
      const Vec3 actual_dir = rf::rot_x(a, rf::rot_z(rf::psi_arcsec(a) / 3600.0, rf::rot_z(c, Vec3::UnitX())));
      TA_CHECK(near3(rig.get3(v::kConvertDirectionX), actual_dir, 1e-12));
      TA_REQUIRE(convert(rig, a, c, rf::actual_ball(a, c), actual_dir, 1.0) == kDone);
      TA_CHECK(near3(rig.get3(v::kConvertPointX), rf::theory_ball(a, c), kMmTolerance));
      TA_CHECK(near3(rig.get3(v::kConvertDirectionX), dir, 1e-12));
    }
  }
}

TA_TEST("9832 R = 1 while locked fails with table_locked, stores nothing and keeps the live table") {
  ModuleRig rig;
  rf::stored(rig);
  TA_REQUIRE(query(rig, 30.0, 0.0, 0.0) == kDone);
  const ModuleRig::Results before = rig.results();
  rig.lock();
  rig.snapshot();
  rig.set(v::kArgR, 1.0);
  TA_CHECK_EQ(rig.refuse(9832), Status::kTableLocked);
  TA_CHECK(rig.unchanged_but_log());  // the refusal logged (measuring_log.hpp convention 1), nothing else
  TA_CHECK(rig.logged_refusal(Status::kTableLocked));
  TA_CHECK(rig.logs_refusal(Status::kTableLocked));
  TA_CHECK(rig.results() == before);
  TA_REQUIRE(query(rig, 30.0, 0.0, 0.0) == kDone);
  TA_CHECK(rig.results() == before);
}

TA_TEST("a failed build (two poses) stores nothing, keeps the outputs and the live table") {
  ModuleRig rig;
  rf::stored(rig);
  TA_REQUIRE(query(rig, 30.0, 0.0, 0.0) == kDone);
  const ModuleRig::Results answer = rig.results();
  rf::stream(rig, 2);
  rig.snapshot();
  const ModuleRig::Results before = rig.results();
  TA_CHECK_EQ(rf::build(rig, true), kError);
  TA_CHECK_EQ(rig.code(), Status::kTooFewPoses);
  TA_CHECK(rig.unchanged());
  TA_CHECK(rig.results() == before);
  TA_REQUIRE(query(rig, 30.0, 0.0, 0.0) == kDone);
  TA_CHECK(rig.results() == answer);
}

TA_TEST("9834 R = 0 reports only a table whose 9832 succeeded") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(rf::build(rig, false) == kDone);
  TA_CHECK_EQ(pose(rig, 5, 0.0), kDone);
  rig.set(v::kArgR, 1.0);  // store while locked: built, then refused
  TA_CHECK_EQ(rig.refuse(9832), Status::kTableLocked);
  TA_CHECK_EQ(pose(rig, 5, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
}

namespace {

// 9833, 9834 (R = 1), 9835 and the direct call all answer `status`.
void expect_everywhere(ModuleRig& rig, Status status) {
  TA_CHECK_EQ(query(rig, 10.0, 0.0, 0.0), kError);
  TA_CHECK_EQ(rig.code(), status);
  TA_CHECK_EQ(pose(rig, 1, 1.0), kError);
  TA_CHECK_EQ(rig.code(), status);
  TA_CHECK_EQ(convert(rig, 10.0, 0.0, Vec3(1, 2, 3), Vec3::UnitZ(), 0.0), kError);
  TA_CHECK_EQ(rig.code(), status);
  TA_CHECK_EQ(m::rigidity::compensation_rad(rig.module().state<m::rigidity::Method>(), 10.0,
                                            trueaxis::core::Blend::kLinear, false)
                  .status(),
              status);
}

std::size_t first_slot_of_table() {
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != m::RigidityTableRecord::kRecord.key) ++index;
  return m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);
}

}  // namespace

TA_TEST("a stored table that fails its CRC says table_damaged everywhere until a table is stored again") {
  ModuleRig rig;
  rf::stored(rig);  // the first save went to slot 0, its only copy
  rig.storage().bytes[first_slot_of_table() + m::KeyedStore::kHeaderBytes + 100] ^= 0x04;
  TA_REQUIRE(rig.start() == Status::kOk);
  expect_everywhere(rig, Status::kTableDamaged);
  rf::stored(rig);
  TA_CHECK_EQ(query(rig, 10.0, 0.0, 0.0), kDone);
}

TA_TEST("a stored record with a good CRC that does not decode says table_invalid; none stored says no_table") {
  ModuleRig rig;
  expect_everywhere(rig, Status::kNoTable);
  static std::uint8_t scratch[m::kStoreScratchBytes];
  m::KeyedStore store(rig.storage(), m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
  TA_REQUIRE(store.mount() == Status::kOk);
  const std::uint8_t garbage[64] = {1, 2, 3};
  TA_REQUIRE(store.save(m::RigidityTableRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
  TA_REQUIRE(rig.start() == Status::kOk);
  expect_everywhere(rig, Status::kTableInvalid);
}

namespace {

// 9837 for part q (0 the header, n pose n) of the last built (R = 0) or the stored (R = 1) table: its #9001.
double reals(ModuleRig& rig, double q, double r) {
  rig.set(v::kArgQ, q);
  rig.set(v::kArgR, r);
  return rig.run(9837);
}

}  // namespace

TA_TEST("9837's reals, rebuilt by encode_rigidity_reals, are the stored record bit for bit, from the built and the stored table") {
  ModuleRig rig;
  TA_REQUIRE(rig.unlock());
  rig.set(v::kHomeIdentity, 4711.0);
  rf::stored(rig);
  static std::uint8_t scratch[m::kStoreScratchBytes];
  m::KeyedStore store(rig.storage(), m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
  TA_REQUIRE(store.mount() == Status::kOk);
  static std::uint8_t record[trueaxis::core::kRigidityTableMaxBytes];
  std::size_t length = 0;
  TA_REQUIRE(store.load(m::RigidityTableRecord::kRecord.key, record, sizeof record, length) == Status::kOk);
  for (const double r : {0.0, 1.0}) {
    TA_CASE_INDEX(static_cast<int>(r));
    TA_REQUIRE(reals(rig, 0.0, r) == kDone);
    const auto poses = static_cast<std::size_t>(rig.get(v::kRealsPoseCount));
    const auto reference = static_cast<std::size_t>(rig.get(v::kRealsReference));
    TA_REQUIRE(poses == static_cast<std::size_t>(rf::kPoses));
    TA_REQUIRE(reference >= 1 && reference <= poses);
    static double header[trueaxis::core::kRigidityHeaderReals];
    static double pose_reals[trueaxis::core::kMaxAPoses * trueaxis::core::kRigidityPoseReals];
    for (std::size_t k = 0; k < trueaxis::core::kRigidityHeaderReals; ++k) {
      header[k] = rig.get(static_cast<std::uint16_t>(v::kRealsFirst + k));
    }
    // The header leaves the pose's further places 0.
    TA_CHECK_EQ(rig.get(static_cast<std::uint16_t>(v::kRealsFirst + trueaxis::core::kRigidityHeaderReals)), 0.0);
    for (std::size_t q = 1; q <= poses; ++q) {
      TA_REQUIRE(reals(rig, static_cast<double>(q), r) == kDone);
      TA_CHECK_EQ(rig.get(v::kRealsFirst), rf::pose_a_deg(static_cast<int>(q) - 1));
      for (std::size_t k = 0; k < trueaxis::core::kRigidityPoseReals; ++k) {
        pose_reals[(q - 1) * trueaxis::core::kRigidityPoseReals + k] = rig.get(static_cast<std::uint16_t>(v::kRealsFirst + k));
      }
    }
    static std::uint8_t rebuilt[trueaxis::core::kRigidityTableMaxBytes];
    const auto home = static_cast<std::uint16_t>(rig.get(v::kRealsHomeIdentity));
    TA_CHECK_EQ(home, 4711);  // the home it was built under (#129), as stored
    const std::size_t n = trueaxis::core::encode_rigidity_reals(poses, reference - 1, home, header, pose_reals, rebuilt,
                                                                sizeof rebuilt);
    TA_CHECK_EQ(n, length);
    TA_CHECK(std::memcmp(rebuilt, record, length) == 0);
  }
  const ModuleRig::Results kept = rig.results();
  for (const double q : {-1.0, 0.5, static_cast<double>(rf::kPoses) + 1.0}) {
    TA_CASE_INDEX(static_cast<int>(10 * q));
    TA_CHECK_EQ(reals(rig, q, 1.0), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  TA_CHECK_EQ(reals(rig, 1.0, 2.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == kept);
}

TA_TEST("a table is applied only under the home it was built under (#904): 9833, 9835, 9836 and the direct call say "
        "home_changed; 9834 and 9837 still report it; at that home again, or once stored anew, all answer") {
  ModuleRig rig;
  TA_REQUIRE(rig.unlock());
  rig.set(v::kHomeIdentity, 7.0);
  rf::stored(rig);
  TA_REQUIRE(query(rig, 10.0, 0.0, 0.0) == kDone);
  const Vec3 at_home(rig.get(v::kRigidityRotvecX), rig.get(v::kRigidityRotvecX + 1), rig.get(v::kRigidityRotvecX + 2));
  TA_REQUIRE(rig.unlock());
  rig.set(v::kHomeIdentity, 8.0);  // a home switch moved: the integrator says so
  TA_CHECK_EQ(query(rig, 10.0, 0.0, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kHomeChanged);
  TA_CHECK_EQ(convert(rig, 10.0, 0.0, Vec3(1, 2, 3), Vec3::UnitZ(), 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kHomeChanged);
  TA_CHECK_EQ(m::rigidity::compensation_rad(rig.module().state<m::rigidity::Method>(), 10.0,
                                            trueaxis::core::Blend::kLinear, false)
                  .status(),
              Status::kHomeChanged);
#ifdef TRUEAXIS_WITH_LEVEL
  // M1 on the calibrated axes (#508 = 1) does not level on them either.
  TA_REQUIRE(rig.unlock());
  rig.set(v::kLevelAxes, 1.0);
  rig.set3(v::kG57, Vec3(0, 0, 10));
  rig.set3(v::kG58, Vec3(100, 0, 30));
  rig.set3(v::kG59, Vec3(0, 100, 10));
  TA_CHECK_EQ(rig.refuse(9810), Status::kHomeChanged);
  rig.set(v::kLevelAxes, 0.0);
#endif
  rf::stream(rig);
  TA_REQUIRE(rf::build(rig, false) == kDone);  // a build is made under today's home
  TA_CHECK_EQ(rig.refuse(9836), Status::kHomeChanged);  // not checked against a table of another home
  // The reports still show the stored table, and which home it holds.
  TA_CHECK_EQ(pose(rig, 1, 1.0), kDone);
  TA_CHECK_EQ(reals(rig, 0.0, 1.0), kDone);
  TA_CHECK_EQ(rig.get(v::kRealsHomeIdentity), 7.0);
  TA_CHECK_EQ(reals(rig, 0.0, 0.0), kDone);
  TA_CHECK_EQ(rig.get(v::kRealsHomeIdentity), 8.0);
  // Over a restart the stored #904 and the table's home still differ.
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(query(rig, 10.0, 0.0, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kHomeChanged);
  // Homed as then: the same answers, bit for bit.
  TA_REQUIRE(rig.unlock());
  rig.set(v::kHomeIdentity, 7.0);
  TA_REQUIRE(query(rig, 10.0, 0.0, 0.0) == kDone);
  TA_CHECK(Vec3(rig.get(v::kRigidityRotvecX), rig.get(v::kRigidityRotvecX + 1), rig.get(v::kRigidityRotvecX + 2)) == at_home);
  // Or measured and stored under the new home: applied there.
  TA_REQUIRE(rig.unlock());
  rig.set(v::kHomeIdentity, 8.0);
  rf::stored(rig);
  TA_CHECK_EQ(query(rig, 10.0, 0.0, 0.0), kDone);
  TA_CHECK_EQ(reals(rig, 0.0, 1.0), kDone);
  TA_CHECK_EQ(rig.get(v::kRealsHomeIdentity), 8.0);
  // #904 is a whole number of 16 bits.
  TA_REQUIRE(rig.unlock());
  TA_CHECK_EQ(rig.put(v::kHomeIdentity, 65536.0), m::AccessFault::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kHomeIdentity, 1.5), m::AccessFault::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kHomeIdentity, 65535.0), m::AccessFault::kNone);
}

TA_TEST("9831 and 9832 answer session_closed once another method's session replaced this one; 9830 opens it again") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(rig.open_foreign_session());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(rf::add(rig, 0.0, 0.0, rf::actual_ball(0.0, 0.0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK_EQ(rf::build(rig, false), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK(rig.results() == kept);
  TA_CHECK(rig.module().session<m::rigidity::Method>() == nullptr);
  rf::stream(rig);
  TA_CHECK_EQ(rig.get(v::kRigiditySessionCount), 30.0);
  TA_CHECK_EQ(rf::build(rig, false), kDone);
}

TA_TEST("9834 R = 0 answers result_replaced after another method's computation; R = 1 still answers") {
  ModuleRig rig;
  rf::stored(rig);
  TA_REQUIRE(pose(rig, 2, 0.0) == kDone);
  TA_REQUIRE(rig.open_foreign_work());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(pose(rig, 2, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kResultReplaced);
  TA_CHECK(rig.results() == kept);
  TA_CHECK_EQ(pose(rig, 2, 1.0), kDone);
  TA_CHECK(near3(rig.get3(v::kPoseRotvecX), rf::rotvec_arcsec(-30.0), kArcsecTolerance));
}

TA_TEST("9836 checks the last build against the stored table: the same table passes with every deviation 0") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(rf::build(rig, false) == kDone);
  TA_CHECK_EQ(rig.refuse(9836), Status::kNoTable);  // nothing stored yet
  rf::stored(rig);
  const double poses = rig.get(v::kRigidityPoses);
  TA_REQUIRE(rig.done(9836));
  TA_CHECK_EQ(rig.get(v::kCheckVerdict), 0.0);
  TA_CHECK_EQ(rig.get(v::kCheckFigures), 2.0 * (poses - 1.0));  // every pose but the reference, 2 figures each
  for (double q = 1.0; q <= 2.0 * (poses - 1.0); q += 1.0) {
    rig.set(v::kArgQ, q);
    TA_REQUIRE(rig.done(9836));
    const bool a_error = q == 2.0 * std::floor(q / 2.0);  // rotation, A error, rotation, ...
    TA_CHECK_EQ(rig.get(v::kCheckFigureKind), a_error ? 2.0 : 1.0);
    TA_CHECK_EQ(rig.get(v::kCheckFigureDeviation), 0.0);
    TA_CHECK_EQ(rig.get(v::kCheckFigureStored), rig.get(v::kCheckFigureMeasured));
    TA_CHECK_EQ(rig.get(v::kCheckFigureTolerance),
                a_error ? m::rigidity::kDefaultCheckAErrorArcsec : m::rigidity::kDefaultCheckRotationArcsec);
    TA_CHECK(rig.get(v::kCheckFigureSigma) >= 0.0);
    TA_CHECK_EQ(rig.get(v::kCheckFigureVerdict), 0.0);
  }
  const ModuleRig::Results kept = rig.results();
  rig.set(v::kArgQ, 2.0 * poses - 1.0);  // one beyond the last figure
  TA_CHECK_EQ(rig.refuse(9836), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == kept);
}

// ---- recipes (method_tests.hpp) ------------------------------------------------------------

namespace {

void one_sample(ModuleRig& rig) {
  rig.set(v::kArgA, 0.0);
  rig.set(v::kArgC, 0.0);
  rig.set3(v::kArgX, rf::kBall);
}
void streamed(ModuleRig& rig) { rf::stream(rig); }
void stored(ModuleRig& rig) { rf::stored(rig); }
void build_and_store(ModuleRig& rig) {
  rig.unlock();
  rig.set(v::kArgR, 1.0);
}
void query_arguments(ModuleRig& rig) { rig.set(v::kArgA, 45.0); }
void pose_arguments(ModuleRig& rig) {
  rig.set(v::kArgQ, 2.0);
  rig.set(v::kArgR, 1.0);
}
void convert_arguments(ModuleRig& rig) {
  rig.set(v::kArgA, 30.0);
  rig.set(v::kArgC, 60.0);
  rig.set3(v::kArgX, rf::theory_ball(30.0, 60.0));
  rig.set3(v::kArgI, Vec3::UnitZ());
}

}  // namespace

TA_RECIPE(9830, nullptr, nullptr);
TA_RECIPE(9831, nullptr, one_sample);
TA_RECIPE(9832, streamed, build_and_store);
TA_RECIPE(9833, stored, query_arguments);
TA_RECIPE(9834, stored, pose_arguments);
TA_RECIPE(9835, stored, convert_arguments);
TA_RECIPE(9836, stored, nullptr);  // the build stored is the build checked: every figure 0, pass
TA_RECIPE(9837, stored, pose_arguments);
