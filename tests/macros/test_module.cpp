#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <algorithm>

#include "alloc_counter.hpp"
#include "fakes.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/record_codec.hpp"

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;
using F = trueaxis::macros::AccessFault;

namespace {

struct Rig {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  m::Module module{storage, clock};
  Rig() { REQUIRE(module.start() == Status::kOk); }

  F put(std::uint16_t n, double value) { return module.write(n, 1, &value); }
  double get(std::uint16_t n) {
    double value = std::numeric_limits<double>::quiet_NaN();
    REQUIRE(module.read(n, 1, &value) == F::kNone);
    return value;
  }
  void put_point(std::uint16_t x_number, double x, double y, double z) {
    const double p[3] = {x, y, z};
    REQUIRE(module.write(x_number, 3, p) == F::kNone);
  }
  // A face tilted by atan(0.2) about Y (rising towards +X), probed at the table's zero.
  void put_inclined_face() {
    put_point(v::kG57, 0, 0, 10);
    put_point(v::kG58, 100, 0, 30);
    put_point(v::kG59, 0, 100, 10);
  }
  double run(double macro) {
    REQUIRE(put(v::kCmd, macro) == F::kNone);
    CHECK(get(v::kStatus) == 1.0);
    module.step();
    return get(v::kStatus);
  }
  std::array<double, 16> results() {
    std::array<double, 16> r{};
    REQUIRE(module.read(v::kLevelC, 16, r.data()) == F::kNone);
    return r;
  }
};

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("starts from the map's defaults on blank storage", "[module]") {
  Rig rig;
  CHECK(rig.get(v::kAMin) == -120.0);
  CHECK(rig.get(v::kProbeSigma) == 0.0005);
  CHECK(rig.get(v::kASign) == 1.0);
  CHECK(rig.get(v::kStatus) == 0.0);
  CHECK(rig.get(v::kInterfaceVersion) == 1.0);
  CHECK(rig.get(v::kUnlock) == 0.0);
}

TEST_CASE("macro 9810 levels a face and completes the handshake", "[module][9810]") {
  Rig rig;
  rig.put_inclined_face();
  CHECK(rig.run(9810) == 2.0);
  CHECK(rig.get(v::kError) == 0.0);
  CHECK(rig.get(v::kDoneCount) == 1.0);
  CHECK(rig.get(v::kRunTime) == 7.0);  // one tick of the fake clock
  const auto r = rig.results();
  const double tilt = std::atan(0.2) * 180.0 / trueaxis::core::kPi;
  CHECK(r[7] == Approx(tilt).margin(1e-12));
  // The normal (-0.2, 0, 1)/|.| needs C = -90 and A = tilt, or C = 90 and A = -tilt.
  // From the table at zero both cost 90 + tilt degrees of travel: the tie goes to
  // solution 1 (C = atan2(nx, ny) = -90).
  CHECK(r[0] == Approx(-90.0).margin(1e-12));
  CHECK(r[1] == Approx(tilt).margin(1e-12));
  CHECK(r[2] == Approx(90.0).margin(1e-12));
  CHECK(r[3] == Approx(-tilt).margin(1e-12));
  CHECK(r[12] == 3.0);
  CHECK(r[15] == 1.0);
  CHECK(r[8] > 0.0);
}

TEST_CASE("every argument and the whole point list are cleared after every macro, work offsets kept",
          "[module]") {
  Rig rig;
  rig.put_inclined_face();
  std::array<double, v::kPointListCount> pts{};
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = 1.0 + static_cast<double>(i);
  const auto put_inputs = [&] {
    for (const m::VarInfo& info : m::kPlatformArgRows) REQUIRE(rig.put(info.number, 0.25 + info.number) == F::kNone);
    for (std::size_t at = 0; at < pts.size(); at += 30) {
      const auto n = static_cast<std::uint16_t>(std::min<std::size_t>(30, pts.size() - at));
      REQUIRE(rig.module.write(static_cast<std::uint16_t>(v::kPointList + at), n, pts.data() + at) == F::kNone);
    }
  };
  const auto all_cleared = [&] {
    for (const m::VarInfo& info : m::kPlatformArgRows) CHECK(rig.get(info.number) == 0.0);
    for (std::uint16_t k = 0; k < v::kPointListCount; ++k) CHECK(rig.get(static_cast<std::uint16_t>(v::kPointList + k)) == 0.0);
  };
  SECTION("after a macro that succeeds") {
    put_inputs();
    REQUIRE(rig.put(v::kArgA, 0.0) == F::kNone);
    REQUIRE(rig.put(v::kArgC, 0.0) == F::kNone);
    REQUIRE(rig.put(v::kArgI, 0.0) == F::kNone);
    REQUIRE(rig.run(9810) == 2.0);
    all_cleared();
  }
  SECTION("after a macro that fails") {
    put_inputs();
    REQUIRE(rig.run(1234) == 3.0);
    all_cleared();
  }
  CHECK(rig.get(v::kG58 + 2) == 30.0);
  CHECK(rig.get(v::kG59 + 1) == 100.0);
}

TEST_CASE("a failing macro sets status 3 and its code and changes no result or table", "[module][errors]") {
  Rig rig;
  rig.put_inclined_face();
  REQUIRE(rig.run(9810) == 2.0);
  const auto before = rig.results();
  // Runs the macro and checks that it failed with `code` and stored nothing.
  const auto fails_with = [&](double macro, Status code) {
    const auto stored = rig.storage.bytes;
    CHECK(rig.run(macro) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(code));
    CHECK(rig.storage.bytes == stored);
  };

  SECTION("collinear points") {
    rig.put_point(v::kG59, 50, 0, 20);
    fails_with(9810, Status::kPointsCollinear);
  }
  SECTION("coincident points") {
    rig.put_point(v::kG58, 0, 0, 10);
    rig.put_point(v::kG59, 0, 0, 10);
    fails_with(9810, Status::kPointsCoincident);
  }
  SECTION("unreachable face") {
    REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
    REQUIRE(rig.put(v::kAMin, -1.0) == F::kNone);
    REQUIRE(rig.put(v::kAMax, 1.0) == F::kNone);
    fails_with(9810, Status::kUnreachable);
  }
  SECTION("inconsistent configuration") {
    REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
    REQUIRE(rig.put(v::kAMin, 50.0) == F::kNone);
    REQUIRE(rig.put(v::kAMax, 10.0) == F::kNone);
    fails_with(9810, Status::kConfigInvalid);
  }
  SECTION("unknown macro") {
    fails_with(1234, Status::kUnknownMacro);
  }
  SECTION("9811 with a point count out of range") {
    REQUIRE(rig.put(v::kArgQ, 2.0) == F::kNone);
    fails_with(9811, Status::kArgumentOutOfRange);
  }
  CHECK(rig.results() == before);
  CHECK(rig.get(v::kDoneCount) == 2.0);
}

TEST_CASE("refuses non-finite and out-of-range values and changes nothing", "[module][errors]") {
  Rig rig;
  rig.put_inclined_face();
  const double bad_point[3] = {1.0, 2.0, kNaN};
  CHECK(rig.module.write(v::kG57, 3, bad_point) == F::kNotFinite);
  CHECK(rig.get(v::kG57) == 0.0);  // the whole write was refused, X too
  CHECK(rig.get(v::kAccessFault) == static_cast<double>(F::kNotFinite));
  CHECK(rig.put(v::kG57, std::numeric_limits<double>::infinity()) == F::kNotFinite);
  CHECK(rig.put(v::kG57, 2e5) == F::kOutOfRange);
  CHECK(rig.put(v::kCmd, 9810.5) == F::kOutOfRange);
  CHECK(rig.put(v::kCmd, -1.0) == F::kOutOfRange);
  CHECK(rig.get(v::kG57 + 2) == 10.0);
  CHECK(rig.get(v::kStatus) == 0.0);
}

TEST_CASE("refuses undefined numbers and read-only variables", "[module][errors]") {
  Rig rig;
  double out[3] = {-1, -1, -1};
  CHECK(rig.module.read(10, 1, out) == F::kUndefined);  // letter G has no variable
  CHECK(rig.module.read(8, 3, out) == F::kUndefined);   // #8, #9 defined, #10 not
  CHECK(out[0] == -1.0);
  CHECK(rig.module.read(16383, 1, out) == F::kUndefined);
  CHECK(rig.module.read(16383, 2, out) == F::kUndefined);
  CHECK(rig.put(v::kLevelC, 1.0) == F::kReadOnly);
  CHECK(rig.put(v::kStatus, 2.0) == F::kReadOnly);
  CHECK(rig.put(v::kDoneCount, 5.0) == F::kReadOnly);
  CHECK(rig.put(116, 1.0) == F::kReadOnly);  // the result block
  CHECK(rig.put(200, 1.0) == F::kUndefined);
  CHECK(rig.get(v::kAccessFault) == static_cast<double>(F::kUndefined));
  CHECK(rig.get(v::kDoneCount) == 0.0);
}

TEST_CASE("configuration is writable only while unlocked", "[module][config]") {
  Rig rig;
  const auto stored = rig.storage.bytes;
  CHECK(rig.put(v::kAMin, -90.0) == F::kLocked);
  CHECK(rig.get(v::kAMin) == -120.0);
  CHECK(rig.put(v::kUnlock, 1234.0) == F::kBadUnlockCode);
  CHECK(rig.get(v::kUnlock) == 0.0);
  CHECK(rig.put(v::kUnlock, kNaN) == F::kNotFinite);
  CHECK(rig.storage.bytes == stored);
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  CHECK(rig.get(v::kUnlock) == 1.0);
  CHECK(rig.put(v::kAMin, -90.0) == F::kNone);
  CHECK(rig.put(v::kASign, 0.5) == F::kOutOfRange);
  CHECK(rig.put(v::kASign, -1.0) == F::kNone);
  CHECK(rig.put(v::kProbeSigma, -0.001) == F::kOutOfRange);
  REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
  CHECK(rig.put(v::kAMax, 90.0) == F::kLocked);
  CHECK(rig.get(v::kAMin) == -90.0);
}

TEST_CASE("persistent variables survive a restart, volatile ones do not", "[module][persist]") {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  {
    m::Module first(storage, clock);
    REQUIRE(first.start() == Status::kOk);
    const double unlock = m::kUnlockCode;
    const double limits[2] = {-45.0, 100.0};
    const double offset = 12.5;
    const double arg = 3.0;
    REQUIRE(first.write(v::kUnlock, 1, &unlock) == F::kNone);
    REQUIRE(first.write(v::kAMin, 2, limits) == F::kNone);
    REQUIRE(first.write(v::kG54 + 1, 1, &offset) == F::kNone);
    REQUIRE(first.write(v::kArgA, 1, &arg) == F::kNone);
  }
  m::Module second(storage, clock);
  REQUIRE(second.start() == Status::kOk);
  CHECK(second.value(v::kAMin) == -45.0);
  CHECK(second.value(v::kAMax) == 100.0);
  CHECK(second.value(v::kG54 + 1) == 12.5);
  CHECK(second.value(v::kArgA) == 0.0);
  CHECK_FALSE(second.unlocked());
}

TEST_CASE("a storage failure refuses the write and keeps the old value", "[module][persist]") {
  Rig rig;
  rig.storage.refuse = true;
  CHECK(rig.put(v::kG57, 5.0) == F::kStorageFailure);
  CHECK(rig.get(v::kG57) == 0.0);
  CHECK(rig.get(v::kAccessFault) == static_cast<double>(F::kStorageFailure));
  rig.storage.refuse = false;
  CHECK(rig.put(v::kG57, 5.0) == F::kNone);
  CHECK(rig.get(v::kG57) == 5.0);
}

TEST_CASE("while busy, commands and macro inputs are refused and reads still work", "[module][busy]") {
  Rig rig;
  rig.put_inclined_face();
  REQUIRE(rig.put(v::kCmd, 9810.0) == F::kNone);
  CHECK(rig.module.busy());
  CHECK(rig.get(v::kStatus) == 1.0);
  CHECK(rig.put(v::kCmd, 9810.0) == F::kBusy);
  CHECK(rig.put(v::kArgA, 5.0) == F::kBusy);
  CHECK(rig.put(v::kG57, 5.0) == F::kBusy);
  CHECK(rig.get(v::kAccessFault) == static_cast<double>(F::kBusy));
  CHECK(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  CHECK(rig.put(v::kAMin, -10.0) == F::kBusy);
  rig.module.step();
  CHECK_FALSE(rig.module.busy());
  CHECK(rig.get(v::kStatus) == 2.0);
  CHECK(rig.get(v::kDoneCount) == 1.0);
  CHECK(rig.put(v::kCmd, 9810.0) == F::kNone);
}

TEST_CASE("macro 9811 fits the point list and flags an outlier", "[module][9811]") {
  Rig rig;
  std::array<double, 3 * 8> pts{};
  for (std::size_t k = 0; k < 8; ++k) {
    const double x = 20.0 * static_cast<double>(k % 4);
    const double y = 30.0 * static_cast<double>(k / 4) + 5.0 * static_cast<double>(k % 3);
    pts[3 * k] = x;
    pts[3 * k + 1] = y;
    pts[3 * k + 2] = 0.1 * x + ((k % 2) ? 0.0004 : -0.0004);
  }
  pts[3 * 5 + 2] += 0.05;
  REQUIRE(rig.module.write(v::kPointList, static_cast<std::uint16_t>(pts.size()), pts.data()) == F::kNone);
  REQUIRE(rig.put(v::kArgQ, 8.0) == F::kNone);
  REQUIRE(rig.run(9811) == 2.0);
  const auto r = rig.results();
  CHECK(r[12] == 8.0);
  CHECK(r[13] == 6.0);
  // The module publishes the core fit's flatness of the same points (wiring, not math: test_plane_fit.cpp).
  trueaxis::core::Vec3 p[8];
  for (std::size_t k = 0; k < 8; ++k) p[k] = trueaxis::core::Vec3(pts[3 * k], pts[3 * k + 1], pts[3 * k + 2]);
  const auto fit = trueaxis::core::fit_plane(p, 8);
  REQUIRE(fit.ok());
  CHECK(r[11] == fit.value().flatness_mm);
  CHECK(r[11] > 0.04);
  for (std::uint16_t k = 0; k < 3 * 8; ++k) CHECK(rig.get(static_cast<std::uint16_t>(v::kPointList + k)) == 0.0);
}

TEST_CASE("macro 9811 takes Q = 32, its documented maximum, and refuses 33", "[module][9811]") {
  Rig rig;
  std::array<double, v::kPointListCount> pts{};
  for (std::size_t k = 0; k < 32; ++k) {
    const double x = 10.0 * static_cast<double>(k % 8);
    const double y = 10.0 * static_cast<double>(k / 8) + static_cast<double>(k % 3);
    pts[3 * k] = x;
    pts[3 * k + 1] = y;
    pts[3 * k + 2] = 5.0 + 0.1 * y;  // tilted about X, atan(0.1)
  }
  for (std::size_t at = 0; at < pts.size(); at += 30) {
    const auto n = static_cast<std::uint16_t>(std::min<std::size_t>(30, pts.size() - at));
    REQUIRE(rig.module.write(static_cast<std::uint16_t>(v::kPointList + at), n, pts.data() + at) == F::kNone);
  }
  REQUIRE(rig.put(v::kArgQ, 32.0) == F::kNone);
  REQUIRE(rig.run(9811) == 2.0);
  const auto r = rig.results();
  CHECK(r[12] == 32.0);
  CHECK(r[7] == Approx(std::atan(0.1) * 180.0 / trueaxis::core::kPi).margin(1e-12));
  REQUIRE(rig.put(v::kArgQ, 33.0) == F::kNone);
  CHECK(rig.run(9811) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kArgumentOutOfRange));
  CHECK(rig.results() == r);
}

TEST_CASE("a whole level cycle through the module allocates nothing", "[module][alloc]") {
  Rig rig;
  const trueaxis::test::AllocationScope scope;
  rig.put_inclined_face();
  for (int i = 0; i < 10; ++i) {
    const double cmd = 9810.0;
    REQUIRE(rig.module.write(v::kCmd, 1, &cmd) == F::kNone);
    rig.module.step();
  }
  double out[16];
  REQUIRE(rig.module.read(v::kLevelC, 16, out) == F::kNone);
  CHECK(scope.count() == 0);
}

TEST_CASE("the chosen solution is the one nearest the table's present position", "[module][9810]") {
  Rig rig;
  rig.put_inclined_face();  // probed with the table at zero
  REQUIRE(rig.put(v::kArgC, 80.0) == F::kNone);  // ...but say it was at C = 80
  REQUIRE(rig.put(v::kArgA, 0.0) == F::kNone);
  // The points are the same, so the face normal at table zero is Rz(80)^T (-0.2, 0, 1):
  // C1 = -90 + 80 = -10 or C2 = 170; from C = 80 solution 1 is nearer.
  REQUIRE(rig.run(9810) == 2.0);
  const auto r = rig.results();
  const double tilt = std::atan(0.2) * 180.0 / trueaxis::core::kPi;
  CHECK(r[0] == Approx(-10.0).margin(1e-9));
  CHECK(r[1] == Approx(tilt).margin(1e-12));
  CHECK(r[2] == Approx(170.0).margin(1e-9));
}

TEST_CASE("writing 0 to the command runs nothing and keeps the last status and error", "[module]") {
  Rig rig;
  CHECK(rig.run(1234) == 3.0);
  REQUIRE(rig.put(v::kCmd, 0.0) == F::kNone);
  CHECK_FALSE(rig.module.busy());
  CHECK(rig.get(v::kStatus) == 3.0);
  CHECK(rig.get(v::kError) == static_cast<double>(Status::kUnknownMacro));
  CHECK(rig.get(v::kDoneCount) == 1.0);
}

// ---------------------------------------------------------------------------
// The platform under the methods: sessions, bounded steps, staged tables.

namespace {

// Extra macros a test hands the module, as an integrator could.
int g_steps_seen = 0;
m::MacroStep three_steps(m::MacroContext& ctx) {
  if (ctx.first_step()) g_steps_seen = 0;
  ++g_steps_seen;
  if (g_steps_seen < 3) return m::more();
  ctx.out<100>(static_cast<double>(g_steps_seen));
  return m::done(Status::kOk);
}

constexpr std::size_t kTableValues = 300;

// Stages a 300-value table v_i = A + i as the rigidity record; fails instead
// when Q = 1 (after staging), to show a failed macro commits nothing.
m::MacroStep stage_table(m::MacroContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(m::RecordKey::kRigidityTable, 8 * kTableValues);
  if (bytes == nullptr) return m::done(Status::kStorageFailure);
  for (std::size_t i = 0; i < kTableValues; ++i) m::put_f64(bytes + 8 * i, ctx.in<v::kArgA>() + static_cast<double>(i));
  if (ctx.in<v::kArgQ>() == 1.0) return m::done(Status::kArgumentOutOfRange);
  ctx.out<100>(1.0);
  return m::done(Status::kOk);
}

// Reads the stored rigidity record: #100 its number of values, #101 value Q.
m::MacroStep read_table(m::MacroContext& ctx) {
  static std::uint8_t bytes[m::kMaxRecordPayloadBytes];
  std::size_t length = 0;
  const Status s = ctx.load_record(m::RecordKey::kRigidityTable, bytes, sizeof bytes, length);
  if (s != Status::kOk) return m::done(s);
  if (length == 0) return m::done(Status::kNoTable);
  const auto q = static_cast<std::size_t>(ctx.in<v::kArgQ>());
  ctx.out<100>(static_cast<double>(length / 8));
  ctx.out<101>(q < length / 8 ? m::get_f64(bytes + 8 * q) : -1.0);
  return m::done(Status::kOk);
}

constexpr m::OutputInfo kTestOutputs[] = {{100, "test", "", "Test output."}};
constexpr m::MacroInfo kTestMacros[] = {
    m::macro(9901, &three_steps, "three_steps", "Takes three steps.", kTestOutputs),
    m::macro(9902, &stage_table, "stage_table", "Stages a 300-value table.", kTestOutputs),
    m::macro(9903, &read_table, "read_table", "Reads the stored table.", kTestOutputs),
};

struct TableRig {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  std::unique_ptr<m::Module> module;
  TableRig() { restart(); }
  void restart() {
    module = std::make_unique<m::Module>(storage, clock, kTestMacros, 3);
    REQUIRE(module->start() == Status::kOk);
  }
  F put(std::uint16_t n, double value) { return module->write(n, 1, &value); }
  double get(std::uint16_t n) { return module->value(n); }
  double run(double macro) {
    REQUIRE(put(v::kCmd, macro) == F::kNone);
    for (int i = 0; i < 10 && module->busy(); ++i) module->step();
    REQUIRE_FALSE(module->busy());
    return get(v::kStatus);
  }
};

// Bytes [first, end) of a record's two slots in the storage layout.
std::pair<std::size_t, std::size_t> region_of(m::RecordKey key) {
  std::size_t at = 0;
  for (const m::RecordSpec& spec : m::kRecordSpecs) {
    const std::size_t n = 2 * m::KeyedStore::slot_bytes(spec);
    if (spec.key == static_cast<std::uint8_t>(key)) return {at, at + n};
    at += n;
  }
  return {0, 0};
}

}  // namespace

TEST_CASE("a macro that needs several steps stays busy until its last step", "[module][steps]") {
  TableRig rig;
  REQUIRE(rig.put(v::kCmd, 9901) == F::kNone);
  rig.module->step();
  CHECK(rig.module->busy());
  CHECK(rig.get(v::kStatus) == 1.0);
  CHECK(rig.put(v::kCmd, 9810) == F::kBusy);
  CHECK(rig.put(v::kArgA, 1.0) == F::kBusy);
  rig.module->step();
  CHECK(rig.module->busy());
  CHECK(rig.get(v::kDoneCount) == 0.0);
  rig.module->step();
  CHECK_FALSE(rig.module->busy());
  CHECK(rig.get(v::kStatus) == 2.0);
  CHECK(rig.get(v::kDoneCount) == 1.0);
  CHECK(rig.get(v::kStepCount) == 3.0);
  CHECK(rig.get(100) == 3.0);
  CHECK(rig.get(v::kRunTime) == 7.0);  // the clock is read at the start and at the end
  rig.module->step();                       // idle: nothing changes
  CHECK(rig.get(v::kDoneCount) == 1.0);
  REQUIRE(rig.put(v::kCmd, 9810) == F::kNone);
  rig.module->step();
  CHECK(rig.get(v::kStepCount) == 1.0);
}

TEST_CASE("a 300-value table staged by one macro is committed once and survives a restart", "[module][table]") {
  TableRig rig;
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  REQUIRE(rig.put(v::kArgA, 1000.0) == F::kNone);
  REQUIRE(rig.put(v::kCmd, 9902) == F::kNone);
  rig.storage.forget_writes();
  rig.module->step();  // the macro: stages the table, publishes nothing yet
  CHECK(rig.module->busy());
  CHECK(rig.storage.written_bytes == 0);
  CHECK(rig.get(100) == 0.0);
  rig.module->step();  // the commit: one save of the rigidity record, then the results
  CHECK_FALSE(rig.module->busy());
  CHECK(rig.get(v::kStatus) == 2.0);
  CHECK(rig.get(v::kStepCount) == 2.0);
  CHECK(rig.get(100) == 1.0);
  const auto [first, end] = region_of(m::RecordKey::kRigidityTable);
  CHECK(rig.storage.written_first >= first);
  CHECK(rig.storage.written_end <= end);
  CHECK(rig.storage.written_bytes >= 8 * kTableValues);

  rig.restart();
  REQUIRE(rig.put(v::kArgQ, 299.0) == F::kNone);
  REQUIRE(rig.run(9903) == 2.0);
  CHECK(rig.get(100) == 300.0);
  CHECK(rig.get(101) == 1299.0);
  REQUIRE(rig.put(v::kArgQ, 0.0) == F::kNone);
  REQUIRE(rig.run(9903) == 2.0);
  CHECK(rig.get(101) == 1000.0);
}

TEST_CASE("a table is refused while locked, and a failed macro or save commits nothing", "[module][table]") {
  TableRig rig;
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  REQUIRE(rig.put(v::kArgA, 1000.0) == F::kNone);
  REQUIRE(rig.run(9902) == 2.0);  // the old table: 1000 + i
  const auto stored = rig.storage.bytes;
  const auto check_old_table = [&] {
    CHECK(rig.storage.bytes == stored);
    REQUIRE(rig.put(v::kArgQ, 7.0) == F::kNone);
    REQUIRE(rig.run(9903) == 2.0);
    CHECK(rig.get(101) == 1007.0);
  };

  SECTION("locked") {
    REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
    REQUIRE(rig.put(v::kArgA, 5.0) == F::kNone);
    CHECK(rig.run(9902) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTableLocked));
    CHECK(rig.get(100) == 1.0);  // the last successful macro's result, not this one's
    check_old_table();
  }
  SECTION("the macro fails after staging") {
    REQUIRE(rig.put(v::kArgA, 5.0) == F::kNone);
    REQUIRE(rig.put(v::kArgQ, 1.0) == F::kNone);
    CHECK(rig.run(9902) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kArgumentOutOfRange));
    check_old_table();
  }
  SECTION("storage refuses the save") {
    REQUIRE(rig.put(v::kArgA, 5.0) == F::kNone);
    REQUIRE(rig.put(v::kCmd, 9902) == F::kNone);
    rig.module->step();
    rig.storage.refuse = true;
    rig.module->step();
    rig.storage.refuse = false;
    CHECK(rig.get(v::kStatus) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kStorageFailure));
    CHECK(rig.get(100) == 1.0);
    check_old_table();
    rig.restart();  // and after a restart too
    check_old_table();
  }
}

