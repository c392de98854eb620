// M3's gates through the module (rigidity_macros.hpp 9832, gates.hpp): the
// newcomer's mistakes refused with a code that names the likely cause (A in
// radians, ball positions in metres), the fit against the ball noise, the
// change against the stored table with its confirmation M = 1; each at its
// exact boundary, each refusal leaving the results, the stored table and the
// session as they were, with #9012 .. #9014 naming what was refused.
#include <cmath>
#include <cstdint>

#include "gate_rig.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "rigidity_fixture.hpp"
#include "split_mix64.hpp"
#include "trueaxis/core/chi_square.hpp"
#include "trueaxis/macros/module.hpp"

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

// 9830, then the fixture's poses with the commanded A and the ball positions
// changed: A commanded = a_scale * A + a_shift(i), positions times p_scale,
// the table's C error psi times psi_scale, each position moved by `moved`.
struct Stream {
  double a_scale = 1.0;
  double a_shift_last = 0.0;  // added to the last pose's commanded A only
  double p_scale = 1.0;
  double psi_scale = 1.0;
  double noise_mm = 0.0;  // uniform in +-noise_mm per axis, seed 4242
};
void stream(ModuleRig& rig, const Stream& s) {
  TA_REQUIRE(rig.done(9830));
  t::SplitMix64 noise(4242);
  for (int i = 0; i < rf::kPoses; ++i) {
    const double a = rf::pose_a_deg(i);
    const double commanded = s.a_scale * a + (i == rf::kPoses - 1 ? s.a_shift_last : 0.0);
    for (int k = 0; k < rf::kCPositions; ++k) {
      const double c = 360.0 / rf::kCPositions * k;
      const Vec3 p = rf::rot_x(a, rf::rot_z(s.psi_scale * rf::psi_arcsec(a) / 3600.0, rf::rot_z(c, rf::kBall)));
      const Vec3 moved(noise.uniform(-s.noise_mm, s.noise_mm), noise.uniform(-s.noise_mm, s.noise_mm),
                       noise.uniform(-s.noise_mm, s.noise_mm));
      TA_REQUIRE(rf::add(rig, commanded, c, s.p_scale * p + moved) == kDone);
    }
  }
}


// 9832 with R (unlocked when 1) and M.
double build(ModuleRig& rig, bool store, double confirm = 0.0) {
  if (store && !rig.unlock()) return -1.0;
  rig.set(v::kArgR, store ? 1.0 : 0.0);
  rig.set(v::kArgM, confirm);
  return rig.run(9832);
}

// 9832 that a gate must refuse: its code, #9012 .. #9014; the results and the
// stored table's answer at A = 30 (or its absence) as they were.
t::Answer stored_answer(ModuleRig& rig) {
  rig.set(v::kArgA, 30.0);
  rig.set(v::kArgQ, 0.0);
  rig.set(v::kArgR, 1.0);
  const double status = rig.run(9833);
  return {status, rig.get3(v::kRigidityRotvecX)};
}
t::Refused refused_build(ModuleRig& rig, bool store, double confirm = 0.0) {
  return t::refused(rig, [&](ModuleRig& r) { return build(r, store, confirm); }, stored_answer);
}

}  // namespace

TA_TEST("9832 refuses A in radians with a_error_implausible, naming the pose and its error; nothing stored") {
  ModuleRig rig;
  Stream radians;
  radians.a_scale = rf::kArcsecToRad * 3600.0;  // A commanded in radians, the machine turned in degrees
  stream(rig, radians);
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::rigidity::kAErrorImplausible);
  TA_CHECK(r.item == 1.0 || r.item == 5.0);  // A = -60 or +60: the first beyond the limit, in A order
  TA_CHECK(std::abs(r.value) > 100000.0);    // (60 deg - 1.047 deg) in arcsec
  TA_CHECK_EQ(r.limit, m::rigidity::kDefaultMaxAErrorArcsec);
}

