// Access control (module.hpp contract 7), in every module set: one case per
// row of (no unlock, wrong code, right code, timed out, connection closed) x
// (each kind of write that needs the unlock: a configuration variable, the
// unlock code itself, a table a macro stores), plus the back-off's exact
// boundaries, the code's persistence and its secrecy. The transport's half of
// "connection closed" (the TCP server calling lock()) is tested with the
// server (tests/sim/server).
#include <cstdint>

#include "module_rig.hpp"
#include "platform_fixture.hpp"
#include "portable_test.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
using F = trueaxis::macros::AccessFault;
using t::ModuleRig;
using trueaxis::core::Status;

// Stages 16 bytes as the set's first table record (the module commits without
// decoding).
m::MacroStep stage_table(m::PlatformContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(t::table_record(2).key, 16);
  if (bytes == nullptr) return m::done(Status::kTableInvalid);
  for (std::uint8_t i = 0; i < 16; ++i) bytes[i] = i;
  return m::done(Status::kOk);
}
constexpr m::OutputInfo kNoOutputs[] = {{100, "x", "", "unused"}};
constexpr m::MacroInfo kStageMacro[] = {m::macro<&stage_table>(9902, "stage", "stage a record", kNoOutputs)};

// A rig whose clock moves only when the test moves it.
struct Rig : ModuleRig {
  Rig() : ModuleRig(t::RigOptions{}.with_macros(kStageMacro)) { clock.step = 0; }
  // 0 when the table was stored, else the macro's code.
  double run_store() { return run(9902) == t::kDone ? 0.0 : static_cast<double>(code()); }
};

enum class Row { kNoUnlock, kWrongCode, kRightCode, kTimedOut, kConnectionClosed };

void prepare(Rig& rig, Row row) {
  switch (row) {
    case Row::kNoUnlock: break;
    case Row::kWrongCode: TA_CHECK_EQ(rig.put(v::kUnlock, 1234), F::kBadUnlockCode); break;
    case Row::kRightCode: TA_CHECK(rig.unlock()); break;
    case Row::kTimedOut:
      TA_CHECK(rig.unlock());
      rig.clock.now += m::Module::kUnlockIdleUs;  // exactly the idle time after the last write
      break;
    case Row::kConnectionClosed:
      TA_CHECK(rig.unlock());
      rig.module().lock();
      break;
  }
}

}  // namespace

TA_TEST("each row of the unlock states against each kind of protected write") {
  const Row rows[] = {Row::kNoUnlock, Row::kWrongCode, Row::kRightCode, Row::kTimedOut, Row::kConnectionClosed};
  const t::ConfigVariable config = t::config_variable();
  for (int r = 0; r < 5; ++r) {
    TA_CASE_INDEX(r);
    const bool allowed = rows[r] == Row::kRightCode;
    {
      Rig rig;
      prepare(rig, rows[r]);
      rig.snapshot();
      TA_CHECK_EQ(rig.get(v::kUnlock), allowed ? 1.0 : 0.0);
      TA_CHECK_EQ(rig.put(config.number, config.changed), allowed ? F::kNone : F::kLocked);
      TA_CHECK_EQ(rig.get(config.number), allowed ? config.changed : config.default_value);
      if (!allowed) TA_CHECK(rig.unchanged());
    }
    {
      Rig rig;
      prepare(rig, rows[r]);
      TA_CHECK_EQ(rig.put(v::kUnlockCodeSetting, 4321), allowed ? F::kNone : F::kLocked);
      // The code that unlocks afterwards (past any back-off): the new one only when the change was allowed.
      rig.clock.now += m::Module::kMaxBackoffUs;
      TA_REQUIRE(rig.lock());
      TA_CHECK_EQ(rig.put(v::kUnlock, allowed ? 4321 : m::kUnlockCode), F::kNone);
      rig.clock.now += m::Module::kMaxBackoffUs;
      TA_REQUIRE(rig.lock());
      TA_CHECK_EQ(rig.put(v::kUnlock, allowed ? m::kUnlockCode : 4321), F::kBadUnlockCode);
    }
    if (t::table_record(2).key != 0) {
      Rig rig;
      prepare(rig, rows[r]);
      rig.snapshot();
      TA_CHECK_EQ(rig.run_store(), allowed ? 0.0 : static_cast<double>(Status::kTableLocked));
      if (!allowed) TA_CHECK(rig.unchanged());
    }
  }
}

