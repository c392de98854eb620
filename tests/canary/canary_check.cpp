// The canary method inside a module (tests/canary/run_canary.cmake builds this
// program in a copy of the repository where the canary is the fifth entry of
// the method list): the dispatch runs its macros, its configuration row is in
// the map, its session and work share the arenas, its table is a record of the
// keyed store that survives a restart, its status code has its name. Prints
// one line per failed check; exit 0 when every check holds.
#include <cstdio>
#include <cstring>

#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;

int g_failed = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::printf("canary: FAILED: %s\n", what);
    ++g_failed;
  }
}

// The module rig's steps that fail (a refused write, a macro that never ends,
// a start that fails) are failed checks too.
void on_rig_failure(const trueaxis::test::Where& where, const char* what) {
  std::printf("canary: FAILED: %s:%d: %s\n", where.file, where.line, what);
  ++g_failed;
}

double run(trueaxis::test::ModuleRig& rig, double number, double a = 0.0, double r = 0.0) {
  rig.set(v::kArgA, a);
  rig.set(v::kArgR, r);
  return rig.run(number);
}

}  // namespace

int main() {
  using Canary = m::canary::Method;
  // What the fold over the list gives at compile time: a failure is a build error.
  static_assert(m::BuiltMethods::kCount == 5, "the canary is the fifth built method");
  static_assert(m::is_defined(m::canary::kGain) && m::find_var(m::canary::kGain)->default_value == 2.0,
                "the map defines the canary's #950 with its default");
  static_assert(m::is_macro(9850) && m::is_macro(9854) && m::find_macro_entry(9850).method == 4,
                "the canary's macros are in the table");
  static_assert(m::kRecordSpecs[m::kRecordCount - 2].key == 6 && m::kRecordSpecs[4].key == 5 &&
                    m::kRecordSpecs[m::kRecordCount - 1].key == m::kLogRecord.key,
                "the canary's record (key 6) follows the four methods', which keep their places; the log comes last");
  static_assert(m::Module::kSessionArenaBytes >= sizeof(Canary::Session), "the session arena holds the canary's session");
  check(std::strcmp(m::BuiltMethods::kNames[4], "canary") == 0, "the fifth method is named canary");
  check(std::strcmp(m::kRecordSpecs[m::kRecordCount - 2].name, "canary_sum") == 0, "the last table record is canary_sum");
  check(std::strcmp(m::status_name(m::canary::kCanaryEmpty), "canary_empty") == 0,
        "the status table names the canary's code 1901");

  trueaxis::test::g_rig_failure = on_rig_failure;
  trueaxis::test::ModuleRig rig;  // the module rig of every test (tests/portable/module_rig.hpp), started
  m::Module& module = rig.module();
  check(run(rig, 9850, 3.0) == 2.0 && rig.get(100) == 6.0, "9850: A times the default gain");
  check(run(rig, 9853) == 3.0 && rig.get(v::kError) == 1901.0, "9853 on no session: canary_empty (1901)");
  check(run(rig, 9851) == 2.0, "9851 opens the session");
  check(run(rig, 9852, 1.5) == 2.0 && run(rig, 9852, 2.5) == 2.0 && rig.get(100) == 2.0, "9852 adds to the session");
  check(module.session<Canary>() != nullptr && module.session<Canary>()->size() == 2,
        "the session lives in the shared arena");
  check(run(rig, 9853, 0.0, 1.0) == 3.0 && rig.get(v::kError) == static_cast<double>(Status::kTableLocked),
        "9853 R = 1 while locked: table_locked");
  check(rig.unlock(), "unlock");
  check(run(rig, 9853, 0.0, 1.0) == 2.0 && rig.get(100) == 8.0, "9853 R = 1: gain times the sum, stored");
  check(run(rig, 9854) == 2.0 && rig.get(100) == 4.0, "9854 reads the stored sum");
  check(run(rig, 9810) == 2.0 || rig.get(v::kError) != static_cast<double>(Status::kUnknownMacro),
        "another method's macro still dispatches");

  check(rig.start() == Status::kOk, "the module starts again (a restart over the same device)");
  check(run(rig, 9854) == 2.0 && rig.get(100) == 4.0, "the stored sum survives a restart (record key 6)");
  check(run(rig, 9852, 1.0) == 2.0 && rig.get(100) == 1.0, "after a restart the first add opens an empty session");
  std::printf("canary: %s\n", g_failed == 0 ? "every check holds" : "checks failed");
  return g_failed == 0 ? 0 : 1;
}
