// M3, AC-axis rigidity: its rows of the register map, its outputs, its blocks
// and its status codes (docs/METHODS.md M3, docs/INTERFACE.md "M3 rigidity").
// Its descriptor is method.hpp.
//
// Conventions
//  1. Configuration #600.. (block #600..#699); no data rows: the ball positions
//     stream through the session (9830..9831), samples of (A, C, X, Y, Z).
//  2. Angles in degrees, rotation vectors and their sigmas in arc-seconds,
//     lengths in mm, all in machine coordinates.
//  3. Status codes: block 1100..1199; those it owned before the block (106,
//     208..213) keep their numbers.
#pragma once

#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kRigidityMinCArc = 600;
inline constexpr std::uint16_t kRigidityBallNoise = 601;
inline constexpr std::uint16_t kRigidityMaxAError = 602;
inline constexpr std::uint16_t kRigidityMinCRadius = 603;
inline constexpr std::uint16_t kRigidityMaxChange = 604;
inline constexpr std::uint16_t kRigidityCheckRotation = 605;
inline constexpr std::uint16_t kRigidityCheckAError = 606;

// 9830, 9831
inline constexpr std::uint16_t kRigiditySessionCount = 100;
inline constexpr std::uint16_t kRigiditySessionCapacity = 101;
// 9832
inline constexpr std::uint16_t kRigidityPoses = 100;
inline constexpr std::uint16_t kRigidityWorst = 101;
inline constexpr std::uint16_t kRigidityWorstSigma = 102;
inline constexpr std::uint16_t kRigidityAPointX = 103;
inline constexpr std::uint16_t kRigidityADirectionX = 106;
inline constexpr std::uint16_t kRigidityCToAOffset = 109;
inline constexpr std::uint16_t kRigidityCToASquareness = 110;
inline constexpr std::uint16_t kRigidityWorstCircleRms = 111;
inline constexpr std::uint16_t kRigidityWorstCircleRmsFloor = 112;
inline constexpr std::uint16_t kRigidityWorstCircleRmsSigma = 113;
inline constexpr std::uint16_t kRigidityChange = 114;
inline constexpr std::uint16_t kRigidityChangePose = 115;
inline constexpr std::uint16_t kRigidityFitRatio = 116;
inline constexpr std::uint16_t kRigidityFitPose = 117;
// 9833
inline constexpr std::uint16_t kRigidityRotvecX = 100;
inline constexpr std::uint16_t kRigidityRotvecNorm = 103;
// 9834
inline constexpr std::uint16_t kPoseA = 100;
inline constexpr std::uint16_t kPoseRotvecX = 101;
inline constexpr std::uint16_t kPoseRotvecSigmaX = 104;
inline constexpr std::uint16_t kPoseRigidity = 107;
inline constexpr std::uint16_t kPoseRigiditySigma = 108;
inline constexpr std::uint16_t kPoseAError = 109;
inline constexpr std::uint16_t kPoseCCentreX = 110;
inline constexpr std::uint16_t kPoseCDirectionX = 113;
inline constexpr std::uint16_t kPoseCCircleRms = 116;
inline constexpr std::uint16_t kPoseCount = 117;
inline constexpr std::uint16_t kPoseAErrorSigma = 118;
inline constexpr std::uint16_t kPoseCCircleRmsSigma = 119;
inline constexpr std::uint16_t kPoseCCircleRmsFloor = 120;
// 9835
inline constexpr std::uint16_t kConvertPointX = 100;
inline constexpr std::uint16_t kConvertDirectionX = 103;
// 9837
inline constexpr std::uint16_t kRealsPoseCount = 100;
inline constexpr std::uint16_t kRealsReference = 101;
inline constexpr std::uint16_t kRealsFirst = 102;
inline constexpr std::uint16_t kRealsHomeIdentity = 129;  // after the 27 reals
}  // namespace var

