// One client at a time (module.hpp contract 8), in every module set: which
// writes take the macro interface (arguments, data blocks, #9000, #9015,
// #9018, #9009 = 1) and which take nothing (work offsets, configuration,
// #9004), who may write while another client holds it, how long it is held
// (2 s after a macro or a write; #903 with a session open or after #9009 = 1:
// each boundary exact), when a session opens and ends, what #9009 reads to
// each client, the lock that is accepted from anyone, the unlock that belongs
// to its client and closes when the interface changes hands, the table stored
// only under its runner's unlock, and #9011's seconds of back-off. The
// transport's half (each TCP connection its own client, its close calling
// disconnected()) is tested with the server (tests/sim/server).
#include <cstdint>

#include "method_tests.hpp"
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
constexpr m::ClientId kLocal = m::kLocalClient;  // the rig's own writes, and the recipes'
constexpr std::uint64_t kGrace = m::Module::kInterfaceGraceUs;
constexpr std::uint64_t kIdle = static_cast<std::uint64_t>(m::kDefaultInterfaceIdleS) * 1'000'000;
static_assert(kGrace == 2'000'000 && kIdle == 30'000'000, "the hold times issue 31 names");

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
  // Runs `macro` as `c` to its end (rig.run() is the local client's).
  double run_as(m::ClientId c, std::uint16_t macro) {
    if (put_as(c, v::kCmd, macro) != F::kNone) return -1.0;
    for (int i = 0; i < t::kMaxSteps && module().busy(); ++i) module().step();
    return get(v::kStatus);
  }
};

// The first data block row of the built set (a kReadWrite row at #1000 or
// above), 0 when the set has none.
std::uint16_t first_data_block() {
  for (const m::VarInfo& info : m::kRegisterMap) {
    if (info.access == m::Access::kReadWrite && info.number >= v::kDataFirst) return info.number;
  }
  return 0;
}

}  // namespace

TA_TEST("a write while another client holds the interface is refused (interface_held, Modbus 06), changes nothing") {
  Rig rig;
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 0.0);  // free at start
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.5) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 2.0);
  TA_CHECK_EQ(m::modbus_exception(F::kInterfaceHeld), m::ModbusException::kServerDeviceBusy);
  // Every writable kind: an argument, the command, a work offset, #9009 both
  // ways, an unlock code, a configuration variable; the local client's too.
  const t::ConfigVariable config = t::config_variable();
  const std::uint16_t numbers[] = {v::kArgX, v::kArgY, v::kCmd, v::kG57, v::kInterface, v::kInterface, v::kUnlock,
                                   config.number};
  const double values[] = {2.5, 3.0, 9903.0, 10.0, 1.0, 0.0, m::kUnlockCode, config.changed};
  for (const m::ClientId other : {kB, kLocal}) {
    for (int i = 0; i < 8; ++i) {
      TA_CASE_INDEX(i);
      rig.snapshot();
      TA_CHECK_EQ(rig.put_as(other, numbers[i], values[i]), F::kInterfaceHeld);
      TA_CHECK_EQ(rig.get(v::kAccessFault), static_cast<double>(static_cast<int>(F::kInterfaceHeld)));
      TA_CHECK(rig.unchanged());
    }
  }
  TA_CHECK_EQ(rig.get(v::kArgX), 1.5);
  TA_CHECK_EQ(rig.get(v::kArgY), 0.0);
  TA_CHECK_EQ(rig.get(v::kG57), 0.0);
  TA_CHECK(!rig.module().busy());
  TA_CHECK(!rig.module().unlocked());
  TA_CHECK_EQ(rig.get_as(kB, v::kArgX), 1.5);  // reads stay open
  TA_CHECK_EQ(rig.module().holder(), kA);
  // The holder goes on writing.
  TA_CHECK_EQ(rig.put_as(kA, v::kArgY, 4.0), F::kNone);
}

TA_TEST("an argument, a data block, #9000, #9015, #9018 and #9009 = 1 take the interface") {
  const std::uint16_t data = first_data_block();
  const std::uint16_t numbers[] = {v::kArgA, v::kArgZ, v::kCmd, v::kLogTime, v::kLogSelect, v::kInterface, data};
  const double values[] = {1.0, -2.0, 9903.0, 1.7e9, 1.0, 1.0, 0.5};
  for (int i = 0; i < 7; ++i) {
    if (numbers[i] == 0) continue;  // a set without a data block
    TA_CASE_INDEX(numbers[i]);
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, numbers[i], values[i]) == F::kNone);
    TA_CHECK_EQ(rig.module().holder(), kA);
    TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 2.0);
    TA_CHECK_EQ(rig.put_as(kB, v::kG57, 1.0), F::kInterfaceHeld);
  }
}

