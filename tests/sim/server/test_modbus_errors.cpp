// Every refusal docs/INTERFACE.md promises, over real Modbus TCP against trueaxis-sim,
// and in each case proof that nothing else changed.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "sim_fixture.hpp"
#include "trueaxis/sim/server/sim_map.hpp"

namespace {

using trueaxis::sim::test::kUnlockCode;
using trueaxis::sim::test::SimFixture;
using trueaxis::sim::VariableClient;
namespace simvar = trueaxis::sim::simvar;

constexpr int kIllegalFunction = 1;
constexpr int kIllegalAddress = 2;
constexpr int kIllegalValue = 3;
constexpr int kBusy = 6;

constexpr int kStatusDone = 2;
constexpr int kStatusError = 3;

// Results, configuration and points from one successful leveling, so that a
// later refusal that cleared or overwrote any of them would show.
void level_once(SimFixture& f) {
  f.probe_triangle();
  REQUIRE(f.run().status == kStatusDone);
  REQUIRE(f.get(107) > 12.0);
}

// #100..#115 and #500..#507: what a failed macro must leave alone.
std::vector<double> results_and_config(SimFixture& f) {
  std::vector<double> v = f.snapshot();
  return std::vector<double>(v.begin(), v.begin() + 24);
}

void check_failed_macro(SimFixture& f, int expected_error) {
  const std::vector<double> before = results_and_config(f);
  const double done_before = f.get(9003);
  const auto outcome = f.run();
  CHECK(outcome.status == kStatusError);
  CHECK(outcome.error == expected_error);
  CHECK(f.get(9001) == kStatusError);
  CHECK(f.get(9002) == expected_error);
  CHECK(f.get(9003) == done_before + 1);
  CHECK(results_and_config(f) == before);
}

}  // namespace

TEST_CASE("9810 refuses three collinear points and changes no result") {
  SimFixture f;
  level_once(f);
  f.set_points({{0.0, 0.0, 40.0}, {50.0, 0.0, 45.0}, {100.0, 0.0, 50.0}});
  check_failed_macro(f, 201);
}

TEST_CASE("9810 refuses three nearly collinear points") {
  SimFixture f;
  level_once(f);
  // The third point 1 nm off the line through the first two, 100 mm apart.
  f.set_points({{0.0, 0.0, 40.0}, {50.0, 0.0, 40.0}, {100.0, 1e-6, 40.0}});
  const std::vector<double> before = results_and_config(f);
  const auto outcome = f.run();
  CHECK(outcome.status == kStatusError);
  CHECK((outcome.error == 201 || outcome.error == 202));
  CHECK(results_and_config(f) == before);
}

TEST_CASE("9810 refuses coincident points and changes no result") {
  SimFixture f;
  level_once(f);
  f.set_points({{10.0, 20.0, 40.0}, {10.0, 20.0, 40.0}, {10.0, 20.0, 40.0}});
  check_failed_macro(f, 200);
}

TEST_CASE("9810 refuses a face no solution can level inside narrowed A limits") {
  SimFixture f;
  level_once(f);
  f.set(9004, kUnlockCode);
  f.set(500, {-1.0, 1.0});
  f.probe_triangle();
  check_failed_macro(f, 204);
  CHECK(f.get(500) == -1.0);
  CHECK(f.get(501) == 1.0);
}

TEST_CASE("a NaN or an infinity written to a point is exception 03 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(f.write_exception(5281, {nan}) == kIllegalValue);
  CHECK(f.write_exception(5281, {1.0, 2.0, inf}) == kIllegalValue);
  CHECK(f.write_exception(5301, {-inf, 0.0, 0.0}) == kIllegalValue);
  CHECK(f.write_exception(simvar::kAxisA, {nan}) == kIllegalValue);
  CHECK(f.write_exception(1, {nan}) == kIllegalValue);
  CHECK(f.snapshot() == before);
}

TEST_CASE("a value out of range is exception 03 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  CHECK(f.write_exception(1, {1e9}) == kIllegalValue);
  CHECK(f.write_exception(simvar::kHold, {0.5}) == kIllegalValue);
  CHECK(f.write_exception(simvar::kProbeSigma, {-0.001}) == kIllegalValue);
  CHECK(f.snapshot() == before);
}

