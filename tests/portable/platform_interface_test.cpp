// One client at a time (module.hpp contract 8), in every module set: who may
// write while another client holds the macro interface, when the interface is
// free again (given back, disconnected, idle: its exact boundary, never while
// the holder's macro runs), what #9009 reads to each client, the lock that is
// taken from anyone, the unlock that closes when the interface changes hands,
// the table stored only under its runner's unlock, and #9011's seconds of
// back-off. The transport's half (each TCP connection its own client, its
// close calling disconnected()) is tested with the server (tests/sim/server).
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

constexpr m::ClientId kA = 7;
constexpr m::ClientId kB = 8;
constexpr std::uint64_t kIdle = m::Module::kInterfaceIdleUs;

// A macro that takes three steps and then stages 16 bytes as the set's first
// table record (the module commits without decoding).
int g_steps_left = 0;
m::MacroStep slow_store(m::PlatformContext& ctx) {
  if (ctx.first_step()) g_steps_left = 3;
  if (--g_steps_left > 0) return m::more();
  std::uint8_t* bytes = ctx.stage_record(t::table_record(2).key, 16);
  if (bytes == nullptr) return m::done(Status::kTableInvalid);
  for (std::uint8_t i = 0; i < 16; ++i) bytes[i] = i;
  return m::done(Status::kOk);
}
constexpr m::OutputInfo kNoOutputs[] = {{100, "x", "", "unused"}};
constexpr m::MacroInfo kSlowMacro[] = {m::macro<&slow_store>(9903, "slow_store", "three steps, then stage a record",
                                                             kNoOutputs)};

// A rig whose clock moves only when the test moves it, written to by clients A and B.
struct Rig : ModuleRig {
  Rig() : ModuleRig(t::RigOptions{}.with_macros(kSlowMacro)) { clock.step = 0; }
  F put_as(m::ClientId c, std::uint16_t n, double value) { return module().write(n, 1, &value, c); }
  double get_as(m::ClientId c, std::uint16_t n) {
    double out = -1.0;
    TA_CHECK_EQ(module().read(n, 1, &out, c), F::kNone);
    return out;
  }
  void step_until_idle() {
    for (int i = 0; i < 16 && module().busy(); ++i) module().step();
  }
};

}  // namespace

TA_TEST("a write while another client holds the interface is refused (interface_held, Modbus 06), changes nothing") {
  Rig rig;
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 0.0);  // free at start
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.5) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 2.0);
  TA_CHECK_EQ(m::modbus_exception(F::kInterfaceHeld), m::ModbusException::kServerDeviceBusy);
  // Every writable kind: an argument, the command, a work offset, #9009 both ways, an unlock code.
  const std::uint16_t numbers[] = {v::kArgX, v::kArgY, v::kCmd, v::kG57, v::kInterface, v::kInterface, v::kUnlock};
  const double values[] = {2.5, 3.0, 9903.0, 10.0, 1.0, 0.0, m::kUnlockCode};
  for (int i = 0; i < 7; ++i) {
    TA_CASE_INDEX(i);
    rig.snapshot();
    TA_CHECK_EQ(rig.put_as(kB, numbers[i], values[i]), F::kInterfaceHeld);
    TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(static_cast<int>(F::kInterfaceHeld)));
    TA_CHECK(rig.unchanged());
  }
  TA_CHECK_EQ(rig.get(v::kArgX), 1.5);
  TA_CHECK_EQ(rig.get(v::kArgY), 0.0);
  TA_CHECK(!rig.module().busy());
  TA_CHECK(!rig.module().unlocked());
  TA_CHECK_EQ(rig.get_as(kB, v::kArgX), 1.5);  // reads stay open
  TA_CHECK_EQ(rig.module().holder(), kA);
  // The holder goes on writing.
  TA_CHECK_EQ(rig.put_as(kA, v::kArgY, 4.0), F::kNone);
}

TA_TEST("the interface is free exactly kInterfaceIdleUs after the holder's last write, and a write keeps it") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
  rig.clock.now += kIdle - 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 2.0), F::kInterfaceHeld);
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 3.0) == F::kNone);  // a write: idle counts from here
  rig.clock.now += kIdle - 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 2.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 2.0);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 0.0);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 2.0), F::kNone);
  TA_CHECK_EQ(rig.module().holder(), kB);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 5.0), F::kInterfaceHeld);
}

