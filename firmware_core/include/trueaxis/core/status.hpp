// Status codes and Result<T>: how every trueaxis routine reports failure.
//
// Conventions
//  1. Errors are values. No routine throws, asserts on data or returns NaN in
//     an output; a routine that fails returns a Status and leaves its outputs
//     untouched.
//  2. The numbers are stable: they appear in register #9002 and in
//     macros/register_map.json. Never renumber. The enum holds every code the
//     math returns; a method's own new codes may be defined beside its map, in
//     its block of 1000 and above (macros/include/trueaxis/macros/method.hpp
//     convention 2).
//       0        success
//       100-199  input values (not finite, out of range, wrong count)
//       200-299  geometry (degenerate point sets, unreachable poses)
//       300-399  configuration
//       400-499  the macro layer and the platform (unknown macro, storage)
//       500-599  the gates: a result refused before it is published or stored
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
  kDuplicateSample = 108,  // a sample repeats, bit for bit, one already in the session

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
  kSessionClosed = 406,     // another method's calibration session has replaced this method's
  kResultReplaced = 407,    // another method's computation has replaced this method's last one
  kMethodNotBuilt = 408,    // the method this needs is not built into this module
  kNothingToCheck = 409,    // a check found no figure the build and the stored table share
  kHomeChanged = 410,       // the stored table was measured under another home than the machine's now

  kFitBeyondNoise = 500,    // a fit's residuals far beyond the instrument's stated noise (a gate)
  kChangeBeyondLimit = 501, // a new table differs from the stored one beyond the change limit, unconfirmed (a gate)
};

// A status's name (snake_case, stable) and its message (one sentence for an
// operator's screen). The tables live with their owners: the platform's in
// macros/include/trueaxis/macros/statuses.hpp, each method's in its own map;
// the module's map joins them.
struct StatusInfo {
  Status status;
  const char* name;
  const char* message;
};


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
