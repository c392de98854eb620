// The module as a method's flow test drives it, in process: RAM storage the test
// can read, copy and corrupt (`nv`), a fake clock, a started module, and macros
// run to their end however many steps they take.
#pragma once

#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "fakes.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test {

struct FlowRig {
  std::vector<std::uint8_t> nv = std::vector<std::uint8_t>(macros::kRequiredStorageBytes);
  hal::RamNvStorage storage{nv.data(), nv.size()};
  FakeClock clock;
  macros::Module module{storage, clock};
  FlowRig() { REQUIRE(module.start() == core::Status::kOk); }

  void put(std::uint16_t n, double value) { REQUIRE(module.write(n, 1, &value) == macros::AccessFault::kNone); }
  double get(std::uint16_t n) const { return module.value(n); }
  // Runs a macro to its end (any number of steps): its #9001 status.
  double run(double macro) {
    put(macros::var::kCmd, macro);
    for (int i = 0; i < 10000 && module.busy(); ++i) module.step();
    REQUIRE_FALSE(module.busy());
    return get(macros::var::kStatus);
  }
  core::Vec3 out3(std::uint16_t first) const { return core::Vec3(get(first), get(first + 1), get(first + 2)); }
  // Runs a macro that must fail (#9001 = 3); its code.
  core::Status refuse(double macro) {
    REQUIRE(run(macro) == 3.0);
    return static_cast<core::Status>(static_cast<int>(get(macros::var::kError)));
  }
};

}  // namespace trueaxis::test