namespace rigidity {

// Its macros, named once: the descriptor (kMacros, kSession, kCheck), the
// host's flows and plans use these names (docs/INTERFACE.md has the numbers).
inline constexpr std::uint16_t kMacroSessionClear = 9830;
inline constexpr std::uint16_t kMacroSessionAdd = 9831;
inline constexpr std::uint16_t kMacroBuild = 9832;
inline constexpr std::uint16_t kMacroQuery = 9833;
inline constexpr std::uint16_t kMacroPose = 9834;
inline constexpr std::uint16_t kMacroConvert = 9835;
inline constexpr std::uint16_t kMacroCheck = 9836;
inline constexpr std::uint16_t kMacroTableReals = 9837;

inline constexpr MethodBlock kBlock{"rigidity", 600, 699, 2000, 2999};

// Ball positions the session holds: 16 A poses of 32 C positions.
inline constexpr std::uint16_t kSessionCapacity = 512;
// Samples one A pose may hold (C every 10 deg): a pose's circle fit is one step
// of 9832, and this keeps it inside Module::kStepBoundInstructions.
inline constexpr std::uint16_t kMaxPoseSamples = 36;
// The default of #601: a ball-centre instrument measuring to 1 um (1 sigma per
// axis), the simulator's (host_sim calibration_ball.hpp).
inline constexpr double kDefaultBallNoiseMm = 0.001;
// The plausibility gates' defaults (gates.hpp): a cradle's A positioning
// error is arc-seconds to a few arc-minutes, A in radians gives 10^5"; the
// ball sits tens to hundreds of mm off the C axis, in metres below 1.
inline constexpr double kDefaultMaxAErrorArcsec = 1800.0;
inline constexpr double kDefaultMinCRadiusMm = 5.0;
// The change gate's default: a pose's rotation vector may move this far from
// the stored table's at its A before a store needs M = 1 (repeat calibrations
// of one machine differ by a few arc-seconds).
inline constexpr double kDefaultMaxChangeArcsec = 30.0;
// The check's tolerances' defaults (check.hpp): a pose's rotation vector and
// its A positioning error may move this far from the stored table's.
inline constexpr double kDefaultCheckRotationArcsec = 12.0;
inline constexpr double kDefaultCheckAErrorArcsec = 12.0;

// The check's figures (check.hpp convention 1), one of each per pose but the reference.
inline constexpr std::uint16_t kCheckRotation = 1;
inline constexpr std::uint16_t kCheckAError = 2;
// What a build logs (measuring_log.hpp).
inline constexpr std::uint16_t kLogRigidity = 1;
inline constexpr std::uint16_t kLogAError = 2;

// Its status codes (block 1100..1199).
inline constexpr core::Status kAErrorImplausible = static_cast<core::Status>(1100);
inline constexpr core::Status kCRadiusImplausible = static_cast<core::Status>(1101);

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(var::kRigidityMinCArc, 1.0, 360.0, 45.0, "rigidity_min_c_arc", "deg",
               "Rigidity: a pose whose C positions span a shorter arc is refused (arc_too_short)."),
  rows::config(var::kRigidityBallNoise, 0.0, 1.0, kDefaultBallNoiseMm, "rigidity_ball_noise", "mm",
               "Rigidity: the ball-centre instrument's stated noise, 1 sigma per axis; the C-circle RMS's noise floor and sigma come from it, and the fit gate compares each pose's C-circle residuals with it (0: not stated, both 0 and no fit gate)."),
  rows::config(var::kRigidityMaxAError, 1.0, 1e6, kDefaultMaxAErrorArcsec, "rigidity_max_a_error", "arcsec",
               "Rigidity: a pose whose A positioning error exceeds this is refused (a_error_implausible: A in radians?)."),
  rows::config(var::kRigidityMinCRadius, 0.0, 1e4, kDefaultMinCRadiusMm, "rigidity_min_c_radius", "mm",
               "Rigidity: a build whose ball circles C at a smaller radius is refused (c_radius_implausible: ball positions in metres?); 0 switches the gate off."),
  rows::config(var::kRigidityMaxChange, 0.0, 1e6, kDefaultMaxChangeArcsec, "rigidity_max_change", "arcsec",
               "Rigidity: a store whose pose rotation vectors differ from the stored table's at their A by more than this is refused unless M = 1 (change_beyond_limit)."),
  rows::config(var::kRigidityCheckRotation, 1e-3, 1e6, kDefaultCheckRotationArcsec, "rigidity_check_rotation_tolerance", "arcsec",
               "Rigidity check (9836): the tolerance of a pose's rotation vector against the stored pose's at the same A (the length of the difference)."),
  rows::config(var::kRigidityCheckAError, 1e-3, 1e6, kDefaultCheckAErrorArcsec, "rigidity_check_a_error_tolerance", "arcsec",
               "Rigidity check (9836): the tolerance of a pose's A positioning error against the stored pose's at the same A."),
};

