// M4's gates through the module (spindle_macros.hpp 9842, gates.hpp): the
// balls' spacing against V - U (samples in metres, a ball distance typed
// wrong), the fit against the probe noise and the form allowance per ball,
// and the change of the tool tip at V against the stored model with its
// confirmation M = 1; each at its exact boundary, each refusal leaving the
// results and the stored model as they were, #9012 .. #9014 naming it.
#include <cmath>
#include <cstdint>

#include "gate_rig.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "spindle_fixture.hpp"
#include "split_mix64.hpp"
#include "trueaxis/core/chi_square.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
namespace sf = trueaxis::test::spindle;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;

// The fixture's samples, ball 2 moved along the axis by `shift` (mm), every
// sample moved by uniform noise in +-noise_mm per axis (seed 99), and the
// geometry's ball distances as given (the fixture's unless changed).
struct Stream {
  double shift_mm = 0.0;
  double noise_mm = 0.0;
  double scale = 1.0;
  Vec3 e_extra = Vec3::Zero();  // added to the tool line's offset e: another spindle
  Vec3 axis_tilt = Vec3::Zero();  // (t_x, t_y, 0) rad: the spindle axis along (t_x, t_y, -1), another spindle
  int revolutions = 1;          // each a new draw of the noise at the same angles (phi + 360 k)
};
Vec3 sample(const Stream& s, int k, double phi, t::SplitMix64& noise) {
  const double b = sf::kBallMm[k - 1];
  Vec3 exact = sf::kO1 + (sf::kGaugeMm + b) * Vec3(0.0, 0.0, -1.0) + sf::turn(phi, sf::kE + s.e_extra + b * sf::kW);
  if (s.axis_tilt != Vec3::Zero()) {  // the same spindle about a tilted axis a: R(phi) v = cos v + sin a x v, v normal to a
    const Vec3 a = (s.axis_tilt + Vec3(0.0, 0.0, -1.0)).normalized();
    Vec3 v = sf::kE + s.e_extra + b * sf::kW;
    v -= v.dot(a) * a;
    const double r = trueaxis::core::deg_to_rad(phi);
    exact = sf::kO1 + (sf::kGaugeMm + b) * a + std::cos(r) * v + std::sin(r) * a.cross(v);
  }
  const Vec3 moved(noise.uniform(-s.noise_mm, s.noise_mm), noise.uniform(-s.noise_mm, s.noise_mm),
                   noise.uniform(-s.noise_mm, s.noise_mm));
  return s.scale * (exact + (k == 2 ? s.shift_mm : 0.0) * Vec3(0.0, 0.0, -1.0) + moved);
}
void stream(ModuleRig& rig, const Stream& s) {
  TA_REQUIRE(rig.done(9840));
  t::SplitMix64 noise(99);
  for (int rev = 0; rev < s.revolutions; ++rev) {
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < sf::kAngles; ++i) {
        const double phi = 360.0 / sf::kAngles * i;
        TA_REQUIRE(sf::add(rig, phi + 360.0 * rev, k, sample(s, k, phi, noise)) == kDone);
      }
    }
  }
}


double build(ModuleRig& rig, bool store, double confirm = 0.0) {
  if (store && !rig.unlock()) return -1.0;
  sf::arguments(rig, store ? 1.0 : 0.0);
  rig.set(v::kArgM, confirm);
  return rig.run(9842);
}

// 9842 that a gate must refuse: its code and #9012 .. #9014; the results and
// the stored model's answer (9843 at 90 deg, 200 mm) as they were.
t::Answer stored_answer(ModuleRig& rig) {
  const double status = sf::correction(rig, 90.0, 200.0);
  return {status, rig.get3(v::kSpindleTipX)};
}
t::Refused refused_build(ModuleRig& rig, bool store, double confirm = 0.0) {
  return t::refused(rig, [&](ModuleRig& r) { return build(r, store, confirm); }, stored_answer);
}

}  // namespace

TA_TEST("9842 refuses samples in metres and a typed ball distance with ball_spacing_implausible; nothing stored") {
  ModuleRig rig;
  Stream metres;
  metres.scale = 1e-3;
  stream(rig, metres);
  t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::spindle::kBallSpacingImplausible);
  TA_CHECK_NEAR(r.value, 0.1 - 100.0, 1e-6);  // the centres 0.1 apart where V - U is 100
  TA_CHECK_EQ(r.limit, m::spindle::kDefaultMaxSpacingErrorMm);

  stream(rig, Stream{});
  TA_REQUIRE(rig.unlock());
  sf::arguments(rig, 1.0, sf::kGaugeMm, sf::kBallMm[0], 140.0);  // ball 2 typed 140 for 150
  TA_CHECK_EQ(rig.run(9842), kError);
  TA_CHECK_EQ(rig.code(), m::spindle::kBallSpacingImplausible);
  TA_CHECK_NEAR(rig.get(v::kGateValue), 10.0, 1e-6);
  TA_CHECK_EQ(sf::correction(rig, 0.0, 0.0), kError);  // nothing stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
}

