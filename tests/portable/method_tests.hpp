// What each method's portable tests register besides their cases, so that the
// platform's tests can hold every built method to them:
//
//  1. TA_METHOD_TESTED("gantry") in a method's test file says that its tests
//     are in this program; platform_module_test.cpp checks that every built
//     method (BuiltMethods::kNames) said so, so a method whose tests are not
//     registered for a module set (tests/portable/CMakeLists.txt) fails.
//  2. TA_RECIPE(9821, prepare, arguments): how to make macro 9821 succeed.
//     prepare(rig) builds what the macro needs (a session, a computation, a
//     stored table; it may run other macros), arguments(rig) writes its
//     arguments (after the test kit's prefill, since the module clears the
//     arguments after every macro). Either may be nullptr.
//     platform_outputs_test.cpp runs every macro of the built methods from its
//     recipe; a macro without one fails it.
// Registration is static, as TA_TEST's (portable_test.hpp contract 2).
#pragma once

#include <cstdint>
#include <cstring>

#include "portable_test.hpp"

namespace trueaxis::test {

class ModuleRig;

class TestedMethod {
 public:
  explicit TestedMethod(const char* name) : name_(name) {
    next_ = head_;
    head_ = this;
  }
  TestedMethod(const TestedMethod&) = delete;
  TestedMethod& operator=(const TestedMethod&) = delete;

  static bool registered(const char* name) {
    for (const TestedMethod* t = head_; t != nullptr; t = t->next_) {
      if (std::strcmp(t->name_, name) == 0) return true;
    }
    return false;
  }

 private:
  const char* name_;
  const TestedMethod* next_ = nullptr;
  inline static const TestedMethod* head_ = nullptr;
};

struct Recipe {
  std::uint16_t macro;
  void (*prepare)(ModuleRig& rig);
  void (*arguments)(ModuleRig& rig);
};

class RecipeEntry {
 public:
  explicit RecipeEntry(const Recipe& recipe) : recipe_(recipe) {
    next_ = head_;
    head_ = this;
  }
  RecipeEntry(const RecipeEntry&) = delete;
  RecipeEntry& operator=(const RecipeEntry&) = delete;

  // The recipe of a macro, or nullptr.
  static const Recipe* find(std::uint16_t macro) {
    for (const RecipeEntry* e = head_; e != nullptr; e = e->next_) {
      if (e->recipe_.macro == macro) return &e->recipe_;
    }
    return nullptr;
  }

 private:
  Recipe recipe_;
  const RecipeEntry* next_ = nullptr;
  inline static const RecipeEntry* head_ = nullptr;
};

}  // namespace trueaxis::test

#define TA_METHOD_TESTED(name) \
  static ::trueaxis::test::TestedMethod TA_TEST_CAT(ta_tested_method_, __LINE__) { name }

#define TA_RECIPE(macro, prepare, arguments)                                          \
  static ::trueaxis::test::RecipeEntry TA_TEST_CAT(ta_recipe_, __LINE__) {             \
    ::trueaxis::test::Recipe { macro, prepare, arguments }                             \
  }
