// The module as a controller drives it, for the macros tests: storage that can
// fail, a fake clock, a started module, and the reads and writes a test needs.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include <catch2/catch.hpp>

#include "fakes.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using F = trueaxis::macros::AccessFault;
using trueaxis::core::Status;

struct Rig {
  FlakyStorage storage;
  FakeClock clock;
  m::Module module{storage, clock};
  Rig() { REQUIRE(module.start() == Status::kOk); }

  F put(std::uint16_t n, double value) { return module.write(n, 1, &value); }
  double get(std::uint16_t n) {
    double value = std::numeric_limits<double>::quiet_NaN();
    REQUIRE(module.read(n, 1, &value) == F::kNone);
    return value;
  }
  void put_point(std::uint16_t x_number, double x, double y, double z) {
    const double p[3] = {x, y, z};
    REQUIRE(module.write(x_number, 3, p) == F::kNone);
  }
  // A face tilted by atan(0.2) about Y (rising towards +X), probed at the table's zero.
  void put_inclined_face() {
    put_point(v::kG57, 0, 0, 10);
    put_point(v::kG58, 100, 0, 30);
    put_point(v::kG59, 0, 100, 10);
  }
  double run(double macro) {
    REQUIRE(put(v::kCmd, macro) == F::kNone);
    CHECK(get(v::kStatus) == 1.0);
    module.step();
    return get(v::kStatus);
  }
  std::array<double, 16> results() {
    std::array<double, 16> r{};
    REQUIRE(module.read(v::kLevelC, 16, r.data()) == F::kNone);
    return r;
  }
};

}  // namespace trueaxis::test
