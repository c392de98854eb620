// M1's macros: three-point and N-point auto-level, and the leveling session.
//
// Macro 9810: three-point auto-level (docs/INTERFACE.md, docs/METHODS.md M1).
//  In:  P1 = G57 X,Y,Z (#5281..#5283), P2 = G58 (#5301..), P3 = G59 (#5321..), mm,
//       machine frame, probed with the table at A = #1, C = #3 (deg); optional
//       outward direction I, J, K (#4..#6, machine frame as probed, any length;
//       0,0,0 = +Z). Configuration #500..#507.
//  Out: #100..#118 (level_map.hpp kLevelOutputs). With #508 level_axes = 0 it
//       levels on the ideal axes Rx(A) Rz(C) (core::level_face); with 1 on the
//       calibrated axes of the stored rigidity table (core::level_on_table,
//       not-a-knot cubic blend, no clamping); #116 says which ran. #104..#107
//       are the face at table zero on those axes; #117, #118 the face's tilt
//       in the machine frame where it was probed, and its 1 sigma, on either
//       axes (leveling.hpp convention 8): what an operator's check after
//       leveling reads, the table left at the leveled pose (A, C = it).
//  Status: those of core::level_face or core::level_on_table; kNoTable when
//  #508 = 1 and no rigidity table is stored, kMethodNotBuilt when the module
//  has no rigidity method (the calibrated axes are its stored table, which
//  it offers through the platform: services.hpp).
// Macro 9811: N-point auto-level, 3 <= Q (#17) <= 32 points from the point list
//  #1001.. (X, Y, Z interleaved); otherwise as 9810. kArgumentOutOfRange when Q
//  is not a whole number in 3..32.
// Macro 9812: clear the leveling session. Out: #100 count (0), #101 capacity.
// Macro 9813: add the point X, Y, Z (#24..#26, mm, machine frame) to the
//  session. Out: #100 count, #101 capacity. kSessionFull when it holds
//  kSessionCapacity points (nothing added).
// Macro 9814: level through the session's points, as 9811 (A, C, I, J, K as
//  9810). kTooFewSamples with fewer than 3 points. The session is kept.
// Macro 9815: the centre of a ball from the session's points, probe touches
//  on it (core::fit_sphere: least squares, geometric distances), with R = #18
//  the sphere's radius when known (the ball's plus the stylus tip's; 0 leaves
//  it free) and #506 the touches' noise for the sigmas. Out: #100..#110
//  (kBallOutputs). kTooFewSamples with fewer than 4 points; kTouchesCoplanar
//  (1000) for touches in one plane; kArgumentOutOfRange for R < 0. The session is
//  kept. It serves every controller's ball measurement (M3's samples), so no
//  controller fits a sphere in its own macro language.
// Macro 9816: check (check.hpp), the re-probe after leveling: the face
//  through the session's points, as 9814 (A, C, I, J, K as 9810), its tilt in
//  the machine frame where it was probed (9814's #117, #118) judged against
//  #509. Out: #100..#111 (check.hpp convention 3, one figure). Statuses as
//  9814; kArgumentOutOfRange for Q other than 0 or 1. The session is kept.
#pragma once

#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/session.hpp"