TA_TEST("the spacing gate at its exact boundary, and the fit gate catching what a wider #803 lets through") {
  ModuleRig rig;
  Stream shifted;
  shifted.shift_mm = 0.5;  // ball 2 half a millimetre farther down than V says
  stream(rig, shifted);
  t::configure(rig, v::kSpindleMaxSpacingError, 0.4);
  const t::Refused r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::spindle::kBallSpacingImplausible);
  TA_CHECK_NEAR(r.value, 0.5, 1e-9);
  t::configure(rig, v::kSpindleMaxSpacingError, std::abs(r.value) * (1.0 - 1e-9));
  TA_CHECK_EQ(refused_build(rig, false).code, m::spindle::kBallSpacingImplausible);
  t::configure(rig, v::kSpindleMaxSpacingError, std::abs(r.value) * (1.0 + 1e-9));
  // Past the spacing gate, the model cannot hold a ball half a millimetre off: the fit gate refuses it.
  const t::Refused fit = refused_build(rig, false);
  TA_CHECK_EQ(fit.code, Status::kFitBeyondNoise);
  TA_CHECK(fit.item == 1.0 || fit.item == 2.0);
  TA_CHECK(fit.value > 1000.0);
  t::configure(rig, v::kSpindleFormAllowance, 1.0);  // a 1 mm allowance lets even that through
  TA_CHECK_EQ(build(rig, false), kDone);
  TA_CHECK_NEAR(rig.get(v::kSpindleBallSpacing), 100.5, 1e-9);
}

TA_TEST("the fit gate: each ball's residuals against #801 and #802 at #901's quantile, naming the worse ball") {
  ModuleRig rig;
  Stream noisy;
  noisy.noise_mm = 0.0001;  // uniform +-100 nm: 58 nm per axis
  noisy.revolutions = 2;    // repeats: each bin's scatter is part of the residuals
  stream(rig, noisy);
  t::configure(rig, v::kSpindleFormAllowance, 0.0);
  t::configure(rig, v::kSpindleProbeNoise, 0.001);  // 1 um: far inside
  TA_REQUIRE(build(rig, false) == kDone);
  const double ratio = rig.get(v::kSpindleFitRatio);
  const double ball = rig.get(v::kSpindleFitBall);
  // Each ball's statistic from the model 9845 gives and the samples themselves.
  trueaxis::core::SpindleParams p;
  for (int q = 1; q <= 9; ++q) {
    rig.set(v::kArgQ, q);
    rig.set(v::kArgR, 0.0);
    TA_REQUIRE(rig.run(9845) == kDone);
    p(q - 1) = rig.get(v::kSpindleParamValue);
  }
  const trueaxis::core::SpindleGeometry g{sf::kGaugeMm, {sf::kBallMm[0], sf::kBallMm[1]}};
  t::SplitMix64 noise(99);
  double ssr[2] = {0.0, 0.0};
  for (int rev = 0; rev < noisy.revolutions; ++rev) {
    for (int k = 1; k <= 2; ++k) {
      for (int i = 0; i < sf::kAngles; ++i) {
        const double phi = 360.0 / sf::kAngles * i;
        const Vec3 s = sample(noisy, k, phi, noise);
        ssr[k - 1] += (trueaxis::core::spindle_ball_mm(p, g, k, trueaxis::core::deg_to_rad(phi)) - s).squaredNorm();
      }
    }
  }
  const double z = trueaxis::core::normal_upper_quantile(1.0 - m::kDefaultGateConfidence);
  const double q = trueaxis::core::chi_square_quantile_z(static_cast<std::size_t>(3 * sf::kAngles * noisy.revolutions - 4), z);
  const int worse = ssr[1] > ssr[0] ? 2 : 1;
  const double variance = 0.001 * 0.001;
  TA_CHECK_NEAR(ratio, ssr[worse - 1] / variance / q, 1e-9 * ratio);
  TA_CHECK_EQ(ball, static_cast<double>(worse));
  // The noise at which the worse ball sits on its quantile: above passes, below refuses.
  const double boundary = std::sqrt(ssr[worse - 1] / q);
  t::configure(rig, v::kSpindleProbeNoise, boundary * (1.0 + 1e-6));
  TA_CHECK_EQ(build(rig, false), kDone);
  t::configure(rig, v::kSpindleProbeNoise, boundary * (1.0 - 1e-6));
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kFitBeyondNoise);
  TA_CHECK_EQ(r.item, static_cast<double>(worse));
  TA_CHECK(r.value > 1.0 && r.value < 1.0 + 1e-5);
  // The form allowance enters as #802^2 / 3 per axis: the same boundary with #801 = 0.
  t::configure(rig, v::kSpindleProbeNoise, 0.0);
  t::configure(rig, v::kSpindleFormAllowance, std::sqrt(3.0) * boundary * (1.0 + 1e-6));
  TA_CHECK_EQ(build(rig, false), kDone);
  t::configure(rig, v::kSpindleFormAllowance, std::sqrt(3.0) * boundary * (1.0 - 1e-6));
  TA_CHECK_EQ(refused_build(rig, false).code, Status::kFitBeyondNoise);
}

