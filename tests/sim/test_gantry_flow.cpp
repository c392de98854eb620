// M2 through the register interface, as a controller drives it: tracker points
// of the independent ground truth (tests/core/gantry_truth.hpp, AT960-like noise)
// streamed group by group (9820..9822), the frames computed and stored (9823),
// reported (9824, 9826) and used (9825 and the direct call) against the truth;
// every bad input with its own code, leaving the outputs and the stored frames
// as they were.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "flow_rig.hpp"
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


constexpr double kDone = 2.0;
constexpr double kError = 3.0;

struct Rig : trueaxis::test::FlowRig {
  double add(int sub, g::GroupKind kind, int pass, const Vec3& p) {
    put(v::kArgT, sub);
    put(v::kArgQ, static_cast<double>(kind));
    put(v::kArgD, pass);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(module.write(v::kArgX, 3, xyz) == F::kNone);
    return run(9821);
  }
  void add_all(int sub, g::GroupKind kind, int pass, const std::vector<Vec3>& points) {
    for (const Vec3& p : points) REQUIRE(add(sub, kind, pass, p) == kDone);
  }
  double parameters(int sub, double swing_mm, const Vec3& tool) {
    put(v::kArgT, sub);
    put(v::kArgD, swing_mm);
    const double ijk[3] = {tool.x(), tool.y(), tool.z()};
    REQUIRE(module.write(v::kArgI, 3, ijk) == F::kNone);
    return run(9822);
  }
  // 9825 for sub-machine `sub`: its #9001.
  double convert(int sub, const Vec3& p) {
    put(v::kArgT, sub);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(module.write(v::kArgX, 3, xyz) == F::kNone);
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
  if (store) rig.put(v::kUnlock, m::kUnlockCode);
  rig.put(v::kArgR, store ? 1.0 : 0.0);
  return rig.run(9823);
}

}  // namespace

TEST_CASE("9823 through the registers gives the core's frames bit for bit", "[gantry][flow]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0, 1, 2, 3});
  CHECK(rig.get(v::kGantrySessionCount) == static_cast<double>(session_of(rig.module).size()));
  REQUIRE(build(rig, false) == kDone);
  CHECK(rig.get(v::kGantryBuilt) == 4.0);

  auto whole = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(t::make_input(f.truth, f.samples), core::GantryOptions{}, *whole) ==
          Status::kOk);
  rig.put(v::kArgR, 0.0);
  REQUIRE(rig.run(9824) == kDone);
  CHECK(rig.out3(v::kGlobalOriginX) == whole->global.tracker_T_global.t);
  CHECK(rig.out3(v::kGlobalZX) == Vec3(whole->global.tracker_T_global.R.col(2)));
  CHECK(rig.get(v::kGlobalIdMask) == 15.0);
  CHECK(rig.get(v::kGlobalOriginSigma) == whole->global.uncertainty.origin_sigma_mm);
  for (std::size_t i = 0; i < 4; ++i) {
    const core::SubMachineFrame& w = whole->sub_machines[i];
    INFO("sub-machine " << w.id);
    rig.put(v::kArgT, w.id);
    rig.put(v::kArgR, 0.0);
    REQUIRE(rig.run(9826) == kDone);
    CHECK(rig.out3(v::kSubOriginX) == w.global_T_sub.t);
    CHECK(rig.out3(v::kSubYX) == Vec3(w.global_T_sub.R.col(1)));
    CHECK(rig.get(v::kSubOriginSigma) == w.uncertainty.origin_sigma_mm);
    CHECK(rig.get(v::kSubMasterAxis) == static_cast<double>(w.master_axis));
    CHECK(rig.out3(v::kSubSquarenessXY) == w.squareness_arcsec);
    CHECK(rig.get(v::kSubACOffset) == w.a_c_offset_mm);
    CHECK(rig.get(v::kSubACircleRms) == w.a_circle.rms_distance_mm);
  }
  // Computed, not stored: the conversion has nothing to convert with.
  CHECK(rig.convert(1, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));
}

