// A module set without M3 (levelling alone, the gantry set): its macros
// 9830..9837 answer unknown_macro and its variables (#600.., #2000..) are not
// defined (absent_method.hpp); with M1 built, leveling on the calibrated axes
// (#508 = 1) has no table to level on: method_not_built (408), and leveling on
// the ideal axes still works.
#include "absent_method.hpp"
#include "portable_test.hpp"

#if __has_include("trueaxis/macros/level/level_map.hpp")
#include "trueaxis/macros/level/level_map.hpp"
#define TRUEAXIS_WITH_LEVEL 1
#endif

TA_TEST("without rigidity, 9830..9837 answer unknown_macro and #600..#699, #2000..#2999 are undefined") {
  trueaxis::test::check_absent({"rigidity", 9830, 9837, 600, 699, 2000, 2999});
}

#ifdef TRUEAXIS_WITH_LEVEL
TA_TEST("without rigidity, leveling on the calibrated axes fails with method_not_built and on the ideal ones works") {
  namespace v = trueaxis::macros::var;
  trueaxis::test::ModuleRig rig;
  TA_REQUIRE(rig.unlock());
  rig.set(v::kLevelAxes, 1.0);
  const auto face = [&] {
    rig.set3(v::kG57, trueaxis::core::Vec3(0, 0, 10));
    rig.set3(v::kG58, trueaxis::core::Vec3(100, 0, 30));
    rig.set3(v::kG59, trueaxis::core::Vec3(0, 100, 10));
  };
  face();
  TA_CHECK_EQ(rig.refuse(9810), trueaxis::core::Status::kMethodNotBuilt);
  rig.set(v::kLevelAxes, 0.0);
  face();
  TA_CHECK(rig.done(9810));
  TA_CHECK_EQ(rig.get(v::kLevelAxesUsed), 0.0);
}
#endif
