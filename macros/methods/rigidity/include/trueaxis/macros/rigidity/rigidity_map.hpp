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
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kRigidityMinCArc = 600;
inline constexpr std::uint16_t kRigidityBallNoise = 601;

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
}  // namespace var

namespace rigidity {

inline constexpr MethodBlock kBlock{"rigidity", 600, 699, 2000, 2999};

// Ball positions the session holds: 16 A poses of 32 C positions.
inline constexpr std::uint16_t kSessionCapacity = 512;
// Samples one A pose may hold (C every 10 deg): a pose's circle fit is one step
// of 9832, and this keeps it inside Module::kStepBoundInstructions.
inline constexpr std::uint16_t kMaxPoseSamples = 36;
// The default of #601: a ball-centre instrument measuring to 1 um (1 sigma per
// axis), the simulator's (host_sim calibration_ball.hpp).
inline constexpr double kDefaultBallNoiseMm = 0.001;

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(var::kRigidityMinCArc, 1.0, 360.0, 45.0, "rigidity_min_c_arc", "deg",
               "Rigidity: a pose whose C positions span a shorter arc is refused (arc_too_short)."),
  rows::config(var::kRigidityBallNoise, 0.0, 1.0, kDefaultBallNoiseMm, "rigidity_ball_noise", "mm",
               "Rigidity: the ball-centre instrument's stated noise, 1 sigma per axis; the C-circle RMS's noise floor and sigma come from it (0: not stated, both 0)."),
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
  {core::Status::kCPhaseInconsistent, "c_phase_inconsistent", "The ball's measured positions around a C circle disagree with the commanded C angles."},
};
// clang-format on

}  // namespace rigidity
}  // namespace trueaxis::macros