TEST_CASE("9825 and the direct call agree with the truth within the stated uncertainty", "[gantry][flow]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0, 1, 2, 3});
  REQUIRE(build(rig, true) == kDone);
  double worst_sigmas = 0.0;
  for (const t::TrueSub& s : f.truth.subs) {
    rig.put(v::kArgT, s.id);
    rig.put(v::kArgR, 1.0);
    REQUIRE(rig.run(9826) == kDone);
    const double origin_sigma = rig.get(v::kSubOriginSigma);
    const double angle_sigma_rad = rig.out3(v::kSubAngleSigmaX).norm() / core::kArcsecPerRad;
    for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(500, -300, -800), Vec3(-1500, 1000, -1200)}) {
      // A workpiece point near the sub-machine's tool tip, in the global frame.
      const t::Vec3L p_l = s.origin + s.R * offset.cast<long double>();
      const Vec3 p = p_l.cast<double>();
      const Vec3 truth = (s.R.transpose() * (p_l - s.origin)).cast<double>();
      REQUIRE(rig.convert(s.id, p) == kDone);
      const Vec3 by_macro = rig.out3(v::kGantryPointX);
      const auto direct = g::sub_point_mm(rig.module.state<m::gantry::Method>(), s.id, p);
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
  SECTION("the stored frames survive a restart, bit for bit") {
    Rig second;
    second.nv = rig.nv;
    REQUIRE(second.module.start() == Status::kOk);
    const Vec3 p(1234.5, -678.9, 2000.0);
    REQUIRE(rig.convert(2, p) == kDone);
    REQUIRE(second.convert(2, p) == kDone);
    CHECK(second.out3(v::kGantryPointX) == rig.out3(v::kGantryPointX));
  }
}

TEST_CASE("storing merges by sub-machine: the others stay as they were", "[gantry][flow]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0, 1});
  REQUIRE(build(rig, true) == kDone);
  const Vec3 p(800.0, 600.0, 1500.0);
  REQUIRE(rig.convert(1, p) == kDone);
  const Vec3 first_1 = rig.out3(v::kGantryPointX);
  REQUIRE(rig.convert(2, p) == kDone);
  const Vec3 first_2 = rig.out3(v::kGantryPointX);
  CHECK(rig.convert(3, p) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));

  // Sub-machines 2 and 3 measured again (other noise): 1 keeps its frame.
  Fixture again;
  again.samples = t::Sampler(again.truth, again.rng, t::kTracker).sample();
  stream(rig, again, {1, 2});
  REQUIRE(build(rig, true) == kDone);
  rig.put(v::kArgR, 1.0);
  REQUIRE(rig.run(9824) == kDone);
  CHECK(rig.get(v::kGlobalIdMask) == 7.0);
  CHECK(rig.get(v::kGlobalSubMachines) == 3.0);
  REQUIRE(rig.convert(1, p) == kDone);
  CHECK(rig.out3(v::kGantryPointX) == first_1);
  REQUIRE(rig.convert(2, p) == kDone);
  CHECK(rig.out3(v::kGantryPointX) != first_2);
  CHECK(rig.convert(3, p) == kDone);
}