TA_TEST("an unlock closes exactly kUnlockIdleUs after the last write, and a write keeps it open") {
  Rig rig;
  const t::ConfigVariable config = t::config_variable();
  TA_REQUIRE(rig.unlock());
  rig.clock.now += m::Module::kUnlockIdleUs - 1;
  TA_CHECK_EQ(rig.get(v::kUnlock), 1.0);
  TA_REQUIRE(rig.put(v::kArgA, 1.0) == F::kNone);  // any write that succeeds restarts the idle clock
  rig.clock.now += m::Module::kUnlockIdleUs - 1;
  TA_CHECK_EQ(rig.put(config.number, config.changed), F::kNone);
  rig.clock.now += m::Module::kUnlockIdleUs;
  TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
  // A write after the idle time does not reopen it.
  TA_REQUIRE(rig.put(v::kArgA, 1.0) == F::kNone);
  TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
  TA_CHECK_EQ(rig.put(config.number, config.other), F::kLocked);
}

TA_TEST("wrong codes are counted and slowed down: 1 s, doubling, at most 64 s") {
  Rig rig;
  TA_CHECK_EQ(rig.get(v::kFailedUnlocks), 0.0);
  std::uint64_t backoff = 1'000'000;
  for (int k = 1; k <= 9; ++k) {
    TA_CASE_INDEX(k);
    TA_REQUIRE(rig.put(v::kUnlock, 1111) == F::kBadUnlockCode);
    TA_CHECK_EQ(rig.get(v::kFailedUnlocks), static_cast<double>(k));
    // Inside the back-off even the right code is refused (and not counted).
    rig.clock.now += backoff - 1;
    TA_CHECK_EQ(rig.put(v::kUnlock, m::kUnlockCode), F::kUnlockBackoff);
    TA_CHECK_EQ(rig.get(v::kFailedUnlocks), static_cast<double>(k));
    TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
    rig.clock.now += 1;  // exactly at its end: codes are judged again
    backoff = backoff * 2 > m::Module::kMaxBackoffUs ? m::Module::kMaxBackoffUs : backoff * 2;
  }
  TA_CHECK_EQ(backoff, std::uint64_t{64'000'000});
  // Locking is never slowed down; the right code resets the doubling.
  TA_CHECK(rig.lock());
  TA_REQUIRE(rig.unlock());
  TA_REQUIRE(rig.lock());
  TA_REQUIRE(rig.put(v::kUnlock, 1111) == F::kBadUnlockCode);
  rig.clock.now += 1'000'000;
  TA_CHECK(rig.unlock());
}

TA_TEST("a lock during an active back-off is accepted: a wrong code never keeps a controller unlocked") {
  ModuleRig rig;
  const t::ConfigVariable config = t::config_variable();
  TA_REQUIRE(rig.unlock());
  TA_REQUIRE(rig.put(v::kUnlock, 1111) == F::kBadUnlockCode);  // the unlock stays open; a 1 s back-off starts
  TA_CHECK_EQ(rig.get(v::kUnlock), 1.0);
  rig.clock.now += 1;  // inside the back-off
  TA_CHECK_EQ(rig.put(v::kUnlock, m::kUnlockCode), F::kUnlockBackoff);
  TA_CHECK_EQ(rig.put(v::kUnlock, 0.0), F::kNone);
  TA_CHECK_EQ(rig.get(v::kUnlock), 0.0);
  TA_CHECK(!rig.module().unlocked());
  TA_CHECK_EQ(rig.put(config.number, config.changed), F::kLocked);
}

TA_TEST("the unlock code is stored, reads 0, and takes 1..9999") {
  Rig rig;
  TA_REQUIRE(rig.unlock());
  TA_CHECK_EQ(rig.put(v::kUnlockCodeSetting, 0.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kUnlockCodeSetting, 10000.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kUnlockCodeSetting, 77.5), F::kOutOfRange);
  TA_REQUIRE(rig.put(v::kUnlockCodeSetting, 9999.0) == F::kNone);
  TA_CHECK_EQ(rig.get(v::kUnlockCodeSetting), 0.0);
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(rig.put(v::kUnlock, m::kUnlockCode), F::kBadUnlockCode);
  rig.clock.now += 1'000'000;
  TA_CHECK_EQ(rig.put(v::kUnlock, 9999.0), F::kNone);
}
