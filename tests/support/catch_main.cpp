// The Catch2 programs' main, and the module rig's failure handler for them
// (tests/portable/rig_failure.hpp): a step of the rig that fails ends the test
// case, as a failed REQUIRE does, at the test's own line.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include "rig_failure.hpp"

namespace {

void fail_test_case(const trueaxis::test::Where& where, const char* what) {
  FAIL(where.file << ":" << where.line << ": " << what);
}

[[maybe_unused]] const bool g_rig_handler_installed = [] {
  trueaxis::test::g_rig_failure = &fail_test_case;
  return true;
}();

}  // namespace
