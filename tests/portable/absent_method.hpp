// A method a module set does not build, as the controller sees it
// (methods/CMakeLists.txt: "the others' macros answer unknown_macro
// (400) and their variables are not defined"): every macro of its range fails
// with 400 and changes no result, every number of its blocks of #500..#999 and
// #1000..#4999 is refused for reading and for writing as undefined (#9007 says
// so). The numbers are the published ones (macros/register_map.json): the
// method's own headers are not on an absent method's tests' include path.
#pragma once

#include <cstdint>
#include <cstring>

#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::test {

struct AbsentMethod {
  const char* name;
  std::uint16_t first_macro, last_macro;
  std::uint16_t config_first, config_last;
  std::uint16_t data_first, data_last;
};

inline void check_absent(const AbsentMethod& a) {
  for (const char* name : macros::BuiltMethods::kNames) TA_CHECK(std::strcmp(name, a.name) != 0);
  ModuleRig rig;
  TA_REQUIRE(rig.prefill());
  const ModuleRig::Results before = rig.results();
  for (std::uint16_t macro = a.first_macro; macro <= a.last_macro; ++macro) {
    TA_CASE_INDEX(macro);
    TA_CHECK_EQ(rig.refuse(macro), core::Status::kUnknownMacro);
    TA_CHECK(rig.results() == before);
  }
  const std::uint16_t ranges[2][2] = {{a.config_first, a.config_last}, {a.data_first, a.data_last}};
  for (const auto& range : ranges) {
    for (std::uint16_t n = range[0]; n <= range[1]; ++n) {
      TA_CASE_INDEX(n);
      double value = -1.0;
      TA_CHECK_EQ(rig.read(n, 1, &value), macros::AccessFault::kUndefined);
      TA_CHECK_EQ(value, -1.0);
      TA_CHECK_EQ(rig.put(n, 1.0), macros::AccessFault::kUndefined);
      TA_CHECK_EQ(rig.get(macros::var::kAccessFault), static_cast<double>(macros::AccessFault::kUndefined));
    }
  }
  TA_CHECK(rig.unlock());  // unlocked, still undefined
  TA_CHECK_EQ(rig.put(a.config_first, 1.0), macros::AccessFault::kUndefined);
}

}  // namespace trueaxis::test
