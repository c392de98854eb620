// M4's macros: the analyser's sample session, the identification of the
// tool-axis model and its storage, the reports, the correction query
// (docs/INTERFACE.md macro 9843); and the direct C++ correction for the
// controller's programs.
//
// The session lives in the shared session arena and the identification in the
// shared work arena (method_context.hpp contract 4): 9841 and 9842 answer
// kSessionClosed when another method's session has replaced this one, and
// 9844/9845 with R = 0 kResultReplaced when another method's computation has
// used the work arena since.
//
// Macro 9840: clear the session (opening it, and closing another method's).
//  Out: #100..#103 (kSessionOutputs).
// Macro 9841: add an analyser sample: S = #19 spindle angle (deg, any number of
//  revolutions: taken modulo 360), T = #20 ball (1 nearer the spindle, 2
//  farther along the tool), X, Y, Z = #24..#26 the ball's centre (mm, analyser
//  frame). The session keeps sums and 2-deg angle bins, not samples
//  (spindle_model.hpp convention 4): any sampling (an encoder's up to 4,096 a
//  revolution, or on time with angles that never repeat), any number of
//  revolutions, in fixed memory. Out: #100..#103. Refused, nothing added:
//  kArgumentOutOfRange (T not 1 or 2), kSessionFull (a bin's 2^23 + 1-th
//  sample), kDuplicateSample (S, X, Y, Z as the first or the latest sample of
//  its bin, bit for bit: a file, a revolution or a row given twice;
//  convention 4 says what it cannot see).
// Macro 9842: identify the model from the session (core::SpindleBuilder, several
//  steps): D = #7 O1 to the gauge line (mm, > 0), U = #21 and V = #22 the ball
//  centres below the gauge line (mm, 0 <= U < V), the gap limit #800. R = #18: 1
//  also stores the model (only while unlocked: kTableLocked), committed whole
//  through the keyed store and then made live; 0 identifies only (9844, 9845
//  with R = 0 report it). Out: #100..#104 (kBuildOutputs). Status:
//  kArgumentOutOfRange (D, U, V, R), kMissingGroup (a ball without samples),
//  kTooFewSamples (fewer than 8 angle bins of a ball holding samples),
//  kRevolutionIncomplete, kNotIdentifiable, kNoConvergence, kArgumentOutOfRange
//  also for an axis more than 30 deg from -Z (core::kMaxSpindleTilt: the model
//  stores only what it can load again). The session is kept either way.
//  The gates (gates.hpp): spacing at the first step (ball_spacing_implausible:
//  the balls' mean centres farther than #803 from V - U apart); after the fit,
//  in steps of their own, fit (fit_beyond_noise: a ball's sum of squared
//  residuals, scatter of its bins included, over #801^2 + #802^2 / 3 against
//  the chi-square quantile of 3 n_b - 4 degrees of freedom), then change
//  (change_beyond_limit: with R = 1 and a stored model, the tool-tip error at
//  V more than #804 from the stored model's at an angle of 0, 10, .. 350,
//  unless M = #13 is 1). #105..#109 publish the figures.
// Macro 9843: correction query (docs/INTERFACE.md): S = #19 spindle angle (deg), Z =
//  #26 tool length (mm below the gauge line, 0..1e5) -> #100 theta_e (arcsec),
//  #101 d_e (mm), #102..#104 the tool-tip error (mm), from the stored model.
//  kNoTable (none stored), kTableDamaged / kTableInvalid (the stored record
//  failed its CRC or did not decode at start), kArgumentOutOfRange (Z).
// Macro 9844: the same with uncertainties and the mean over a revolution: R =
//  #18 0 the last identification since start, 1 the stored model; S, Z as 9843.
//  Out: #100..#115 (kReportOutputs).
// Macro 9845: the model: R as 9844, Q = #17 a parameter 1..9 (spindle_map.hpp
//  convention 3). Out: #100..#111 (kModelOutputs).
// Macro 9847: the model's record (core::encode_spindle_model, 512 bytes)
//  exactly, in two parts of 32-bit words: R = #18 as 9845, Q = #17 0 words
//  1..98, 1 words 99..128. Out: #100 the record's bytes, #101 the words in
//  this part, #102.. the words (little-endian, whole numbers; 0 beyond the
//  part): a client rebuilds the stored record bit for bit (the LinuxCNC
//  kinematics' spindle file). Statuses as 9845.
// Macro 9846: check (check.hpp): the last identification (9842 with R = 0)
//  against the stored model, nothing stored: a_x, a_y, w_x, w_y (arcsec,
//  tolerance #805) and e_x, e_y (mm, #806), each its parameter's difference
//  with the sigma of both fits' covariances. Out: #100..#111 (check.hpp
//  convention 3) for Q = #17. kNoTable when none was identified or none is
//  stored, kResultReplaced, kArgumentOutOfRange (Q).
#pragma once

#include <cstdint>

#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/applied_records.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros::spindle {

// The record of the stored model (key 5; applied_records.hpp, as the kinematics read it too).
using ModelRecord = SpindleModelRecord;