TEST_CASE("a misaligned or partial register range is exception 02 and changes nothing") {
  SimFixture f;
  level_once(f);
  f.set(1, 5.0);
  const std::vector<double> before = f.snapshot();
  CHECK(f.read_registers_exception(4 * 100 + 1, 4) == kIllegalAddress);
  CHECK(f.read_registers_exception(4 * 100, 2) == kIllegalAddress);
  CHECK(f.read_registers_exception(4 * 100, 6) == kIllegalAddress);
  CHECK(f.read_registers_exception(4 * 100 + 3, 1) == kIllegalAddress);
  CHECK(f.write_registers_exception(4 * 1 + 2, {0x4000, 0, 0, 0}) == kIllegalAddress);
  CHECK(f.write_registers_exception(4 * 1, {0x4000, 0}) == kIllegalAddress);
  CHECK(f.write_registers_exception(4 * 5281, {0x4000, 0, 0, 0, 0x4000, 0}) == kIllegalAddress);
  CHECK(f.get(1) == 5.0);
  CHECK(f.snapshot() == before);
}

TEST_CASE("a number the map does not define is exception 02 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  for (int number : {0, 10, 27, 99, 200, 499, 1000, 5220, 5227, 8999, 9999, 11999, 12014, 16383}) {
    INFO("#" << number);
    CHECK(f.read_registers_exception(4 * number, 4) == kIllegalAddress);
    CHECK(f.write_registers_exception(4 * number, {0x3FF0, 0, 0, 0}) == kIllegalAddress);
  }
  // A whole-variable range that runs from defined into undefined numbers.
  CHECK(f.read_registers_exception(4 * 26, 8) == kIllegalAddress);
  CHECK(f.write_exception(5326, {0.0, 0.0}) == kIllegalAddress);
  CHECK(f.write_exception(simvar::kLast, {0.0, 0.0}) == kIllegalAddress);
  CHECK(f.snapshot() == before);
}

TEST_CASE("FC6 write single register is exception 02 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  for (int address : {4 * 1, 4 * 1 + 3, 4 * 5281, 4 * 9000}) {
    CHECK(modbus_write_register(f.client().raw(), address, 0x4000) == -1);
    CHECK(errno == EMBXILADD);
  }
  CHECK(f.snapshot() == before);
}

TEST_CASE("a function code the server does not serve is exception 01") {
  SimFixture f;
  std::uint8_t bits[8];
  CHECK(modbus_read_bits(f.client().raw(), 0, 8, bits) == -1);
  CHECK(errno == EMBXILFUN);
  std::uint16_t words[4];
  CHECK(modbus_read_input_registers(f.client().raw(), 400, 4, words) == -1);
  CHECK(errno == EMBXILFUN);
  CHECK(f.get(9006) == 1.0);
}

TEST_CASE("a write to a read-only variable is exception 02 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  CHECK(f.write_exception(100, {1.0}) == kIllegalAddress);
  CHECK(f.write_exception(107, {0.0}) == kIllegalAddress);
  CHECK(f.write_exception(9001, {0.0}) == kIllegalAddress);
  CHECK(f.write_exception(9003, {0.0}) == kIllegalAddress);
  CHECK(f.write_exception(simvar::kTrueTilt, {0.0}) == kIllegalAddress);
  CHECK(f.write_exception(simvar::kLastProbeX, {0.0}) == kIllegalAddress);
  CHECK(f.snapshot() == before);
}

TEST_CASE("a write to the configuration while locked is exception 02 and changes nothing") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  CHECK(f.get(9004) == 0.0);
  CHECK(f.write_exception(500, {-10.0}) == kIllegalAddress);
  CHECK(f.write_exception(506, {0.001}) == kIllegalAddress);
  CHECK(f.snapshot() == before);
  f.set(9004, kUnlockCode);
  f.set(506, 0.001);
  f.set(9004, 0.0);
  CHECK(f.write_exception(506, {0.002}) == kIllegalAddress);
  CHECK(f.get(506) == 0.001);
}

TEST_CASE("a wrong unlock code is exception 03 and leaves the configuration locked") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  CHECK(f.write_exception(9004, {1234.0}) == kIllegalValue);
  // Within the wrong code's back-off (1 s) every code is refused with 06, the
  // right one too, and only the wrong codes judged are counted (#9010).
  CHECK(f.write_exception(9004, {kUnlockCode + 1.0}) == 6);
  CHECK(f.write_exception(9004, {kUnlockCode}) == 6);
  CHECK(f.get(9010) == 1.0);
  CHECK(f.get(9004) == 0.0);
  CHECK(f.write_exception(500, {-10.0}) == kIllegalAddress);
  CHECK(f.snapshot() == before);
}

