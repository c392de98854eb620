// What only the host can count: the module's allocations. Its contract checks
// are portable tests (tests/portable/platform_*_test.cpp, level_macros_test.cpp).
#include <catch2/catch.hpp>

#include "alloc_counter.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"

namespace v = trueaxis::macros::var;
using F = trueaxis::macros::AccessFault;

TEST_CASE("a whole level cycle through the module allocates nothing", "[module][alloc]") {
  trueaxis::test::ModuleRig rig;
  const trueaxis::test::AllocationScope scope;
  rig.set3(v::kG57, trueaxis::core::Vec3(0, 0, 10));
  rig.set3(v::kG58, trueaxis::core::Vec3(100, 0, 30));
  rig.set3(v::kG59, trueaxis::core::Vec3(0, 100, 10));
  for (int i = 0; i < 10; ++i) {
    const double cmd = 9810.0;
    REQUIRE(rig.module().write(v::kCmd, 1, &cmd) == F::kNone);
    rig.step();
  }
  double out[16];
  REQUIRE(rig.module().read(v::kLevelC, 16, out) == F::kNone);
  CHECK(scope.count() == 0);
  CHECK(out[7] > 11.0);  // atan(0.2): the cycle levelled
}
