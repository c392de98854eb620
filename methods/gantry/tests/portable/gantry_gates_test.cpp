// M2's gates through the module (gantry_macros.hpp 9823, gates.hpp): the bed's
// span (points in metres) before the computation, and the change of each
// stored sub-machine's origin and axes with its confirmation M = 1; each at
// its exact boundary, each refusal leaving the results and the stored frames
// as they were, #9012 .. #9014 naming it.
#include <cmath>
#include <cstdint>

#include "gantry_fixture.hpp"
#include "gate_rig.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/core/chi_square.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
namespace gf = trueaxis::test::gantry;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;


// 9823 that a gate must refuse: its code and #9012 .. #9014; the results and
// 9825's answer for sub-machine 1 as they were.
t::Answer stored_answer(ModuleRig& rig) {
  const double status = gf::convert(rig, 1, Vec3(800.0, 600.0, 1500.0));
  return {status, rig.get3(v::kGantryPointX)};
}
t::Refused refused_build(ModuleRig& rig, bool store, double confirm = 0.0) {
  return t::refused(rig,
                    [&](ModuleRig& r) {
                      r.set(v::kArgM, confirm);
                      return gf::build(r, store);
                    },
                    stored_answer);
}

// The fixture's bed span, computed here: the largest distance of a bed point from the first.
double bed_span() {
  double span = 0.0;
  const Vec3 first(100.0, 200.0, 0.0);
  for (int i = 0; i < 8; ++i) {
    const double x = i % 2 == 0 ? 100.0 + 50.0 * i : 5000.0 - 40.0 * i;
    const double y = i < 4 ? 200.0 + 30.0 * i : 2500.0 - 20.0 * i;
    span = std::fmax(span, (Vec3(x, y, 0.0) - first).norm());
  }
  return span;
}

}  // namespace

TA_TEST("9823 refuses a bed spanning less than #703 with bed_span_implausible, at the exact boundary") {
  ModuleRig rig;
  gf::stream(rig);
  const double span = bed_span();
  t::configure(rig, v::kGantryMinBedSpan, span * (1.0 - 1e-9));
  TA_REQUIRE(gf::build(rig, false) == kDone);
  TA_CHECK_NEAR(rig.get(v::kGantryBedSpan), span, 1e-9);
  t::configure(rig, v::kGantryMinBedSpan, span * (1.0 + 1e-9));
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::gantry::kBedSpanImplausible);
  TA_CHECK_NEAR(r.value, span, 1e-9);
  TA_CHECK_EQ(r.limit, span * (1.0 + 1e-9));
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3::Zero()), kError);  // nothing stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
}

TA_TEST("the change gate: a sub-machine's origin moved beyond #704 needs M = 1, at the exact boundary") {
  ModuleRig rig;
  gf::stored(rig);  // sub-machines 1 and 2, swing 300
  TA_CHECK_EQ(rig.get(v::kGantryOriginChange), 0.0);  // the first store: nothing to compare with
  TA_CHECK_EQ(rig.get(v::kGantryOriginChangeId), 0.0);
  // Sub-machine 2 with a swing 0.3 mm longer: its origin 0.3 mm lower.
  const auto restream = [&rig] {
    TA_REQUIRE(rig.done(9820));
    gf::stream_machine(rig);
    gf::stream_sub(rig, 1);
    gf::stream_sub(rig, 2);
    TA_REQUIRE(gf::parameters(rig, 2, gf::kSwingMm + 0.3, Vec3(0, 0, -1)) == kDone);
  };
  restream();
  TA_REQUIRE(gf::build(rig, false) == kDone);  // R = 0: never refused, the change published
  TA_CHECK_NEAR(rig.get(v::kGantryOriginChange), 0.3, 1e-9);
  TA_CHECK_EQ(rig.get(v::kGantryOriginChangeId), 2.0);
  TA_CHECK_NEAR(rig.get(v::kGantryAngleChange), 0.0, 1e-6);
  restream();
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kChangeBeyondLimit);
  TA_CHECK_EQ(r.item, 2.0);
  TA_CHECK_NEAR(r.value, 0.3, 1e-9);
  TA_CHECK_EQ(r.limit, m::gantry::kDefaultMaxOriginChangeMm);
  t::configure(rig, v::kGantryMaxOriginChange, r.value * (1.0 - 1e-9));
  restream();
  TA_CHECK_EQ(refused_build(rig, true).code, Status::kChangeBeyondLimit);
  t::configure(rig, v::kGantryMaxOriginChange, r.value * (1.0 + 1e-9));
  restream();
  TA_CHECK_EQ(gf::build(rig, true), kDone);
  TA_REQUIRE(gf::convert(rig, 2, Vec3(800.0, 600.0, 1500.0)) == kDone);
  TA_CHECK(std::abs(rig.get3(v::kGantryPointX).z() - (1500.0 - gf::origin(2).z() + 0.3)) < 1e-9);
}

