// The platform under the methods, through the module, in every module set:
// the handshake, macros of several steps, the inputs cleared after every
// macro, refused writes, the records kept apart and over a restart, tables
// staged by a macro and committed only while unlocked (module.hpp contracts
// 2-6); and that every built method's tests are in the program.
#include <cstdint>
#include <limits>

#include "method_tests.hpp"
#include "module_rig.hpp"
#include "platform_fixture.hpp"
#include "portable_test.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/record_codec.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
using F = trueaxis::macros::AccessFault;
using t::kDone;
using t::kError;
using t::ModuleRig;
using t::RigOptions;
using trueaxis::core::Status;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// ---- extra macros, as an integrator could hand them in (module.hpp contract 6) -----------

int g_steps_seen = 0;
m::MacroStep three_steps(m::PlatformContext& ctx) {
  if (ctx.first_step()) g_steps_seen = 0;
  ++g_steps_seen;
  if (g_steps_seen < 3) return m::more();
  ctx.out<100>(static_cast<double>(g_steps_seen));
  return m::done(Status::kOk);
}

constexpr std::size_t kTableValues = 300;

// Stages the set's first table record, value i = A + i; fails after staging
// when Q = 1, to show that a failed macro commits nothing.
m::MacroStep stage_table(m::PlatformContext& ctx) {
  const t::TableRecord rec = t::table_record(kTableValues);
  std::uint8_t* bytes = ctx.stage_record(rec.key, 8 * rec.values);
  if (bytes == nullptr) return m::done(Status::kStorageFailure);
  for (std::size_t i = 0; i < rec.values; ++i) m::put_f64(bytes + 8 * i, ctx.in<v::kArgA>() + static_cast<double>(i));
  if (ctx.in<v::kArgQ>() == 1.0) return m::done(Status::kArgumentOutOfRange);
  ctx.out<100>(1.0);
  return m::done(Status::kOk);
}

// Reads the stored record back: #100 its number of values, #101 value Q.
std::uint8_t g_record[m::kMaxRecordPayloadBytes > 0 ? m::kMaxRecordPayloadBytes : 1];
m::MacroStep read_table(m::PlatformContext& ctx) {
  std::size_t length = 0;
  const Status s = ctx.load_record(t::table_record(kTableValues).key, g_record, sizeof g_record, length);
  if (s != Status::kOk) return m::done(s);
  if (length == 0) return m::done(Status::kNoTable);
  const auto q = static_cast<std::size_t>(ctx.in<v::kArgQ>());
  ctx.out<100>(static_cast<double>(length / 8));
  ctx.out<101>(q < length / 8 ? m::get_f64(g_record + 8 * q) : -1.0);
  return m::done(Status::kOk);
}

constexpr m::OutputInfo kTestOutputs[] = {{100, "n", "", "Test output."}, {101, "value", "", "Test output."}};
constexpr m::MacroInfo kTestMacros[] = {
    m::macro<&three_steps>(9901, "three_steps", "Takes three steps.", kTestOutputs),
    m::macro<&stage_table>(9902, "stage_table", "Stages a table record.", kTestOutputs),
    m::macro<&read_table>(9903, "read_table", "Reads the stored table record.", kTestOutputs),
};

RigOptions with_test_macros() { return RigOptions{}.with_macros(kTestMacros); }

}  // namespace

TA_TEST("a blank device starts idle, at interface version 1, locked, every variable at its default") {
  ModuleRig rig;
  TA_CHECK_EQ(rig.get(v::kStatus), 0.0);
  TA_CHECK_EQ(rig.get(v::kError), 0.0);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 0.0);
  TA_CHECK_EQ(rig.get(v::kInterfaceVersion), 1.0);
  TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
  TA_CHECK(!rig.module().unlocked());
  for (const m::VarInfo& info : m::kRegisterMap) {
    if (info.access != m::Access::kConfig && info.access != m::Access::kPersistent) continue;
    for (std::uint16_t k = 0; k < info.count; ++k) {
      const auto n = static_cast<std::uint16_t>(info.number + k);
      TA_CASE_INDEX(n);
      TA_CHECK_EQ(rig.get(n), n == v::kUnlockCodeSetting ? 0.0 : info.default_value);
    }
  }
}

