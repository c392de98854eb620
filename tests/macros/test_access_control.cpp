// Access control (module.hpp contract 7), one case per row of
// (no unlock, wrong code, right code, timed out, connection closed) x (each kind
// of write that needs the unlock: a configuration variable, the unlock code
// itself, a table a macro stores), plus the back-off's exact boundaries, the
// code's persistence and its secrecy. The transport's half of "connection
// closed" (the TCP server calling lock()) is tested with the server.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>

#include "fakes.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;
using F = trueaxis::macros::AccessFault;

// A test macro that stages a small spindle-model record (any bytes: the module
// commits without decoding).
m::MacroStep stage_table(m::PlatformContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(m::spindle::ModelRecord::kRecord.key, 16);
  if (bytes == nullptr) return m::done(Status::kTableInvalid);
  for (std::uint8_t i = 0; i < 16; ++i) bytes[i] = i;
  return m::done(Status::kOk);
}
constexpr m::OutputInfo kNoOutputs[] = {{100, "x", "", "unused"}};
const m::MacroInfo kStageMacro[] = {m::macro<&stage_table>(9990, "stage", "stage a record", kNoOutputs)};

struct Rig {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  m::Module module{storage, clock, kStageMacro, 1};
  Rig() {
    clock.step = 0;  // time moves only when a test moves it
    REQUIRE(module.start() == Status::kOk);
  }
  F put(std::uint16_t n, double value) { return module.write(n, 1, &value); }
  double get(std::uint16_t n) {
    double value = -1;
    REQUIRE(module.read(n, 1, &value) == F::kNone);
    return value;
  }
  double run_store() {
    REQUIRE(put(v::kCmd, 9990) == F::kNone);
    for (int i = 0; i < 10 && module.busy(); ++i) module.step();
    return get(v::kStatus) == 2.0 ? 0.0 : get(v::kError);
  }
};

enum class Row { kNoUnlock, kWrongCode, kRightCode, kTimedOut, kConnectionClosed };

void prepare(Rig& rig, Row row) {
  switch (row) {
    case Row::kNoUnlock: break;
    case Row::kWrongCode: CHECK(rig.put(v::kUnlock, 1234) == F::kBadUnlockCode); break;
    case Row::kRightCode: REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone); break;
    case Row::kTimedOut:
      REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
      rig.clock.now += m::Module::kUnlockIdleUs;  // exactly the idle time after the last write
      break;
    case Row::kConnectionClosed:
      REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
      rig.module.lock();
      break;
  }
}

}  // namespace

TEST_CASE("each row of the unlock states against each kind of protected write", "[module][access]") {
  const Row rows[] = {Row::kNoUnlock, Row::kWrongCode, Row::kRightCode, Row::kTimedOut, Row::kConnectionClosed};
  const char* names[] = {"no unlock", "wrong code", "right code", "timed out", "connection closed"};
  for (int r = 0; r < 5; ++r) {
    const bool allowed = rows[r] == Row::kRightCode;
    INFO(names[r]);
    {
      Rig rig;
      prepare(rig, rows[r]);
      const auto before = rig.storage.bytes;
      CHECK(rig.get(v::kUnlock) == (allowed ? 1.0 : 0.0));
      CHECK(rig.put(v::kAMin, -90.0) == (allowed ? F::kNone : F::kLocked));
      CHECK(rig.get(v::kAMin) == (allowed ? -90.0 : -120.0));
      if (!allowed) CHECK(rig.storage.bytes == before);
    }
    {
      Rig rig;
      prepare(rig, rows[r]);
      CHECK(rig.put(v::kUnlockCodeSetting, 4321) == (allowed ? F::kNone : F::kLocked));
      // The code that unlocks afterwards (past any back-off): the new one only when the change was allowed.
      rig.clock.now += m::Module::kMaxBackoffUs;
      REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
      CHECK(rig.put(v::kUnlock, allowed ? 4321 : m::kUnlockCode) == F::kNone);
      rig.clock.now += m::Module::kMaxBackoffUs;
      REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
      CHECK(rig.put(v::kUnlock, allowed ? m::kUnlockCode : 4321) == F::kBadUnlockCode);
    }
    {
      Rig rig;
      prepare(rig, rows[r]);
      const auto before = rig.storage.bytes;
      CHECK(rig.run_store() == (allowed ? 0.0 : static_cast<double>(Status::kTableLocked)));
      if (!allowed) CHECK(rig.storage.bytes == before);
    }
  }
}

