// The platform under the methods, as the controller sees it, on the host and on
// the Cortex-M7: a session that refuses a sample at capacity, 9811 at its
// documented maximum, inputs cleared after every macro, a macro that takes
// several steps, and a table staged by a macro that survives a restart and is
// refused while locked.
#include <cstdint>

#include "fakes.hpp"
#include "portable_test.hpp"
#include "static_slot.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/record_codec.hpp"

namespace {

namespace m = trueaxis::macros;
namespace var = trueaxis::macros::var;
using trueaxis::core::Status;
using trueaxis::macros::AccessFault;
using trueaxis::macros::Module;

std::uint8_t g_bytes[m::kRequiredStorageBytes];
trueaxis::test::StaticSlot<Module> g_slots[2];  // modules live in static storage (static_slot.hpp)

void blank_storage() {
  for (std::uint8_t& b : g_bytes) b = 0;
}

int g_steps = 0;
m::MacroStep four_steps(m::PlatformContext& ctx) {
  if (ctx.first_step()) g_steps = 0;
  return ++g_steps < 4 ? m::more() : m::done(Status::kOk);
}

constexpr std::size_t kValues = 300;
m::MacroStep stage_300(m::PlatformContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(m::RigidityTableRecord::kRecord.key, 8 * kValues);
  if (bytes == nullptr) return m::done(Status::kStorageFailure);
  for (std::size_t i = 0; i < kValues; ++i) m::put_f64(bytes + 8 * i, ctx.in<var::kArgA>() * static_cast<double>(i));
  return m::done(Status::kOk);
}

std::uint8_t g_record[m::kMaxRecordPayloadBytes];
m::MacroStep read_back(m::PlatformContext& ctx) {
  std::size_t length = 0;
  const Status s = ctx.load_record(m::RigidityTableRecord::kRecord.key, g_record, sizeof g_record, length);
  if (s != Status::kOk) return m::done(s);
  ctx.out<100>(static_cast<double>(length / 8));
  ctx.out<101>(length >= 8 * kValues ? m::get_f64(g_record + 8 * (kValues - 1)) : -1.0);
  return m::done(Status::kOk);
}

constexpr m::OutputInfo kOut[] = {{100, "n", "", "test"}, {101, "last", "", "test"}};
constexpr m::MacroInfo kExtra[] = {
    m::macro<&four_steps>(9901, "four_steps", "", kOut),
    m::macro<&stage_300>(9902, "stage_300", "", kOut),
    m::macro<&read_back>(9903, "read_back", "", kOut),
};

double read1(Module& mod, std::uint16_t n) {
  double v = -12345.0;
  static_cast<void>(mod.read(n, 1, &v));
  return v;
}
AccessFault write1(Module& mod, std::uint16_t n, double v) { return mod.write(n, 1, &v); }

// Runs a macro to its end; the status (#9001), or -1 when it stays busy.
double run(Module& mod, double macro) {
  if (write1(mod, var::kCmd, macro) != AccessFault::kNone) return -1.0;
  for (int i = 0; i < 20 && mod.busy(); ++i) mod.step();
  return mod.busy() ? -1.0 : read1(mod, var::kStatus);
}

constexpr double kDone = 2.0;
constexpr double kError = 3.0;

}  // namespace

TA_TEST("the leveling session refuses a point at its capacity and keeps the others") {
  blank_storage();
  trueaxis::hal::RamNvStorage storage(g_bytes, sizeof g_bytes);
  trueaxis::test::FakeClock clock;
  Module& mod = g_slots[0].emplace(storage, clock);
  TA_REQUIRE(mod.start() == Status::kOk);
  TA_REQUIRE(run(mod, 9812) == kDone);
  for (std::size_t k = 0; k < m::level::kSessionCapacity; ++k) {
    const double p[3] = {10.0 * static_cast<double>(k % 8), 10.0 * static_cast<double>(k / 8), 0.5 * static_cast<double>(k % 8)};
    TA_REQUIRE(mod.write(var::kArgX, 3, p) == AccessFault::kNone);
    TA_REQUIRE(run(mod, 9813) == kDone);
  }
  TA_CHECK_EQ(read1(mod, var::kLevelSessionCount), static_cast<double>(m::level::kSessionCapacity));
  const double extra[3] = {1.0, 2.0, 3.0};
  TA_REQUIRE(mod.write(var::kArgX, 3, extra) == AccessFault::kNone);
  TA_CHECK_EQ(run(mod, 9813), kError);
  TA_CHECK_EQ(read1(mod, var::kError), static_cast<double>(Status::kSessionFull));
  TA_CHECK_EQ(read1(mod, var::kLevelSessionCount), static_cast<double>(m::level::kSessionCapacity));
  TA_CHECK_EQ(run(mod, 9814), kDone);
  TA_CHECK_EQ(read1(mod, var::kLevelPointCount), static_cast<double>(m::level::kSessionCapacity));
  TA_CHECK_NEAR(read1(mod, var::kLevelTilt), 2.862405226111748, 1e-12);  // atan(0.05)
}