TEST_CASE("bad points and parameters get their own codes and change nothing", "[gantry][flow][errors]") {
  Rig rig;
  REQUIRE(rig.run(9820) == kDone);
  REQUIRE(rig.add(0, g::GroupKind::kBed, 0, Vec3(1, 2, 3)) == kDone);
  const Vec3 outputs = rig.out3(v::kGantrySessionCount);
  CHECK(outputs == Vec3(1, g::kSessionCapacity, 1));
  const auto refused = [&](int sub, double kind, int pass, const Vec3& p) {
    rig.put(v::kArgT, sub);
    rig.put(v::kArgQ, kind);
    rig.put(v::kArgD, pass);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(rig.module.write(v::kArgX, 3, xyz) == F::kNone);
    const Status s = rig.refuse(9821);
    CHECK(rig.out3(v::kGantrySessionCount) == outputs);
    CHECK(session_of(rig.module).size() == 1);
    return s;
  };
  const Vec3 p(10, 20, 30);
  CHECK(refused(9, 5, 1, p) == Status::kArgumentOutOfRange);    // T beyond 8
  CHECK(refused(-1, 1, 0, p) == Status::kArgumentOutOfRange);
  CHECK(refused(1, 0, 1, p) == Status::kArgumentOutOfRange);    // Q 0
  CHECK(refused(1, 10, 1, p) == Status::kArgumentOutOfRange);   // Q 10
  CHECK(refused(1, 1, 0, p) == Status::kArgumentOutOfRange);    // the bed belongs to T = 0
  CHECK(refused(0, 5, 1, p) == Status::kArgumentOutOfRange);    // an x pass needs a sub-machine
  CHECK(refused(1, 5, 0, p) == Status::kArgumentOutOfRange);    // pass 0
  CHECK(refused(1, 5, g::kMaxPasses + 1, p) == Status::kArgumentOutOfRange);
  CHECK(refused(1, 5.5, 1, p) == Status::kArgumentOutOfRange);
  // Non-finite and out-of-range coordinates never reach the macro: the write is
  // refused (Modbus exception 03) and the arguments keep their values.
  const double nan_point[3] = {NAN, 0, 0};
  const double far_point[3] = {0, 0, std::nextafter(1e5, 2e5)};
  CHECK(rig.module.write(v::kArgX, 3, nan_point) == F::kNotFinite);
  CHECK(rig.module.write(v::kArgX, 3, far_point) == F::kOutOfRange);
  CHECK(session_of(rig.module).size() == 1);
  REQUIRE(rig.add(0, g::GroupKind::kBed, 0, Vec3(0, 0, 1e5)) == kDone);  // the bound itself is accepted
  REQUIRE(rig.add(1, g::GroupKind::kXPass, g::kMaxPasses, p) == kDone);  // the last pass number too
  // The bed again after another group: not contiguous.
  rig.put(v::kArgT, 0);
  rig.put(v::kArgQ, 1);
  CHECK(rig.refuse(9821) == Status::kGroupNotContiguous);
  CHECK(session_of(rig.module).size() == 3);

  SECTION("9822: a bad sub-machine, swing or direction") {
    CHECK(rig.parameters(1, 250, Vec3(0, 0, -1)) == kDone);
    const auto bad = [&](int sub, double swing, const Vec3& tool) {
      rig.put(v::kArgT, sub);
      rig.put(v::kArgD, swing);
      const double ijk[3] = {tool.x(), tool.y(), tool.z()};
      REQUIRE(rig.module.write(v::kArgI, 3, ijk) == F::kNone);
      return rig.refuse(9822);
    };
    CHECK(bad(0, 250, Vec3(0, 0, -1)) == Status::kArgumentOutOfRange);
    CHECK(bad(9, 250, Vec3(0, 0, -1)) == Status::kArgumentOutOfRange);
    CHECK(bad(1, -1e-9, Vec3(0, 0, -1)) == Status::kArgumentOutOfRange);
    CHECK(bad(1, 250, Vec3(0, 0, 0)) == Status::kArgumentOutOfRange);
    const double inf_tool[3] = {0, INFINITY, -1};
    CHECK(rig.module.write(v::kArgI, 3, inf_tool) == F::kNotFinite);
    const double nan_swing = NAN;
    CHECK(rig.module.write(v::kArgD, 1, &nan_swing) == F::kNotFinite);
    CHECK(session_of(rig.module).parameters(1).swing_mm == 250.0);
    CHECK(rig.parameters(1, 0.0, Vec3(0, 0, -1)) == kDone);  // a swing of 0 is a wrist-centred program frame
  }
}

TEST_CASE("each group holds exactly its capacity, the session exactly 2048 points", "[gantry][flow][errors]") {
  Rig rig;
  REQUIRE(rig.run(9820) == kDone);
  const auto fill = [&](int sub, g::GroupKind kind, int pass, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) REQUIRE(rig.add(sub, kind, pass, Vec3(static_cast<double>(i), 0, 0)) == kDone);
  };
  fill(0, g::GroupKind::kBed, 0, g::kMaxPlanePoints);
  CHECK(rig.add(0, g::GroupKind::kBed, 0, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooManyPoints));
  fill(2, g::GroupKind::kCCircle, 0, g::kMaxCirclePoints);
  CHECK(rig.add(2, g::GroupKind::kCCircle, 0, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooManyPoints));
  fill(2, g::GroupKind::kYPass, 3, g::kMaxPassPoints);
  CHECK(rig.add(2, g::GroupKind::kYPass, 3, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooManyPoints));
  // Fill to exactly 2048 with whole passes, then one more point anywhere.
  std::size_t count = session_of(rig.module).size();
  for (int sub = 3; sub <= 8 && count < g::kSessionCapacity; ++sub) {
    for (int axis = 0; axis < 3 && count < g::kSessionCapacity; ++axis) {
      for (int k = 1; k <= g::kMaxPasses && count < g::kSessionCapacity; ++k) {
        const std::size_t n = std::min<std::size_t>(g::kMaxPassPoints, g::kSessionCapacity - count);
        fill(sub, static_cast<g::GroupKind>(static_cast<int>(g::GroupKind::kXPass) + axis), k, n);
        count += n;
      }
    }
  }
  REQUIRE(session_of(rig.module).size() == g::kSessionCapacity);
  CHECK(rig.get(v::kGantrySessionCount) == static_cast<double>(g::kSessionCapacity));
  CHECK(rig.add(8, g::GroupKind::kACircle, 0, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kSessionFull));
  CHECK(rig.get(v::kGantrySessionCount) == static_cast<double>(g::kSessionCapacity));
  REQUIRE(rig.run(9820) == kDone);
  CHECK(rig.get(v::kGantrySessionCount) == 0.0);
}

