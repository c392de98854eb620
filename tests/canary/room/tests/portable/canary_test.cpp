// The canary through the module (its portable test, on the host and, in a
// build with it, on the Cortex-M7): the session, the sum by its core
// function, the store and the stored sum; and every macro's recipe.
#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/core/canary_sum.hpp"
#include "trueaxis/macros/canary/canary_macros.hpp"

TA_METHOD_TESTED("canary");

namespace {

namespace v = trueaxis::macros::var;
namespace t = trueaxis::test;
using t::kDone;
using t::ModuleRig;

void three_values(ModuleRig& rig) {
  rig.run(9851);
  for (const double a : {1.5, -0.25, 4.0}) {
    rig.set(v::kArgA, a);
    rig.run(9852);
  }
}
void one_value(ModuleRig& rig) { rig.set(v::kArgA, 2.0); }
void stored(ModuleRig& rig) {
  three_values(rig);
  rig.unlock();
  rig.set(v::kArgR, 1.0);
  rig.run(9853);
  rig.lock();
}

}  // namespace

TA_RECIPE(9850, nullptr, one_value);
TA_RECIPE(9851, nullptr, nullptr);
TA_RECIPE(9852, nullptr, one_value);
TA_RECIPE(9853, three_values, nullptr);
TA_RECIPE(9854, stored, nullptr);

TA_TEST("canary: 9853 gives the gain times the core's sum of the session; R = 1 stores the sum, 9854 reads it") {
  ModuleRig rig;
  three_values(rig);
  const double values[] = {1.5, -0.25, 4.0};
  TA_CHECK_EQ(rig.run(9853), kDone);
  TA_CHECK_EQ(rig.get(100), 2.0 * trueaxis::core::canary_sum(values, 3));
  TA_CHECK_EQ(rig.get(100), 10.5);
  TA_CHECK(rig.run(9854) != kDone);  // nothing stored yet
  rig.unlock();
  rig.set(v::kArgR, 1.0);
  TA_CHECK_EQ(rig.run(9853), kDone);
  rig.lock();
  TA_CHECK_EQ(rig.run(9854), kDone);
  TA_CHECK_EQ(rig.get(100), 5.25);
}
