// The simulator's own variables: not part of the module, served only by
// trueaxis-sim, and published in register_map.json with "simulator_only": true.
// They live at #12000.., outside every range the module defines, so an
// integrator's PLC program can never come to depend on them. #12000..#12013:
// table, probe and face (M1); #12020..#12047: calibration ball, the machine's
// geometric errors and their ground truth (M3; calibration_ball.hpp,
// cradle_machine.hpp convention 3, cradle_errors.hpp); #12048..#12054: the
// face's plane and the ball's centre in the machine frame at the table's
// present pose, for a virtual probe outside the simulator (LinuxCNC's,
// integrations/linuxcnc/sim); #12057..#12062: the spindle's tool tip (M4,
// for the LinuxCNC kinematics' proof); #12055..#12056: a drift of the machine with
// errors, for scripting checks. #12014..#12019 are not defined.
#pragma once

#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::sim {

namespace simvar {
inline constexpr std::uint16_t kFirst = 12000;
inline constexpr std::uint16_t kAxisA = 12000;
inline constexpr std::uint16_t kAxisC = 12001;
inline constexpr std::uint16_t kProbeX = 12002;
inline constexpr std::uint16_t kProbeY = 12003;
inline constexpr std::uint16_t kProbeInto = 12004;
inline constexpr std::uint16_t kLastProbeX = 12005;
inline constexpr std::uint16_t kLastProbeY = 12006;
inline constexpr std::uint16_t kLastProbeZ = 12007;
inline constexpr std::uint16_t kProbeSigma = 12008;
inline constexpr std::uint16_t kHold = 12009;
inline constexpr std::uint16_t kTrueNormalX = 12010;
inline constexpr std::uint16_t kTrueNormalY = 12011;
inline constexpr std::uint16_t kTrueNormalZ = 12012;
inline constexpr std::uint16_t kTrueTilt = 12013;
inline constexpr std::uint16_t kErrors = 12020;
inline constexpr std::uint16_t kBallX = 12021;
inline constexpr std::uint16_t kBallY = 12022;
inline constexpr std::uint16_t kBallZ = 12023;
inline constexpr std::uint16_t kBallSigma = 12024;
inline constexpr std::uint16_t kBallMeasure = 12025;
inline constexpr std::uint16_t kLastBallX = 12026;
inline constexpr std::uint16_t kLastBallY = 12027;
inline constexpr std::uint16_t kLastBallZ = 12028;
inline constexpr std::uint16_t kTrueRotvecX = 12029;
inline constexpr std::uint16_t kTrueRotvecY = 12030;
inline constexpr std::uint16_t kTrueRotvecZ = 12031;
inline constexpr std::uint16_t kTrueAPositioningError = 12032;
inline constexpr std::uint16_t kTrueADriveError = 12033;
inline constexpr std::uint16_t kTrueCToAOffset = 12034;
inline constexpr std::uint16_t kTrueCToASquareness = 12035;
inline constexpr std::uint16_t kTrueAPointX = 12036;
inline constexpr std::uint16_t kTrueAPointY = 12037;
inline constexpr std::uint16_t kTrueAPointZ = 12038;
inline constexpr std::uint16_t kTrueADirX = 12039;
inline constexpr std::uint16_t kTrueADirY = 12040;
inline constexpr std::uint16_t kTrueADirZ = 12041;
inline constexpr std::uint16_t kTrueCCentreX = 12042;
inline constexpr std::uint16_t kTrueCCentreY = 12043;
inline constexpr std::uint16_t kTrueCCentreZ = 12044;
inline constexpr std::uint16_t kTrueCDirX = 12045;
inline constexpr std::uint16_t kTrueCDirY = 12046;
inline constexpr std::uint16_t kTrueCDirZ = 12047;
inline constexpr std::uint16_t kFaceNormalX = 12048;
inline constexpr std::uint16_t kFaceNormalY = 12049;
inline constexpr std::uint16_t kFaceNormalZ = 12050;
inline constexpr std::uint16_t kFaceOffset = 12051;
inline constexpr std::uint16_t kBallMachineX = 12052;
inline constexpr std::uint16_t kBallMachineY = 12053;
inline constexpr std::uint16_t kBallMachineZ = 12054;
inline constexpr std::uint16_t kDriftA = 12055;
inline constexpr std::uint16_t kDriftArcsec = 12056;
inline constexpr std::uint16_t kSpindle = 12057;
inline constexpr std::uint16_t kSpindleAngle = 12058;
inline constexpr std::uint16_t kToolLength = 12059;
inline constexpr std::uint16_t kTipErrorX = 12060;
inline constexpr std::uint16_t kTipErrorY = 12061;
inline constexpr std::uint16_t kTipErrorZ = 12062;
inline constexpr std::uint16_t kLast = 12062;
}  // namespace simvar

namespace detail {
using macros::Access;
using macros::ValueKind;
inline constexpr double kBig = 1e5;
inline constexpr double kTable = 1000.0;       // mm: any point of a machine table
inline constexpr double kHalfTurn = 648000.0;  // arcsec
}  // namespace detail