TEST_CASE("a work-offset write rewrites only the work-offset record, a config write only the config record",
          "[module][persist]") {
  Rig rig;
  const auto offsets = region_of(m::RecordKey::kWorkOffsets);
  const auto config = region_of(m::RecordKey::kConfig);
  REQUIRE(offsets.second > offsets.first);
  REQUIRE(config.second > config.first);

  // Once a record has two valid copies a save is one write of header + payload
  // (its first two saves also clear the target slot's CRC, 4 bytes: keyed_store.hpp).
  REQUIRE(rig.put(v::kG57, 10.0) == F::kNone);
  REQUIRE(rig.put(v::kG57, 11.0) == F::kNone);
  rig.storage.forget_writes();
  REQUIRE(rig.put(v::kG57, 12.0) == F::kNone);
  CHECK(rig.storage.written_first >= offsets.first);
  CHECK(rig.storage.written_end <= offsets.second);
  CHECK(rig.storage.written_bytes == m::KeyedStore::kHeaderBytes + 10 * m::kWorkOffsetCount);
  CAPTURE(rig.storage.written_bytes);

  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  REQUIRE(rig.put(v::kAMin, -110.0) == F::kNone);
  REQUIRE(rig.put(v::kAMin, -105.0) == F::kNone);
  rig.storage.forget_writes();
  REQUIRE(rig.put(v::kAMin, -100.0) == F::kNone);
  CHECK(rig.storage.written_first >= config.first);
  CHECK(rig.storage.written_end <= config.second);
  CHECK(rig.storage.written_bytes == m::KeyedStore::kHeaderBytes + 10 * m::kConfigCount);

  rig.storage.forget_writes();  // the unlock code and the arguments are not persistent
  REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
  REQUIRE(rig.put(v::kArgA, 3.0) == F::kNone);
  CHECK(rig.storage.written_bytes == 0);
}

