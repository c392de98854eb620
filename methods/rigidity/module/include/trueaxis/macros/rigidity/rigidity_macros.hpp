// M3's macros: the ball-position session, the table build, the compensation
// query (docs/INTERFACE.md macro 9833), the per-pose report and the point
// conversion; and the direct C++ query for the controller's real-time task.
//
// The session lives in the shared session arena and the build in the shared
// work arena (method_context.hpp contract 4).
//
// Macro 9830: clear the session (opening it, and closing another method's).
//  Out: #100 count (0), #101 capacity (512).
// Macro 9831: add a ball position: A = #1, C = #3 (commanded, deg), X, Y, Z =
//  #24..#26 (ball centre, mm, machine frame). Out: #100 count, #101 capacity.
//  kDuplicateSample for a sample whose A, C, X, Y and Z all equal, bit for
//  bit, those of one already in the session (a file or a row given twice; a
//  pose measured again differs in its measured centre); kSessionFull at
//  capacity; nothing added either way. kSessionClosed when another method's
//  session has replaced this one (9830 opens it again). At most 512
//  comparisons (the session's capacity).
// Macro 9832: build the table from the session (core RigidityBuilder, several
//  steps): min C arc from #600, ball noise from #601. R = #18: 1 also stores the table (only while
//  unlocked: kTableLocked; committed whole through the keyed store, then made
//  live), 0 builds it only (9834 R = 0 reports it). Out: #100..#113
//  (rigidity_map.hpp kBuildOutputs). Status: those of the builder (too_few_poses,
//  no_reference_pose, too_few_c_positions, arc_too_short, too_many_points for
//  a pose of more than kMaxPoseSamples (36) ...), kSessionClosed; the session
//  is kept either way. The gates (gates.hpp), after the build and before
//  anything is published or stored, in a step of their own: fit
//  (fit_beyond_noise: a pose's C-circle residuals against #601), a_error
//  (a_error_implausible: |A positioning error| above #602), c_radius
//  (c_radius_implausible: the reference pose's mean ball radius from its C
//  circle below #603), change (change_beyond_limit: with R = 1 and a stored
//  table, a pose's rotation vector more than #604 from the stored table's at
//  its A, unless M = #13 is 1). #114..#117 publish the change and the fit
//  figure. The table records #904, the axes' home it was measured under
//  (stored_table.hpp contract 4).
// Macro 9833: the rotation vector at commanded A = #1 from the stored (live)
//  table: Q = #17 blend (0 linear, 1 geodesic, 2 natural cubic spline, 3 cubic
//  spline with not-a-knot ends: more exact near the ends of the range for a
//  smooth law; rigidity_compensation.hpp), R = #18 (1 clamps an A
//  outside the measured range to the nearest pose, 0 refuses it). Out: #100..#102
//  (arcsec, machine frame), #103 norm. Without a stored table kNoTable (none
//  stored), kTableDamaged (its record failed the CRC at start) or kTableInvalid
//  (it did not decode); kArgumentOutOfRange for a blend or R not in its set;
//  kOutsideMeasuredRange for A outside the measured range with R = 0;
//  kHomeChanged when the stored table was built under another #904 than now
//  (so 9835, 9836 and compensation_rad too; 9834 and 9837 still report it).
// Macro 9834: pose Q = #17 (1..n, in A order) of the table: R = #18 0 the last
//  table built since start, 1 the stored one. Out: #100..#120 (kPoseOutputs):
//  #118 the A positioning error's sigma (stored with the table); #119, #120
//  the C-circle RMS's sigma and noise floor, computed at the query from the
//  pose's RMS and sample count and the ball noise #601 (core
//  residual_rms_noise), so a stored table shows them under today's #601.
//  With R = 0: kNoTable when none was built, kResultReplaced when another
//  method's computation has used the work arena since.
// Macro 9835: convert a point X, Y, Z (#24..#26) and a direction I, J, K
//  (#4..#6) at commanded A = #1, C = #3 from where the ideal (theory) machine
//  puts them to where the real (actual) one does; R = #18 = 1 the other way.
//  Blend Q = #17 as 9833, no clamping. Out: #100..#105 (kConvertOutputs).
// Macro 9837: the table's stored reals (rigidity_codec.hpp): R = #18 0 the
//  table built last, 1 the stored one; Q = #17 0 the header, 1..n pose Q.
//  Out: #100 pose count, #101 the reference pose (1-based), #102.. the reals
//  (Q = 0: 10, Q = n: 27), exactly as stored (radians, mm), #129 the home
//  identity it was built under: a client rebuilds
//  the stored record bit for bit (core::encode_rigidity_reals), e.g. the
//  LinuxCNC kinematics' table file. Statuses as 9834.
// Macro 9836: check (check.hpp): the table built last (9832 with R = 0)
//  against the stored one, nothing stored. Per pose of the build but the
//  reference that the stored table has too (A within kPoseAToleranceDeg; the
//  others are not judged), item its number in the build (1-based, A order):
//  its rotation vector against the stored pose's (kCheckRotation, tolerance
//  #605) and its A positioning error likewise (kCheckAError, #606). Out:
//  #100..#111 (check.hpp convention 3) for Q = #17. kNoTable when none was
//  built or none is stored, kResultReplaced, kNothingToCheck (no pose in
//  common), kArgumentOutOfRange (Q).
#pragma once

