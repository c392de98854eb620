// Every macro of the built methods writes exactly the outputs the map
// publishes for it (its MacroInfo outputs, which the JSON map and
// trueaxis-var print): #100..#199 are first filled with a sentinel (the test
// kit's macro 9990, module_rig.hpp contract 3), then the macro runs from its
// method's recipe (method_tests.hpp) to a success, and every result variable
// must differ from the sentinel exactly when the map publishes it for that
// macro. A macro without a recipe fails.
#include <cstdint>

#include "method_tests.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace {

namespace m = trueaxis::macros;
namespace t = trueaxis::test;
using t::ModuleRig;

bool published(const m::MacroInfo& info, std::uint16_t number) {
  for (std::size_t i = 0; i < info.output_count; ++i) {
    if (info.outputs[i].number == number) return true;
  }
  return false;
}

void fail(const m::MacroInfo& info, const char* what, std::uint16_t number, int line) {
  t::Line text;
  text.text("macro ").uint(info.number).text(" (").text(info.name).text(") ").text(what);
  if (number != 0) text.text(" #").uint(number);
  t::TestCase::fail(__FILE__, line, text);
}

void check_macro(const m::MacroInfo& info) {
  const t::Recipe* recipe = t::RecipeEntry::find(info.number);
  if (recipe == nullptr) {
    fail(info, "has no recipe in its method's portable tests (method_tests.hpp)", 0, __LINE__);
    return;
  }
  ModuleRig rig;
  if (recipe->prepare != nullptr) recipe->prepare(rig);
  if (!rig.prefill()) return;
  if (recipe->arguments != nullptr) recipe->arguments(rig);
  if (!rig.done(info.number)) return;
  for (std::uint16_t n = m::var::kResultFirst; n <= m::var::kResultLast; ++n) {
    const bool written = rig.get(n) != t::kSentinel;
    if (written && !published(info, n)) fail(info, "writes a result the map does not publish for it:", n, __LINE__);
    if (!written && published(info, n)) fail(info, "does not write a result the map publishes for it:", n, __LINE__);
  }
}

}  // namespace

TA_TEST("every macro of the built methods writes exactly the results the map publishes for it") {
  std::size_t macros = 0;
  for (const m::List<m::MacroInfo>& list : m::BuiltMethods::kMacros) {
    for (const m::MacroInfo& info : list) {
      TA_CASE_INDEX(info.number);
      check_macro(info);
      ++macros;
    }
  }
  TA_CHECK(macros > 0);
}