TEST_CASE("a failed computation stores nothing and keeps the stored frames", "[gantry][flow][errors]") {
  Fixture f;
  Rig rig;
  stream(rig, f, {0, 1, 2, 3});
  REQUIRE(build(rig, true) == kDone);
  const Vec3 p(100.0, 200.0, 300.0);
  REQUIRE(rig.convert(3, p) == kDone);
  const Vec3 before_point = rig.out3(v::kGantryPointX);
  Status expected = Status::kOk;
  const t::TrueSub& s2 = f.truth.subs[1];
  const auto to_tracker = [&](const t::Vec3L& q) { return (f.truth.R_tg * q + f.truth.O_t).cast<double>(); };

  SECTION("a sub-machine without its A circle: missing_group") {
    f.samples.subs[1].a.clear();
    expected = Status::kMissingGroup;
  }
  SECTION("a bed of 3 points: too_few_points") {
    f.samples.bed.resize(core::kMinPlanePoints - 1);
    expected = Status::kTooFewPoints;
  }
  SECTION("a C circle of 4 points: too_few_points") {
    f.samples.subs[2].c.resize(core::kMinCirclePoints - 1);
    expected = Status::kTooFewPoints;
  }
  SECTION("a sub-machine without 9822: missing_group") {
    stream(rig, f, {0});
    rig.add_all(s2.id, g::GroupKind::kCCircle, 0, f.samples.subs[1].c);
    rig.put(v::kUnlock, m::kUnlockCode);
    rig.put(v::kArgR, 1.0);
    CHECK(rig.refuse(9823) == Status::kMissingGroup);
  }
  SECTION("an A circle on a shorter arc than #700: arc_too_short") {
    rig.put(v::kUnlock, m::kUnlockCode);
    rig.put(v::kGantryMinArc, 181.0);  // the A circles span 180 deg
    expected = Status::kArcTooShort;
  }
  const std::vector<std::uint8_t> nv_config = rig.nv;  // a config write is stored too
  SECTION("A turning about the C axis: axes_parallel") {
    // The A samples replaced by a circle about the C axis through the wrist centre.
    std::vector<Vec3>& a = f.samples.subs[1].a;
    const t::Vec3L target = s2.wrist + 100 * s2.c + 120 * t::unit_l(s2.c.cross(t::Vec3L(0.3L, 0.5L, 0.7L)));
    for (std::size_t j = 0; j < a.size(); ++j) {
      const long double th = t::deg_l(-90.0L + 10.0L * static_cast<long double>(j));
      a[j] = to_tracker(s2.wrist + t::rodrigues_l(th * s2.c) * (target - s2.wrist));
    }
    expected = Status::kAxesParallel;
  }
  SECTION("every x pass measured backwards: axis_opposite_gantry") {
    for (auto& pass : f.samples.subs[1].passes[0]) std::reverse(pass.begin(), pass.end());
    expected = Status::kAxisOppositeGantry;
  }
  SECTION("one x pass measured backwards: passes_disagree") {
    auto& pass = f.samples.subs[1].passes[0][1];
    std::reverse(pass.begin(), pass.end());
    expected = Status::kPassesDisagree;
  }
  SECTION("R = 2") {
    rig.put(v::kUnlock, m::kUnlockCode);
    rig.put(v::kArgR, 2.0);
    CHECK(rig.refuse(9823) == Status::kArgumentOutOfRange);
  }
  SECTION("locked: table_locked") {
    rig.put(v::kUnlock, 0.0);  // any other value locks
    rig.put(v::kArgR, 1.0);
    CHECK(rig.refuse(9823) == Status::kTableLocked);
  }
  if (expected != Status::kOk) {
    stream(rig, f, {0, 1, 2, 3});
    rig.put(v::kUnlock, m::kUnlockCode);
    rig.put(v::kArgR, 1.0);
    CHECK(rig.refuse(9823) == expected);
  }
  CHECK(rig.nv == nv_config);
  REQUIRE(rig.convert(3, p) == kDone);
  CHECK(rig.out3(v::kGantryPointX) == before_point);
}

