// Status codes and Result<T>: how every trueaxis routine reports failure.
//
// Conventions
//  1. Errors are values. No routine throws, asserts on data or returns NaN in
//     an output; a routine that fails returns a Status and leaves its outputs
//     untouched.
//  2. The numbers are stable: they appear in register #9002 and in
//     macros/register_map.json. Never renumber; add new codes at the end of
//     their group.
//       0        success
//       100-199  input values (not finite, out of range, wrong count)
//       200-299  geometry (degenerate point sets, unreachable poses)
//       300-399  configuration
//       400-499  the macro layer and the platform (unknown macro, storage)
#pragma once

#include <cstddef>
#include <cstdint>

namespace trueaxis::core {

enum class Status : std::uint16_t {
  kOk = 0,

  kNotFinite = 100,        // an input value is NaN or infinite
  kTooFewPoints = 101,     // fewer points than the fit needs
  kTooManyPoints = 102,    // more points than the compile-time capacity
  kArgumentOutOfRange = 103,  // a macro argument is outside its documented range
  kTooFewSamples = 104,    // a compute macro ran on a session with fewer samples than it needs
  kMissingGroup = 105,     // a group of points the method needs was not given
  kOutsideMeasuredRange = 106,  // a query outside the range a table was measured over, not clamped
  kGroupNotContiguous = 107,    // a point for a group that other groups' points have followed

  kPointsCoincident = 200,  // the points do not span a line
  kPointsCollinear = 201,   // the points do not span a plane
  kPointsTooClose = 202,    // probe repeatability swamps the face's direction
  kOrientationAmbiguous = 203,  // the face is perpendicular to the orientation hint
  kUnreachable = 204,       // neither leveling solution lies inside the travel limits
  kArcTooShort = 205,       // the points span too short an arc for the required accuracy
  kNoConvergence = 206,     // an iterative fit did not converge
  kPointsNotOnLine = 207,   // the points are too wide across to define a line's direction
  kTooFewPoses = 208,       // fewer than 3 A poses
  kNoReferencePose = 209,   // no A pose at A = 0
  kTooFewCPositions = 210,  // an A pose has fewer than 4 distinct C positions
  kTooManyPoses = 211,      // more A poses than the table holds
  kAAxisUndetermined = 212, // the poses' C centres do not determine the A axis
  kCPhaseInconsistent = 213,  // a pose's measured phases disagree with its commanded C
  kTableInvalid = 214,      // a serialized table is malformed
  kAxesParallel = 215,      // two lines (axes) that must cross at an angle are (nearly) parallel
  kPlanesDegenerate = 216,  // three planes do not meet in one well-defined point
  kAxisOppositeGantry = 217,  // a sub-machine's X axis points against the gantry's +X
  kPassesDisagree = 218,    // the passes of one axis point in opposite directions
  kToolDirectionAmbiguous = 219,  // the nominal tool direction is perpendicular to the C axis
  kBedNotLevel = 220,       // the bed plane's normal is far from the data's +Z (not levelled)
  kNotIdentifiable = 221,   // the data do not determine every parameter of the model
  kRevolutionIncomplete = 222,  // the spindle angles leave a gap wider than a revolution allows

  kConfigInvalid = 300,     // the stored configuration is inconsistent

