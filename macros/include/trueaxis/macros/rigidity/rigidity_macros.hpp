// M3's macros: the ball-position session, the table build, the compensation
// query (INTERFACE.md macro 9833), the per-pose report and the point
// conversion; and the direct C++ query for the controller's real-time task.
//
// Macro 9830: clear the session. Out: #100 count (0), #101 capacity (512).
// Macro 9831: add a ball position: A = #1, C = #3 (commanded, deg), X, Y, Z =
//  #24..#26 (ball centre, mm, machine frame). Out: #100 count, #101 capacity.
//  kSessionFull at capacity (nothing added).
// Macro 9832: build the table from the session (core RigidityBuilder, several
//  steps): min C arc from #600. R = #18: 1 also stores the table (only while
//  unlocked: kTableLocked; committed whole through the keyed store, then made
//  live), 0 builds it only (9834 R = 0 reports it). Out: #100..#111
//  (rigidity_map.hpp kBuildOutputs). Status: those of the builder (too_few_poses,
//  no_reference_pose, too_few_c_positions, arc_too_short, too_many_points for
//  a pose of more than kMaxPoseSamples (36) ...); the session is kept either
//  way.
// Macro 9833: the rotation vector at commanded A = #1 from the stored (live)
//  table: Q = #17 blend (0 linear, 1 geodesic, 2 natural cubic spline, 3 cubic
//  spline with not-a-knot ends: more exact near the ends of the range for a
//  smooth law; rigidity_compensation.hpp), R = #18 (1 clamps an A
//  outside the measured range to the nearest pose, 0 refuses it). Out: #100..#102
//  (arcsec, machine frame), #103 norm. Without a stored table kNoTable (none
//  stored), kTableDamaged (its record failed the CRC at start) or kTableInvalid
//  (it did not decode); kArgumentOutOfRange for a blend or R not in its set;
//  kOutsideMeasuredRange for A outside the measured range with R = 0.
// Macro 9834: pose Q = #17 (1..n, in A order) of the table: R = #18 0 the last
//  table built since start, 1 the stored one. Out: #100..#117 (kPoseOutputs).
// Macro 9835: convert a point X, Y, Z (#24..#26) and a direction I, J, K
//  (#4..#6) at commanded A = #1, C = #3 from where the ideal (theory) machine
//  puts them to where the real (actual) one does; R = #18 = 1 the other way.
//  Blend Q = #17 as 9833, no clamping. Out: #100..#105 (kConvertOutputs).
#pragma once

#include <cstdint>

#include "trueaxis/core/rigidity_compensation.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/macros/live_table.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/session.hpp"

namespace trueaxis::macros::rigidity {

static_assert(kSessionCapacity <= core::kMaxRigiditySamples, "the builder takes the whole session");

struct State {
  Session<core::RigiditySample, kSessionCapacity> samples;
  core::RigidityBuilder builder;
  bool built = false;   // builder.table() holds the table of the last 9832 that succeeded
  bool staged = false;  // 9832 staged builder.table() for the commit now under way
  LiveTable<core::RigidityTable> live;   // the stored table the controller queries
  // Why `live` holds no table: kNoTable (none stored), kTableDamaged (the stored
  // record failed its CRC at start) or kTableInvalid (it did not decode).
  core::Status missing = core::Status::kNoTable;
  core::RigidityTable decoded;           // where a stored record is decoded before it goes live
};

// The direct call for the controller's real-time task: the rotation vector
// (rad, machine frame) at commanded A from the live table; const, no
// allocation, no lock (live_table.hpp). Without a live table State::missing
// (kNoTable, kTableDamaged or kTableInvalid); the statuses of
// core::rigidity_rotvec_rad otherwise.
[[nodiscard]] core::Result<core::Vec3> compensation_rad(const State& state, double a_deg, core::Blend blend,
                                                        bool clamp);

// A stored rigidity record (at start) becomes the live table; a malformed one
// does not (the controller then has no table, and its queries say kTableInvalid).
void on_record(State& state, const std::uint8_t* bytes, std::size_t length);

// The stored rigidity record failed its CRC at start: no live table, and the
// queries say kTableDamaged until a table is stored again.
void on_damaged(State& state);

// The table 9832 built and staged has been committed: the macro succeeds, its
// table becomes the last built one and the live one.
void on_committed(State& state);

MacroStep run_session_clear(MacroContext& ctx);
MacroStep run_session_add(MacroContext& ctx);
MacroStep run_build(MacroContext& ctx);
MacroStep run_query(MacroContext& ctx);
MacroStep run_pose(MacroContext& ctx);
MacroStep run_convert(MacroContext& ctx);

// clang-format off
inline constexpr InputRef kAddInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgC, 1, "Commanded C (deg)."},
  {var::kArgX, 3, "Ball centre X, Y, Z (mm, machine frame)."},
};
inline constexpr InputRef kBuildInputs[] = {
  {var::kArgR, 1, "1 stores the table (unlocked only), 0 builds it only."},
  {var::kRigidityMinCArc, 1, "Shortest C arc a pose may span."},
};
inline constexpr InputRef kQueryInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgQ, 1, "Blend: 0 linear, 1 geodesic, 2 cubic (natural), 3 cubic (not-a-knot)."},
  {var::kArgR, 1, "1 clamps an A outside the measured range to the nearest pose; 0 refuses it."},
};
inline constexpr InputRef kPoseInputs[] = {
  {var::kArgQ, 1, "Pose number, 1..n in A order."},
  {var::kArgR, 1, "0 the table built last, 1 the stored table."},
};
inline constexpr InputRef kConvertInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgC, 1, "Commanded C (deg)."},
  {var::kArgI, 3, "Direction I, J, K (machine frame)."},
  {var::kArgQ, 1, "Blend: 0 linear, 1 geodesic, 2 cubic (natural), 3 cubic (not-a-knot)."},
  {var::kArgR, 1, "0 theory to actual, 1 actual to theory."},
  {var::kArgX, 3, "Point X, Y, Z (mm, machine frame)."},
};

inline constexpr MacroInfo kMacros[] = {
  macro(9830, &run_session_clear, "rigidity_session_clear", "Empty the rigidity session.", kSessionOutputs),
  macro(9831, &run_session_add, "rigidity_session_add",
        "Add one ball position (commanded A, C and the ball centre) to the rigidity session.",
        kAddInputs, kSessionOutputs),
  macro(9832, &run_build, "rigidity_build",
        "Build the rigidity table from the session (several steps); R = 1 stores it.", kBuildInputs, kBuildOutputs),
  macro(9833, &run_query, "rigidity_query",
        "Compensation query: the rotation vector at a commanded A from the stored table.", kQueryInputs,
        kQueryOutputs),
  macro(9834, &run_pose, "rigidity_pose", "One pose of the rigidity table, for reports.", kPoseInputs,
        kPoseOutputs),
  macro(9835, &run_convert, "rigidity_convert",
        "Convert a point and a direction between the theoretical and the actual machine at (A, C).",
        kConvertInputs, kConvertOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::rigidity