TA_TEST("work offsets, configuration and #9004 take nothing: accepted from any client while none holds it") {
  const t::ConfigVariable config = t::config_variable();
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kG57, 1.0) == F::kNone);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 0.0);
  TA_CHECK_EQ(rig.put_as(kB, v::kG57 + 1, 2.0), F::kNone);  // sixteen HMIs' offsets: no one waits
  TA_CHECK_EQ(rig.put_as(kLocal, v::kG58, 3.0), F::kNone);
  TA_CHECK_EQ(rig.get(v::kG57), 1.0);
  TA_CHECK_EQ(rig.get(v::kG57 + 1), 2.0);
  TA_CHECK_EQ(rig.get(v::kG58), 3.0);
  // A's unlock and configuration write take nothing either.
  TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, config.number, config.changed) == F::kNone);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  // A configuration write is taken under its writer's own unlock only.
  TA_CHECK_EQ(rig.put_as(kB, config.number, config.other), F::kLocked);
  TA_CHECK_EQ(rig.get(config.number), config.changed);
  TA_CHECK(rig.module().unlocked());
  TA_CHECK_EQ(rig.put_as(kB, v::kG57, 4.0), F::kNone);  // another's offset leaves A's unlock open
  TA_CHECK(rig.module().unlocked());
  TA_CHECK_EQ(rig.put_as(kB, v::kUnlock, 0.0), F::kNone);  // a lock from anyone
  TA_CHECK(!rig.module().unlocked());
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
}

TA_TEST("without a session the interface is free exactly kInterfaceGraceUs after the holder's last taking write") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
  rig.clock.now += kGrace - 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 2.0), F::kInterfaceHeld);
  TA_REQUIRE(rig.put_as(kA, v::kArgY, 3.0) == F::kNone);  // an argument: the hold counts from here
  rig.clock.now += kGrace - 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kG57, 2.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 2.0);
  TA_REQUIRE(rig.put_as(kA, v::kG57, 3.0) == F::kNone);  // the holder's work offset: accepted, holds no longer
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 0.0);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kB, v::kG57, 2.0), F::kNone);  // takes nothing
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgZ, 2.0), F::kNone);  // takes it
  TA_CHECK_EQ(rig.module().holder(), kB);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 5.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.get(v::kArgZ), 2.0);
}

TA_TEST("a holder's plain writes never keep the interface: work offsets every 1.9 s after one macro") {
  Rig rig;
  TA_REQUIRE(rig.run_as(kA, t::kPrefillMacro) == t::kDone);
  for (int i = 0; i < 10; ++i) {
    rig.clock.now += kGrace - 100'000;
    if (rig.module().holder() != kA) break;
    TA_REQUIRE(rig.put_as(kA, v::kG57, static_cast<double>(i)) == F::kNone);
  }
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);  // the second sync came after the grace
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);
}

TA_TEST("taking over a hold that ran out clears the arguments and data blocks its holder left; giving back does not") {
  const std::uint16_t data = first_data_block();
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kArgZ, 5.0) == F::kNone);  // A writes, runs no macro
  if (data != 0) TA_REQUIRE(rig.put_as(kA, data, 7.0) == F::kNone);
  rig.clock.now += kGrace;
  TA_REQUIRE(rig.put_as(kA, v::kArgY, 1.0) == F::kNone);  // its own again: its inputs stay
  TA_CHECK_EQ(rig.get(v::kArgZ), 5.0);
  rig.clock.now += kGrace;
  TA_REQUIRE(rig.put_as(kB, v::kArgX, 2.0) == F::kNone);  // B takes it: A's inputs are not B's
  TA_CHECK_EQ(rig.get(v::kArgX), 2.0);
  TA_CHECK_EQ(rig.get(v::kArgY), 0.0);
  TA_CHECK_EQ(rig.get(v::kArgZ), 0.0);
  if (data != 0) TA_CHECK_EQ(rig.get(data), 0.0);
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 0.0) == F::kNone);  // given back: B's stay, for its next connection
  TA_CHECK_EQ(rig.get(v::kArgX), 2.0);
  rig.module().disconnected(kB);
  TA_REQUIRE(rig.put_as(kA, v::kArgY, 4.0) == F::kNone);  // one variable a connection, as mbpoll writes
  TA_CHECK_EQ(rig.get(v::kArgX), 2.0);
  TA_CHECK_EQ(rig.get(v::kArgY), 4.0);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
  rig.step_until_idle();
  TA_REQUIRE(rig.run_as(kB, t::kPrefillMacro) == t::kDone);  // any macro's end clears them
  TA_CHECK_EQ(rig.get(v::kArgX), 0.0);
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 0.0) == F::kNone);
  // A running macro keeps its inputs when its runner gives the interface back.
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 3.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
  TA_CHECK_EQ(rig.get(v::kArgX), 3.0);
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 1.0) == F::kNone);  // B takes it while A's macro runs
  TA_CHECK_EQ(rig.get(v::kArgX), 3.0);
  rig.step_until_idle();
  TA_CHECK_EQ(rig.get(v::kArgX), 0.0);  // the macro's end clears them, as after every macro
}

