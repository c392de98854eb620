// M2 through the module, as a controller drives it (docs/INTERFACE.md macros
// 9820..9826), on the closed-form gantry of gantry_fixture.hpp: the session
// and its capacities, the computation in steps with and without storing, the
// reports and the point conversion against the closed form, storing merged by
// sub-machine, every refusal with its code leaving the outputs and the stored
// frames as they were, and the shared arenas (session_closed,
// result_replaced).
#include <cmath>
#include <cstdint>
#include <limits>

#include "gantry_fixture.hpp"
#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

TA_METHOD_TESTED("gantry");

namespace {

namespace m = trueaxis::macros;
namespace g = trueaxis::macros::gantry;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
namespace gf = trueaxis::test::gantry;
using F = trueaxis::macros::AccessFault;
using t::kDone;
using t::kError;
using t::ModuleRig;
using trueaxis::core::Status;
using trueaxis::core::Vec3;

constexpr double kMmTolerance = 1e-9;  // exact points: rounding only
const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool near3(const Vec3& a, const Vec3& b, double tolerance) { return (a - b).cwiseAbs().maxCoeff() <= tolerance; }

double report(ModuleRig& rig, double macro, double id, double r) {
  rig.set(v::kArgT, id);
  rig.set(v::kArgR, r);
  return rig.run(macro);
}

// Points in the method's session (0 when another method's session holds the arena).
std::size_t session_size(const ModuleRig& rig) {
  const g::PointSession* s = rig.module().session<g::Method>();
  return s != nullptr ? s->size() : 0;
}

const Vec3 kPoints[3] = {Vec3(0, 0, 0), Vec3(2500.0, 1200.0, 400.0), Vec3(-1500, 1000, -1200)};

}  // namespace

TA_TEST("9820 opens an empty session of 2048 points; 9821 and 9822 report its points and groups") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9820));
  TA_CHECK(near3(rig.get3(v::kGantrySessionCount), Vec3(0, g::kSessionCapacity, 0), 0.0));
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, Vec3(1, 2, 3)), kDone);
  TA_CHECK(near3(rig.get3(v::kGantrySessionCount), Vec3(1, g::kSessionCapacity, 1), 0.0));
  TA_CHECK_EQ(gf::add(rig, 1, gf::kXPass, 2, Vec3(1, 2, 3)), kDone);
  TA_CHECK(near3(rig.get3(v::kGantrySessionCount), Vec3(2, g::kSessionCapacity, 2), 0.0));
  TA_CHECK_EQ(gf::parameters(rig, 1, 250.0, Vec3(0, 0, -1)), kDone);
  TA_CHECK(near3(rig.get3(v::kGantrySessionCount), Vec3(2, g::kSessionCapacity, 2), 0.0));
  TA_REQUIRE(rig.done(9820));
  TA_CHECK(near3(rig.get3(v::kGantrySessionCount), Vec3(0, g::kSessionCapacity, 0), 0.0));
}

