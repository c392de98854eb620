// The macro layer as a controller drives it: variables written through
// VariableAccess, macro 9810 run by writing #9000, results and the handshake read
// back; the configuration's lock and its persistence over a restart.
#include <cstdint>

#include "fixtures.hpp"
#include "portable_test.hpp"
#include "static_slot.hpp"
#include "fakes.hpp"
#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

using trueaxis::core::Status;
using trueaxis::macros::AccessFault;
using trueaxis::macros::MacroState;
using trueaxis::macros::Module;
namespace var = trueaxis::macros::var;

constexpr std::size_t kStorageBytes = trueaxis::macros::kRequiredStorageBytes;

// One device's bytes: static, so a Bench fits the target's stack.
std::uint8_t g_storage_bytes[kStorageBytes];

trueaxis::test::StaticSlot<Module> g_module_slots[2];

// A fresh device: storage, clock and a started module, as main would own them
// (the module in static storage: see static_slot.hpp).
struct Bench {
  trueaxis::hal::RamNvStorage storage{g_storage_bytes, kStorageBytes};
  trueaxis::test::FakeClock clock;
  Module& module = g_module_slots[0].emplace(storage, clock);

  Bench() {
    for (std::uint8_t& b : g_storage_bytes) b = 0;
    static_cast<void>(module.start());
  }
};

AccessFault write1(Module& m, std::uint16_t number, double value) { return m.write(number, 1, &value); }

double read1(Module& m, std::uint16_t number) {
  double v = -12345.0;
  static_cast<void>(m.read(number, 1, &v));
  return v;
}

bool write_point(Module& m, std::uint16_t x_number, const trueaxis::core::Vec3& p) {
  const double xyz[3] = {p.x(), p.y(), p.z()};
  return m.write(x_number, 3, xyz) == AccessFault::kNone;
}

// Writes the three points and the probe pose, runs macro 9810 and returns #9001.
double run_9810(Module& m, const trueaxis::core::Vec3 (&points)[3], double a_deg, double c_deg,
                const trueaxis::core::Vec3& hint) {
  const double ijk[3] = {hint.x(), hint.y(), hint.z()};
  if (!write_point(m, var::kG57, points[0]) || !write_point(m, var::kG58, points[1]) ||
      !write_point(m, var::kG59, points[2]) || write1(m, var::kArgA, a_deg) != AccessFault::kNone ||
      write1(m, var::kArgC, c_deg) != AccessFault::kNone ||
      m.write(var::kArgI, 3, ijk) != AccessFault::kNone || write1(m, var::kCmd, 9810.0) != AccessFault::kNone) {
    return -1.0;
  }
  m.step();
  return read1(m, var::kStatus);
}

// Axis signs, and a perfect probe: exactness is the property these cases check
// (under probe noise a face tilted less than the noise is left at A = 0).
bool set_signs(Module& m, double a_sign, double c_sign) {
  return write1(m, var::kUnlock, trueaxis::macros::kUnlockCode) == AccessFault::kNone &&
         write1(m, var::kASign, a_sign) == AccessFault::kNone && write1(m, var::kCSign, c_sign) == AccessFault::kNone &&
         write1(m, var::kProbeSigma, 0.0) == AccessFault::kNone && write1(m, var::kUnlock, 0.0) == AccessFault::kNone;
}

constexpr double kDone = static_cast<double>(MacroState::kDone);
constexpr double kError = static_cast<double>(MacroState::kError);

const trueaxis::core::Vec3 kCollinear[3] = {trueaxis::core::Vec3(0.0, 0.0, 0.0),
                                            trueaxis::core::Vec3(50.0, 10.0, 5.0),
                                            trueaxis::core::Vec3(100.0, 20.0, 10.0)};

