// What the module knows of a macro: its number, its handler, and the inputs
// and outputs the JSON map publishes.
//
// Contract of a handler
//  1. A method's handler is `MacroStep run_x(Context& ctx, State& state)`:
//     Context is its method's MethodContext (method_context.hpp), State its
//     method's own state, nothing of any other method. It reads variables
//     through ctx.in<N>() and writes results only through ctx.out<N>(), which
//     stages them; it may stage one persistent record (a calibration table).
//  2. It does a bounded amount of work per call. It returns more() to be called
//     again at the next Module::step() (the macro stays busy), or done(status).
//     ctx.first_step() tells the first call.
//  3. The module copies the staged results into #100..#199, and commits the
//     staged record, only when the macro ends with kOk (the record first: if
//     its save fails the macro fails with kStorageFailure and nothing is
//     published). On any other status every result, every session sample and
//     every stored table stays as it was, unless the handler's contract says
//     otherwise (a clear macro clears its session).
//  4. Each handler's comment lists its inputs, outputs and status codes.
//  5. The module calls every handler through a MacroThunk, one per handler,
//     made by macro<&handler>(...) (method_context.hpp): the thunk builds the
//     method's context and hands the handler its state.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

struct MacroCall;

struct MacroStep {
  // A status alone is a finished step: done(status).
  constexpr MacroStep(core::Status s, bool m = false) : status(s), more(m) {}  // NOLINT: implicit by design
  core::Status status;
  bool more;
};
constexpr MacroStep done(core::Status s) { return {s, false}; }
constexpr MacroStep more() { return {core::Status::kOk, true}; }

// Contract 5: what the module calls.
using MacroThunk = MacroStep (*)(MacroCall&);

struct MacroInfo {
  std::uint16_t number;
  MacroThunk run;
  const char* name;
  const char* description;
  const InputRef* inputs;
  std::size_t input_count;
  const OutputInfo* outputs;
  std::size_t output_count;
};
// tools/stack_report.py reads the Cortex-M7's macro tables with this layout
// (its MacroThunk rule): the handler at byte 4 of each 32-byte entry.
static_assert(sizeof(void*) != 4 || (sizeof(MacroInfo) == 32 && offsetof(MacroInfo, run) == 4),
              "tools/stack_report.py's MacroThunk rule states MacroInfo's layout: change both");

}  // namespace trueaxis::macros
