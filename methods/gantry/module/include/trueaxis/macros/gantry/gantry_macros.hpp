// M2's macros: the tracker-point session, the computation of the frames and
// their storage, the reports, the point conversion (docs/INTERFACE.md macro
// 9825); and the direct C++ conversion for the controller's programs.
//
// The session lives in the shared session arena and the computation in the
// shared work arena (method_context.hpp contract 4): 9821, 9822 and 9823 answer
// kSessionClosed when another method's session has replaced this one, and
// 9824/9826 with R = 0 kResultReplaced when another method's computation has
// used the work arena since.
//
// Macro 9820: clear the session (points and sub-machine parameters), opening
//  it and closing another method's.
//  Out: #100 points (0), #101 capacity (2048), #102 groups (0).
// Macro 9821: add a tracker point X, Y, Z = #24..#26 (mm, tracker frame) to the
//  group T = #20, Q = #17, D = #7 (gantry_map.hpp convention 3). Out: #100..#102.
//  A group's points arrive together and in measuring order: a point for a group
//  that another group's points have followed is refused (group_not_contiguous).
//  Refused, nothing added: kDuplicateSample (X, Y, Z equal bit for bit to a
//  point already in the same group: a file or a row given twice; checked
//  first, against at most the group's capacity of points),
//  kArgumentOutOfRange (T not 0..8, Q not 1..9, Q not
//  allowed for T: 1..4 need T = 0, 5..9 need T = 1..8; D not 1..4 for a pass;
//  a coordinate beyond 1e5 mm), kNotFinite, kTooManyPoints (the group is at its
//  capacity: kMaxPlanePoints, kMaxPassPoints, kMaxCirclePoints), kSessionFull.
// Macro 9822: sub-machine T = #20 (1..8): swing length D = #7 (mm, >= 0) and the
//  nominal tool direction I, J, K = #4..#6 (tracker frame, only its sense is
//  used); with Q = #17 = 1, X, Y, Z = #24..#26 its nominal origin (the tool tip
//  at home, mm, global frame: from the machine's drawing), which 9823 holds
//  the measured origin to within #708. Given again, it replaces. Out:
//  #100..#102. kArgumentOutOfRange for a T, a negative or huge D, a zero
//  direction, or a Q other than 0 and 1; kNotFinite.
// Macro 9823: compute the frames of every sub-machine in the session (any
//  point or 9822), in id order (core::GantryBuilder, one fit per step), with the
//  arc limit #700 and each fit's own residuals as its noise (docs/INTERFACE.md:
//  sigmas from the data's scatter); the noise floors and form errors of the bed
//  and the gantry from the tracker's stated noise, sigma = #701 + #702 per metre
//  of distance (core GantryOptions::instrument, additive, the tracker at the
//  points' origin). R = #18: 1 also stores them (only while
//  unlocked: kTableLocked): the computed sub-machines replace theirs in the
//  stored frames, the others stay, committed whole through the keyed store and
//  then made live; 0 computes only (9824, 9826 with R = 0 report it). Out:
//  #100..#103 (kBuildOutputs). Status: those of core::compute_gantry_frames
//  (gantry_frames.hpp, gantry_fits.hpp); a sub-machine with points but no 9822,
//  or with a 9822 but no points, is kMissingGroup (give 9822 only for the
//  sub-machines measured). Gates (gates.hpp), in this order: the bed's span
//  (#703), each swing length (#709), the circles' fit (#901), each measured
//  origin against its nominal one (#708), then with R = 1 the change against
//  the stored frames (#704, #705). The session is kept either way.
// Macro 9824: the global frame and the set of sub-machines: R = #18 0 of the
//  last computation since start, 1 of the stored frames. Out: #100..#125
//  (#120..#125 the noise floors and form errors: -1 from a table stored before
//  them, gantry_table.hpp convention 4).
// Macro 9825: point conversion (docs/INTERFACE.md): T = #20 sub-machine, X, Y, Z =
//  #24..#26 a point in the global frame -> #100..#102 the point in that
//  sub-machine's frame, from the stored frames. kArgumentOutOfRange for T not
//  1..8, kNoTable when that sub-machine has no stored frame (or none is stored),
//  kTableDamaged / kTableInvalid when the stored record failed its CRC or did
//  not decode at start, kNotFinite.
// Macro 9826: one sub-machine's frame and figures: T = #20, R = #18 as 9824.
//  Out: #100..#131 (kSubOutputs; #127..#131 the squareness, A-to-C offset and
//  angle sigmas, -1 from a table stored before them). kNoTable when that sub-machine is not in the
//  chosen set.
// Macro 9827: check (check.hpp): the frames computed last (9823 with R = 0)
//  against the stored frames, nothing stored. Per sub-machine both hold, in
//  id order: its origin (kCheckOrigin, tolerance #706) and its axes' turn
//  (kCheckAngle, #707). Out: #100..#111 (check.hpp convention 3) for Q =
//  #17. kNoTable when none was computed or none is stored, kResultReplaced,
//  kNothingToCheck (no sub-machine in both), kArgumentOutOfRange (Q).
#pragma once