TEST_CASE("a command while a macro is busy is exception 06 and changes nothing") {
  SimFixture f;
  level_once(f);
  f.probe_triangle();
  f.set(simvar::kHold, 1.0);
  const double done_before = f.get(9003);
  f.set(9000, 9810.0);
  CHECK(f.get(9001) == 1.0);
  const std::vector<double> before = f.snapshot();
  CHECK(f.write_exception(9000, {9810.0}) == kBusy);
  CHECK(f.write_exception(9000, {9811.0}) == kBusy);
  CHECK(f.write_exception(5281, {1.0}) == kBusy);
  CHECK(f.write_exception(1, {1.0}) == kBusy);
  CHECK(f.snapshot() == before);
  // Probing writes through the module too, so it is refused the same way.
  CHECK(f.write_exception(simvar::kProbeInto, {5281.0}) == kBusy);
  CHECK(f.snapshot() == before);
  // Releasing the hold lets the pending macro run after that very request.
  f.set(simvar::kHold, 0.0);
  CHECK(f.get(9001) == 2.0);
  CHECK(f.get(9003) == done_before + 1);
}

TEST_CASE("probing a face too steep to touch is exception 03 and changes nothing") {
  SimFixture f;
  level_once(f);
  f.set(simvar::kAxisA, {-80.0, 90.0});  // face falls towards azimuth 30 deg: now about 82 deg
  REQUIRE(f.get(simvar::kTrueTilt) > 75.0);
  const std::vector<double> before = f.snapshot();
  CHECK(f.write_exception(simvar::kProbeInto, {5281.0}) == kIllegalValue);
  CHECK(f.write_exception(simvar::kProbeX, {1.0, 2.0, 5301.0}) == kIllegalValue);
  CHECK(f.snapshot() == before);
}

TEST_CASE("probing into a number that is not a work offset or point-list X is exception 03") {
  SimFixture f;
  level_once(f);
  const std::vector<double> before = f.snapshot();
  for (double target : {5282.0, 5222.0, 5341.0, 1002.0, 1097.0, 100.0, 0.0}) {
    CHECK(f.write_exception(simvar::kProbeInto, {target}) == kIllegalValue);
  }
  CHECK(f.snapshot() == before);
}

TEST_CASE("an unlock closes when the connection that opened it closes, and only then; meanwhile it is that connection's") {
  SimFixture f;
  const auto unlocked = [&f] { return f.get(9004) == 1.0; };
  const auto wait_locked = [&] {
    for (int i = 0; i < 200 && unlocked(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return !unlocked();
  };
  {
    VariableClient owner;
    REQUIRE(owner.connect("127.0.0.1", f.port()));
    REQUIRE(owner.write_one(9004, kUnlockCode));
    CHECK(unlocked());  // seen from the fixture's own connection
    {
      VariableClient other;  // another connection comes and goes: the unlock stays
      REQUIRE(other.connect("127.0.0.1", f.port()));
      double v = 0.0;
      REQUIRE(other.read_one(9004, v));
      CHECK(v == 1.0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(unlocked());
    // Another connection's configuration write under the owner's unlock
    // (module.hpp contract 8: an unlock takes no interface, and configuration
    // is written under the writer's own unlock only): refused, locked.
    const double before = f.get(506);
    CHECK(f.write_exception(506, {before + 0.001}) == kIllegalAddress);
    CHECK(f.get(9007) == 4.0);
    CHECK(f.get(506) == before);
    REQUIRE(owner.write_one(506, 0.002));  // the owner's own
  }
  CHECK(wait_locked());
  // The owner has gone: the interface is free, and locked.
  CHECK(f.write_exception(506, {0.003}) == kIllegalAddress);
  CHECK(f.get(9007) == 4.0);  // locked
  CHECK(f.get(506) == 0.002);
  // The fixture's connection unlocks now: its unlock is its own.
  f.set(9004, kUnlockCode);
  {
    VariableClient passer;
    REQUIRE(passer.connect("127.0.0.1", f.port()));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(unlocked());
}