TA_TEST("a macro that needs several steps stays busy until its last step, then publishes") {
  ModuleRig rig(with_test_macros());
  TA_REQUIRE(rig.put(v::kCmd, 9901) == F::kNone);
  TA_CHECK_EQ(rig.get(v::kStatus), t::kBusy);
  rig.step();
  TA_CHECK(rig.busy());
  TA_CHECK_EQ(rig.get(v::kStatus), t::kBusy);
  rig.step();
  TA_CHECK(rig.busy());
  TA_CHECK_EQ(rig.get(v::kDoneCount), 0.0);
  TA_CHECK_EQ(rig.get(100), 0.0);  // nothing published before the end
  rig.step();
  TA_CHECK(!rig.busy());
  TA_CHECK_EQ(rig.get(v::kStatus), kDone);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 1.0);
  TA_CHECK_EQ(rig.get(v::kStepCount), 3.0);
  TA_CHECK_EQ(rig.get(100), 3.0);
  TA_CHECK_EQ(rig.get(v::kRunTime), 7.0);  // the clock is read at the start and at the end
  rig.step();  // idle: nothing changes
  TA_CHECK_EQ(rig.get(v::kDoneCount), 1.0);
  TA_CHECK_EQ(rig.run(t::kPrefillMacro), kDone);
  TA_CHECK_EQ(rig.get(v::kStepCount), 1.0);
}

TA_TEST("while busy, commands and every macro input are refused, reads and the unlock still work") {
  ModuleRig rig(with_test_macros());
  const t::ConfigVariable config = t::config_variable();
  TA_REQUIRE(rig.put(v::kCmd, 9901) == F::kNone);
  TA_CHECK(rig.busy());
  TA_CHECK_EQ(rig.put(v::kCmd, 9901), F::kBusy);
  TA_CHECK_EQ(rig.put(v::kArgA, 5.0), F::kBusy);
  TA_CHECK_EQ(rig.put(v::kG57, 5.0), F::kBusy);
  TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(F::kBusy));
  TA_CHECK_EQ(rig.put(v::kUnlock, m::kUnlockCode), F::kNone);
  TA_CHECK_EQ(rig.get(v::kUnlock), 1.0);
  TA_CHECK_EQ(rig.put(config.number, config.changed), F::kBusy);
  TA_CHECK_EQ(rig.get(config.number), config.default_value);
  rig.step();
  TA_CHECK(rig.busy());
  TA_CHECK_EQ(rig.put(v::kCmd, 9901), F::kBusy);
  rig.step();
  rig.step();
  TA_CHECK(!rig.busy());
  TA_CHECK_EQ(rig.get(v::kStatus), kDone);
  TA_CHECK_EQ(rig.put(v::kArgA, 5.0), F::kNone);
  TA_CHECK_EQ(rig.put(config.number, config.changed), F::kNone);
  TA_CHECK_EQ(rig.put(v::kCmd, 9901), F::kNone);
}

TA_TEST("every argument is cleared after a macro that succeeds and after one that fails; work offsets are kept") {
  ModuleRig rig;
  rig.set(v::kG58 + 2, 30.0);
  for (const double macro : {static_cast<double>(t::kPrefillMacro), 1234.0}) {
    TA_CASE_INDEX(static_cast<int>(macro));
    for (const m::VarInfo& info : m::kPlatformArgRows) rig.set(info.number, 0.25 + info.number);
    const double status = rig.run(macro);
    TA_CHECK_EQ(status, macro == 1234.0 ? kError : kDone);
    for (const m::VarInfo& info : m::kPlatformArgRows) TA_CHECK_EQ(rig.get(info.number), 0.0);
    TA_CHECK_EQ(rig.get(v::kG58 + 2), 30.0);
  }
}

