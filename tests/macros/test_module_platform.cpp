// The platform under the methods, through the module: multi-step macros,
// tables staged and committed by a macro, records kept apart, sessions.
#include <catch2/catch.hpp>

#include <algorithm>
#include <memory>
#include <utility>

#include "fakes.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/record_codec.hpp"

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;
using trueaxis::test::Rig;
using F = trueaxis::macros::AccessFault;

namespace {

// Extra macros a test hands the module, as an integrator could.
int g_steps_seen = 0;
m::MacroStep three_steps(m::PlatformContext& ctx) {
  if (ctx.first_step()) g_steps_seen = 0;
  ++g_steps_seen;
  if (g_steps_seen < 3) return m::more();
  ctx.out<100>(static_cast<double>(g_steps_seen));
  return m::done(Status::kOk);
}

constexpr std::size_t kTableValues = 300;

// Stages a 300-value table v_i = A + i as the rigidity record; fails instead
// when Q = 1 (after staging), to show a failed macro commits nothing.
m::MacroStep stage_table(m::PlatformContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(m::RigidityTableRecord::kRecord.key, 8 * kTableValues);
  if (bytes == nullptr) return m::done(Status::kStorageFailure);
  for (std::size_t i = 0; i < kTableValues; ++i) m::put_f64(bytes + 8 * i, ctx.in<v::kArgA>() + static_cast<double>(i));
  if (ctx.in<v::kArgQ>() == 1.0) return m::done(Status::kArgumentOutOfRange);
  ctx.out<100>(1.0);
  return m::done(Status::kOk);
}

// Reads the stored rigidity record: #100 its number of values, #101 value Q.
m::MacroStep read_table(m::PlatformContext& ctx) {
  static std::uint8_t bytes[m::kMaxRecordPayloadBytes];
  std::size_t length = 0;
  const Status s = ctx.load_record(m::RigidityTableRecord::kRecord.key, bytes, sizeof bytes, length);
  if (s != Status::kOk) return m::done(s);
  if (length == 0) return m::done(Status::kNoTable);
  const auto q = static_cast<std::size_t>(ctx.in<v::kArgQ>());
  ctx.out<100>(static_cast<double>(length / 8));
  ctx.out<101>(q < length / 8 ? m::get_f64(bytes + 8 * q) : -1.0);
  return m::done(Status::kOk);
}

constexpr m::OutputInfo kTestOutputs[] = {{100, "test", "", "Test output."}};
constexpr m::MacroInfo kTestMacros[] = {
    m::macro<&three_steps>(9901, "three_steps", "Takes three steps.", kTestOutputs),
    m::macro<&stage_table>(9902, "stage_table", "Stages a 300-value table.", kTestOutputs),
    m::macro<&read_table>(9903, "read_table", "Reads the stored table.", kTestOutputs),
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
std::pair<std::size_t, std::size_t> region_of(std::uint8_t key) {
  std::size_t at = 0;
  for (const m::RecordSpec& spec : m::kRecordSpecs) {
    const std::size_t n = 2 * m::KeyedStore::slot_bytes(spec);
    if (spec.key == key) return {at, at + n};
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
  const auto [first, end] = region_of(m::RigidityTableRecord::kRecord.key);
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
  const auto offsets = region_of(static_cast<std::uint8_t>(m::RecordKey::kWorkOffsets));
  const auto config = region_of(static_cast<std::uint8_t>(m::RecordKey::kConfig));
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

TEST_CASE("a start that cannot read one record loads the others, and a write keeps them", "[module][persist]") {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  {
    m::Module first(storage, clock);
    REQUIRE(first.start() == Status::kOk);
    const double unlock = m::kUnlockCode;
    const double a_max = 45.0;
    const double g57 = 7.5;
    REQUIRE(first.write(v::kUnlock, 1, &unlock) == F::kNone);
    REQUIRE(first.write(v::kAMax, 1, &a_max) == F::kNone);
    REQUIRE(first.write(v::kG57, 1, &g57) == F::kNone);
  }
  const auto offsets = region_of(static_cast<std::uint8_t>(m::RecordKey::kWorkOffsets));
  storage.unreadable_first = offsets.first;
  storage.unreadable_end = offsets.first + 1;
  {
    m::Module second(storage, clock);
    CHECK(second.start() == Status::kStorageFailure);
    CHECK(second.value(v::kAMax) == 45.0);  // the config record was read
    CHECK(second.value(v::kG57) == 0.0);    // the work offsets were not: defaults
    const double unlock = m::kUnlockCode;
    const double a_min = -10.0;
    const double g58 = 1.0;
    REQUIRE(second.write(v::kUnlock, 1, &unlock) == F::kNone);
    CHECK(second.write(v::kAMin, 1, &a_min) == F::kNone);          // config still works
    CHECK(second.write(v::kG58, 1, &g58) == F::kStorageFailure);  // the unread record refuses
  }
  storage.unreadable_end = 0;
  m::Module third(storage, clock);
  REQUIRE(third.start() == Status::kOk);
  CHECK(third.value(v::kAMax) == 45.0);  // not wiped by the write above
  CHECK(third.value(v::kAMin) == -10.0);
  CHECK(third.value(v::kG57) == 7.5);
}