inline constexpr CheckFigureInfo kCheckFigureKinds[] = {
  {kCheckRotation, "rotation_change", "arcsec", "A pose's rotation vector against the stored table's pose at the same A (item: the pose's number in the new table, A order): the length of the difference; stored and measured are the vectors' lengths (the rigidity)."},
  {kCheckAError, "a_positioning_error_change", "arcsec", "A pose's A positioning error against the stored pose's at the same A."},
};

inline constexpr CheckFigureInfo kLogFigureKinds[] = {
  {kLogRigidity, "rigidity_worst", "arcsec", "The largest rigidity figure of the table (item: its pose, A order) with its 1-sigma."},
  {kLogAError, "a_positioning_error_worst", "arcsec", "The A positioning error of largest magnitude (signed; item: its pose) with its 1-sigma."},
};

inline constexpr OutputInfo kSessionOutputs[] = {
  {var::kRigiditySessionCount, "rigidity_session_count", "", "Ball positions in the rigidity session after this macro."},
  {var::kRigiditySessionCapacity, "rigidity_session_capacity", "", "Ball positions the rigidity session holds at most."},
};

inline constexpr OutputInfo kBuildOutputs[] = {
  {var::kRigidityPoses, "rigidity_poses", "", "Number of A poses in the table."},
  {var::kRigidityWorst, "rigidity_worst", "arcsec", "Largest rigidity figure (norm of a pose's rotation vector)."},
  {var::kRigidityWorstSigma, "rigidity_worst_sigma", "arcsec", "Its 1-sigma uncertainty."},
  {var::kRigidityAPointX, "rigidity_a_point_x", "mm", "A axis: X of its point (the centre of the circle through the C centres)."},
  {var::kRigidityAPointX + 1, "rigidity_a_point_y", "mm", "A axis: Y of its point."},
  {var::kRigidityAPointX + 2, "rigidity_a_point_z", "mm", "A axis: Z of its point."},
  {var::kRigidityADirectionX, "rigidity_a_direction_x", "", "A axis: X of its unit direction (right-handed for increasing A)."},
  {var::kRigidityADirectionX + 1, "rigidity_a_direction_y", "", "A axis: Y of its unit direction."},
  {var::kRigidityADirectionX + 2, "rigidity_a_direction_z", "", "A axis: Z of its unit direction."},
  {var::kRigidityCToAOffset, "rigidity_c_to_a_offset", "mm", "C-to-A offset: length of the common perpendicular of the C axis (A = 0) and the A axis."},
  {var::kRigidityCToASquareness, "rigidity_c_to_a_squareness", "arcsec", "C-to-A squareness: the angle between the C axis (A = 0) and the A axis minus 90 deg."},
  {var::kRigidityWorstCircleRms, "rigidity_worst_c_circle_rms", "mm", "Largest RMS distance of a pose's ball positions from its fitted C circle."},
  {var::kRigidityWorstCircleRmsFloor, "rigidity_worst_c_circle_rms_noise_floor", "mm", "The RMS the ball noise (#601) alone would give at that pose: an RMS within 3 sigma of it is noise, not geometry."},
  {var::kRigidityWorstCircleRmsSigma, "rigidity_worst_c_circle_rms_sigma", "mm", "1-sigma uncertainty of the largest C-circle RMS, from the ball noise (#601)."},
  {var::kRigidityChange, "rigidity_change", "arcsec", "The change against the stored table: the largest difference of a pose's rotation vector from the stored table's at its A (clamped to the stored range); 0 without a stored table."},
  {var::kRigidityChangePose, "rigidity_change_pose", "", "The pose (1-based, in A order) of that largest change; 0 without a stored table."},
  {var::kRigidityFitRatio, "rigidity_fit_ratio", "", "The fit gate's figure: the largest pose's C-circle chi-square statistic over its quantile at #901 (the build is refused above 1); 0 when #601 is 0."},
  {var::kRigidityFitPose, "rigidity_fit_pose", "", "The pose (1-based) of that largest figure."},
};

inline constexpr OutputInfo kQueryOutputs[] = {
  {var::kRigidityRotvecX, "rigidity_rotvec_x", "arcsec", "X of the rotation vector log(R_actual R_theory^T) at the queried A, machine frame."},
  {var::kRigidityRotvecX + 1, "rigidity_rotvec_y", "arcsec", "Y of the rotation vector."},
  {var::kRigidityRotvecX + 2, "rigidity_rotvec_z", "arcsec", "Z of the rotation vector."},
  {var::kRigidityRotvecNorm, "rigidity_rotvec_norm", "arcsec", "Norm of the rotation vector: the rigidity figure at that A."},
};