TA_TEST("the A-error gate at its exact boundary: #602 just above the largest error passes, just below refuses") {
  ModuleRig rig;
  Stream shifted;
  shifted.a_shift_last = -0.01;  // pose 5 commanded at 59.99: the table turned 36" more than commanded
  stream(rig, shifted);
  TA_REQUIRE(build(rig, false) == kDone);
  rig.set(v::kArgQ, 5.0);
  rig.set(v::kArgR, 0.0);
  TA_REQUIRE(rig.run(9834) == kDone);
  const double error = rig.get(v::kPoseAError);
  TA_CHECK_NEAR(error, 36.0, 1e-6);
  t::configure(rig, v::kRigidityMaxAError, error * (1.0 + 1e-9));
  TA_CHECK_EQ(build(rig, false), kDone);
  t::configure(rig, v::kRigidityMaxAError, error * (1.0 - 1e-9));
  const t::Refused r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::rigidity::kAErrorImplausible);
  TA_CHECK_EQ(r.item, 5.0);
  TA_CHECK_NEAR(r.value, error, 1e-9);
}

TA_TEST("9832 refuses ball positions in metres with c_radius_implausible; the boundary is #603 exactly") {
  ModuleRig rig;
  Stream metres;
  metres.p_scale = 1e-3;
  stream(rig, metres);
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::rigidity::kCRadiusImplausible);
  TA_CHECK_EQ(r.item, 3.0);                    // the reference pose, A = 0
  TA_CHECK_NEAR(r.value, 0.2, 1e-9);           // 200 mm given as 0.2
  TA_CHECK_EQ(r.limit, m::rigidity::kDefaultMinCRadiusMm);

  stream(rig, Stream{});  // in mm: the ball circles C at 200 mm
  t::configure(rig, v::kRigidityMinCRadius, 200.0 * (1.0 - 1e-9));
  TA_CHECK_EQ(build(rig, false), kDone);
  t::configure(rig, v::kRigidityMinCRadius, 200.0 * (1.0 + 1e-9));
  TA_CHECK_EQ(refused_build(rig, false).code, m::rigidity::kCRadiusImplausible);
  t::configure(rig, v::kRigidityMinCRadius, 0.0);  // 0 switches it off
  stream(rig, metres);
  TA_CHECK_EQ(build(rig, false), kDone);
}

TA_TEST("the fit gate: a pose's C-circle residuals against #601 at #901's chi-square quantile, naming the worst pose") {
  ModuleRig rig;
  Stream noisy;
  noisy.noise_mm = 0.002;  // uniform +-2 um: 1.15 um per axis
  stream(rig, noisy);
  TA_REQUIRE(build(rig, false) == kDone);  // #601 = 1 um: well inside the quantile
  // Each pose's statistic from its RMS (9834), and the worst ratio to the quantile.
  const double s = m::rigidity::kDefaultBallNoiseMm;
  const double z = trueaxis::core::normal_upper_quantile(1.0 - m::kDefaultGateConfidence);
  double worst = 0.0;
  int worst_pose = 0;
  double worst_ssr = 0.0;
  double worst_q = 0.0;
  for (int q = 1; q <= rf::kPoses; ++q) {
    rig.set(v::kArgQ, q);
    rig.set(v::kArgR, 0.0);
    TA_REQUIRE(rig.run(9834) == kDone);
    const double rms = rig.get(v::kPoseCCircleRms);
    const double ssr = rms * rms * rf::kCPositions;
    const double quantile = trueaxis::core::chi_square_quantile_z(2 * rf::kCPositions - 6, z);
    if (ssr / (s * s) / quantile > worst) {
      worst = ssr / (s * s) / quantile;
      worst_pose = q;
      worst_ssr = ssr;
      worst_q = quantile;
    }
  }
  TA_REQUIRE(build(rig, false) == kDone);
  TA_CHECK_NEAR(rig.get(v::kRigidityFitRatio), worst, 1e-9 * worst);
  TA_CHECK_EQ(rig.get(v::kRigidityFitPose), static_cast<double>(worst_pose));
  // The noise at which the worst pose sits exactly on the quantile: just above passes, just below refuses.
  const double boundary = std::sqrt(worst_ssr / worst_q);
  t::configure(rig, v::kRigidityBallNoise, boundary * (1.0 + 1e-6));
  TA_CHECK_EQ(build(rig, false), kDone);
  t::configure(rig, v::kRigidityBallNoise, boundary * (1.0 - 1e-6));
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kFitBeyondNoise);
  TA_CHECK_EQ(r.item, static_cast<double>(worst_pose));
  TA_CHECK(r.value > 1.0 && r.value < 1.0 + 1e-5);
  TA_CHECK_EQ(r.limit, 1.0);
  t::configure(rig, v::kRigidityBallNoise, 0.0);  // not stated: no fit gate
  TA_CHECK_EQ(build(rig, false), kDone);
  TA_CHECK_EQ(rig.get(v::kRigidityFitRatio), 0.0);
}