TA_TEST("9811 levels through Q = 32 points and clears the whole point list after") {
  blank_storage();
  trueaxis::hal::RamNvStorage storage(g_bytes, sizeof g_bytes);
  trueaxis::test::FakeClock clock;
  Module& mod = g_slots[0].emplace(storage, clock);
  TA_REQUIRE(mod.start() == Status::kOk);
  for (std::uint16_t k = 0; k < 32; ++k) {
    const double y = 10.0 * static_cast<double>(k / 8) + static_cast<double>(k % 3);
    const double p[3] = {10.0 * static_cast<double>(k % 8), y, 0.25 * y};
    TA_REQUIRE(mod.write(static_cast<std::uint16_t>(var::kPointList + 3 * k), 3, p) == AccessFault::kNone);
  }
  TA_REQUIRE(write1(mod, var::kArgQ, 32.0) == AccessFault::kNone);
  TA_CHECK_EQ(run(mod, 9811), kDone);
  TA_CHECK_EQ(read1(mod, var::kLevelPointCount), 32.0);
  TA_CHECK_NEAR(read1(mod, var::kLevelTilt), 14.036243467926479, 1e-12);  // atan(0.25)
  for (std::uint16_t k = 0; k < var::kPointListCount; ++k) {
    TA_CASE_INDEX(k);
    TA_CHECK_EQ(read1(mod, static_cast<std::uint16_t>(var::kPointList + k)), 0.0);
  }
  TA_CHECK_EQ(read1(mod, var::kArgQ), 0.0);
}

TA_TEST("a macro of four steps stays busy for three and refuses a command meanwhile") {
  blank_storage();
  trueaxis::hal::RamNvStorage storage(g_bytes, sizeof g_bytes);
  trueaxis::test::FakeClock clock;
  Module& mod = g_slots[0].emplace(storage, clock, kExtra, std::size_t{3});
  TA_REQUIRE(mod.start() == Status::kOk);
  TA_REQUIRE(write1(mod, var::kCmd, 9901.0) == AccessFault::kNone);
  for (int i = 0; i < 3; ++i) {
    mod.step();
    TA_CHECK(mod.busy());
    TA_CHECK_EQ(write1(mod, var::kCmd, 9810.0), AccessFault::kBusy);
  }
  mod.step();
  TA_CHECK(!mod.busy());
  TA_CHECK_EQ(read1(mod, var::kStatus), kDone);
  TA_CHECK_EQ(read1(mod, var::kStepCount), 4.0);
}

TA_TEST("a 300-value table staged by a macro survives a restart; locked, it is refused") {
  blank_storage();
  trueaxis::hal::RamNvStorage storage(g_bytes, sizeof g_bytes);
  trueaxis::test::FakeClock clock;
  {
    Module& first = g_slots[0].emplace(storage, clock, kExtra, std::size_t{3});
    TA_REQUIRE(first.start() == Status::kOk);
    TA_REQUIRE(write1(first, var::kArgA, 2.0) == AccessFault::kNone);
    TA_CHECK_EQ(run(first, 9902), kError);  // locked
    TA_CHECK_EQ(read1(first, var::kError), static_cast<double>(Status::kTableLocked));
    TA_REQUIRE(write1(first, var::kUnlock, m::kUnlockCode) == AccessFault::kNone);
    TA_REQUIRE(write1(first, var::kArgA, 2.0) == AccessFault::kNone);
    TA_CHECK_EQ(run(first, 9902), kDone);
    TA_CHECK_EQ(read1(first, var::kStepCount), 2.0);  // the macro, then the commit
  }
  Module& second = g_slots[1].emplace(storage, clock, kExtra, std::size_t{3});
  TA_REQUIRE(second.start() == Status::kOk);
  TA_CHECK_EQ(run(second, 9903), kDone);
  TA_CHECK_EQ(read1(second, 100), 300.0);
  TA_CHECK_EQ(read1(second, 101), 2.0 * 299.0);
  TA_REQUIRE(write1(second, var::kArgA, 3.0) == AccessFault::kNone);
  TA_CHECK_EQ(run(second, 9902), kError);  // a restart locks again
  TA_CHECK_EQ(run(second, 9903), kDone);
  TA_CHECK_EQ(read1(second, 101), 2.0 * 299.0);
}
