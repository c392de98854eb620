// M2 through the register interface against oracles only the host has: tracker
// points of the independent ground truth (methods/gantry/tests/core/gantry_truth.hpp, long
// double, AT960-like noise) streamed group by group (9820..9822), the frames
// computed and stored (9823), reported (9824, 9826) bit for bit as the core
// computes them, and used (9825 and the direct call) within the stated
// uncertainty of the truth. The register contracts (the session, the
// refusals, the stored frames) are portable tests:
// methods/gantry/tests/portable/gantry_macros_test.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "module_rig.hpp"
#include "gantry_truth.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace g = trueaxis::macros::gantry;
namespace v = trueaxis::macros::var;
namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;
using F = m::AccessFault;

// The method's session in the module's shared session arena (it must hold it).
const trueaxis::macros::gantry::PointSession& session_of(const trueaxis::macros::Module& module) {
  const auto* s = module.session<trueaxis::macros::gantry::Method>();
  REQUIRE(s != nullptr);
  return *s;
}


using trueaxis::test::kDone;

struct Rig : trueaxis::test::ModuleRig {
  double add(int sub, g::GroupKind kind, int pass, const Vec3& p) {
    set(v::kArgT, sub);
    set(v::kArgQ, static_cast<double>(kind));
    set(v::kArgD, pass);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(module().write(v::kArgX, 3, xyz) == F::kNone);
    return run(9821);
  }
  void add_all(int sub, g::GroupKind kind, int pass, const std::vector<Vec3>& points) {
    for (const Vec3& p : points) REQUIRE(add(sub, kind, pass, p) == kDone);
  }
  double parameters(int sub, double swing_mm, const Vec3& tool) {
    set(v::kArgT, sub);
    set(v::kArgD, swing_mm);
    const double ijk[3] = {tool.x(), tool.y(), tool.z()};
    REQUIRE(module().write(v::kArgI, 3, ijk) == F::kNone);
    return run(9822);
  }
  // 9825 for sub-machine `sub`: its #9001.
  double convert(int sub, const Vec3& p) {
    set(v::kArgT, sub);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(module().write(v::kArgX, 3, xyz) == F::kNone);
    return run(9825);
  }
};

struct Fixture {
  t::Rng rng{2024};
  t::TrueGantry truth = t::make_truth(rng);
  t::Samples samples;
  Fixture() {
    t::Sampler sampler(truth, rng, t::kTracker);
    samples = sampler.sample();
  }
};

// Streams the machine's groups and the listed sub-machines (0-based indices
// into the truth), with their parameters.
void stream(Rig& rig, const Fixture& f, std::initializer_list<std::size_t> subs) {
  REQUIRE(rig.run(9820) == kDone);
  rig.add_all(0, g::GroupKind::kBed, 0, f.samples.bed);
  rig.add_all(0, g::GroupKind::kSide1, 0, f.samples.side_1);
  rig.add_all(0, g::GroupKind::kSide2, 0, f.samples.side_2);
  for (std::size_t k = 0; k < f.samples.gantry.size(); ++k) {
    rig.add_all(0, g::GroupKind::kGantryPass, static_cast<int>(k + 1), f.samples.gantry[k]);
  }
  const g::GroupKind passes[3] = {g::GroupKind::kXPass, g::GroupKind::kYPass, g::GroupKind::kZPass};
  for (const std::size_t i : subs) {
    const t::TrueSub& s = f.truth.subs[i];
    const t::Samples::Sub& in = f.samples.subs[i];
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t k = 0; k < in.passes[axis].size(); ++k) {
        rig.add_all(s.id, passes[axis], static_cast<int>(k + 1), in.passes[axis][k]);
      }
    }
    rig.add_all(s.id, g::GroupKind::kCCircle, 0, in.c);
    rig.add_all(s.id, g::GroupKind::kACircle, 0, in.a);
    const Vec3 tool = (f.truth.R_tg * s.tool_nominal).cast<double>();
    REQUIRE(rig.parameters(s.id, static_cast<double>(s.swing), tool) == kDone);
  }
}

double build(Rig& rig, bool store) {
  if (store) rig.set(v::kUnlock, m::kUnlockCode);
  rig.set(v::kArgR, store ? 1.0 : 0.0);
  return rig.run(9823);
}

}  // namespace