TA_TEST("the change gate: a store beyond #604 against the stored table needs M = 1; the change is published either way") {
  ModuleRig rig;
  stream(rig, Stream{});
  TA_REQUIRE(build(rig, true) == kDone);  // the first store: nothing to compare with
  TA_CHECK_EQ(rig.get(v::kRigidityChange), 0.0);
  TA_CHECK_EQ(rig.get(v::kRigidityChangePose), 0.0);
  TA_CHECK_EQ(rig.get(v::kGateItem), 0.0);

  Stream moved;
  moved.psi_scale = 3.0;  // psi 60" at A = +-60 where 20" is stored: a change of 40"
  stream(rig, moved);
  TA_REQUIRE(build(rig, false) == kDone);  // R = 0 stores nothing: never refused, the change published
  TA_CHECK_NEAR(rig.get(v::kRigidityChange), 40.0, 1e-6);
  const double pose = rig.get(v::kRigidityChangePose);
  TA_CHECK(pose == 1.0 || pose == 5.0);
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kChangeBeyondLimit);
  TA_CHECK(r.item == 1.0 || r.item == 5.0);
  TA_CHECK_NEAR(r.value, 40.0, 1e-6);
  TA_CHECK_EQ(r.limit, m::rigidity::kDefaultMaxChangeArcsec);
  TA_CHECK_EQ(build(rig, true, 2.0), kError);  // M is 0 or 1
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);

  const double change = r.value;
  t::configure(rig, v::kRigidityMaxChange, change * (1.0 + 1e-9));
  TA_CHECK_EQ(build(rig, true), kDone);  // just inside the limit: stored without M
  TA_CHECK_EQ(rig.get(v::kGateItem), 0.0);  // #9012 .. #9014 read 0 after a success
  TA_CHECK_EQ(rig.get(v::kGateValue), 0.0);
  TA_CHECK_EQ(rig.get(v::kGateLimit), 0.0);

  stream(rig, Stream{});  // back to 20": a change of 40" again
  t::configure(rig, v::kRigidityMaxChange, change * (1.0 - 1e-9));
  TA_CHECK_EQ(refused_build(rig, true).code, Status::kChangeBeyondLimit);
  TA_CHECK_EQ(build(rig, true, 1.0), kDone);  // M = 1 confirms it
  TA_CHECK_NEAR(rig.get(v::kRigidityChange), 40.0, 1e-6);
  rig.set(v::kArgA, 60.0);
  rig.set(v::kArgQ, 0.0);
  rig.set(v::kArgR, 0.0);
  TA_REQUIRE(rig.run(9833) == kDone);
  TA_CHECK_NEAR(rig.get(v::kRigidityRotvecNorm), 20.0, 1e-6);  // the confirmed table is live
}