// The identification under way, and the last one (`computed`, complete when
// the method's State::built says so).
struct Work {
  core::SpindleBuilder builder;
  core::SpindleModel computed;
  // The gates after the fit, in a step of their own (gates.hpp).
  enum class Phase : std::uint8_t { kFit, kGates } phase = Phase::kFit;
  double spacing_mm = 0.0;
};

struct Shape {
  static constexpr List<VarInfo> kRows = list_of(spindle::kRows);
  using Session = core::SpindleBins;
  using Work = spindle::Work;
};
using Context = MethodContext<Shape>;

struct State {
  StoredTable<ModelRecord> table;  // the stored model the controller corrects with
  bool built = false;              // a 9842 has succeeded since start
};

// The direct call for the controller's programs: theta_e (rad), d_e and the
// tool-tip error (mm) at spindle angle phi_deg and tool length tool_mm (below
// the gauge line), from the stored model; const, no allocation, no lock.
// kNotFinite, kArgumentOutOfRange (tool_mm outside 0..1e5), the stored
// table's reason (stored_table.hpp) when no model is stored.
[[nodiscard]] core::Result<core::SpindleCorrection> tool_tip_correction(const State& state, double phi_deg,
                                                                        double tool_mm);

MacroStep run_session_clear(Context& ctx, State& state);
MacroStep run_session_add(Context& ctx, State& state);
MacroStep run_build(Context& ctx, State& state);
MacroStep run_correction(Context& ctx, State& state);
MacroStep run_report(Context& ctx, State& state);
MacroStep run_model(Context& ctx, State& state);
MacroStep run_words(Context& ctx, State& state);
MacroStep run_check(Context& ctx, State& state);

// clang-format off
inline constexpr InputRef kAddInputs[] = {
  {var::kArgS, 1, "Spindle angle (deg from the M19 zero, M03 direction positive; any revolution)."},
  {var::kArgT, 1, "Ball: 1 nearer the spindle, 2 farther along the tool."},
  {var::kArgX, 3, "Ball centre X, Y, Z (mm, analyser frame)."},
};
inline constexpr InputRef kBuildInputs[] = {
  {var::kArgD, 1, "O1 (upper bearing seat centre) to the gauge line along the spindle (mm)."},
  {var::kArgM, 1, "1 confirms a store whose change against the stored model exceeds #804."},
  {var::kArgR, 1, "1 stores the model (unlocked only), 0 identifies only."},
  {var::kArgU, 1, "Ball 1's centre below the gauge line (mm)."},
  {var::kArgV, 1, "Ball 2's centre below the gauge line (mm), more than U."},
  {var::kSpindleMaxGap, 1, "Widest gap a ball's angles may leave."},
  {var::kSpindleProbeNoise, 2, "The fit gate's noise and form allowance."},
  {var::kSpindleMaxSpacingError, 1, "The ball-spacing gate."},
  {var::kSpindleMaxChange, 1, "The change gate's limit."},
  {var::kSpindleMinBallSpacing, 1, "The ball-distance gate."},
  {var::kGateConfidence, 1, "The fit gate's confidence."},
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

inline constexpr InputRef kWordsInputs[] = {
  {var::kArgQ, 1, "Part 0 (words 1..98) or 1 (words 99..128)."},
  {var::kArgR, 1, "0 the last identification, 1 the stored model."},
};

// 9847's words a part.
inline constexpr std::size_t kWordsPerPart = 98;

inline constexpr InputRef kSpindleCheckInputs[] = {
  {var::kArgQ, 1, "The figure to publish in #104..#111: 1..#101, 0 the worst."},
  {var::kSpindleCheckTilt, 2, "The tilts' and the offset's tolerances."},
};

inline constexpr MacroInfo kMacros[] = {
  macro<&run_session_clear>(kMacroSessionClear, "spindle_session_clear", "Empty the spindle analyser session.", kSessionOutputs),
  macro<&run_session_add>(kMacroSessionAdd, "spindle_session_add", "Add one analyser sample (spindle angle, ball, centre) to the session.",
        kAddInputs, kSessionOutputs),
  macro<&run_build>(kMacroBuild, "spindle_build",
        "Identify the tool-axis model from the session (several steps); R = 1 stores it.", kBuildInputs,
        kBuildOutputs),
  macro<&run_correction>(kMacroCorrection, "spindle_correction",
        "Correction query: theta_e, d_e and the tool-tip error at a spindle angle and tool length, from the stored model.",
        kCorrectionInputs, kCorrectionOutputs),
  macro<&run_report>(kMacroReport, "spindle_report",
        "The correction with its uncertainties and its mean over a revolution, for reports.", kReportInputs,
        kReportOutputs),
  macro<&run_model>(kMacroModel, "spindle_model", "A parameter of the model with its uncertainty, and the fit's figures.",
        kModelInputs, kModelOutputs),
  macro<&run_check>(kMacroCheck, "spindle_check",
        "Check: the last identification (R = 0) against the stored model, nothing stored; a verdict against #805, #806.",
        kSpindleCheckInputs, kCheckOutputs),
  macro<&run_words>(kMacroModelWords, "spindle_model_words",
        "The model's stored record exactly, in two parts of 32-bit words: for a client that rebuilds it.",
        kWordsInputs, kWordsOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::spindle