TA_TEST("a hold that ended stays ended, and one that runs keeps its length: #903 changed meanwhile") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
  rig.clock.now += kIdle;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_REQUIRE(rig.unlock());
  TA_REQUIRE(rig.put(v::kInterfaceIdleLimit, 600.0) == F::kNone);  // A's hold ended: raising #903 revives none
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 0.0) == F::kNone);
  TA_REQUIRE(rig.unlock());
  TA_REQUIRE(rig.put(v::kInterfaceIdleLimit, 5.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);  // held for 5 s
  TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kInterfaceIdleLimit, 600.0) == F::kNone);  // the holder raises it: its hold stays 5 s
  rig.clock.now += 5'000'000 - 1;
  TA_CHECK_EQ(rig.module().holder(), kA);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
}

TA_TEST("a macro's end extends only its runner's hold, not another client's that took it meanwhile") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);  // the runner lets go while its macro runs
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 1.0) == F::kNone);  // B takes it for #903
  rig.clock.now += kIdle - 1;
  rig.step_until_idle();  // A's macro ends now
  TA_CHECK_EQ(rig.module().holder(), kB);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);  // B's hold counted from its own write
}

TA_TEST("the holder's macro keeps the interface however long it runs; the grace counts from its end") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kCmd, 9903.0) == F::kNone);
  rig.clock.now += 10 * kIdle;  // a long macro
  TA_CHECK(rig.module().busy());
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.put_as(kB, v::kG57, 1.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.module().holder(), kA);
  rig.step_until_idle();
  TA_CHECK(!rig.module().busy());
  rig.clock.now += kGrace - 1;  // time to read its results, from the macro's end, not from the command
  TA_CHECK_EQ(rig.put_as(kB, v::kCmd, 9903.0), F::kInterfaceHeld);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kNone);
  TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 2.0);
}

TA_TEST("#9009 = 1 holds up to #903 after the last write; 0 gives it back at once; disconnected() frees it") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 1.0);
  TA_CHECK_EQ(rig.put_as(kB, v::kInterface, 1.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.put_as(kA, v::kInterface, 2.0), F::kOutOfRange);
  rig.clock.now += kIdle - 1;
  TA_CHECK_EQ(rig.put_as(kB, v::kG57, 1.0), F::kInterfaceHeld);
  TA_REQUIRE(rig.run_as(kA, t::kPrefillMacro) == t::kDone);  // a macro's end counts as activity too
  rig.clock.now += kIdle - 1;
  TA_CHECK_EQ(rig.module().holder(), kA);
  rig.clock.now += 1;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);

  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
  TA_CHECK_EQ(rig.get_as(kA, v::kInterface), 0.0);
  TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);
  TA_CHECK_EQ(rig.module().holder(), kB);
  TA_CHECK_EQ(rig.put_as(kA, v::kInterface, 0.0), F::kInterfaceHeld);  // only the holder gives it back
  TA_CHECK_EQ(rig.module().holder(), kB);

  rig.module().disconnected(kA);  // another client's disconnection changes nothing
  TA_CHECK_EQ(rig.module().holder(), kB);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 2.0), F::kInterfaceHeld);
  rig.module().disconnected(kB);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.put_as(kA, v::kArgX, 2.0), F::kNone);
  // A holder by #9009 = 1 whose hold ran out takes it again with an argument: the grace only.
  TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
  rig.clock.now += kIdle;
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 3.0) == F::kNone);
  rig.clock.now += kGrace;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
}