namespace trueaxis::macros::level {

// What the handlers see (method_context.hpp contract 1). The leveling session
// is the operator's, not a calibration's: it stays in State, beside the
// calibration sessions' shared arena.
struct Shape {
  static constexpr List<VarInfo> kRows = list_of(level::kRows);
  using Session = NoSession;
  using Work = NoWork;
};
using Context = MethodContext<Shape>;

struct State {
  Session<core::Vec3, kSessionCapacity> points;
};

MacroStep run_level_3pt(Context& ctx, State& state);
MacroStep run_level_points(Context& ctx, State& state);
MacroStep run_session_clear(Context& ctx, State& state);
MacroStep run_session_add(Context& ctx, State& state);
MacroStep run_session_compute(Context& ctx, State& state);
MacroStep run_session_ball(Context& ctx, State& state);
MacroStep run_session_check(Context& ctx, State& state);

// clang-format off
inline constexpr InputRef kPoseInputs[] = {
  {var::kArgA, 1, "Commanded A (deg) while probing."},
  {var::kArgC, 1, "Commanded C (deg) while probing."},
  {var::kArgI, 3, "Outward direction I, J, K (any length; 0,0,0 means +Z)."},
  {var::kAMin, 9, "Configuration: travel limits, axis signs, probe repeatability, direction limit, axes."},
};
inline constexpr InputRef kThreePointInputs[] = {
  {var::kArgA, 1, "Commanded A (deg) while probing."},
  {var::kArgC, 1, "Commanded C (deg) while probing."},
  {var::kArgI, 3, "Outward direction I, J, K (any length; 0,0,0 means +Z)."},
  {var::kAMin, 9, "Configuration: travel limits, axis signs, probe repeatability, direction limit, axes."},
  {var::kG57, 3, "P1 (mm, machine frame)."},
  {var::kG58, 3, "P2 (mm, machine frame)."},
  {var::kG59, 3, "P3 (mm, machine frame)."},
};
inline constexpr InputRef kPointsInputs[] = {
  {var::kArgA, 1, "Commanded A (deg) while probing."},
  {var::kArgC, 1, "Commanded C (deg) while probing."},
  {var::kArgI, 3, "Outward direction I, J, K (any length; 0,0,0 means +Z)."},
  {var::kArgQ, 1, "Number of points, 3..32."},
  {var::kAMin, 9, "Configuration: travel limits, axis signs, probe repeatability, direction limit, axes."},
  {var::kPointList, var::kPointListCount, "Points 1..Q (mm, machine frame)."},
};
inline constexpr InputRef kBallInputs[] = {
  {var::kArgR, 1, "The sphere's radius (mm: the ball's plus the stylus tip's), 0 to fit it."},
  {var::kProbeSigma, 1, "Configuration: probe repeatability, for the sigmas."},
};
inline constexpr InputRef kAddInputs[] = {{var::kArgX, 3, "The point X, Y, Z (mm, machine frame)."}};

inline constexpr InputRef kCheckInputs[] = {
  {var::kArgA, 1, "Commanded A (deg) while probing."},
  {var::kArgC, 1, "Commanded C (deg) while probing."},
  {var::kArgI, 3, "Outward direction I, J, K (any length; 0,0,0 means +Z)."},
  {var::kArgQ, 1, "The figure to publish in #104..#111: 0 or 1 (there is one)."},
  {var::kAMin, 10, "Configuration: travel limits, axis signs, probe repeatability, direction limit, axes, the check's tolerance."},
};

inline constexpr MacroInfo kMacros[] = {
  macro<&run_level_3pt>(kMacroThreePoint, "level_3pt",
        "Three-point auto-level: table angles that make the face through G57, G58, G59 horizontal.",
        kThreePointInputs, kLevelOutputs),
  macro<&run_level_points>(kMacroPoints, "level_points",
        "N-point auto-level: least-squares plane through the point list, with flatness and outlier flag.",
        kPointsInputs, kLevelOutputs),
  macro<&run_session_clear>(kMacroSessionClear, "level_session_clear",
        "Empty the leveling session.", kSessionOutputs),
  macro<&run_session_add>(kMacroSessionAdd, "level_session_add",
        "Add one probed point to the leveling session; refused with session_full at its capacity.",
        kAddInputs, kSessionOutputs),
  macro<&run_session_compute>(kMacroSessionCompute, "level_session_compute",
        "N-point auto-level through the session's points (as 9811); the session is kept.",
        kPoseInputs, kLevelOutputs),
  macro<&run_session_ball>(kMacroSessionBall, "level_session_ball",
        "Ball centre: least-squares sphere through the session's points (4 or more probe touches); the session is kept.",
        kBallInputs, kBallOutputs),
  macro<&run_session_check>(kMacroCheck, "level_check",
        "Check after leveling: the face through the session's points probed again, its tilt judged against #509.",
        kCheckInputs, kCheckOutputs),
};
// clang-format on

}  // namespace trueaxis::macros::level