TA_TEST("the change gate: a store whose tool tip at V moves beyond #804 needs M = 1; the change is published either way") {
  ModuleRig rig;
  stream(rig, Stream{});
  TA_REQUIRE(build(rig, true) == kDone);  // the first store: nothing to compare with
  TA_CHECK_EQ(rig.get(v::kSpindleChange), 0.0);

  Stream other;
  other.e_extra = Vec3(0.0, 0.008, 0.0);  // the tool line 8 um off elsewhere: the tip at V moves 8 um at every angle
  stream(rig, other);
  TA_REQUIRE(build(rig, false) == kDone);
  const double change = rig.get(v::kSpindleChange);
  TA_CHECK_NEAR(change, 0.008, 1e-9);
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kChangeBeyondLimit);
  TA_CHECK_NEAR(r.value, change, 1e-12);
  TA_CHECK_EQ(r.limit, m::spindle::kDefaultMaxChangeMm);
  TA_CHECK(r.item >= 0.0 && r.item < 360.0);
  TA_CHECK_EQ(build(rig, true, 2.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  t::configure(rig, v::kSpindleMaxChange, change * (1.0 - 1e-9));
  TA_CHECK_EQ(refused_build(rig, true).code, Status::kChangeBeyondLimit);
  t::configure(rig, v::kSpindleMaxChange, change * (1.0 + 1e-9));
  TA_CHECK_EQ(build(rig, true), kDone);
  t::configure(rig, v::kSpindleMaxChange, m::spindle::kDefaultMaxChangeMm);
  stream(rig, Stream{});
  TA_CHECK_EQ(refused_build(rig, true).code, Status::kChangeBeyondLimit);
  TA_CHECK_EQ(build(rig, true, 1.0), kDone);  // M = 1 confirms it
  TA_REQUIRE(sf::correction(rig, 0.0, sf::kBallMm[1]) == kDone);
  TA_CHECK((rig.get3(v::kSpindleTipX) - sf::tip_error_mm(0.0, sf::kBallMm[1])).norm() < 1e-9);
}

TA_TEST("the change gate's angle in #9012 and its step in the measuring log, past 255 deg too") {
  ModuleRig rig;
  stream(rig, Stream{});
  TA_REQUIRE(build(rig, true) == kDone);
  // The axis tilted by 10" in a direction of its own (the tip at V moved the same
  // at every angle) and the tool line 8 um off (the tip moved by 8 um turning
  // with the spindle): the two add up at one angle, which goes round with the
  // tilt's direction. Either alone moves the tip as much at every angle, and the
  // angle #9012 names is the rounding's.
  for (const double direction : {0.0, 90.0, 180.0, 270.0, 300.0, 330.0}) {
    Stream other;
    other.axis_tilt = sf::turn(direction, Vec3(0.0, 10.0 * sf::kArcsecToRad, 0.0));
    other.e_extra = Vec3(0.0, 0.008, 0.0);
    stream(rig, other);
    const t::Refused r = refused_build(rig, true);
    TA_CHECK_EQ(r.code, Status::kChangeBeyondLimit);
    TA_CHECK_EQ(r.item, direction);
    TA_REQUIRE(rig.put(v::kLogSelect, rig.get(v::kLogNewest)) == trueaxis::macros::AccessFault::kNone);
    TA_CHECK_EQ(rig.get(v::kLogFigureFirst + 1), r.item / 10.0 + 1.0);
  }
}

TA_TEST("9842 refuses both files in metres with balls_too_close (the spacings agree), at #807's exact boundary") {
  ModuleRig rig;
  Stream metres;
  metres.scale = 1e-3;
  stream(rig, metres);
  TA_REQUIRE(rig.unlock());
  // MACHINE in metres too: D, U and V 1000 times short; V - U = 0.1 agrees with the samples.
  sf::arguments(rig, 1.0, sf::kGaugeMm * 1e-3, sf::kBallMm[0] * 1e-3, sf::kBallMm[1] * 1e-3);
  TA_CHECK_EQ(rig.run(9842), kError);
  TA_CHECK_EQ(rig.code(), m::spindle::kBallsTooClose);
  const double given = (sf::kBallMm[1] - sf::kBallMm[0]) * 1e-3;
  TA_CHECK_NEAR(rig.get(v::kGateValue), given, 1e-15);
  TA_CHECK_EQ(rig.get(v::kGateLimit), m::spindle::kDefaultMinBallSpacingMm);
  TA_CHECK(rig.logged_refusal(m::spindle::kBallsTooClose));
  TA_CHECK_EQ(sf::correction(rig, 0.0, 0.0), kError);  // nothing stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  // The boundary, in mm: V - U = 100 against #807 just above and just below it.
  stream(rig, Stream{});
  const double spacing = sf::kBallMm[1] - sf::kBallMm[0];
  t::configure(rig, v::kSpindleMinBallSpacing, spacing * (1.0 + 1e-9));
  const t::Refused r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::spindle::kBallsTooClose);
  TA_CHECK_EQ(r.value, spacing);
  t::configure(rig, v::kSpindleMinBallSpacing, spacing * (1.0 - 1e-9));
  TA_CHECK_EQ(build(rig, false), kDone);
}