TA_TEST("an unknown macro fails with 400 and changes no result and no stored byte") {
  ModuleRig rig;
  TA_REQUIRE(rig.prefill());
  const ModuleRig::Results before = rig.results();
  rig.snapshot();
  TA_CHECK_EQ(rig.refuse(1234), Status::kUnknownMacro);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 2.0);
  TA_CHECK(rig.results() == before);
  TA_CHECK(rig.unchanged());
}

TA_TEST("writing 0 to the command runs nothing and keeps the last status and error") {
  ModuleRig rig;
  TA_CHECK_EQ(rig.run(1234), kError);
  TA_REQUIRE(rig.put(v::kCmd, 0.0) == F::kNone);
  TA_CHECK(!rig.busy());
  TA_CHECK_EQ(rig.get(v::kStatus), kError);
  TA_CHECK_EQ(rig.code(), Status::kUnknownMacro);
  TA_CHECK_EQ(rig.get(v::kDoneCount), 1.0);
}

TA_TEST("non-finite and out-of-range values are refused whole and change nothing") {
  ModuleRig rig;
  rig.set3(v::kG57, trueaxis::core::Vec3(0.0, 0.0, 10.0));
  const double bad_point[3] = {1.0, 2.0, kNaN};
  TA_CHECK_EQ(rig.put(v::kG57, 3, bad_point), F::kNotFinite);
  TA_CHECK_EQ(rig.get(v::kG57), 0.0);  // the whole write was refused, X too
  TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(F::kNotFinite));
  TA_CHECK_EQ(rig.put(v::kG57, kInf), F::kNotFinite);
  TA_CHECK_EQ(rig.put(v::kG57, 2e5), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kCmd, 9810.5), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kCmd, -1.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kUnlock, kNaN), F::kNotFinite);
  TA_CHECK_EQ(rig.get(v::kG57 + 2), 10.0);
  TA_CHECK_EQ(rig.get(v::kStatus), 0.0);
}

TA_TEST("undefined numbers and read-only variables are refused, and a refused read writes nothing") {
  ModuleRig rig;
  double out[3] = {-1, -1, -1};
  TA_CHECK_EQ(rig.read(10, 1, out), F::kUndefined);  // letter G has no variable
  TA_CHECK_EQ(rig.read(8, 3, out), F::kUndefined);   // #8, #9 defined, #10 not
  TA_CHECK_EQ(out[0], -1.0);
  TA_CHECK_EQ(rig.read(16383, 1, out), F::kUndefined);
  TA_CHECK_EQ(rig.read(16383, 2, out), F::kUndefined);
  TA_CHECK_EQ(rig.put(100, 1.0), F::kReadOnly);
  TA_CHECK_EQ(rig.put(v::kStatus, 2.0), F::kReadOnly);
  TA_CHECK_EQ(rig.put(v::kDoneCount, 5.0), F::kReadOnly);
  TA_CHECK_EQ(rig.put(116, 1.0), F::kReadOnly);  // the result block
  TA_CHECK_EQ(rig.put(200, 1.0), F::kUndefined);
  TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(F::kUndefined));
  TA_CHECK_EQ(rig.get(v::kDoneCount), 0.0);
}

TA_TEST("a storage failure refuses the write and keeps the old value") {
  ModuleRig rig;
  rig.storage().refuse = true;
  TA_CHECK_EQ(rig.put(v::kG57, 5.0), F::kStorageFailure);
  TA_CHECK_EQ(rig.get(v::kG57), 0.0);
  TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(F::kStorageFailure));
  rig.storage().refuse = false;
  TA_CHECK_EQ(rig.put(v::kG57, 5.0), F::kNone);
  TA_CHECK_EQ(rig.get(v::kG57), 5.0);
}