TA_TEST("#903 sets the session-length hold, 5..600 s, exactly") {
  Rig rig;
  TA_CHECK_EQ(rig.get(v::kInterfaceIdleLimit), m::kDefaultInterfaceIdleS);
  TA_REQUIRE(rig.unlock());
  TA_CHECK_EQ(rig.put(v::kInterfaceIdleLimit, 4.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kInterfaceIdleLimit, 601.0), F::kOutOfRange);
  TA_CHECK_EQ(rig.put(v::kInterfaceIdleLimit, 7.5), F::kOutOfRange);
  for (const double seconds : {5.0, 600.0}) {
    TA_CASE_INDEX(seconds);
    TA_REQUIRE(rig.unlock());  // A's taking the interface closed the last one
    TA_REQUIRE(rig.put(v::kInterfaceIdleLimit, seconds) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
    rig.clock.now += static_cast<std::uint64_t>(seconds) * 1'000'000 - 1;
    TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kInterfaceHeld);
    rig.clock.now += 1;
    TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
    rig.module().disconnected(kA);
  }
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
}

TA_TEST("a client's open session holds the interface up to #903 after its last write, until its compute succeeds") {
  std::size_t sessions = 0;
  for (std::size_t k = 0; k < m::BuiltMethods::kCount; ++k) {
    const m::SessionInfo& session = m::BuiltMethods::kSessions[k];
    if (session.capacity == 0) continue;
    ++sessions;
    TA_CASE_INDEX(session.compute);
    const t::Recipe* compute = t::RecipeEntry::find(session.compute);
    TA_REQUIRE(compute != nullptr);
    Rig rig;
    TA_REQUIRE(rig.done(session.clear));  // the local client's session
    rig.clock.now += kIdle - 1;            // probing between two adds
    TA_CHECK_EQ(rig.put_as(kB, v::kCmd, 9903.0), F::kInterfaceHeld);
    TA_CHECK_EQ(rig.put_as(kB, v::kG57, 1.0), F::kInterfaceHeld);
    TA_CHECK_EQ(rig.get_as(kLocal, v::kInterface), 1.0);
    TA_CHECK_EQ(rig.refuse(session.compute) != Status::kOk, true);  // empty: refused, the session kept
    rig.clock.now += kIdle - 1;
    TA_CHECK_EQ(rig.put_as(kB, v::kG57, 1.0), F::kInterfaceHeld);
    rig.clock.now += 1;
    TA_CHECK_EQ(rig.get_as(kB, v::kInterface), 0.0);  // idle past #903: free, the session's data kept
    // The session's client goes on (the recipe clears and adds again) and computes.
    if (compute->prepare != nullptr) compute->prepare(rig);
    if (compute->arguments != nullptr) compute->arguments(rig);
    TA_REQUIRE(rig.done(session.compute));
    rig.clock.now += kGrace - 1;  // the compute's success ends the session: the grace only
    TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kInterfaceHeld);
    rig.clock.now += 1;
    TA_CHECK_EQ(rig.put_as(kB, v::kArgX, 1.0), F::kNone);
    TA_CHECK_EQ(rig.module().holder(), kB);
  }
  TA_CHECK(sessions > 0);
}

TA_TEST("every macro that computes from a session ends it for the hold: compute, compute_also and check") {
  for (std::size_t k = 0; k < m::BuiltMethods::kCount; ++k) {
    const m::SessionInfo& session = m::BuiltMethods::kSessions[k];
    if (session.capacity == 0) continue;
    const std::uint16_t closing[] = {session.compute, session.compute_also, m::BuiltMethods::kChecks[k].macro};
    for (const std::uint16_t macro : closing) {
      if (macro == 0) continue;
      TA_CASE_INDEX(macro);
      const t::Recipe* recipe = t::RecipeEntry::find(macro);
      TA_REQUIRE(recipe != nullptr);
      Rig rig;
      if (recipe->prepare != nullptr) recipe->prepare(rig);
      TA_REQUIRE(rig.done(session.clear));  // the session open right before it, whatever the recipe left
      if (recipe->prepare != nullptr) recipe->prepare(rig);
      if (recipe->arguments != nullptr) recipe->arguments(rig);
      TA_REQUIRE(rig.done(macro));
      rig.clock.now += kGrace - 1;
      TA_CHECK_EQ(rig.module().holder(), kLocal);
      rig.clock.now += 1;
      TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
    }
  }
}