inline constexpr OutputInfo kPoseOutputs[] = {
  {var::kPoseA, "pose_a", "deg", "The pose's commanded A."},
  {var::kPoseRotvecX, "pose_rotvec_x", "arcsec", "X of the pose's rotation vector (machine frame)."},
  {var::kPoseRotvecX + 1, "pose_rotvec_y", "arcsec", "Y of the pose's rotation vector."},
  {var::kPoseRotvecX + 2, "pose_rotvec_z", "arcsec", "Z of the pose's rotation vector."},
  {var::kPoseRotvecSigmaX, "pose_rotvec_sigma_x", "arcsec", "1-sigma uncertainty of X of the rotation vector."},
  {var::kPoseRotvecSigmaX + 1, "pose_rotvec_sigma_y", "arcsec", "1-sigma uncertainty of Y."},
  {var::kPoseRotvecSigmaX + 2, "pose_rotvec_sigma_z", "arcsec", "1-sigma uncertainty of Z."},
  {var::kPoseRigidity, "pose_rigidity", "arcsec", "The pose's rigidity figure (norm of its rotation vector)."},
  {var::kPoseRigiditySigma, "pose_rigidity_sigma", "arcsec", "Its 1-sigma uncertainty."},
  {var::kPoseAError, "pose_a_positioning_error", "arcsec", "A positioning error: actual turn from the reference minus the commanded difference in A."},
  {var::kPoseCCentreX, "pose_c_centre_x", "mm", "X of the pose's C-circle centre."},
  {var::kPoseCCentreX + 1, "pose_c_centre_y", "mm", "Y of the C-circle centre."},
  {var::kPoseCCentreX + 2, "pose_c_centre_z", "mm", "Z of the C-circle centre."},
  {var::kPoseCDirectionX, "pose_c_direction_x", "", "X of the C-circle's unit normal (right-handed for increasing C)."},
  {var::kPoseCDirectionX + 1, "pose_c_direction_y", "", "Y of the C direction."},
  {var::kPoseCDirectionX + 2, "pose_c_direction_z", "", "Z of the C direction."},
  {var::kPoseCCircleRms, "pose_c_circle_rms", "mm", "RMS 3-D distance of the pose's ball positions from its fitted C circle."},
  {var::kPoseCount, "pose_count", "", "Number of poses in the table."},
  {var::kPoseAErrorSigma, "pose_a_positioning_error_sigma", "arcsec", "1-sigma uncertainty of the A positioning error, from the circle fits' own scatter (as the rotation vector's)."},
  {var::kPoseCCircleRmsSigma, "pose_c_circle_rms_sigma", "mm", "1-sigma uncertainty of the C-circle RMS, from the ball noise (#601)."},
  {var::kPoseCCircleRmsFloor, "pose_c_circle_rms_noise_floor", "mm", "The C-circle RMS the ball noise (#601) alone would give at this pose's sample count: an RMS within 3 sigma of it is noise, not geometry."},
};