TA_TEST("bad points and parameters get their own codes and change nothing") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9820));
  TA_REQUIRE(gf::add(rig, 0, gf::kBed, 0, Vec3(1, 2, 3)) == kDone);
  const Vec3 outputs = rig.get3(v::kGantrySessionCount);
  const auto refused = [&](double sub, double kind, double pass) {
    rig.set(v::kArgT, sub);
    rig.set(v::kArgQ, kind);
    rig.set(v::kArgD, pass);
    rig.set3(v::kArgX, Vec3(10, 20, 30));
    const Status s = rig.refuse(9821);
    TA_CHECK(rig.get3(v::kGantrySessionCount) == outputs);
    TA_CHECK_EQ(session_size(rig), std::size_t{1});
    return s;
  };
  TA_CHECK_EQ(refused(9, 5, 1), Status::kArgumentOutOfRange);    // T beyond 8
  TA_CHECK_EQ(refused(-1, 1, 0), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(refused(1, 0, 1), Status::kArgumentOutOfRange);    // Q 0
  TA_CHECK_EQ(refused(1, 10, 1), Status::kArgumentOutOfRange);   // Q 10
  TA_CHECK_EQ(refused(1, 1, 0), Status::kArgumentOutOfRange);    // the bed belongs to T = 0
  TA_CHECK_EQ(refused(0, 5, 1), Status::kArgumentOutOfRange);    // an x pass needs a sub-machine
  TA_CHECK_EQ(refused(1, 5, 0), Status::kArgumentOutOfRange);    // pass 0
  TA_CHECK_EQ(refused(1, 5, g::kMaxPasses + 1), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(refused(1, 5.5, 1), Status::kArgumentOutOfRange);
  // Non-finite and out-of-range coordinates never reach the macro: the write is
  // refused (Modbus exception 03) and the arguments keep their values.
  const double nan_point[3] = {kNaN, 0, 0};
  const double far_point[3] = {0, 0, std::nextafter(1e5, 2e5)};
  TA_CHECK_EQ(rig.put(v::kArgX, 3, nan_point), F::kNotFinite);
  TA_CHECK_EQ(rig.put(v::kArgX, 3, far_point), F::kOutOfRange);
  TA_CHECK_EQ(session_size(rig), std::size_t{1});
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, Vec3(0, 0, 1e5)), kDone);  // the bound itself is accepted
  TA_CHECK_EQ(gf::add(rig, 1, gf::kXPass, g::kMaxPasses, Vec3(10, 20, 30)), kDone);  // the last pass number too
  // The bed again after another group: not contiguous.
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, Vec3(10, 20, 30)), kError);
  TA_CHECK_EQ(rig.code(), Status::kGroupNotContiguous);
  TA_CHECK_EQ(session_size(rig), std::size_t{3});

  // 9822: a bad sub-machine, swing or direction.
  TA_CHECK_EQ(gf::parameters(rig, 1, 250, Vec3(0, 0, -1)), kDone);
  TA_CHECK_EQ(gf::parameters(rig, 0, 250, Vec3(0, 0, -1)), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(gf::parameters(rig, 9, 250, Vec3(0, 0, -1)), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(gf::parameters(rig, 1, -1e-9, Vec3(0, 0, -1)), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(gf::parameters(rig, 1, 250, Vec3(0, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  const double inf_tool[3] = {0, std::numeric_limits<double>::infinity(), -1};
  TA_CHECK_EQ(rig.put(v::kArgI, 3, inf_tool), F::kNotFinite);
  TA_CHECK_EQ(rig.put(v::kArgD, kNaN), F::kNotFinite);
  const g::PointSession* session = rig.module().session<g::Method>();
  TA_REQUIRE(session != nullptr);
  TA_CHECK_EQ(session->parameters(1).swing_mm, 250.0);
  TA_CHECK_EQ(gf::parameters(rig, 1, 0.0, Vec3(0, 0, -1)), kDone);  // a swing of 0: a wrist-centred frame
}

TA_TEST("9821 refuses a point its group already holds bit for bit (duplicate_sample), before any other check") {
  ModuleRig rig;
  gf::stream(rig);
  TA_REQUIRE(gf::build(rig, false) == kDone);
  const ModuleRig::Results built = rig.results();
  const std::size_t count = session_size(rig);
  const g::PointSession* session = rig.module().session<g::Method>();
  TA_REQUIRE(session != nullptr);
  const trueaxis::core::PointSpan a_circle = session->span(g::PointSession::group_of(2, gf::kACircle, 0).value());
  TA_REQUIRE(a_circle.count > 0);
  const Vec3 last = a_circle.points_mm[a_circle.count - 1];
  const Vec3 bed = session->span(0).points_mm[0];
  TA_CHECK_EQ(gf::add(rig, 2, gf::kACircle, 0, last), kError);  // the last point again: a row given twice
  TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, bed), kError);  // the file again: duplicate, not group_not_contiguous
  TA_CHECK_EQ(rig.code(), Status::kDuplicateSample);
  TA_CHECK_EQ(session_size(rig), count);
  TA_REQUIRE(gf::build(rig, false) == kDone);
  TA_CHECK(rig.results() == built);
  // One ulp off in one coordinate, or the same coordinates in another group: points of their own.
  const double up = 1e300;
  TA_CHECK_EQ(gf::add(rig, 2, gf::kACircle, 0, Vec3(std::nextafter(last.x(), up), last.y(), last.z())), kDone);
  TA_CHECK_EQ(gf::add(rig, 2, gf::kACircle, 0, Vec3(last.x(), std::nextafter(last.y(), up), last.z())), kDone);
  TA_CHECK_EQ(gf::add(rig, 2, gf::kACircle, 0, Vec3(last.x(), last.y(), std::nextafter(last.z(), up))), kDone);
  TA_CHECK_EQ(gf::add(rig, 3, gf::kCCircle, 0, last), kDone);
  TA_CHECK_EQ(session_size(rig), count + 4);
}

TA_TEST("each group holds exactly its capacity, the session exactly 2048 points") {
  ModuleRig rig;
  TA_REQUIRE(rig.done(9820));
  const auto fill = [&](int sub, int kind, int pass, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) TA_REQUIRE(gf::add(rig, sub, kind, pass, Vec3(static_cast<double>(i), 0, 0)) == kDone);
  };
  fill(0, gf::kBed, 0, g::kMaxPlanePoints);
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, Vec3(-1, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kTooManyPoints);
  fill(2, gf::kCCircle, 0, g::kMaxCirclePoints);
  TA_CHECK_EQ(gf::add(rig, 2, gf::kCCircle, 0, Vec3(-1, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kTooManyPoints);
  fill(2, gf::kYPass, 3, g::kMaxPassPoints);
  TA_CHECK_EQ(gf::add(rig, 2, gf::kYPass, 3, Vec3(-1, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kTooManyPoints);
  // Fill to exactly 2048 with whole passes, then one more point anywhere.
  std::size_t count = session_size(rig);
  for (int sub = 3; sub <= 8 && count < g::kSessionCapacity; ++sub) {
    for (int axis = 0; axis < 3 && count < g::kSessionCapacity; ++axis) {
      for (int k = 1; k <= g::kMaxPasses && count < g::kSessionCapacity; ++k) {
        const std::size_t n = g::kSessionCapacity - count < g::kMaxPassPoints ? g::kSessionCapacity - count
                                                                                : g::kMaxPassPoints;
        fill(sub, gf::kXPass + axis, k, n);
        count += n;
      }
    }
  }
  TA_REQUIRE(session_size(rig) == g::kSessionCapacity);
  TA_CHECK_EQ(rig.get(v::kGantrySessionCount), static_cast<double>(g::kSessionCapacity));
  TA_CHECK_EQ(gf::add(rig, 8, gf::kACircle, 0, Vec3(0, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionFull);
  TA_CHECK_EQ(rig.get(v::kGantrySessionCount), static_cast<double>(g::kSessionCapacity));
  TA_REQUIRE(rig.done(9820));
  TA_CHECK_EQ(rig.get(v::kGantrySessionCount), 0.0);
}

TA_TEST("9823 computes the closed-form frames in several steps; R = 0 stores nothing, R = 1 stores them") {
  ModuleRig rig;
  gf::stream(rig);
  rig.snapshot();
  TA_REQUIRE(gf::build(rig, false) == kDone);
  TA_CHECK(rig.get(v::kStepCount) > 1.0);
  TA_CHECK(rig.unchanged_but_log());
  TA_CHECK_EQ(rig.get(v::kGantryBuilt), 2.0);
  TA_CHECK_NEAR(rig.get(v::kGantryBuildFlatness), 0.0, kMmTolerance);
  TA_CHECK_NEAR(rig.get(v::kGantryBuildStraightness), 0.0, kMmTolerance);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3(0, 0, 0)), kError);  // computed, not stored: nothing to convert with
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_CHECK_EQ(report(rig, 9824, 0, 1.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_REQUIRE(gf::build(rig, true) == kDone);  // the session is kept after a computation
  TA_CHECK(!rig.unchanged());
  for (const double r : {0.0, 1.0}) {
    TA_CASE_INDEX(static_cast<int>(r));
    TA_REQUIRE(report(rig, 9824, 0, r) == kDone);
    TA_CHECK(near3(rig.get3(v::kGlobalOriginX), Vec3::Zero(), kMmTolerance));
    TA_CHECK(near3(rig.get3(v::kGlobalXX), Vec3::UnitX(), 1e-12));
    TA_CHECK(near3(rig.get3(v::kGlobalYX), Vec3::UnitY(), 1e-12));
    TA_CHECK(near3(rig.get3(v::kGlobalZX), Vec3::UnitZ(), 1e-12));
    TA_CHECK_EQ(rig.get(v::kGlobalSubMachines), 2.0);
    TA_CHECK_EQ(rig.get(v::kGlobalIdMask), 3.0);
    for (int id = 1; id <= gf::kSubMachines; ++id) {
      TA_CASE_INDEX(10 * static_cast<int>(r) + id);
      TA_REQUIRE(report(rig, 9826, id, r) == kDone);
      TA_CHECK(near3(rig.get3(v::kSubOriginX), gf::origin(id), kMmTolerance));
      TA_CHECK(near3(rig.get3(v::kSubXX), Vec3::UnitX(), 1e-12));
      TA_CHECK(near3(rig.get3(v::kSubYX), Vec3::UnitY(), 1e-12));
      TA_CHECK(near3(rig.get3(v::kSubZX), Vec3::UnitZ(), 1e-12));
      TA_CHECK_NEAR(rig.get(v::kSubACOffset), 0.0, kMmTolerance);
    }
    TA_CHECK_EQ(report(rig, 9826, 3, r), kError);  // not in the set
    TA_CHECK_EQ(rig.code(), Status::kNoTable);
  }
}

TA_TEST("9825 converts a global point into each sub-machine's frame as the closed form does, as the direct call") {
  ModuleRig rig;
  gf::stored(rig);
  for (int id = 1; id <= gf::kSubMachines; ++id) {
    for (const Vec3& p : kPoints) {
      TA_CASE_INDEX(id);
      TA_REQUIRE(gf::convert(rig, id, p) == kDone);
      TA_CHECK(near3(rig.get3(v::kGantryPointX), p - gf::origin(id), kMmTolerance));
      const auto direct = g::sub_point_mm(rig.module().state<g::Method>(), id, p);
      TA_REQUIRE(direct.ok());
      TA_CHECK(direct.value() == rig.get3(v::kGantryPointX));
    }
  }
  // The stored frames survive a restart, bit for bit.
  TA_REQUIRE(gf::convert(rig, 2, kPoints[1]) == kDone);
  const Vec3 before = rig.get3(v::kGantryPointX);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_REQUIRE(gf::convert(rig, 2, kPoints[1]) == kDone);
  TA_CHECK(rig.get3(v::kGantryPointX) == before);
}

TA_TEST("9825's own refusals keep its outputs, and the direct call refuses alike") {
  ModuleRig rig;
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3(0, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_CHECK_EQ(g::sub_point_mm(rig.module().state<g::Method>(), 1, Vec3(0, 0, 0)).status(), Status::kNoTable);
  gf::stream(rig, gf::Variation{}, 1);
  TA_REQUIRE(gf::build(rig, true) == kDone);
  TA_REQUIRE(gf::convert(rig, 1, Vec3(1, 2, 3)) == kDone);
  const ModuleRig::Results kept = rig.results();
  for (const double id : {0.0, 9.0, 1.5}) {
    TA_CHECK_EQ(gf::convert(rig, id, Vec3(1, 2, 3)), kError);
    TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  }
  TA_CHECK_EQ(gf::convert(rig, 2, Vec3(1, 2, 3)), kError);  // not stored
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  TA_CHECK(rig.results() == kept);
  const auto& state = rig.module().state<g::Method>();
  TA_CHECK_EQ(g::sub_point_mm(state, 0, Vec3(0, 0, 0)).status(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(g::sub_point_mm(state, 9, Vec3(0, 0, 0)).status(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(g::sub_point_mm(state, 8, Vec3(0, 0, 0)).status(), Status::kNoTable);
  TA_CHECK_EQ(report(rig, 9824, 0, 2.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(report(rig, 9826, 1, 0.5), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK_EQ(report(rig, 9826, 9, 1.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kArgumentOutOfRange);
  TA_CHECK(rig.results() == kept);
}

TA_TEST("storing merges by sub-machine: the others stay as they were") {
  ModuleRig rig;
  gf::stored(rig);  // sub-machines 1 and 2
  const Vec3 p(800.0, 600.0, 1500.0);
  TA_CHECK_EQ(gf::convert(rig, 3, p), kError);
  TA_CHECK_EQ(rig.code(), Status::kNoTable);
  // Sub-machine 2 again with a swing of 250 mm, and sub-machine 3: 1 keeps its frame.
  TA_REQUIRE(rig.done(9820));
  gf::stream_machine(rig);
  gf::stream_sub(rig, 3);
  gf::stream_sub(rig, 2);
  TA_REQUIRE(gf::parameters(rig, 2, 250.0, Vec3(0, 0, -1)) == kDone);
  rig.set(v::kArgM, 1.0);  // sub-machine 2's origin moves with its swing: beyond #704, confirmed
  TA_REQUIRE(gf::build(rig, true) == kDone);
  TA_REQUIRE(report(rig, 9824, 0, 1.0) == kDone);
  TA_CHECK_EQ(rig.get(v::kGlobalIdMask), 7.0);
  TA_CHECK_EQ(rig.get(v::kGlobalSubMachines), 3.0);
  TA_REQUIRE(gf::convert(rig, 1, p) == kDone);
  TA_CHECK(near3(rig.get3(v::kGantryPointX), p - gf::origin(1), kMmTolerance));
  TA_REQUIRE(gf::convert(rig, 2, p) == kDone);
  TA_CHECK(near3(rig.get3(v::kGantryPointX), p - (gf::wrist(2) - Vec3(0, 0, 250.0)), kMmTolerance));
  TA_REQUIRE(gf::convert(rig, 3, p) == kDone);
  TA_CHECK(near3(rig.get3(v::kGantryPointX), p - gf::origin(3), kMmTolerance));
}

namespace {

// Stored frames first; then `variation` streamed (or `extra` done) and 9823
// with R = 1 must fail with `expected`, storing nothing and keeping 9825's answer.
template <typename Extra>
void failed_computation(const gf::Variation& variation, Extra extra, Status expected) {
  ModuleRig rig;
  gf::stored(rig);
  TA_REQUIRE(gf::convert(rig, 1, kPoints[1]) == kDone);
  const Vec3 answer = rig.get3(v::kGantryPointX);
  gf::stream(rig, variation);
  rig.unlock();
  extra(rig);
  rig.snapshot();  // after extra: a configuration write is stored too
  const ModuleRig::Results before = rig.results();
  rig.set(v::kArgR, rig.get(v::kArgR) == 0.0 ? 1.0 : rig.get(v::kArgR));
  TA_CHECK_EQ(rig.refuse(9823), expected);
  TA_CHECK(rig.unchanged_after(expected));
  TA_CHECK(rig.results() == before);
  TA_REQUIRE(gf::convert(rig, 1, kPoints[1]) == kDone);
  TA_CHECK(rig.get3(v::kGantryPointX) == answer);
}

void nothing(ModuleRig&) {}

gf::Variation varied(int gf::Variation::*field, int value) {
  gf::Variation v;
  v.*field = value;
  return v;
}

}  // namespace

TA_TEST("9823 without a sub-machine's A circle fails with missing_group and keeps the stored frames") {
  failed_computation(varied(&gf::Variation::a_points, 0), nothing, Status::kMissingGroup);
}

TA_TEST("9823 with a bed of 3 points fails with too_few_points and keeps the stored frames") {
  failed_computation(varied(&gf::Variation::bed_points, 3), nothing, Status::kTooFewPoints);
}

TA_TEST("9823 with a C circle of 4 points fails with too_few_points and keeps the stored frames") {
  failed_computation(varied(&gf::Variation::c_points, 4), nothing, Status::kTooFewPoints);
}

TA_TEST("9823 with a sub-machine measured but without its 9822 fails with missing_group") {
  gf::Variation variation;
  variation.parameters_1 = false;
  failed_computation(variation, nothing, Status::kMissingGroup);
}

TA_TEST("9823 with an A circle on a shorter arc than #700 fails with arc_too_short") {
  failed_computation(gf::Variation{}, [](ModuleRig& rig) { rig.set(v::kGantryMinArc, 181.0); },
                     Status::kArcTooShort);  // the A circles span 180 deg
}

TA_TEST("9823 with A turning about the C axis fails with axes_parallel") {
  gf::Variation variation;
  variation.a_about_c = true;
  failed_computation(variation, nothing, Status::kAxesParallel);
}

TA_TEST("9823 with every x pass measured backwards fails with axis_opposite_gantry") {
  failed_computation(varied(&gf::Variation::reversed_x, 1), nothing, Status::kAxisOppositeGantry);
}

TA_TEST("9823 with one of two x passes measured backwards fails with passes_disagree") {
  gf::Variation variation;
  variation.x_passes = 2;
  variation.reversed_x = 1;
  failed_computation(variation, nothing, Status::kPassesDisagree);
}

TA_TEST("9823 with R = 2 fails with argument_out_of_range") {
  failed_computation(gf::Variation{}, [](ModuleRig& rig) { rig.set(v::kArgR, 2.0); }, Status::kArgumentOutOfRange);
}

TA_TEST("9823 R = 1 while locked fails with table_locked and keeps the stored frames") {
  failed_computation(gf::Variation{}, [](ModuleRig& rig) { rig.lock(); }, Status::kTableLocked);
}

namespace {

std::size_t first_slot_of_frames() {
  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != g::FramesRecord::kRecord.key) ++index;
  return m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0);
}

}  // namespace

TA_TEST("stored frames that fail their CRC say table_damaged at 9825 and 9824 until frames are stored again") {
  ModuleRig rig;
  gf::stream(rig, gf::Variation{}, 1);
  TA_REQUIRE(gf::build(rig, true) == kDone);
  rig.storage().bytes[first_slot_of_frames() + m::KeyedStore::kHeaderBytes + 300] ^= 0x10;
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3(0, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableDamaged);
  TA_CHECK_EQ(report(rig, 9824, 0, 1.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableDamaged);
  gf::stream(rig, gf::Variation{}, 1);
  TA_REQUIRE(gf::build(rig, true) == kDone);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3(0, 0, 0)), kDone);
}

TA_TEST("a stored frames record with a good CRC that does not decode says table_invalid") {
  ModuleRig rig;
  static std::uint8_t scratch[m::kStoreScratchBytes];
  m::KeyedStore store(rig.storage(), m::kRecordSpecs.data(), m::kRecordCount, scratch, sizeof scratch);
  TA_REQUIRE(store.mount() == Status::kOk);
  static std::uint8_t garbage[trueaxis::core::kGantryTableBytes] = {1, 0, 1};
  TA_REQUIRE(store.save(g::FramesRecord::kRecord.key, garbage, sizeof garbage) == Status::kOk);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(gf::convert(rig, 1, Vec3(0, 0, 0)), kError);
  TA_CHECK_EQ(rig.code(), Status::kTableInvalid);
  TA_CHECK_EQ(g::sub_point_mm(rig.module().state<g::Method>(), 1, Vec3(0, 0, 0)).status(), Status::kTableInvalid);
}

TA_TEST("9821, 9822 and 9823 answer session_closed once another method's session replaced this one") {
  ModuleRig rig;
  gf::stream(rig, gf::Variation{}, 1);
  TA_REQUIRE(rig.open_foreign_session());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(gf::add(rig, 0, gf::kBed, 0, Vec3(1, 2, 3)), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK_EQ(gf::parameters(rig, 1, 300.0, Vec3(0, 0, -1)), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK_EQ(gf::build(rig, false), kError);
  TA_CHECK_EQ(rig.code(), Status::kSessionClosed);
  TA_CHECK(rig.results() == kept);
  gf::stream(rig, gf::Variation{}, 1);  // 9820 opens it again
  TA_CHECK_EQ(gf::build(rig, false), kDone);
}

TA_TEST("9824 and 9826 R = 0 answer result_replaced after another method's computation; R = 1 still answers") {
  ModuleRig rig;
  gf::stored(rig);
  TA_REQUIRE(report(rig, 9826, 1, 0.0) == kDone);
  TA_REQUIRE(rig.open_foreign_work());
  const ModuleRig::Results kept = rig.results();
  TA_CHECK_EQ(report(rig, 9824, 0, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kResultReplaced);
  TA_CHECK_EQ(report(rig, 9826, 1, 0.0), kError);
  TA_CHECK_EQ(rig.code(), Status::kResultReplaced);
  TA_CHECK(rig.results() == kept);
  TA_CHECK_EQ(report(rig, 9826, 1, 1.0), kDone);
  TA_CHECK(near3(rig.get3(v::kSubOriginX), gf::origin(1), kMmTolerance));
}

// ---- recipes (method_tests.hpp) ------------------------------------------------------------

namespace {

void one_point(ModuleRig& rig) {
  rig.set(v::kArgT, 0.0);
  rig.set(v::kArgQ, gf::kBed);
  rig.set3(v::kArgX, Vec3(1, 2, 3));
}
void sub_parameters(ModuleRig& rig) {
  rig.set(v::kArgT, 1.0);
  rig.set(v::kArgD, gf::kSwingMm);
  rig.set3(v::kArgI, Vec3(0, 0, -1));
}
void streamed(ModuleRig& rig) { gf::stream(rig); }
void stored(ModuleRig& rig) { gf::stored(rig); }
void store_arguments(ModuleRig& rig) {
  rig.unlock();
  rig.set(v::kArgR, 1.0);
}
void stored_report(ModuleRig& rig) {
  rig.set(v::kArgT, 1.0);
  rig.set(v::kArgR, 1.0);
}
void convert_arguments(ModuleRig& rig) {
  rig.set(v::kArgT, 2.0);
  rig.set3(v::kArgX, kPoints[1]);
}

}  // namespace

TA_RECIPE(9820, nullptr, nullptr);
TA_RECIPE(9821, nullptr, one_point);
TA_RECIPE(9822, nullptr, sub_parameters);
TA_RECIPE(9823, streamed, store_arguments);
TA_RECIPE(9824, stored, stored_report);
TA_RECIPE(9825, stored, convert_arguments);
TA_RECIPE(9826, stored, stored_report);
TA_RECIPE(9827, stored, nullptr);  // the build stored is the build checked: every figure 0, pass