TEST_CASE("9825's own refusals keep its outputs", "[gantry][flow][errors]") {
  const Fixture f;
  Rig rig;
  CHECK(rig.convert(1, Vec3(0, 0, 0)) == kError);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kNoTable));
  CHECK(g::sub_point_mm(rig.module.state<m::gantry::Method>(), 1, Vec3(0, 0, 0)).status() == Status::kNoTable);
  stream(rig, f, {0});
  REQUIRE(build(rig, true) == kDone);
  REQUIRE(rig.convert(1, Vec3(1, 2, 3)) == kDone);
  const Vec3 kept = rig.out3(v::kGantryPointX);
  const auto refused = [&](double sub, const Vec3& p) {
    rig.put(v::kArgT, sub);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(rig.module.write(v::kArgX, 3, xyz) == F::kNone);
    const Status s = rig.refuse(9825);
    CHECK(rig.out3(v::kGantryPointX) == kept);
    return s;
  };
  CHECK(refused(0, Vec3(1, 2, 3)) == Status::kArgumentOutOfRange);
  CHECK(refused(9, Vec3(1, 2, 3)) == Status::kArgumentOutOfRange);
  CHECK(refused(1.5, Vec3(1, 2, 3)) == Status::kArgumentOutOfRange);
  CHECK(refused(2, Vec3(1, 2, 3)) == Status::kNoTable);  // not stored
  CHECK(g::sub_point_mm(rig.module.state<m::gantry::Method>(), 0, Vec3(0, 0, 0)).status() == Status::kArgumentOutOfRange);
  CHECK(g::sub_point_mm(rig.module.state<m::gantry::Method>(), 9, Vec3(0, 0, 0)).status() == Status::kArgumentOutOfRange);
  CHECK(g::sub_point_mm(rig.module.state<m::gantry::Method>(), 8, Vec3(0, 0, 0)).status() == Status::kNoTable);
}

TEST_CASE("a damaged or undecodable record says so at 9825, not no_table", "[gantry][flow][errors]") {
  const Fixture f;
  Rig rig;
  stream(rig, f, {0});
  REQUIRE(build(rig, true) == kDone);
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != m::gantry::FramesRecord::kRecord.key) ++index;
  const std::size_t slot = m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);

  SECTION("a bit lost: table_damaged, until frames are stored again") {
    rig.nv[slot + m::KeyedStore::kHeaderBytes + 300] ^= 0x10;
    Rig second;
    second.nv = rig.nv;
    REQUIRE(second.module.start() == Status::kOk);
    CHECK(second.convert(1, Vec3(0, 0, 0)) == kError);
    CHECK(second.get(v::kError) == static_cast<double>(Status::kTableDamaged));
    second.put(v::kArgR, 1.0);
    CHECK(second.refuse(9824) == Status::kTableDamaged);
    stream(second, f, {0});
    REQUIRE(build(second, true) == kDone);
    CHECK(second.convert(1, Vec3(0, 0, 0)) == kDone);
  }
  SECTION("a good CRC over bytes that do not decode: table_invalid") {
    Rig second;
    std::uint8_t scratch[m::kStoreScratchBytes];
    m::KeyedStore store(second.storage, m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
    REQUIRE(store.mount() == Status::kOk);
    const std::uint8_t garbage[core::kGantryTableBytes] = {1, 0, 1};
    REQUIRE(store.save(m::gantry::FramesRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
    REQUIRE(second.module.start() == Status::kOk);
    CHECK(second.convert(1, Vec3(0, 0, 0)) == kError);
    CHECK(second.get(v::kError) == static_cast<double>(Status::kTableInvalid));
    CHECK(g::sub_point_mm(second.module.state<m::gantry::Method>(), 1, Vec3(0, 0, 0)).status() == Status::kTableInvalid);
  }
}