#include <cstdint>

#include "trueaxis/core/gantry_frames.hpp"
#include "trueaxis/core/gantry_table.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros::gantry {

static_assert(kMaxPasses <= core::kMaxPasses && kMaxPlanePoints <= core::kMaxGroupPoints &&
                  kMaxPassPoints <= core::kMaxGroupPoints && kMaxCirclePoints <= core::kMaxCirclePoints,
              "the module's group capacities must be within the core's");

// The session's groups, numbered compactly: 0 bed, 1 side_1, 2 side_2, 3.. the
// gantry's passes, then per sub-machine its x, y, z passes, C and A circles.
inline constexpr std::size_t kGlobalGroups = 3 + kMaxPasses;
inline constexpr std::size_t kSubGroups = 3 * kMaxPasses + 2;
inline constexpr std::size_t kGroupCount = kGlobalGroups + core::kMaxSubMachines * kSubGroups;

struct SubMachineParameters {
  bool given = false;
  double swing_mm = 0.0;
  core::Vec3 tool_direction = core::Vec3::Zero();
  bool nominal_given = false;                 // Q = 1 in its 9822
  core::Vec3 nominal_origin_mm = core::Vec3::Zero();  // global frame
};

// The tracker points, group by group (gantry_macros.hpp 9821), and the
// sub-machines' parameters. Points of one group are contiguous, so a group is a
// core::PointSpan into `points`.
class PointSession {
 public:
  void clear();
  // The group index of (T, Q, D), or kArgumentOutOfRange.
  static core::Result<std::size_t> group_of(double t, double q, double d);
  [[nodiscard]] core::Status add(std::size_t group, const core::Vec3& p_mm);
  [[nodiscard]] core::Status set_parameters(double t, double swing_mm, const core::Vec3& tool, double nominal_flag,
                                           const core::Vec3& nominal_origin_mm);

  std::size_t size() const { return count_; }
  std::size_t groups() const;
  core::PointSpan span(std::size_t group) const { return {points_ + first_[group], count_in_[group]}; }
  const SubMachineParameters& parameters(std::size_t id) const { return parameters_[id - 1]; }
  // True when sub-machine `id` has a point or parameters in the session.
  bool mentions(std::size_t id) const;

 private:
  core::Vec3 points_[kSessionCapacity];
  std::uint16_t first_[kGroupCount] = {};
  std::uint16_t count_in_[kGroupCount] = {};
  SubMachineParameters parameters_[core::kMaxSubMachines];
  std::size_t count_ = 0;
  std::size_t last_group_ = kGroupCount;  // none
};

// The record of the stored frames (key 4).
struct FramesRecord : TableCodec<core::GantryTable, &core::decode_gantry_table, &core::encode_gantry_table,
                                 core::kGantryTableBytes> {
  static constexpr RecordSpec kRecord{4, 1, 3072, "gantry_frames"};
};
static_assert(core::kGantryTableBytes <= FramesRecord::kRecord.capacity_bytes, "the frames must fit their record");

// The computation under way, and the last one (`frames`, complete when the
// method's State::built says so).
struct Work {
  core::GantryInput input;      // spans into the session, for the build under way
  core::GantryBuilder builder;
  core::GantryFrames frames;
  bool computed = false;        // 9823: the builder has finished; outputs and storing follow
  core::GantryTable merged;     // the stored frames with the computation merged in (R = 1), or a report's table
  double bed_span_mm = 0.0;     // the bed-span gate's figure (9823 #108)
};

struct Shape {
  static constexpr List<VarInfo> kRows = list_of(gantry::kRows);
  using Session = PointSession;
  using Work = gantry::Work;
};
using Context = MethodContext<Shape>;

struct State {
  StoredTable<FramesRecord> table;  // the stored frames the controller converts with
  bool built = false;               // a 9823 has succeeded since start
};

// The direct call for the controller's programs: a point in the global frame
// (mm) in sub-machine `id`'s frame, from the stored frames; const, no
// allocation, no lock. kArgumentOutOfRange for an id outside 1..8, kNoTable
// when that sub-machine has no stored frame, the stored table's reason
// (stored_table.hpp) when no frames are stored.
[[nodiscard]] core::Result<core::Vec3> sub_point_mm(const State& state, int id, const core::Vec3& p_global_mm);