inline constexpr OutputInfo kRealsOutputs[] = {
  {var::kRealsPoseCount, "table_pose_count", "", "Number of poses in the table."},
  {var::kRealsReference, "table_reference_pose", "", "The reference pose (A = 0), 1-based in A order."},
  {var::kRealsFirst, "table_real_1", "", "Q = 0: the header's a_axis_point_x (mm); Q = n: the pose's a (deg); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 1, "table_real_2", "", "Q = 0: the header's a_axis_point_y (mm); Q = n: the pose's rotvec_x (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 2, "table_real_3", "", "Q = 0: the header's a_axis_point_z (mm); Q = n: the pose's rotvec_y (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 3, "table_real_4", "", "Q = 0: the header's a_axis_direction_x (unit); Q = n: the pose's rotvec_z (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 4, "table_real_5", "", "Q = 0: the header's a_axis_direction_y (unit); Q = n: the pose's rotvec_sigma_x (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 5, "table_real_6", "", "Q = 0: the header's a_axis_direction_z (unit); Q = n: the pose's rotvec_sigma_y (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 6, "table_real_7", "", "Q = 0: the header's c_to_a_offset (mm); Q = n: the pose's rotvec_sigma_z (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 7, "table_real_8", "", "Q = 0: the header's c_to_a_offset_sigma (mm); Q = n: the pose's rigidity (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 8, "table_real_9", "", "Q = 0: the header's c_to_a_squareness (rad); Q = n: the pose's rigidity_sigma (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 9, "table_real_10", "", "Q = 0: the header's c_to_a_squareness_sigma (rad); Q = n: the pose's theta (rad); exactly as stored (rigidity_codec.hpp)."},
  {var::kRealsFirst + 10, "table_real_11", "", "Q = n: the pose's a_error (rad); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 11, "table_real_12", "", "Q = n: the pose's a_error_sigma (rad); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 12, "table_real_13", "", "Q = n: the pose's origin_offset_x (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 13, "table_real_14", "", "Q = n: the pose's origin_offset_y (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 14, "table_real_15", "", "Q = n: the pose's origin_offset_z (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 15, "table_real_16", "", "Q = n: the pose's c_centre_x (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 16, "table_real_17", "", "Q = n: the pose's c_centre_y (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 17, "table_real_18", "", "Q = n: the pose's c_centre_z (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 18, "table_real_19", "", "Q = n: the pose's c_direction_x (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 19, "table_real_20", "", "Q = n: the pose's c_direction_y (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 20, "table_real_21", "", "Q = n: the pose's c_direction_z (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 21, "table_real_22", "", "Q = n: the pose's c_x_axis_x (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 22, "table_real_23", "", "Q = n: the pose's c_x_axis_y (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 23, "table_real_24", "", "Q = n: the pose's c_x_axis_z (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 24, "table_real_25", "", "Q = n: the pose's c_circle_rms (mm); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 25, "table_real_26", "", "Q = n: the pose's c_arc (deg); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsFirst + 26, "table_real_27", "", "Q = n: the pose's c_count (unit); exactly as stored (rigidity_codec.hpp); Q = 0: 0."},
  {var::kRealsHomeIdentity, "table_home_identity", "", "The home identity the table was built under (#904 at its 9832): a client rebuilding the record writes it too (core::encode_rigidity_reals)."},
};

inline constexpr OutputInfo kConvertOutputs[] = {
  {var::kConvertPointX, "convert_point_x", "mm", "X of the point in the actual machine position (or theoretical, R = 1)."},
  {var::kConvertPointX + 1, "convert_point_y", "mm", "Y of the converted point."},
  {var::kConvertPointX + 2, "convert_point_z", "mm", "Z of the converted point."},
  {var::kConvertDirectionX, "convert_direction_x", "", "X of the converted unit direction."},
  {var::kConvertDirectionX + 1, "convert_direction_y", "", "Y of the converted direction."},
  {var::kConvertDirectionX + 2, "convert_direction_z", "", "Z of the converted direction."},
};

inline constexpr core::StatusInfo kStatuses[] = {
  {core::Status::kOutsideMeasuredRange, "outside_measured_range", "The query is outside the range the table was measured over: query inside it, or ask to clamp to the nearest measured pose (R = 1)."},
  {core::Status::kTooFewPoses, "too_few_poses", "The rigidity samples hold fewer than 3 A poses: measure at more A angles."},
  {core::Status::kNoReferencePose, "no_reference_pose", "No A pose is at A = 0: the reference pose is missing."},
  {core::Status::kTooFewCPositions, "too_few_c_positions", "An A pose has fewer than 4 distinct C positions: measure that pose at more C angles."},
  {core::Status::kTooManyPoses, "too_many_poses", "The rigidity samples hold more A poses than the table can hold (16)."},
  {core::Status::kAAxisUndetermined, "a_axis_undetermined", "The C centres of the A poses do not determine the A axis: place the ball away from the A axis or spread the A angles wider."},
  {core::Status::kCPhaseInconsistent, "c_phase_inconsistent", "The ball's measured positions around a C circle disagree with the commanded C angles: were the angles given in radians instead of degrees?"},
  {kAErrorImplausible, "a_error_implausible", "An A pose's positioning error exceeds #602 (#9012 the pose, #9013 its error in arcsec): the ball turned far more or less than A was commanded. Were A and C given in radians instead of degrees? Nothing was published or stored."},
  {kCRadiusImplausible, "c_radius_implausible", "The ball circles the C axis at a radius below #603 (#9013 the radius in mm): were the ball positions given in metres instead of millimetres? (Or the ball sits on the C axis: place it well away from it.) Nothing was published or stored."},
};
// clang-format on

}  // namespace rigidity
}  // namespace trueaxis::macros
