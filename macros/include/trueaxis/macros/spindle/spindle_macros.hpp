// M4's macros: the analyser's sample session, the identification of the
// tool-axis model and its storage, the reports, the correction query
// (INTERFACE.md macro 9843); and the direct C++ correction for the controller's
// programs.
//
// Macro 9840: clear the session. Out: #100..#103 (kSessionOutputs).
// Macro 9841: add an analyser sample: S = #19 spindle angle (deg, any number of
//  revolutions: taken modulo 360), T = #20 ball (1 nearer the spindle, 2
//  farther along the tool), X, Y, Z = #24..#26 the ball's centre (mm, analyser
//  frame). Samples at an angle already in the session (within 1e-6 deg) join
//  its bin (spindle_model.hpp convention 4). Out: #100..#103. Refused, nothing
//  added: kArgumentOutOfRange (T not 1 or 2), kSessionFull (a ball's 361st
//  distinct angle, or a repeat beyond 2^24 of one).
// Macro 9842: identify the model from the session (core::SpindleBuilder, several
//  steps): D = #7 O1 to the gauge line (mm, > 0), U = #21 and V = #22 the ball
//  centres below the gauge line (mm, 0 <= U < V), the gap limit #800. R = #18: 1
//  also stores the model (only while unlocked: kTableLocked), committed whole
//  through the keyed store and then made live; 0 identifies only (9844, 9845
//  with R = 0 report it). Out: #100..#104 (kBuildOutputs). Status:
//  kArgumentOutOfRange (D, U, V, R), kMissingGroup (a ball without samples),
//  kTooFewSamples (fewer than 8 distinct angles of a ball),
//  kRevolutionIncomplete, kNotIdentifiable, kNoConvergence, kArgumentOutOfRange
//  also for an axis more than 30 deg from -Z (core::kMaxSpindleTilt: the model
//  stores only what it can load again). The session is kept either way.
// Macro 9843: correction query (INTERFACE.md): S = #19 spindle angle (deg), Z =
//  #26 tool length (mm below the gauge line, 0..1e5) -> #100 theta_e (arcsec),
//  #101 d_e (mm), #102..#104 the tool-tip error (mm), from the stored model.
//  kNoTable (none stored), kTableDamaged / kTableInvalid (the stored record
//  failed its CRC or did not decode at start), kArgumentOutOfRange (Z).
// Macro 9844: the same with uncertainties and the mean over a revolution: R =
//  #18 0 the last identification since start, 1 the stored model; S, Z as 9843.
//  Out: #100..#115 (kReportOutputs).
// Macro 9845: the model: R as 9844, Q = #17 a parameter 1..9 (spindle_map.hpp
//  convention 3). Out: #100..#111 (kModelOutputs).
#pragma once

#include <cstdint>

#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/live_table.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"

namespace trueaxis::macros::spindle {

struct State {
  core::SpindleBins bins;            // the session
  core::SpindleBuilder builder;
  core::SpindleModel computed;       // the last identification (complete when `built`)
  bool built = false;
  bool staged = false;               // 9842 staged `computed` for the commit under way
  LiveTable<core::SpindleModel> live;  // the stored model the controller corrects with
  core::Status missing = core::Status::kNoTable;  // why `live` holds none
  core::SpindleModel decoded;
};

// The direct call for the controller's programs: theta_e (rad), d_e and the
// tool-tip error (mm) at spindle angle phi_deg and tool length tool_mm (below
// the gauge line), from the stored model; const, no allocation, no lock.
// kNotFinite, kArgumentOutOfRange (tool_mm outside 0..1e5), State::missing when
// no model is stored.
[[nodiscard]] core::Result<core::SpindleCorrection> tool_tip_correction(const State& state, double phi_deg,
                                                                        double tool_mm);

void on_record(State& state, const std::uint8_t* bytes, std::size_t length);
void on_damaged(State& state);
void on_committed(State& state);

MacroStep run_session_clear(MacroContext& ctx);
MacroStep run_session_add(MacroContext& ctx);
MacroStep run_build(MacroContext& ctx);
MacroStep run_correction(MacroContext& ctx);
MacroStep run_report(MacroContext& ctx);
MacroStep run_model(MacroContext& ctx);

// clang-format off
inline constexpr InputRef kAddInputs[] = {
  {var::kArgS, 1, "Spindle angle (deg from the M19 zero, M03 direction positive; any revolution)."},
  {var::kArgT, 1, "Ball: 1 nearer the spindle, 2 farther along the tool."},
  {var::kArgX, 3, "Ball centre X, Y, Z (mm, analyser frame)."},
};
inline constexpr InputRef kBuildInputs[] = {
  {var::kArgD, 1, "O1 (upper bearing seat centre) to the gauge line along the spindle (mm)."},
  {var::kArgR, 1, "1 stores the model (unlocked only), 0 identifies only."},
  {var::kArgU, 1, "Ball 1's centre below the gauge line (mm)."},
  {var::kArgV, 1, "Ball 2's centre below the gauge line (mm), more than U."},
  {var::kSpindleMaxGap, 1, "Widest gap a ball's angles may leave."},
};
inline constexpr InputRef kCorrectionInputs[] = {
  {var::kArgS, 1, "Spindle angle (deg)."},
  {var::kArgZ, 1, "Tool length below the gauge line (mm)."},
};
inline constexpr InputRef kReportInputs[] = {
  {var::kArgR, 1, "0 the last identification, 1 the stored model."},
  {var::kArgS, 1, "Spindle angle (deg)."},
  {var::kArgZ, 1, "Tool length below the gauge line (mm)."},
};
inline constexpr InputRef kModelInputs[] = {
  {var::kArgQ, 1, "Parameter 1..9: o_x, o_y, o_z, a_x, a_y, e_x, e_y, w_x, w_y."},
  {var::kArgR, 1, "0 the last identification, 1 the stored model."},
};

inline constexpr MacroInfo kMacros[] = {
  macro(9840, &run_session_clear, "spindle_session_clear", "Empty the spindle analyser session.", kSessionOutputs),
  macro(9841, &run_session_add, "spindle_session_add", "Add one analyser sample (spindle angle, ball, centre) to the session.",
        kAddInputs, kSessionOutputs),
  macro(9842, &run_build, "spindle_build",
        "Identify the tool-axis model from the session (several steps); R = 1 stores it.", kBuildInputs,
        kBuildOutputs),
  macro(9843, &run_correction, "spindle_correction",
        "Correction query: theta_e, d_e and the tool-tip error at a spindle angle and tool length, from the stored model.",
        kCorrectionInputs, kCorrectionOutputs),
  macro(9844, &run_report, "spindle_report",
        "The correction with its uncertainties and its mean over a revolution, for reports.", kReportInputs,
        kReportOutputs),
  macro(9845, &run_model, "spindle_model", "A parameter of the model with its uncertainty, and the fit's figures.",
        kModelInputs, kModelOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::spindle
