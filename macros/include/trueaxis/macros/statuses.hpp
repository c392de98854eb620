// The platform's status codes: their names and messages (core::Status holds
// the numbers). Each method lists its own codes in its map; the module's map
// joins them all (method_list.hpp) into the one table the JSON map, the
// register page and every tool read.
//
// Conventions
//  1. Codes 0..999 are the platform's and the shared math's: 100-199 input
//     values, 200-299 geometry, 300-399 configuration, 400-499 the macro layer
//     and storage, 500-599 the gates (a result refused before it is published
//     or stored). Sorted by number, each once.
#pragma once

#include "trueaxis/core/status.hpp"

namespace trueaxis::macros {

// clang-format off
inline constexpr core::StatusInfo kPlatformStatuses[] = {
  {core::Status::kOk, "ok", "The macro succeeded."},
  {core::Status::kNotFinite, "not_finite", "An input value is not a finite number."},
  {core::Status::kTooFewPoints, "too_few_points", "Fewer points were given than the method needs."},
  {core::Status::kTooManyPoints, "too_many_points", "More points were given than the module can hold."},
  {core::Status::kArgumentOutOfRange, "argument_out_of_range", "A macro argument is outside its documented range."},
  {core::Status::kTooFewSamples, "too_few_samples", "The session holds fewer samples than the computation needs: add more, then compute again."},
  {core::Status::kMissingGroup, "missing_group", "A group of points the method needs (a plane, a pass or a circle) was not measured."},
  {core::Status::kDuplicateSample, "duplicate_sample", "The sample repeats one already in the session bit for bit (a file or a row given twice?): it was not added."},
  {core::Status::kPointsCoincident, "points_coincident", "The probed points coincide: they do not span a line."},
  {core::Status::kPointsCollinear, "points_collinear", "The probed points lie on one line: they do not span a plane."},
  {core::Status::kPointsTooClose, "points_too_close", "The probed points are too close together for the probe repeatability: the face's direction would be uncertain by more than the configured limit."},
  {core::Status::kArcTooShort, "arc_too_short", "The measured points span too short an arc: the circle's centre would be too uncertain. Turn the axis through a larger angle."},
  {core::Status::kNoConvergence, "no_convergence", "An iterative fit did not converge: the points do not describe the expected shape."},
  {core::Status::kPointsNotOnLine, "points_not_on_line", "The measured points do not run along one line: they spread too widely across it for its direction to be defined."},
  {core::Status::kTableInvalid, "table_invalid", "A stored calibration table is malformed (layout version, counts or values)."},
  {core::Status::kConfigInvalid, "config_invalid", "The stored configuration is inconsistent (for example a lower limit above the upper one)."},
  {core::Status::kUnknownMacro, "unknown_macro", "No macro has that number."},
  {core::Status::kStorageFailure, "storage_failure", "Non-volatile storage could not be written; nothing was changed."},
  {core::Status::kSessionFull, "session_full", "The session is full (its capacity is in the register map): the sample was not added."},
  {core::Status::kTableLocked, "table_locked", "Calibration tables are stored only after the unlock code is written to #9004; nothing was stored."},
  {core::Status::kNoTable, "no_table", "There is no stored calibration table for this query."},
  {core::Status::kTableDamaged, "table_damaged", "The stored calibration table failed its integrity check (CRC) at start and was not loaded: calibrate and store it again."},
  {core::Status::kSessionClosed, "session_closed", "Another method's calibration session has replaced this one since it was opened (the methods share one session memory): clear the session (its clear macro) and send its samples again."},
  {core::Status::kResultReplaced, "result_replaced", "Another method's computation has replaced this method's last one since (the methods share one working memory): compute again (R = 0), or query the stored table (R = 1)."},
  {core::Status::kMethodNotBuilt, "method_not_built", "The method this needs is not built into this controller's module (for example leveling on the calibrated axes needs the rigidity method)."},
  {core::Status::kNothingToCheck, "nothing_to_check", "The check found nothing to compare: the stored table shares no pose, sub-machine or parameter with the measurement just built. Measure at the stored table's poses (or sub-machines), then check again."},
  {core::Status::kHomeChanged, "home_changed", "The stored calibration table was measured under another home of the axes than the machine's now (the table's in 9837's #129, the machine's in #904 home_identity): its zeros are not the axes' zeros, so it is not applied. Home the axes as they were then and set #904 back, or measure and store the calibration again."},
  {core::Status::kFitBeyondNoise, "fit_beyond_noise", "The fit's residuals are far beyond the instrument's stated noise (a chi-square test at #901's confidence; #9012 names the pose or group with the largest, #9013 its statistic over the quantile): nothing was published or stored. Likely causes: a file in metres where millimetres are due, a nominal size typed wrong (a ball distance), another machine's or another session's data mixed in, or the instrument's noise configured too small."},
  {core::Status::kChangeBeyondLimit, "change_beyond_limit", "The new calibration differs from the stored one by more than the configured change limit (#9013 the change, #9014 the limit, #9012 where): nothing was stored. Check the machine (a collision? a wrong file or setup?); to store it all the same, run the macro again with M = 1."},
};
// clang-format on

}  // namespace trueaxis::macros