TA_TEST("macro 9810 levels random faces written into G57..G59") {
  Bench bench;
  Module& m = bench.module;
  trueaxis::test::SplitMix64 rng(0x5EED'0002);
  for (int i = 0; i < 40; ++i) {
    TA_CASE_INDEX(i);
    const trueaxis::test::Face f = trueaxis::test::random_face(rng);
    TA_REQUIRE(set_signs(m, f.a_sign, f.c_sign));
    const double done_before = read1(m, var::kDoneCount);
    TA_CHECK_EQ(run_9810(m, f.points_machine, f.probe_a_deg, f.probe_c_deg, f.hint_machine), kDone);
    TA_CHECK_EQ(read1(m, var::kError), 0.0);
    TA_CHECK_EQ(read1(m, var::kDoneCount), done_before + 1.0);
    const double c = read1(m, var::kLevelC);
    const double a = read1(m, var::kLevelA);
    TA_CHECK(trueaxis::test::leveling_error_rad(f.normal_table, a, c, f.a_sign, f.c_sign) <= 1e-12);
    TA_CHECK(trueaxis::test::leveling_error_rad(f.normal_table, read1(m, var::kLevelOtherA),
                                                read1(m, var::kLevelOtherC), f.a_sign, f.c_sign) <= 1e-12);
    TA_CHECK(a >= -120.0 && a <= 120.0);
    TA_CHECK_NEAR(read1(m, var::kLevelNormalX), f.normal_table.x(), 1e-12);
    TA_CHECK_NEAR(read1(m, var::kLevelNormalY), f.normal_table.y(), 1e-12);
    TA_CHECK_NEAR(read1(m, var::kLevelNormalZ), f.normal_table.z(), 1e-12);
    TA_CHECK_NEAR(read1(m, var::kLevelTilt), trueaxis::core::rad_to_deg(f.tilt_rad), 1e-10);
    TA_CHECK_EQ(read1(m, var::kLevelPointCount), 3.0);
    TA_CHECK_EQ(read1(m, var::kArgA), 0.0);  // arguments are cleared after every macro
  }
}

// Runs one good face, then `bad` points; the error must leave #100..#115 alone.
void check_error_keeps_results(const trueaxis::core::Vec3 (&bad)[3], Status expected) {
  Bench bench;
  Module& m = bench.module;
  trueaxis::test::SplitMix64 rng(0x5EED'0004);
  const trueaxis::test::Face f = trueaxis::test::random_face(rng);
  TA_REQUIRE(set_signs(m, f.a_sign, f.c_sign));
  TA_REQUIRE(run_9810(m, f.points_machine, f.probe_a_deg, f.probe_c_deg, f.hint_machine) == kDone);
  double before[16];
  TA_REQUIRE(m.read(var::kResultFirst, 16, before) == AccessFault::kNone);
  const double done_before = read1(m, var::kDoneCount);

  TA_CHECK_EQ(run_9810(m, bad, 0.0, 0.0, trueaxis::core::Vec3::Zero()), kError);
  TA_CHECK_EQ(read1(m, var::kError), static_cast<double>(expected));
  TA_CHECK_EQ(read1(m, var::kDoneCount), done_before + 1.0);
  double after[16];
  TA_REQUIRE(m.read(var::kResultFirst, 16, after) == AccessFault::kNone);
  for (int k = 0; k < 16; ++k) {
    TA_CASE_INDEX(var::kResultFirst + k);
    TA_CHECK_EQ(after[k], before[k]);
  }
}

TA_TEST("macro 9810 with collinear points sets status 3, code 201 and keeps the results") {
  check_error_keeps_results(kCollinear, Status::kPointsCollinear);
}

TA_TEST("macro 9810 with coincident points sets status 3, code 200 and keeps the results") {
  const trueaxis::core::Vec3 p(10.0, 20.0, 30.0);
  const trueaxis::core::Vec3 coincident[3] = {p, p, p};
  check_error_keeps_results(coincident, Status::kPointsCoincident);
}

TA_TEST("macro 9810 outside the A travel sets status 3 and code 204") {
  Bench bench;
  Module& m = bench.module;
  TA_REQUIRE(write1(m, var::kUnlock, trueaxis::macros::kUnlockCode) == AccessFault::kNone);
  TA_REQUIRE(write1(m, var::kAMin, -5.0) == AccessFault::kNone);
  TA_REQUIRE(write1(m, var::kAMax, 5.0) == AccessFault::kNone);
  const trueaxis::core::Vec3 tilted[3] = {trueaxis::core::Vec3(0.0, 0.0, 0.0),
                                          trueaxis::core::Vec3(100.0, 0.0, 0.0),
                                          trueaxis::core::Vec3(0.0, 100.0, 50.0)};
  TA_CHECK_EQ(run_9810(m, tilted, 0.0, 0.0, trueaxis::core::Vec3::Zero()), kError);
  TA_CHECK_EQ(read1(m, var::kError), static_cast<double>(Status::kUnreachable));
  TA_CHECK_EQ(read1(m, var::kLevelA), 0.0);  // never written
}

TA_TEST("a configuration write while locked is refused with kLocked and changes nothing") {
  Bench bench;
  Module& m = bench.module;
  const double a_min_before = read1(m, var::kAMin);
  TA_CHECK_EQ(write1(m, var::kAMin, -90.0), AccessFault::kLocked);
  TA_CHECK_EQ(read1(m, var::kAMin), a_min_before);
  TA_CHECK_EQ(write1(m, var::kUnlock, 1234.0), AccessFault::kBadUnlockCode);
  TA_CHECK_EQ(write1(m, var::kAMin, -90.0), AccessFault::kLocked);
}

TA_TEST("after unlocking, a configuration write is taken, and locking again refuses the next") {
  Bench bench;
  Module& m = bench.module;
  TA_CHECK_EQ(write1(m, var::kUnlock, trueaxis::macros::kUnlockCode), AccessFault::kNone);
  TA_CHECK_EQ(read1(m, var::kUnlock), 1.0);
  TA_CHECK_EQ(write1(m, var::kAMin, -90.0), AccessFault::kNone);
  TA_CHECK_EQ(read1(m, var::kAMin), -90.0);
  TA_CHECK_EQ(write1(m, var::kUnlock, 0.0), AccessFault::kNone);
  TA_CHECK_EQ(write1(m, var::kAMin, -80.0), AccessFault::kLocked);
  TA_CHECK_EQ(read1(m, var::kAMin), -90.0);
}

TA_TEST("a second module over the same storage sees the configuration after start") {
  for (std::uint8_t& b : g_storage_bytes) b = 0;
  trueaxis::hal::RamNvStorage storage(g_storage_bytes, kStorageBytes);
  trueaxis::test::FakeClock clock;
  {
    Module& first = g_module_slots[0].emplace(storage, clock);
    TA_REQUIRE(first.start() == Status::kOk);
    TA_REQUIRE(write1(first, var::kUnlock, trueaxis::macros::kUnlockCode) == AccessFault::kNone);
    TA_REQUIRE(write1(first, var::kAMin, -95.5) == AccessFault::kNone);
    TA_REQUIRE(write1(first, var::kProbeSigma, 0.002) == AccessFault::kNone);
    TA_REQUIRE(write1(first, var::kG57 + 1, 42.25) == AccessFault::kNone);
  }
  Module& second = g_module_slots[1].emplace(storage, clock);
  TA_REQUIRE(second.start() == Status::kOk);
  TA_CHECK_EQ(read1(second, var::kAMin), -95.5);
  TA_CHECK_EQ(read1(second, var::kProbeSigma), 0.002);
  TA_CHECK_EQ(read1(second, var::kG57 + 1), 42.25);
  TA_CHECK_EQ(read1(second, var::kUnlock), 0.0);  // the unlock itself does not persist
  TA_CHECK_EQ(write1(second, var::kAMin, -90.0), AccessFault::kLocked);
}

}  // namespace