TA_TEST("the change gate: a sub-machine's axes turned beyond #705 need M = 1, at the exact boundary") {
  ModuleRig rig;
  gf::stored(rig);
  gf::Variation turned;
  turned.turn_deg = 0.01;  // sub-machine 1's axes turned 36" about the vertical
  const auto restream = [&rig, &turned] {
    TA_REQUIRE(rig.done(9820));
    gf::stream_machine(rig);
    gf::stream_sub(rig, 1, turned);
    gf::stream_sub(rig, 2);
  };
  restream();
  TA_REQUIRE(gf::build(rig, false) == kDone);
  const double angle = rig.get(v::kGantryAngleChange);
  TA_CHECK_NEAR(angle, 36.0, 1e-6);
  TA_CHECK_EQ(rig.get(v::kGantryAngleChangeId), 1.0);
  t::configure(rig, v::kGantryMaxAngleChange, angle * (1.0 - 1e-9));
  restream();
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kChangeBeyondLimit);
  TA_CHECK_EQ(r.item, 1.0);
  TA_CHECK_NEAR(r.value, angle, 1e-9);
  restream();
  rig.set(v::kArgM, 2.0);
  TA_CHECK_EQ(gf::build(rig, true), kError);  // M is 0 or 1
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  restream();
  rig.set(v::kArgM, 1.0);
  TA_CHECK_EQ(gf::build(rig, true), kDone);  // confirmed
  TA_CHECK_EQ(rig.get(v::kGateItem), 0.0);
  t::configure(rig, v::kGantryMaxAngleChange, angle * (1.0 + 1e-9));
  gf::stream(rig);  // back by 36": inside the limit now
  TA_CHECK_EQ(gf::build(rig, true), kDone);
}

TA_TEST("the fit gate: a sub-machine's C circle against the tracker's noise at #901's quantile, at the exact boundary") {
  ModuleRig rig;
  gf::Variation bumped;
  bumped.c_bump_mm = 0.05;  // one C point of sub-machine 1 50 um off its circle
  TA_REQUIRE(rig.done(9820));
  gf::stream_machine(rig);
  gf::stream_sub(rig, 1, bumped);
  gf::stream_sub(rig, 2);
  t::configure(rig, v::kGantryTrackerNoisePerM, 0.0);  // a constant noise #701 alone: the boundary in closed form
  TA_REQUIRE(gf::build(rig, false) == kDone);
  const double ratio = rig.get(v::kGantryFitRatio);
  TA_CHECK_EQ(rig.get(v::kGantryFitSubMachine), 1.0);
  rig.set(v::kArgT, 1.0);
  rig.set(v::kArgR, 0.0);
  TA_REQUIRE(rig.run(9826) == kDone);
  const double rms = rig.get(v::kSubCCircleRms);
  TA_CHECK(rms > 0.01);
  // The statistic 6 rms^2 / a^2 with 2 * 6 - 6 degrees of freedom: ratio 1 at a = sqrt(6 rms^2 / q).
  const double z = trueaxis::core::normal_upper_quantile(1.0 - m::kDefaultGateConfidence);
  const double q = trueaxis::core::chi_square_quantile_z(6, z);
  const double a = m::gantry::kDefaultTrackerNoiseMm;
  TA_CHECK_NEAR(ratio, 6.0 * rms * rms / (a * a) / q, 1e-9 * ratio);
  const double boundary = std::sqrt(6.0 * rms * rms / q);
  t::configure(rig, v::kGantryTrackerNoise, boundary * (1.0 + 1e-6));
  TA_CHECK_EQ(gf::build(rig, false), kDone);
  t::configure(rig, v::kGantryTrackerNoise, boundary * (1.0 - 1e-6));
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kFitBeyondNoise);
  TA_CHECK_EQ(r.item, 1.0);
  TA_CHECK(r.value > 1.0 && r.value < 1.0 + 1e-5);
  t::configure(rig, v::kGantryTrackerNoise, 0.0);  // no stated noise: no fit gate
  TA_CHECK_EQ(gf::build(rig, false), kDone);
  TA_CHECK_EQ(rig.get(v::kGantryFitRatio), 0.0);
}