TA_TEST("a work-offset write rewrites only the work-offset record, a configuration write only its record") {
  ModuleRig rig;
  const t::ConfigVariable config = t::config_variable();
  const t::Region offsets = t::region_of(m::record_key(m::RecordKey::kWorkOffsets));
  const t::Region configuration = t::region_of(m::record_key(m::RecordKey::kConfig));
  TA_REQUIRE(offsets.end > offsets.first);
  TA_REQUIRE(configuration.end > configuration.first);

  // Once a record has two valid copies a save is one write of header + payload
  // (its first two saves also clear the target slot's CRC, 4 bytes: keyed_store.hpp).
  rig.set(v::kG57, 10.0);
  rig.set(v::kG57, 11.0);
  rig.storage().forget_writes();
  rig.set(v::kG57, 12.0);
  TA_CHECK(rig.storage().written_first >= offsets.first);
  TA_CHECK(rig.storage().written_end <= offsets.end);
  TA_CHECK_EQ(rig.storage().written_bytes, m::KeyedStore::kHeaderBytes + 10 * m::kWorkOffsetCount);

  TA_REQUIRE(rig.unlock());
  rig.set(config.number, config.changed);
  rig.set(config.number, config.other);
  rig.storage().forget_writes();
  rig.set(config.number, config.changed);
  TA_CHECK(rig.storage().written_first >= configuration.first);
  TA_CHECK(rig.storage().written_end <= configuration.end);
  TA_CHECK_EQ(rig.storage().written_bytes, m::KeyedStore::kHeaderBytes + 10 * m::kConfigCount);

  rig.storage().forget_writes();  // the unlock and the arguments are not persistent
  TA_REQUIRE(rig.lock());
  rig.set(v::kArgA, 3.0);
  TA_CHECK_EQ(rig.storage().written_bytes, std::size_t{0});
}

TA_TEST("configuration and work offsets survive a restart; arguments and the unlock do not") {
  ModuleRig rig;
  const t::ConfigVariable config = t::config_variable();
  TA_REQUIRE(rig.unlock());
  rig.set(config.number, config.changed);
  rig.set(v::kG54 + 1, 12.5);
  rig.set(v::kG57 + 1, 42.25);
  rig.set(v::kArgA, 3.0);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(rig.get(config.number), config.changed);
  TA_CHECK_EQ(rig.get(v::kG54 + 1), 12.5);
  TA_CHECK_EQ(rig.get(v::kG57 + 1), 42.25);
  TA_CHECK_EQ(rig.get(v::kArgA), 0.0);
  TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
  TA_CHECK(!rig.module().unlocked());
  TA_CHECK_EQ(rig.put(config.number, config.other), F::kLocked);
}

TA_TEST("a start that cannot read one record loads the others, and a write keeps them") {
  ModuleRig rig;
  const t::ConfigVariable config = t::config_variable();
  TA_REQUIRE(rig.unlock());
  rig.set(config.number, config.changed);
  rig.set(v::kG57, 7.5);
  const t::Region offsets = t::region_of(m::record_key(m::RecordKey::kWorkOffsets));
  rig.storage().unreadable_first = offsets.first;
  rig.storage().unreadable_end = offsets.first + 1;
  TA_CHECK_EQ(rig.start(), Status::kStorageFailure);
  TA_CHECK_EQ(rig.get(config.number), config.changed);  // the configuration record was read
  TA_CHECK_EQ(rig.get(v::kG57), 0.0);                   // the work offsets were not: defaults
  TA_REQUIRE(rig.unlock());
  TA_CHECK_EQ(rig.put(config.number, config.other), F::kNone);  // the configuration still works
  TA_CHECK_EQ(rig.put(v::kG58, 1.0), F::kStorageFailure);       // the unread record refuses
  rig.storage().unreadable_end = 0;
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(rig.get(config.number), config.other);  // not wiped by the write above
  TA_CHECK_EQ(rig.get(v::kG57), 7.5);
}