#include <cstdint>

#include "trueaxis/core/rigidity_compensation.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/services.hpp"
#include "trueaxis/macros/session.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros::rigidity {

static_assert(kSessionCapacity <= core::kMaxRigiditySamples, "the builder takes the whole session");
static_assert(kMaxPoseSamples <= core::kMaxCirclePoints, "a pose's circle fit takes the pose's samples");

using RigiditySession = Session<core::RigiditySample, kSessionCapacity>;

// The build under way, and the last table built (builder.table()).
struct Work {
  core::RigidityBuilder builder;
  bool built = false;  // the builder has finished: the next step runs the gates
};

struct Shape {
  static constexpr List<VarInfo> kRows = list_of(rigidity::kRows);
  using Session = RigiditySession;
  using Work = rigidity::Work;
};
using Context = MethodContext<Shape>;

struct State {
  StoredTable<RigidityTableRecord> table;  // the stored table the controller queries
  bool built = false;  // a 9832 has succeeded since start (its table is the work's, while it lasts)
};

// The direct call for the controller's real-time task: the rotation vector
// (rad, machine frame) at commanded A from the stored table; const, no
// allocation, no lock (live_table.hpp). Without a stored table kNoTable,
// kTableDamaged or kTableInvalid (stored_table.hpp); the statuses of
// core::rigidity_rotvec_rad otherwise.
[[nodiscard]] core::Result<core::Vec3> compensation_rad(const State& state, double a_deg, core::Blend blend,
                                                        bool clamp);

MacroStep run_session_clear(Context& ctx, State& state);
MacroStep run_session_add(Context& ctx, State& state);
MacroStep run_build(Context& ctx, State& state);
MacroStep run_query(Context& ctx, State& state);
MacroStep run_pose(Context& ctx, State& state);
MacroStep run_convert(Context& ctx, State& state);
MacroStep run_check(Context& ctx, State& state);
MacroStep run_reals(Context& ctx, State& state);