TA_TEST("the fit gate reads #702 in mm per metre of range: the boundary with #701 = 0, at b = #702 / 1000 per mm") {
  ModuleRig rig;
  gf::Variation bumped;
  bumped.c_bump_mm = 0.05;
  TA_REQUIRE(rig.done(9820));
  gf::stream_machine(rig);
  gf::stream_sub(rig, 1, bumped);
  gf::stream_sub(rig, 2);
  t::configure(rig, v::kGantryTrackerNoise, 0.0);  // a range noise #702 alone: sigma_i = b |p_i|
  t::configure(rig, v::kGantryTrackerNoisePerM, 0.01);
  TA_REQUIRE(gf::build(rig, false) == kDone);
  const double ratio = rig.get(v::kGantryFitRatio);
  TA_CHECK_EQ(rig.get(v::kGantryFitSubMachine), 1.0);
  rig.set(v::kArgT, 1.0);
  rig.set(v::kArgR, 0.0);
  TA_REQUIRE(rig.run(9826) == kDone);
  const double rms = rig.get(v::kSubCCircleRms);
  TA_CHECK(rms > 0.01);
  // The statistic n rms^2 / mean(sigma_i^2) over sub-machine 1's six C points
  // (the fixture's, the tracker at the origin), sigma_i = b |p_i|, b in mm per mm.
  double mean_r2 = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double th = trueaxis::core::deg_to_rad(60.0 * i);
    const double radius = 120.0 + (i == 0 ? 0.05 : 0.0);
    mean_r2 += (gf::wrist(1) + Vec3(radius * std::cos(th), radius * std::sin(th), -200.0)).squaredNorm() / 6.0;
  }
  const double z = trueaxis::core::normal_upper_quantile(1.0 - m::kDefaultGateConfidence);
  const double q = trueaxis::core::chi_square_quantile_z(6, z);
  const double b = 0.01 / 1000.0;  // 0.01 mm per metre
  TA_CHECK_NEAR(ratio, 6.0 * rms * rms / (b * b * mean_r2) / q, 1e-9 * ratio);
  const double boundary_per_m = 1000.0 * std::sqrt(6.0 * rms * rms / (q * mean_r2));
  TA_CHECK(boundary_per_m > 1e-3 && boundary_per_m < 1.0);  // within #702's range, mm/m
  t::configure(rig, v::kGantryTrackerNoisePerM, boundary_per_m * (1.0 + 1e-6));
  TA_CHECK_EQ(gf::build(rig, false), kDone);
  TA_CHECK(rig.get(v::kGantryFitRatio) < 1.0 && rig.get(v::kGantryFitRatio) > 1.0 - 1e-5);
  t::configure(rig, v::kGantryTrackerNoisePerM, boundary_per_m * (1.0 - 1e-6));
  const t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, Status::kFitBeyondNoise);
  TA_CHECK_EQ(r.item, 1.0);
  TA_CHECK(r.value > 1.0 && r.value < 1.0 + 1e-5);
}

namespace {
// 9822 for sub-machine `id` with a nominal origin (Q = 1, X, Y, Z).
double nominal_parameters(ModuleRig& rig, int id, double swing_mm, const Vec3& tool, const Vec3& nominal) {
  rig.set(v::kArgQ, 1.0);
  rig.set3(v::kArgX, nominal);
  return gf::parameters(rig, id, swing_mm, tool);
}
// The fixture again, sub-machine 1's 9822 as given.
void restream(ModuleRig& rig, double swing_mm, const Vec3& tool, const Vec3* nominal) {
  TA_REQUIRE(rig.done(9820));
  gf::stream_machine(rig);
  gf::stream_sub(rig, 1);
  gf::stream_sub(rig, 2);
  const double s = nominal != nullptr ? nominal_parameters(rig, 1, swing_mm, tool, *nominal)
                                      : gf::parameters(rig, 1, swing_mm, tool);
  TA_REQUIRE(s == kDone);
}
}  // namespace