// clang-format off
inline constexpr macros::VarInfo kSimMap[] = {
  {12000, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_axis_a", "deg", "Simulator: the virtual table's A position (commanded); writing moves it."},
  {12001, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_axis_c", "deg", "Simulator: the virtual table's C position (commanded); writing moves it."},
  {12002, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_probe_x", "mm", "Simulator: machine X at which the next probe comes down."},
  {12003, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_probe_y", "mm", "Simulator: machine Y at which the next probe comes down."},
  {12004, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 16383.0, 0.0, "sim_probe_into", "", "Simulator: write a work-offset X number (5221, 5241, .., 5321) or a point-list X number (1001, 1004, ..): the probe comes down at (sim_probe_x, sim_probe_y) and stores the touch point X, Y, Z there."},
  {12005, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_x", "mm", "Simulator: X of the last touch point (machine frame)."},
  {12006, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_y", "mm", "Simulator: Y of the last touch point."},
  {12007, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_probe_z", "mm", "Simulator: Z of the last touch point."},
  {12008, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, 0.0, 1.0, 0.0005, "sim_probe_sigma", "mm", "Simulator: the virtual probe's noise, 1 sigma per coordinate."},
  {12009, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 1.0, 0.0, "sim_hold", "", "Simulator: 1 keeps a commanded macro busy (not run) until set back to 0; for testing the busy handshake."},
  {12010, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_normal_x", "", "Simulator ground truth: X of the face's outward unit normal, table at zero."},
  {12011, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_normal_y", "", "Simulator ground truth: Y of the outward unit normal, table at zero."},
  {12012, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 1.0, "sim_true_normal_z", "", "Simulator ground truth: Z of the outward unit normal, table at zero."},
  {12013, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, 0.0, 180.0, 0.0, "sim_true_tilt", "deg", "Simulator ground truth: the face's tilt from horizontal at the table's present position."},
  {12020, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 1.0, 0.0, "sim_errors", "", "Simulator: the machine's geometric errors, 0 none (the ideal Rx(A) Rz(C) machine), 1 realistic (A and C axis location, A positioning, C-table deflection); trueaxis-sim --errors realistic starts at 1. Probe, ball and ground truth all follow it."},
  {12021, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kTable, detail::kTable, 200.0, "sim_ball_x", "mm", "Simulator: X of the calibration ball's centre on the table (table coordinates: origin on the C axis, Z along it, axes turning with C)."},
  {12022, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kTable, detail::kTable, 0.0, "sim_ball_y", "mm", "Simulator: Y of the calibration ball's centre on the table (table coordinates)."},
  {12023, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kTable, detail::kTable, 50.0, "sim_ball_z", "mm", "Simulator: Z of the calibration ball's centre above the table (table coordinates); the ground truth below is for a ball at this height."},
  {12024, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, 0.0, 1.0, 0.001, "sim_ball_sigma", "mm", "Simulator: the ball-measuring instrument's noise, 1 sigma per coordinate."},
  {12025, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 1.0, 0.0, "sim_ball_measure", "", "Simulator: write 1 to measure the ball's centre with the table at (sim_axis_a, sim_axis_c) into sim_last_ball_x, _y, _z; 0 measures nothing."},
  {12026, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_ball_x", "mm", "Simulator: X of the last measured ball centre (machine frame)."},
  {12027, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_ball_y", "mm", "Simulator: Y of the last measured ball centre (machine frame)."},
  {12028, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_last_ball_z", "mm", "Simulator: Z of the last measured ball centre (machine frame)."},
  {12029, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_rotvec_x", "arcsec", "Simulator ground truth: X of the M3 rotation vector log(R_actual R_theory^T) at the present A (machine frame, ball at sim_ball_z; 0 at A = 0)."},
  {12030, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_rotvec_y", "arcsec", "Simulator ground truth: Y of the M3 rotation vector at the present A."},
  {12031, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_rotvec_z", "arcsec", "Simulator ground truth: Z of the M3 rotation vector at the present A."},
  {12032, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_a_positioning_error", "arcsec", "Simulator ground truth: M3's A positioning error at the present A, the turn about the true A axis from the reference C centre to this one minus the commanded A (ball at sim_ball_z)."},
  {12033, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_a_drive_error", "arcsec", "Simulator ground truth: the cradle's actual angle minus the commanded A, at the present A (0 at A = 0 only when the error law has no constant term)."},
  {12034, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, 0.0, detail::kBig, 0.0, "sim_true_c_to_a_offset", "mm", "Simulator ground truth: the length of the common perpendicular of the C and A axes at A = 0."},
  {12035, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kHalfTurn, detail::kHalfTurn, 0.0, "sim_true_c_to_a_squareness", "arcsec", "Simulator ground truth: the angle between the C and A axes at A = 0 minus 90 deg."},
  {12036, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_true_a_point_x", "mm", "Simulator ground truth: X of the A axis' point nearest the C axis (machine frame)."},
  {12037, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_true_a_point_y", "mm", "Simulator ground truth: Y of the A axis' point nearest the C axis."},
  {12038, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_true_a_point_z", "mm", "Simulator ground truth: Z of the A axis' point nearest the C axis."},
  {12039, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 1.0, "sim_true_a_dir_x", "", "Simulator ground truth: X of the A axis' unit direction (right-handed for increasing A)."},
  {12040, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_a_dir_y", "", "Simulator ground truth: Y of the A axis' unit direction."},
  {12041, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_a_dir_z", "", "Simulator ground truth: Z of the A axis' unit direction."},
  {12042, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_true_c_centre_x", "mm", "Simulator ground truth: X of the C circle's centre at the present A, the point of the C axis at the ball's height (machine frame)."},
  {12043, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_true_c_centre_y", "mm", "Simulator ground truth: Y of the C circle's centre at the present A."},
  {12044, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 50.0, "sim_true_c_centre_z", "mm", "Simulator ground truth: Z of the C circle's centre at the present A."},
  {12045, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_c_dir_x", "", "Simulator ground truth: X of the C axis' unit direction at the present A (right-handed for increasing C)."},
  {12046, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_true_c_dir_y", "", "Simulator ground truth: Y of the C axis' unit direction at the present A."},
  {12047, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 1.0, "sim_true_c_dir_z", "", "Simulator ground truth: Z of the C axis' unit direction at the present A."},
  {12048, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_face_normal_x", "", "Simulator ground truth: X of the face's outward unit normal in the machine frame with the table at (sim_axis_a, sim_axis_c): what a virtual probe (LinuxCNC's) trips on."},
  {12049, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 0.0, "sim_face_normal_y", "", "Simulator ground truth: Y of that normal."},
  {12050, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -1.0, 1.0, 1.0, "sim_face_normal_z", "", "Simulator ground truth: Z of that normal."},
  {12051, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 40.0, "sim_face_offset", "mm", "Simulator ground truth: the face's plane n . p = this, machine frame, table at (sim_axis_a, sim_axis_c)."},
  {12052, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 200.0, "sim_ball_machine_x", "mm", "Simulator ground truth: X of the calibration ball's centre in the machine frame with the table at (sim_axis_a, sim_axis_c), no noise."},
  {12053, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_ball_machine_y", "mm", "Simulator ground truth: Y of that centre."},
  {12054, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 50.0, "sim_ball_machine_z", "mm", "Simulator ground truth: Z of that centre."},
  {12055, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -180.0, 180.0, 60.0, "sim_drift_a", "deg", "Simulator: the commanded A at which the machine with errors (sim_errors = 1) shows the extra rigidity sim_drift_arcsec (a clamp worked loose at that tilt)."},
  {12056, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -3600.0, 3600.0, 0.0, "sim_drift_arcsec", "arcsec", "Simulator: that extra rigidity, about the table's Y axis, at exactly sim_drift_a; for scripting a machine that drifts between checks (0: none)."},
  {12057, 1, detail::Access::kReadWrite, detail::ValueKind::kInteger, 0.0, 1.0, 0.0, "sim_spindle", "", "Simulator: the spindle's errors at the tool tip, 0 none, 1 the realistic spindle of trueaxis-measure-spindle (host_sim virtual_spindle.hpp realistic_spindle): sim_tip_error_x, _y, _z."},
  {12058, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_spindle_angle", "deg", "Simulator: the spindle's angle (oriented, M19's; growing in the M03 sense) for sim_tip_error."},
  {12059, 1, detail::Access::kReadWrite, detail::ValueKind::kReal, 0.0, detail::kTable, 250.0, "sim_tool_length", "mm", "Simulator: the tool's length below the gauge line for sim_tip_error (trueaxis-measure-spindle's default 250)."},
  {12060, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_tip_error_x", "mm", "Simulator ground truth: X of the tool tip's error (the true tip minus the ideal one) at sim_spindle_angle and sim_tool_length, machine axes; 0 with sim_spindle = 0. Its Z holds the axial errors no analyser sees."},
  {12061, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_tip_error_y", "mm", "Simulator ground truth: Y of the tool tip's error."},
  {12062, 1, detail::Access::kReadOnly, detail::ValueKind::kReal, -detail::kBig, detail::kBig, 0.0, "sim_tip_error_z", "mm", "Simulator ground truth: Z of the tool tip's error."},
};
// clang-format on

static_assert(macros::map_is_well_formed(kSimMap, sizeof(kSimMap) / sizeof(kSimMap[0])), "kSimMap: unsorted, overlapping or inconsistent entry");
inline constexpr std::size_t kSimMapSize = sizeof(kSimMap) / sizeof(kSimMap[0]);

constexpr const macros::VarInfo* find_sim_var(std::uint16_t number) {
  return macros::find_in(kSimMap, kSimMapSize, number);
}

}  // namespace trueaxis::sim