TA_TEST("a session ends for its client when another client clears it, or when it gives the interface back") {
  for (std::size_t k = 0; k < m::BuiltMethods::kCount; ++k) {
    const m::SessionInfo& session = m::BuiltMethods::kSessions[k];
    if (session.capacity == 0) continue;
    TA_CASE_INDEX(session.clear);
    {
      Rig rig;
      TA_REQUIRE(rig.run_as(kA, session.clear) == t::kDone);
      rig.clock.now += kIdle;
      TA_REQUIRE(rig.run_as(kB, session.clear) == t::kDone);  // B's session now
      rig.clock.now += kIdle;
      TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);  // A comes back: no session of its own
      rig.clock.now += kGrace;
      TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
      TA_REQUIRE(rig.put_as(kB, v::kArgX, 1.0) == F::kNone);  // B's is open: the long hold
      rig.clock.now += kIdle - 1;
      TA_CHECK_EQ(rig.module().holder(), kB);
    }
    {
      Rig rig;
      TA_REQUIRE(rig.run_as(kA, session.clear) == t::kDone);
      TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);
      TA_CHECK_EQ(rig.module().holder(), m::kNoClient);  // at once
      TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
      rig.clock.now += kGrace;
      TA_CHECK_EQ(rig.module().holder(), m::kNoClient);  // the claim went with it
    }
    {
      Rig rig;
      TA_REQUIRE(rig.run_as(kA, session.clear) == t::kDone);
      rig.module().disconnected(kA);
      TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);  // the same number, a new connection
      rig.clock.now += kGrace;
      TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
    }
  }
}

TA_TEST("a clear of one arena session ends the claims on the others, whose data it replaced") {
  std::size_t arena[2] = {0, 0};
  std::size_t found = 0;
  for (std::size_t k = 0; k < m::BuiltMethods::kCount; ++k) {
    if (m::BuiltMethods::kSessionInArena[k] && found < 2) arena[found++] = k;
  }
  if (found < 2) return;  // a set with fewer than two arena sessions
  const std::size_t first = arena[0];
  const std::size_t second = arena[1];
  Rig rig;
  TA_REQUIRE(rig.run_as(kA, m::BuiltMethods::kSessions[first].clear) == t::kDone);
  rig.clock.now += kGrace;
  TA_CHECK_EQ(rig.module().holder(), kA);  // its session open
  rig.clock.now += kIdle;
  TA_REQUIRE(rig.run_as(kB, m::BuiltMethods::kSessions[second].clear) == t::kDone);  // replaces A's in the arena
  TA_REQUIRE(rig.put_as(kB, v::kInterface, 0.0) == F::kNone);
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);  // A has no session any more: the grace only
  rig.clock.now += kGrace;
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
}

TA_TEST("a lock alone is accepted from anyone; an unlock closes when the interface changes hands or its client leaves") {
  const t::ConfigVariable config = t::config_variable();
  {
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_CHECK_EQ(rig.put_as(kB, v::kUnlock, 0.0), F::kNone);  // the safe direction, from anyone
    TA_CHECK(!rig.module().unlocked());
    TA_CHECK_EQ(rig.module().holder(), kA);  // the lock took nothing
    TA_CHECK_EQ(rig.put_as(kA, config.number, config.changed), F::kLocked);
  }
  {
    Rig rig;
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 1.0) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    TA_REQUIRE(rig.put_as(kA, v::kInterface, 0.0) == F::kNone);  // given back, still unlocked
    TA_CHECK(rig.module().unlocked());
    // B's configuration write is not under its own unlock, and its refusal changes nothing.
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
    TA_CHECK_EQ(rig.put_as(kA, config.number, config.changed), F::kNone);
    rig.module().disconnected(kB);
    TA_CHECK(rig.module().unlocked());
    rig.module().disconnected(kA);
    TA_CHECK(!rig.module().unlocked());
  }
  {
    Rig rig;  // an unlock closes kUnlockIdleUs after its own client's last write, whoever else writes
    TA_REQUIRE(rig.put_as(kA, v::kUnlock, m::kUnlockCode) == F::kNone);
    rig.clock.now += m::Module::kUnlockIdleUs - 1;
    TA_REQUIRE(rig.put_as(kB, v::kG57, 1.0) == F::kNone);
    TA_CHECK(rig.module().unlocked());
    rig.clock.now += 1;
    TA_CHECK(!rig.module().unlocked());
  }
}

TA_TEST("the controller's own writes (Module::write naming no client) follow the same rule") {
  Rig rig;
  TA_REQUIRE(rig.put_as(kA, v::kArgX, 1.0) == F::kNone);
  TA_CHECK_EQ(rig.put(v::kG57, 5.0), F::kInterfaceHeld);
  TA_CHECK_EQ(rig.put(v::kCmd, 9903.0), F::kInterfaceHeld);
  rig.clock.now += kGrace;
  TA_CHECK_EQ(rig.put(v::kG57, 5.0), F::kNone);
  TA_CHECK_EQ(rig.module().holder(), m::kNoClient);
  TA_CHECK_EQ(rig.run(t::kPrefillMacro), t::kDone);
  TA_CHECK_EQ(rig.module().holder(), kLocal);
  TA_CHECK_EQ(rig.put_as(kA, v::kG57, 1.0), F::kInterfaceHeld);
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
