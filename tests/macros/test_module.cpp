#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <algorithm>

#include "alloc_counter.hpp"
#include "fakes.hpp"
#include "module_rig.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;
using F = trueaxis::macros::AccessFault;

using trueaxis::test::Rig;

namespace {

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
  rig.clock.now += 1'000'000;  // past the wrong code's back-off (test_access_control.cpp)
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