TA_TEST("9823 refuses a swing length below #709 (MACHINE in metres) with swing_implausible, at the exact boundary") {
  ModuleRig rig;
  restream(rig, gf::kSwingMm * 1e-3, Vec3(0, 0, -1), nullptr);
  t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::gantry::kSwingImplausible);
  TA_CHECK_EQ(r.item, 1.0);
  TA_CHECK_EQ(r.value, gf::kSwingMm * 1e-3);
  TA_CHECK_EQ(r.limit, m::gantry::kDefaultMinSwingMm);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3::Zero()), kError);  // nothing stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  t::configure(rig, v::kGantryMinSwing, gf::kSwingMm * (1.0 + 1e-9));
  restream(rig, gf::kSwingMm, Vec3(0, 0, -1), nullptr);
  r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::gantry::kSwingImplausible);
  TA_CHECK_EQ(r.value, gf::kSwingMm);
  t::configure(rig, v::kGantryMinSwing, gf::kSwingMm);  // the length itself passes
  restream(rig, gf::kSwingMm, Vec3(0, 0, -1), nullptr);
  TA_CHECK_EQ(gf::build(rig, false), kDone);
}

TA_TEST("9823 holds a measured origin to its nominal one within #708: a swing typed wrong, a tool flipped; the boundary") {
  ModuleRig rig;
  const Vec3 off(3.0, 4.0, 0.0);  // the drawing 5 mm off the truth
  const Vec3 nominal = gf::origin(1) + off;
  restream(rig, gf::kSwingMm, Vec3(0, 0, -1), &nominal);
  TA_CHECK_EQ(gf::build(rig, false), kDone);  // within the default 10 mm
  // A swing length with a digit typed twice: the origin 2,700 mm off.
  restream(rig, gf::kSwingMm * 10.0, Vec3(0, 0, -1), &nominal);
  t::Refused r = refused_build(rig, true);
  TA_CHECK_EQ(r.code, m::gantry::kOriginOffNominal);
  TA_CHECK_EQ(r.item, 1.0);
  TA_CHECK_NEAR(r.value, (Vec3(0, 0, -9.0 * gf::kSwingMm) - off).norm(), 1e-6);
  TA_CHECK_EQ(r.limit, m::gantry::kDefaultMaxNominalOffsetMm);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3::Zero()), kError);  // nothing stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  // The tool direction the wrong way round: the origin above the wrist, 600 mm off.
  restream(rig, gf::kSwingMm, Vec3(0, 0, 1), &nominal);
  r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::gantry::kOriginOffNominal);
  TA_CHECK_NEAR(r.value, (Vec3(0, 0, 2.0 * gf::kSwingMm) - off).norm(), 1e-6);
  // The exact boundary: the right parameters, #708 just below and just above the 5 mm.
  t::configure(rig, v::kGantryMaxNominalOffset, 5.0 * (1.0 - 1e-9));
  restream(rig, gf::kSwingMm, Vec3(0, 0, -1), &nominal);
  r = refused_build(rig, false);
  TA_CHECK_EQ(r.code, m::gantry::kOriginOffNominal);
  TA_CHECK_NEAR(r.value, 5.0, 1e-9);
  t::configure(rig, v::kGantryMaxNominalOffset, 5.0 * (1.0 + 1e-9));
  restream(rig, gf::kSwingMm, Vec3(0, 0, -1), &nominal);
  TA_CHECK_EQ(gf::build(rig, false), kDone);
  // Without Q = 1 a swing typed wrong is taken as given: computed (the host says so).
  restream(rig, gf::kSwingMm * 10.0, Vec3(0, 0, -1), nullptr);
  TA_CHECK_EQ(gf::build(rig, false), kDone);
  // Q other than 0 and 1 is refused at 9822.
  TA_REQUIRE(rig.done(9820));
  rig.set(v::kArgQ, 2.0);
  TA_CHECK_EQ(gf::parameters(rig, 1, gf::kSwingMm, Vec3(0, 0, -1)), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
}