MacroStep run_session_clear(Context& ctx, State& state);
MacroStep run_session_add(Context& ctx, State& state);
MacroStep run_parameters(Context& ctx, State& state);
MacroStep run_build(Context& ctx, State& state);
MacroStep run_global(Context& ctx, State& state);
MacroStep run_convert(Context& ctx, State& state);
MacroStep run_sub(Context& ctx, State& state);
MacroStep run_check(Context& ctx, State& state);

// clang-format off
inline constexpr InputRef kAddInputs[] = {
  {var::kArgD, 1, "Pass number K, 1..4 (passes only)."},
  {var::kArgQ, 1, "Group kind: 1 bed, 2 side_1, 3 side_2, 4 gantry pass, 5 x pass, 6 y pass, 7 z pass, 8 C circle, 9 A circle."},
  {var::kArgT, 1, "Sub-machine N, 1..8; 0 for bed, sides and gantry."},
  {var::kArgX, 3, "Point X, Y, Z (mm, tracker frame)."},
};
inline constexpr InputRef kParameterInputs[] = {
  {var::kArgI, 3, "Nominal tool direction I, J, K (tracker frame)."},
  {var::kArgD, 1, "Swing length L, wrist centre to tool tip (mm)."},
  {var::kArgQ, 1, "1: X, Y, Z hold the nominal origin; 0: none given."},
  {var::kArgT, 1, "Sub-machine N, 1..8."},
  {var::kArgX, 3, "Nominal origin X, Y, Z (the tool tip at home, mm, global frame), with Q = 1."},
};
inline constexpr InputRef kBuildInputs[] = {
  {var::kArgM, 1, "1 confirms a store whose change against the stored frames exceeds #704 or #705."},
  {var::kArgR, 1, "1 stores the frames (unlocked only), 0 computes only."},
  {var::kGantryMinArc, 1, "Shortest arc a C or A circle may span."},
  {var::kGantryTrackerNoise, 2, "The tracker's stated noise: constant part and part per metre (1 sigma per axis)."},
  {var::kGantryMinBedSpan, 3, "The gates: the bed's span, the largest origin move and axes' turn a store takes without M = 1."},
  {var::kGantryMaxNominalOffset, 2, "The gates: a measured origin's largest distance from its nominal one, the shortest swing length."},
  {var::kGateConfidence, 1, "The fit gate's confidence."},
};
inline constexpr InputRef kGlobalInputs[] = {
  {var::kArgR, 1, "0 the last computation, 1 the stored frames."},
};
inline constexpr InputRef kConvertInputs[] = {
  {var::kArgT, 1, "Sub-machine N, 1..8."},
  {var::kArgX, 3, "Point X, Y, Z (mm, global frame)."},
};
inline constexpr InputRef kSubInputs[] = {
  {var::kArgR, 1, "0 the last computation, 1 the stored frames."},
  {var::kArgT, 1, "Sub-machine N, 1..8."},
};

inline constexpr InputRef kGantryCheckInputs[] = {
  {var::kArgQ, 1, "The figure to publish in #104..#111: 1..#101, 0 the worst."},
  {var::kGantryCheckOrigin, 2, "The origin's and the axes' tolerances."},
};

inline constexpr MacroInfo kMacros[] = {
  macro<&run_session_clear>(kMacroSessionClear, "gantry_session_clear", "Empty the gantry session (points and sub-machine parameters).",
        kSessionOutputs),
  macro<&run_session_add>(kMacroSessionAdd, "gantry_session_add", "Add one tracker point to a group of the gantry session.",
        kAddInputs, kSessionOutputs),
  macro<&run_parameters>(kMacroSubMachine, "gantry_sub_machine",
        "Set a sub-machine's swing length and nominal tool direction in the gantry session.", kParameterInputs,
        kSessionOutputs),
  macro<&run_build>(kMacroBuild, "gantry_build",
        "Compute the global and sub-machine frames from the session (several steps); R = 1 stores them.",
        kBuildInputs, kBuildOutputs),
  macro<&run_global>(kMacroGlobal, "gantry_global", "The global frame and the set of sub-machines, for reports.",
        kGlobalInputs, kGlobalOutputs),
  macro<&run_convert>(kMacroConvert, "gantry_convert",
        "Point conversion: a point in the global frame into a sub-machine's frame, from the stored frames.",
        kConvertInputs, kPointOutputs),
  macro<&run_sub>(kMacroSubReport, "gantry_sub_report", "One sub-machine's frame and figures, for reports.", kSubInputs,
        kSubOutputs),
  macro<&run_check>(kMacroCheck, "gantry_check",
        "Check: the frames computed last (R = 0) against the stored frames, nothing stored; a verdict against #706, #707.",
        kGantryCheckInputs, kCheckOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::gantry