TEST_CASE("an unlock closes exactly kUnlockIdleUs after the last write, and a write keeps it open", "[module][access]") {
  Rig rig;
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  rig.clock.now += m::Module::kUnlockIdleUs - 1;
  CHECK(rig.get(v::kUnlock) == 1.0);
  REQUIRE(rig.put(v::kArgA, 1.0) == F::kNone);  // any write that succeeds restarts the idle clock
  rig.clock.now += m::Module::kUnlockIdleUs - 1;
  CHECK(rig.put(v::kAMin, -100.0) == F::kNone);
  rig.clock.now += m::Module::kUnlockIdleUs;
  CHECK(rig.get(v::kUnlock) == 0.0);
  // A write after the idle time does not reopen it.
  REQUIRE(rig.put(v::kArgA, 1.0) == F::kNone);
  CHECK(rig.get(v::kUnlock) == 0.0);
  CHECK(rig.put(v::kAMin, -90.0) == F::kLocked);
}

TEST_CASE("wrong codes are counted and slowed down: 1 s, doubling, at most 64 s", "[module][access]") {
  Rig rig;
  CHECK(rig.get(v::kFailedUnlocks) == 0.0);
  std::uint64_t backoff = 1'000'000;
  for (int k = 1; k <= 9; ++k) {
    INFO("wrong code " << k);
    REQUIRE(rig.put(v::kUnlock, 1111) == F::kBadUnlockCode);
    CHECK(rig.get(v::kFailedUnlocks) == k);
    // Inside the back-off even the right code is refused (and not counted).
    rig.clock.now += backoff - 1;
    CHECK(rig.put(v::kUnlock, m::kUnlockCode) == F::kUnlockBackoff);
    CHECK(rig.get(v::kFailedUnlocks) == k);
    CHECK(rig.get(v::kUnlock) == 0.0);
    rig.clock.now += 1;  // exactly at its end: codes are judged again
    backoff = backoff * 2 > m::Module::kMaxBackoffUs ? m::Module::kMaxBackoffUs : backoff * 2;
  }
  CHECK(backoff == 64'000'000);
  // Locking is never slowed down; the right code resets the doubling.
  CHECK(rig.put(v::kUnlock, 0.0) == F::kNone);
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  REQUIRE(rig.put(v::kUnlock, 0.0) == F::kNone);
  REQUIRE(rig.put(v::kUnlock, 1111) == F::kBadUnlockCode);
  rig.clock.now += 1'000'000;
  CHECK(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
}

TEST_CASE("the unlock code is stored, reads 0, and takes 1..9999", "[module][access]") {
  Rig rig;
  REQUIRE(rig.put(v::kUnlock, m::kUnlockCode) == F::kNone);
  CHECK(rig.put(v::kUnlockCodeSetting, 0.0) == F::kOutOfRange);
  CHECK(rig.put(v::kUnlockCodeSetting, 10000.0) == F::kOutOfRange);
  CHECK(rig.put(v::kUnlockCodeSetting, 77.5) == F::kOutOfRange);
  REQUIRE(rig.put(v::kUnlockCodeSetting, 9999.0) == F::kNone);
  CHECK(rig.get(v::kUnlockCodeSetting) == 0.0);
  m::Module second(rig.storage, rig.clock);
  REQUIRE(second.start() == Status::kOk);
  const double published = m::kUnlockCode;
  CHECK(second.write(v::kUnlock, 1, &published) == F::kBadUnlockCode);
  rig.clock.now += 1'000'000;
  const double code = 9999.0;
  CHECK(second.write(v::kUnlock, 1, &code) == F::kNone);
}
