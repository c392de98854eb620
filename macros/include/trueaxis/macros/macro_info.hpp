// What the module knows of a macro: its number, its handler, and the inputs
// and outputs the JSON map publishes.
//
// Contract of a handler (MacroFn)
//  1. It reads variables through MacroContext::in<N>() and writes results only
//     through MacroContext::out<N>(), which stages them; it may stage one
//     persistent record (a calibration table) through MacroContext.
//  2. It does a bounded amount of work per call. It returns more() to be called
//     again at the next Module::step() (the macro stays busy), or done(status).
//     MacroContext::first_step() tells the first call.
//  3. The module copies the staged results into #100..#199, and commits the
//     staged record, only when the macro ends with kOk (the record first: if
//     its save fails the macro fails with kStorageFailure and nothing is
//     published). On any other status every result, every session sample and
//     every stored table stays as it was, unless the handler's contract says
//     otherwise (a clear macro clears its session).
//  4. Each handler's comment lists its inputs, outputs and status codes.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

class MacroContext;

struct MacroStep {
  // A status alone is a finished step: done(status).
  constexpr MacroStep(core::Status s, bool m = false) : status(s), more(m) {}  // NOLINT: implicit by design
  core::Status status;
  bool more;
};
constexpr MacroStep done(core::Status s) { return {s, false}; }
constexpr MacroStep more() { return {core::Status::kOk, true}; }

using MacroFn = MacroStep (*)(MacroContext&);

struct MacroInfo {
  std::uint16_t number;
  MacroFn run;
  const char* name;
  const char* description;
  const InputRef* inputs;
  std::size_t input_count;
  const OutputInfo* outputs;
  std::size_t output_count;
};

template <std::size_t NI, std::size_t NO>
constexpr MacroInfo macro(std::uint16_t number, MacroFn run, const char* name, const char* description,
                          const InputRef (&inputs)[NI], const OutputInfo (&outputs)[NO]) {
  return {number, run, name, description, inputs, NI, outputs, NO};
}

template <std::size_t NO>
constexpr MacroInfo macro(std::uint16_t number, MacroFn run, const char* name, const char* description,
                          const OutputInfo (&outputs)[NO]) {
  return {number, run, name, description, nullptr, 0, outputs, NO};
}

}  // namespace trueaxis::macros