// clang-format off
inline constexpr InputRef kAddInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgC, 1, "Commanded C (deg)."},
  {var::kArgX, 3, "Ball centre X, Y, Z (mm, machine frame)."},
};
inline constexpr InputRef kBuildInputs[] = {
  {var::kArgR, 1, "1 stores the table (unlocked only), 0 builds it only."},
  {var::kArgM, 1, "1 confirms a store whose change against the stored table exceeds #604."},
  {var::kRigidityMinCArc, 1, "Shortest C arc a pose may span."},
  {var::kRigidityBallNoise, 1, "The ball instrument's noise, for the C-circle RMS's noise floor and sigma, and the fit gate."},
  {var::kRigidityMaxAError, 1, "The plausibility gate on the A positioning error."},
  {var::kRigidityMinCRadius, 1, "The plausibility gate on the ball's C radius."},
  {var::kRigidityMaxChange, 1, "The change gate's limit."},
  {var::kGateConfidence, 1, "The fit gate's confidence."},
  {var::kHomeIdentity, 1, "The axes' home the table records."},
};
inline constexpr InputRef kQueryInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgQ, 1, "Blend: 0 linear, 1 geodesic, 2 cubic (natural), 3 cubic (not-a-knot)."},
  {var::kArgR, 1, "1 clamps an A outside the measured range to the nearest pose; 0 refuses it."},
};
inline constexpr InputRef kPoseInputs[] = {
  {var::kArgQ, 1, "Pose number, 1..n in A order."},
  {var::kArgR, 1, "0 the table built last, 1 the stored table."},
  {var::kRigidityBallNoise, 1, "The ball instrument's noise, for the C-circle RMS's noise floor and sigma."},
};
inline constexpr InputRef kConvertInputs[] = {
  {var::kArgA, 1, "Commanded A (deg)."},
  {var::kArgC, 1, "Commanded C (deg)."},
  {var::kArgI, 3, "Direction I, J, K (machine frame)."},
  {var::kArgQ, 1, "Blend: 0 linear, 1 geodesic, 2 cubic (natural), 3 cubic (not-a-knot)."},
  {var::kArgR, 1, "0 theory to actual, 1 actual to theory."},
  {var::kArgX, 3, "Point X, Y, Z (mm, machine frame)."},
};

inline constexpr InputRef kRealsInputs[] = {
  {var::kArgQ, 1, "0 the header, 1..n a pose in A order."},
  {var::kArgR, 1, "0 the table built last, 1 the stored table."},
};

inline constexpr InputRef kRigidityCheckInputs[] = {
  {var::kArgQ, 1, "The figure to publish in #104..#111: 1..#101, 0 the worst."},
  {var::kRigidityCheckRotation, 1, "The rotation vector's tolerance."},
  {var::kRigidityCheckAError, 1, "The A positioning error's tolerance."},
};

inline constexpr MacroInfo kMacros[] = {
  macro<&run_session_clear>(kMacroSessionClear, "rigidity_session_clear", "Empty the rigidity session.", kSessionOutputs),
  macro<&run_session_add>(kMacroSessionAdd, "rigidity_session_add",
        "Add one ball position (commanded A, C and the ball centre) to the rigidity session.",
        kAddInputs, kSessionOutputs),
  macro<&run_build>(kMacroBuild, "rigidity_build",
        "Build the rigidity table from the session (several steps); R = 1 stores it.", kBuildInputs, kBuildOutputs),
  macro<&run_query>(kMacroQuery, "rigidity_query",
        "Compensation query: the rotation vector at a commanded A from the stored table.", kQueryInputs,
        kQueryOutputs),
  macro<&run_pose>(kMacroPose, "rigidity_pose", "One pose of the rigidity table, for reports.", kPoseInputs,
        kPoseOutputs),
  macro<&run_convert>(kMacroConvert, "rigidity_convert",
        "Convert a point and a direction between the theoretical and the actual machine at (A, C).",
        kConvertInputs, kConvertOutputs),
  macro<&run_check>(kMacroCheck, "rigidity_check",
        "Check: the table built last (R = 0) against the stored table, nothing stored; a verdict against #605, #606.",
        kRigidityCheckInputs, kCheckOutputs),
  macro<&run_reals>(kMacroTableReals, "rigidity_table_reals",
        "The table's stored reals, header (Q = 0) or pose Q, exactly: for a client that rebuilds the stored record.",
        kRealsInputs, kRealsOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::rigidity
