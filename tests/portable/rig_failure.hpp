// What the module rig (module_rig.hpp contract 4) does when a step it was
// asked to take fails: in a portable test, a failure of the running case; in
// a Catch2 program, what the program installed (tests/support/catch_main.cpp:
// the test case fails there). Kept apart from the rig so that the Catch2
// support library, built once for every module set, needs no module.
#pragma once

#include "portable_test.hpp"

namespace trueaxis::test {

// Where a test called the rig.
struct Where {
  const char* file;
  int line;
};
// As a default argument: the caller's file and line (GCC and Clang).
#define TA_HERE \
  ::trueaxis::test::Where { __builtin_FILE(), __builtin_LINE() }

using RigFailureHandler = void (*)(const Where& where, const char* what);
inline RigFailureHandler g_rig_failure = nullptr;

inline void rig_failure(const Where& where, const Line& what) {
  if (g_rig_failure != nullptr) {
    g_rig_failure(where, what.c_str());
  } else {
    TestCase::fail(where.file, where.line, what);
  }
}

}  // namespace trueaxis::test