TEST_CASE("the leveling session streams points one at a time and levels through them", "[module][session]") {
  Rig rig;
  const auto add = [&](double x, double y, double z) {
    const double p[3] = {x, y, z};
    REQUIRE(rig.module.write(v::kArgX, 3, p) == F::kNone);
    return rig.run(9813);
  };
  REQUIRE(rig.run(9812) == 2.0);
  CHECK(rig.get(v::kLevelSessionCount) == 0.0);
  CHECK(rig.get(v::kLevelSessionCapacity) == static_cast<double>(m::level::kSessionCapacity));

  SECTION("compute with fewer than 3 points is too_few_samples and keeps the session") {
    REQUIRE(add(0, 0, 10) == 2.0);
    REQUIRE(add(100, 0, 30) == 2.0);
    CHECK(rig.run(9814) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooFewSamples));
    REQUIRE(add(0, 100, 10) == 2.0);
    CHECK(rig.get(v::kLevelSessionCount) == 3.0);
    REQUIRE(rig.run(9814) == 2.0);
    const auto streamed = rig.results();
    rig.put_inclined_face();  // the same three points through 9810
    REQUIRE(rig.run(9810) == 2.0);
    CHECK(rig.results() == streamed);
  }
  SECTION("a full session refuses the next point and keeps the others") {
    for (std::size_t k = 0; k < m::level::kSessionCapacity; ++k) {
      const double x = 10.0 * static_cast<double>(k % 8);
      const double y = 10.0 * static_cast<double>(k / 8);
      REQUIRE(add(x, y, 0.1 * x) == 2.0);
    }
    CHECK(rig.get(v::kLevelSessionCount) == static_cast<double>(m::level::kSessionCapacity));
    CHECK(add(1, 2, 3) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kSessionFull));
    CHECK(rig.get(v::kLevelSessionCount) == static_cast<double>(m::level::kSessionCapacity));
    REQUIRE(rig.run(9814) == 2.0);
    CHECK(rig.get(v::kLevelPointCount) == static_cast<double>(m::level::kSessionCapacity));
    CHECK(rig.get(v::kLevelTilt) == Approx(std::atan(0.1) * 180.0 / trueaxis::core::kPi).margin(1e-12));
    REQUIRE(rig.run(9812) == 2.0);  // clear empties it
    CHECK(rig.run(9814) == 3.0);
    CHECK(rig.get(v::kError) == static_cast<double>(Status::kTooFewSamples));
  }
}