TA_TEST("the holder's macro keeps the interface however long it runs; idle counts from its end") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
  rig.clock.now += 10 * kIdle;  // a long macro
  TA_CHECK(rig.module().busy());
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.module().holder(), kA);
  rig.step_until_idle();
  TA_CHECK(!rig.module().busy());
  rig.clock.now += kIdle - 1;  // idle from the macro's end, not from the command
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kInterfaceHeld);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kNone);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 2.0);
}

TA_TEST("#9009: 1 takes the interface, 0 gives it back (the holder's only); disconnected() frees it") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.put_as(kA, v::kInterface, 2.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.module().holder(), kA);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 0.0);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);
  TA_CHECK_EQ(rig.module().holder(), kB);

  rig.module().disconnected(kA);  // another client's disconnection changes nothing
  TA_CHECK_EQ(rig.module().holder(), kB);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 2.0), F::kInterfaceHeld);
  rig.module().disconnected(kB);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 2.0), F::kNone);
}

TA_TEST("a lock alone is taken from anyone; an unlock closes when the interface changes hands or its client leaves") {
  const t::ConfigVariable config = t::config_variable();
  {
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_CHECK_EQ(rig.put_as(kB, v::kUnlock, 0.0), F::kNone);  // the safe direction, from anyone
    TA_CHECK(!rig.module().unlocked());
    TA_CHECK_EQ(rig.module().holder(), kA);  // the lock took nothing
    TA_CHECK_EQ(rig.put_as(kA, config.number, config.changed), F::kLocked);
  }
  {
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);  // given back, still unlocked
    TA_CHECK(rig.module().unlocked());
    // B's configuration write sees A's unlock as closed, and its refusal changes nothing.
    TA_CHECK_EQ(rig.put_as(kB, config.number, config.changed), F::kLocked);
    TA_CHECK(rig.module().unlocked());
    TA_CHECK_EQ(rig.get(config.number), config.default_value);
    TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);  // B takes the interface: A's unlock closes
    TA_CHECK(!rig.module().unlocked());
    TA_REQUIRE(rig.put_as(kB, v::kInterface, 0.0) == F::kNone);
    TA_CHECK_EQ(rig.put_as(kA, config.number, config.changed), F::kLocked);  // closed for good
  }
  {
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
    TA_CHECK_EQ(rig.put_as(kA, config.number, config.changed), F::kNone);  // its own client takes it back
    rig.module().disconnected(kB);
    TA_CHECK(rig.module().unlocked());
    rig.module().disconnected(kA);
    TA_CHECK(!rig.module().unlocked());
  }
}

TA_TEST("a staged table is stored only under the unlock of the client that started its macro") {
  if (t::table_record(2).key == 0) return;  // a set with no table (levelling alone)
  {
    Rig rig;  // the runner's own unlock: stored
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
    rig.step_until_idle();
    TA_CHECK_EQ(rig.get(v::kStatus), t::kDone);
  }
  {
    Rig rig;  // the runner gives the interface back while its macro runs; another unlocks
    TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
    TA_REQUIRE(rig.put_as(kB, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_CHECK(rig.module().unlocked());
    rig.snapshot();
    rig.step_until_idle();
    TA_CHECK_EQ(rig.get(v::kStatus), t::kError);
    TA_CHECK_EQ(rig.code(), Status::kTableLocked);
    TA_CHECK(rig.unchanged());
  }
}

TA_TEST("#9011 reads the seconds of unlock back-off left, rounded up, 0 when a code is taken") {
  Rig rig;
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 0.0);
  TA_REQUIRE(rig.put(v::kUnlock, 1234.0) == F::kBadUnlockCode);
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 1.0);
  rig.clock.now += 999'999;
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 1.0);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 0.0);
  TA_REQUIRE(rig.put(v::kUnlock, 1234.0) == F::kBadUnlockCode);  // the second in a row: 2 s
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 2.0);
  rig.clock.now += 1'000'001;
  TA_CHECK_EQ(rig.get(v::kUnlockBackoffLeft), 1.0);
  TA_CHECK_EQ(rig.put(v::kUnlock, m::kUnlockCode), F::kUnlockBackoff);
}

TA_TEST("a clock behind the holder's last activity keeps the interface held (fail closed)") {
  Rig rig;
  rig.clock.now = 10 * kIdle;
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
  rig.clock.now = 0;  // a clock the contract forbids: behind
  TA_CHECK_EQ(rig.module().holder(), kA);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 2.0), F::kInterfaceHeld);
}