TA_TEST("a table staged by a macro is committed in a step of its own, once, and survives a restart") {
  ModuleRig rig(with_test_macros());
  const t::TableRecord rec = t::table_record(kTableValues);
  TA_REQUIRE(rig.unlock());
  rig.set(v::kArgA, 1000.0);
  if (rec.key == 0) {  // a set without tables: nothing to stage
    TA_CHECK_EQ(rig.refuse(9902), Status::kStorageFailure);
    return;
  }
  TA_REQUIRE(rig.put(v::kCmd, 9902) == F::kNone);
  rig.storage().forget_writes();
  rig.step();  // the macro: stages the table, publishes nothing yet
  TA_CHECK(rig.busy());
  TA_CHECK_EQ(rig.storage().written_bytes, std::size_t{0});
  TA_CHECK_EQ(rig.get(100), 0.0);
  rig.step();  // the commit: one save of the record, then the results
  TA_CHECK(!rig.busy());
  TA_CHECK_EQ(rig.get(v::kStatus), kDone);
  TA_CHECK_EQ(rig.get(v::kStepCount), 2.0);
  TA_CHECK_EQ(rig.get(100), 1.0);
  const t::Region region = t::region_of(rec.key);
  TA_CHECK(rig.storage().written_first >= region.first);
  TA_CHECK(rig.storage().written_end <= region.end);
  TA_CHECK(rig.storage().written_bytes >= 8 * rec.values);

  TA_REQUIRE(rig.start() == Status::kOk);
  rig.set(v::kArgQ, static_cast<double>(rec.values - 1));
  TA_REQUIRE(rig.done(9903));
  TA_CHECK_EQ(rig.get(100), static_cast<double>(rec.values));
  TA_CHECK_EQ(rig.get(101), 1000.0 + static_cast<double>(rec.values - 1));
  rig.set(v::kArgQ, 0.0);
  TA_REQUIRE(rig.done(9903));
  TA_CHECK_EQ(rig.get(101), 1000.0);
  rig.set(v::kArgA, 3.0);
  TA_CHECK_EQ(rig.refuse(9902), Status::kTableLocked);  // a restart locks again
}

namespace {

// A stored table (1000 + i), then `fail` makes the next store fail; the
// stored bytes, the table and the last results must be as they were.
template <typename Fail>
void store_fails_and_keeps(Fail fail, Status expected) {
  ModuleRig rig(with_test_macros());
  if (t::table_record(kTableValues).key == 0) return;  // a set without tables (the case above)
  TA_REQUIRE(rig.unlock());
  rig.set(v::kArgA, 1000.0);
  TA_REQUIRE(rig.done(9902));
  rig.snapshot();
  fail(rig);
  TA_CHECK_EQ(rig.get(v::kStatus), kError);
  TA_CHECK_EQ(rig.code(), expected);
  TA_CHECK_EQ(rig.get(100), 1.0);  // the last successful macro's result, not this one's
  for (int restart = 0; restart < 2; ++restart) {
    TA_CASE_INDEX(restart);
    TA_CHECK(rig.unchanged());
    rig.set(v::kArgQ, 7.0);
    TA_REQUIRE(rig.done(9903));
    TA_CHECK_EQ(rig.get(101), 1007.0);
    TA_REQUIRE(rig.start() == Status::kOk);
  }
}

}  // namespace

TA_TEST("a table staged while locked is refused with table_locked and commits nothing") {
  store_fails_and_keeps(
      [](ModuleRig& rig) {
        rig.lock();
        rig.set(v::kArgA, 5.0);
        rig.run(9902);
      },
      Status::kTableLocked);
}

TA_TEST("a macro that fails after staging a table commits nothing") {
  store_fails_and_keeps(
      [](ModuleRig& rig) {
        rig.set(v::kArgA, 5.0);
        rig.set(v::kArgQ, 1.0);
        rig.run(9902);
      },
      Status::kArgumentOutOfRange);
}

TA_TEST("a table whose save fails fails the macro with storage_failure and commits nothing") {
  store_fails_and_keeps(
      [](ModuleRig& rig) {
        rig.set(v::kArgA, 5.0);
        TA_REQUIRE(rig.put(v::kCmd, 9902) == F::kNone);
        rig.step();
        rig.storage().refuse = true;
        rig.step();
        rig.storage().refuse = false;
      },
      Status::kStorageFailure);
}

TA_TEST("every built method's portable tests are in this program") {
  for (const char* name : m::BuiltMethods::kNames) {
    if (!t::TestedMethod::registered(name)) {
      trueaxis::test::Line what;
      what.text("no portable tests of method '").text(name).text("' (tests/portable/CMakeLists.txt)");
      trueaxis::test::TestCase::fail(__FILE__, __LINE__, what);
    }
  }
}