  kUnknownMacro = 400,      // no macro has that number
  kStorageFailure = 401,    // non-volatile storage could not be written or read
  kSessionFull = 402,       // a sample was added to a session at its capacity
  kTableLocked = 403,       // a macro would store a table while configuration is locked
  kNoTable = 404,           // a query needs a stored table and there is none
  kTableDamaged = 405,      // the stored table failed its CRC at start and was not loaded
};

struct StatusInfo {
  Status status;
  const char* name;     // snake_case identifier, stable
  const char* message;  // one sentence for an operator's screen
};

// Every status with its name and message, sorted by number. Single source for
// the register map's JSON and for status_message().
inline constexpr StatusInfo kStatusTable[] = {
    {Status::kOk, "ok", "The macro succeeded."},
    {Status::kNotFinite, "not_finite", "An input value is not a finite number."},
    {Status::kTooFewPoints, "too_few_points", "Fewer points were given than the method needs."},
    {Status::kTooManyPoints, "too_many_points", "More points were given than the module can hold."},
    {Status::kArgumentOutOfRange, "argument_out_of_range",
     "A macro argument is outside its documented range."},
    {Status::kTooFewSamples, "too_few_samples",
     "The session holds fewer samples than the computation needs: add more, then compute again."},
    {Status::kMissingGroup, "missing_group",
     "A group of points the method needs (a plane, a pass or a circle) was not measured."},
    {Status::kOutsideMeasuredRange, "outside_measured_range",
     "The query is outside the range the table was measured over: query inside it, or ask to "
     "clamp to the nearest measured pose (R = 1)."},
    {Status::kGroupNotContiguous, "group_not_contiguous",
     "A point was added to a group after other groups' points: send each group's points "
     "together, in measuring order (clear the session and send them again)."},
    {Status::kPointsCoincident, "points_coincident",
     "The probed points coincide: they do not span a line."},
    {Status::kPointsCollinear, "points_collinear",
     "The probed points lie on one line: they do not span a plane."},
    {Status::kPointsTooClose, "points_too_close",
     "The probed points are too close together for the probe repeatability: "
     "the face's direction would be uncertain by more than the configured limit."},
    {Status::kOrientationAmbiguous, "orientation_ambiguous",
     "The face is perpendicular to the orientation hint: give its outward direction "
     "in I, J, K."},
    {Status::kUnreachable, "unreachable",
     "Neither leveling solution lies inside the rotary axes' travel limits."},
    {Status::kArcTooShort, "arc_too_short",
     "The measured points span too short an arc: the circle's centre would be too "
     "uncertain. Turn the axis through a larger angle."},
    {Status::kNoConvergence, "no_convergence",
     "An iterative fit did not converge: the points do not describe the expected shape."},
    {Status::kPointsNotOnLine, "points_not_on_line",
     "The measured points do not run along one line: they spread too widely across it "
     "for its direction to be defined."},
    {Status::kTooFewPoses, "too_few_poses",
     "The rigidity samples hold fewer than 3 A poses: measure at more A angles."},
    {Status::kNoReferencePose, "no_reference_pose",
     "No A pose is at A = 0: the reference pose is missing."},
    {Status::kTooFewCPositions, "too_few_c_positions",
     "An A pose has fewer than 4 distinct C positions: measure that pose at more C angles."},
    {Status::kTooManyPoses, "too_many_poses",
     "The rigidity samples hold more A poses than the table can hold (16)."},
    {Status::kAAxisUndetermined, "a_axis_undetermined",
     "The C centres of the A poses do not determine the A axis: place the ball away from the "
     "A axis or spread the A angles wider."},
    {Status::kCPhaseInconsistent, "c_phase_inconsistent",
     "The ball's measured positions around a C circle disagree with the commanded C angles."},
    {Status::kTableInvalid, "table_invalid",
     "A stored calibration table is malformed (layout version, counts or values)."},
    {Status::kAxesParallel, "axes_parallel",
     "Two axes that must cross at an angle are parallel or nearly so (A and C of a head, two "
     "linear axes, or the gantry and the bed normal): their common perpendicular is undefined."},
    {Status::kPlanesDegenerate, "planes_degenerate",
     "The three planes do not meet in one well-defined point: two of them are parallel or "
     "nearly so (the bed and the two side faces)."},
    {Status::kAxisOppositeGantry, "axis_opposite_gantry",
     "A sub-machine's X axis points against the gantry's positive X: check the order in "
     "which its passes were measured."},
    {Status::kPassesDisagree, "passes_disagree",
     "The passes of one axis run in opposite directions: every pass must be measured moving "
     "the axis in its positive direction."},
    {Status::kToolDirectionAmbiguous, "tool_direction_ambiguous",
     "The nominal tool direction is perpendicular to the measured C axis: it cannot say which "
     "way the C axis points towards the tool tip."},
    {Status::kBedNotLevel, "bed_not_level",
     "The bed plane's normal is far from the measurement's +Z: the tracker data must be "
     "levelled (+Z up)."},
    {Status::kNotIdentifiable, "not_identifiable",
     "The data do not determine every parameter of the model: a combination of them leaves "
     "the measurements unchanged. Measure more (for the spindle: the ball at two heights, over "
     "a whole revolution)."},
    {Status::kRevolutionIncomplete, "revolution_incomplete",
     "The spindle angles of a ball leave a gap wider than 45 degrees: measure the ball over a "
     "whole revolution."},
    {Status::kConfigInvalid, "config_invalid",
     "The stored configuration is inconsistent (for example a lower limit above the "
     "upper one)."},
    {Status::kUnknownMacro, "unknown_macro", "No macro has that number."},
    {Status::kStorageFailure, "storage_failure",
     "Non-volatile storage could not be written; nothing was changed."},
    {Status::kSessionFull, "session_full",
     "The session is full (its capacity is in the register map): the sample was not added."},
    {Status::kTableLocked, "table_locked",
     "Calibration tables are stored only after the unlock code is written to #9004; nothing was stored."},
    {Status::kNoTable, "no_table", "There is no stored calibration table for this query."},
    {Status::kTableDamaged, "table_damaged",
     "The stored calibration table failed its integrity check (CRC) at start and was not loaded: "
     "calibrate and store it again."},
};

constexpr bool status_table_is_sorted() {
  for (std::size_t i = 1; i < sizeof(kStatusTable) / sizeof(kStatusTable[0]); ++i) {
    if (static_cast<int>(kStatusTable[i - 1].status) >= static_cast<int>(kStatusTable[i].status)) {
      return false;
    }
  }
  return true;
}
static_assert(status_table_is_sorted(), "kStatusTable must be sorted by number, without repeats");

// The operator message of a status; "Unknown status." for a number not in the table.
constexpr const char* status_message(Status s) {
  for (const StatusInfo& info : kStatusTable) {
    if (info.status == s) return info.message;
  }
  return "Unknown status.";
}

constexpr const char* status_name(Status s) {
  for (const StatusInfo& info : kStatusTable) {
    if (info.status == s) return info.name;
  }
  return "unknown";
}

// A value or the Status that explains why there is none. T must be
// default-constructible and trivially copyable enough for firmware use.
template <typename T>
class [[nodiscard]] Result {
 public:
  constexpr Result(const T& value) : status_(Status::kOk), value_(value) {}  // NOLINT: implicit by design
  constexpr Result(Status status) : status_(status), value_() {}             // NOLINT: implicit by design

  constexpr bool ok() const { return status_ == Status::kOk; }
  constexpr Status status() const { return status_; }
  // Only meaningful when ok(); a default-constructed T otherwise.
  constexpr const T& value() const { return value_; }

 private:
  Status status_;
  T value_;
};

}  // namespace trueaxis::core
