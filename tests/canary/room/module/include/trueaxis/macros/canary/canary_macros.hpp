// The canary: a fifth method, as small as a method can be while it has every
// part a method may have (a configuration row, a calibration session, a stored
// table, a status code of its own, macros) and every layer a method has (its
// core function, this room, a host flow and plan, a portable test, a report
// page). tests/canary/run_canary.cmake copies the repository, adds this folder
// as methods/canary/ and the name to the one list, and proves that the module,
// the map, the JSON, the record list, the status table, trueaxis-calibrate's
// flows and plans, the report and the portable tests pick it up with no other edit.
//
// Macro 9850: #100 = A (#1) times the gain #950.
// Macro 9851: clear the session (opening it). Out: #100 count.
// Macro 9852: add A (#1) to the session. Out: #100 count. kSessionFull after 4.
// Macro 9853: #100 = the gain times the session's sum; R = #18 = 1 stores the
//  sum as the canary's table (record key 6). kCanaryEmpty on an empty session.
// Macro 9854: #100 = the stored sum (kNoTable when none).
#pragma once

#include <cstdint>

#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/session.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros::canary {

inline constexpr std::uint16_t kGain = 950;
inline constexpr core::Status kCanaryEmpty = static_cast<core::Status>(1901);

inline constexpr MethodBlock kBlock{"canary", 950, 959, 0, 0};

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(kGain, -10.0, 10.0, 2.0, "canary_gain", "", "Canary: the gain of 9850 and 9853."),
};
inline constexpr OutputInfo kOutputs[] = {{100, "canary_result", "", "Canary: the macro's result."}};
inline constexpr core::StatusInfo kStatuses[] = {
  {kCanaryEmpty, "canary_empty", "The canary's session is empty."},
};
// clang-format on

struct Sum {
  double value = 0.0;
};

struct SumRecord {
  using Type = Sum;
  static constexpr RecordSpec kRecord{6, 1, 16, "canary_sum"};
  static core::Status decode(const std::uint8_t* bytes, std::size_t length, Type& out);
  static std::size_t encode(const Type& t, std::uint8_t* out, std::size_t capacity);
  static std::size_t bytes(const Type&) { return 8; }
};

using CanarySession = Session<double, 4>;

struct Work {
  Sum sum;
};

struct Shape {
  static constexpr List<VarInfo> kRows = list_of(canary::kRows);
  using Session = CanarySession;
  using Work = canary::Work;
};
using Context = MethodContext<Shape>;

struct State {
  StoredTable<SumRecord> table;
};

MacroStep run_scale(Context& ctx, State& state);
MacroStep run_clear(Context& ctx, State& state);
MacroStep run_add(Context& ctx, State& state);
MacroStep run_sum(Context& ctx, State& state);
MacroStep run_stored(Context& ctx, State& state);

// clang-format off
inline constexpr InputRef kScaleInputs[] = {{var::kArgA, 1, "The value."}, {kGain, 1, ""}};
inline constexpr InputRef kSumInputs[] = {{var::kArgR, 1, "1 stores the sum."}, {kGain, 1, ""}};
inline constexpr MacroInfo kMacros[] = {
  macro<&run_scale>(9850, "canary_scale", "A times the gain.", kScaleInputs, kOutputs),
  macro<&run_clear>(9851, "canary_clear", "Clear the canary's session.", kOutputs),
  macro<&run_add>(9852, "canary_add", "Add A to the canary's session.", kScaleInputs, kOutputs),
  macro<&run_sum>(9853, "canary_sum", "The gain times the session's sum; R = 1 stores the sum.", kSumInputs, kOutputs),
  macro<&run_stored>(9854, "canary_stored", "The stored sum.", kOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::canary