TEST_CASE("9823 through the registers gives the core's frames bit for bit", "[gantry][flow]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0, 1, 2, 3});
  CHECK(rig.get(v::kGantrySessionCount) == static_cast<double>(session_of(rig.module()).size()));
  REQUIRE(build(rig, false) == kDone);
  CHECK(rig.get(v::kGantryBuilt) == 4.0);

  auto whole = std::make_unique<core::GantryFrames>();
  core::GantryOptions options;  // the module's: #701, #702 at their defaults
  options.instrument = {g::kDefaultTrackerNoiseMm, g::kDefaultTrackerNoisePerMMm / 1000.0, Vec3::Zero(), true};
  CHECK(rig.get(v::kGantryTrackerNoise) == g::kDefaultTrackerNoiseMm);
  CHECK(rig.get(v::kGantryTrackerNoisePerM) == g::kDefaultTrackerNoisePerMMm);
  REQUIRE(core::compute_gantry_frames(t::make_input(f.truth, f.samples), options, *whole) == Status::kOk);
  rig.set(v::kArgR, 0.0);
  REQUIRE(rig.run(9824) == kDone);
  CHECK(rig.get3(v::kGlobalOriginX) == whole->global.tracker_T_global.t);
  CHECK(rig.get3(v::kGlobalZX) == Vec3(whole->global.tracker_T_global.R.col(2)));
  CHECK(rig.get(v::kGlobalIdMask) == 15.0);
  CHECK(rig.get(v::kGlobalOriginSigma) == whole->global.uncertainty.origin_sigma_mm);
  CHECK(rig.get(v::kGlobalBedFlatnessFloor) == whole->global.bed_flatness_noise_floor_mm);
  CHECK(rig.get(v::kGlobalGantryStraightnessFloor) == whole->global.gantry_straightness_noise_floor_mm);
  CHECK(rig.get(v::kGlobalBedFormError) == whole->global.bed_form_error_mm);
  CHECK(rig.get(v::kGlobalBedFormErrorSigma) == whole->global.bed_form_error_sigma_mm);
  CHECK(rig.get(v::kGlobalGantryFormError) == whole->global.gantry_form_error_mm);
  CHECK(rig.get(v::kGlobalGantryFormErrorSigma) == whole->global.gantry_form_error_sigma_mm);
  CHECK(whole->global.bed_flatness_noise_floor_mm > 0.0);
  CHECK(whole->global.gantry_form_error_sigma_mm > 0.0);
  for (std::size_t i = 0; i < 4; ++i) {
    const core::SubMachineFrame& w = whole->sub_machines[i];
    INFO("sub-machine " << w.id);
    rig.set(v::kArgT, w.id);
    rig.set(v::kArgR, 0.0);
    REQUIRE(rig.run(9826) == kDone);
    CHECK(rig.get3(v::kSubOriginX) == w.global_T_sub.t);
    CHECK(rig.get3(v::kSubYX) == Vec3(w.global_T_sub.R.col(1)));
    CHECK(rig.get(v::kSubOriginSigma) == w.uncertainty.origin_sigma_mm);
    CHECK(rig.get(v::kSubMasterAxis) == static_cast<double>(w.master_axis));
    CHECK(rig.get3(v::kSubSquarenessXY) == w.squareness_arcsec);
    CHECK(rig.get(v::kSubACOffset) == w.a_c_offset_mm);
    CHECK(rig.get(v::kSubACircleRms) == w.a_circle.rms_distance_mm);
    CHECK(rig.get3(v::kSubSquarenessSigmaXY) == w.squareness_sigma_arcsec);
    CHECK(rig.get(v::kSubACOffsetSigma) == w.a_c_offset_sigma_mm);
    CHECK(rig.get(v::kSubACAngleSigma) == w.a_c_angle_sigma_deg);
    CHECK(w.squareness_sigma_arcsec.minCoeff() > 0.0);
  }
}

TEST_CASE("9825 and the direct call agree with the truth within the stated uncertainty", "[gantry][flow]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0, 1, 2, 3});
  REQUIRE(build(rig, true) == kDone);
  double worst_sigmas = 0.0;
  for (const t::TrueSub& s : f.truth.subs) {
    rig.set(v::kArgT, s.id);
    rig.set(v::kArgR, 1.0);
    REQUIRE(rig.run(9826) == kDone);
    const double origin_sigma = rig.get(v::kSubOriginSigma);
    const double angle_sigma_rad = rig.get3(v::kSubAngleSigmaX).norm() / core::kArcsecPerRad;
    for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(500, -300, -800), Vec3(-1500, 1000, -1200)}) {
      // A workpiece point near the sub-machine's tool tip, in the global frame.
      const t::Vec3L p_l = s.origin + s.R * offset.cast<long double>();
      const Vec3 p = p_l.cast<double>();
      const Vec3 truth = (s.R.transpose() * (p_l - s.origin)).cast<double>();
      REQUIRE(rig.convert(s.id, p) == kDone);
      const Vec3 by_macro = rig.get3(v::kGantryPointX);
      const auto direct = g::sub_point_mm(rig.module().state<m::gantry::Method>(), s.id, p);
      REQUIRE(direct.ok());
      CHECK(direct.value() == by_macro);
      // 1 sigma of the point: the origin's, and the frame's turn over the lever arm.
      const double sigma = std::hypot(origin_sigma, angle_sigma_rad * truth.norm());
      const double e = (by_macro - truth).norm();
      INFO("sub-machine " << s.id << " offset " << offset.x() << " " << offset.y() << " " << offset.z() << ": error " << e << " mm, sigma " << sigma);
      CHECK(e <= 3.0 * sigma);
      worst_sigmas = std::max(worst_sigmas, e / sigma);
    }
  }
  WARN("9825 against the truth: worst error " << worst_sigmas << " sigma");

  // The stored frames (layout 2) report the figures issue 17 added as the computation did.
  const auto figures = [&](double macro, std::uint16_t first, std::uint16_t last, double stored) {
    rig.set(v::kArgR, stored);
    REQUIRE(rig.run(macro) == kDone);
    std::vector<double> out;
    for (std::uint16_t n = first; n <= last; ++n) out.push_back(rig.get(n));
    return out;
  };
  const std::vector<double> global = figures(9824, v::kGlobalBedFlatnessFloor, v::kGlobalGantryFormErrorSigma, 0.0);
  CHECK(figures(9824, v::kGlobalBedFlatnessFloor, v::kGlobalGantryFormErrorSigma, 1.0) == global);
  CHECK(global[0] > 0.0);
  for (const t::TrueSub& s : f.truth.subs) {
    rig.set(v::kArgT, s.id);
    const std::vector<double> sub = figures(9826, v::kSubSquarenessSigmaXY, v::kSubACAngleSigma, 0.0);
    rig.set(v::kArgT, s.id);
    CHECK(figures(9826, v::kSubSquarenessSigmaXY, v::kSubACAngleSigma, 1.0) == sub);
    CHECK(*std::min_element(sub.begin(), sub.end()) > 0.0);
  }
}
