// M2, gantry frames: its rows of the register map, its outputs, its blocks and
// its status codes (docs/METHODS.md M2, docs/INTERFACE.md "M2 gantry"). Its
// descriptor is method.hpp.
//
// Conventions
//  1. Configuration #700.. (block #700..#799); no data rows: the tracker points
//     stream through the session (9820..9822).
//  2. Lengths in mm, angles in degrees, small angles (squareness, sigmas) in
//     arc-seconds. The global frame's origin and axes are written in the
//     tracker's frame, a sub-machine's in the global frame (docs/INTERFACE.md).
//  3. A group is named by three arguments of 9821: T = #20 the sub-machine
//     (0 for the machine's own groups), Q = #17 the kind (kGroupKind below) and
//     D = #7 the pass number K (1..kMaxPasses = 4, for the passes only). docs/INTERFACE.md's CSV
//     names map one to one: bed = (0, 1), side_1 = (0, 2), side_2 = (0, 3),
//     gantry_K = (0, 4, K), spN_x_K = (N, 5, K), spN_y_K = (N, 6, K),
//     spN_z_K = (N, 7, K), spN_c = (N, 8), spN_a = (N, 9).
//  4. Status codes: block 1200..1299; those it owned before the block (107,
//     215..220) keep their numbers.
#pragma once

#include <cstdint>

#include "trueaxis/core/gantry_frames.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kGantryMinArc = 700;
inline constexpr std::uint16_t kGantryTrackerNoise = 701;
inline constexpr std::uint16_t kGantryTrackerNoisePerM = 702;
inline constexpr std::uint16_t kGantryMinBedSpan = 703;
inline constexpr std::uint16_t kGantryMaxOriginChange = 704;
inline constexpr std::uint16_t kGantryMaxAngleChange = 705;
inline constexpr std::uint16_t kGantryCheckOrigin = 706;
inline constexpr std::uint16_t kGantryCheckAngle = 707;
inline constexpr std::uint16_t kGantryMaxNominalOffset = 708;
inline constexpr std::uint16_t kGantryMinSwing = 709;

// 9820, 9821, 9822
inline constexpr std::uint16_t kGantrySessionCount = 100;
inline constexpr std::uint16_t kGantrySessionCapacity = 101;
inline constexpr std::uint16_t kGantryGroupCount = 102;
// 9823
inline constexpr std::uint16_t kGantryBuilt = 100;
inline constexpr std::uint16_t kGantryWorstOriginSigma = 101;
inline constexpr std::uint16_t kGantryBuildFlatness = 102;
inline constexpr std::uint16_t kGantryBuildStraightness = 103;
inline constexpr std::uint16_t kGantryOriginChange = 104;
inline constexpr std::uint16_t kGantryOriginChangeId = 105;
inline constexpr std::uint16_t kGantryAngleChange = 106;
inline constexpr std::uint16_t kGantryAngleChangeId = 107;
inline constexpr std::uint16_t kGantryBedSpan = 108;
inline constexpr std::uint16_t kGantryFitRatio = 109;
inline constexpr std::uint16_t kGantryFitSubMachine = 110;
// 9824
inline constexpr std::uint16_t kGlobalOriginX = 100;
inline constexpr std::uint16_t kGlobalXX = 103;
inline constexpr std::uint16_t kGlobalYX = 106;
inline constexpr std::uint16_t kGlobalZX = 109;
inline constexpr std::uint16_t kGlobalBedFlatness = 112;
inline constexpr std::uint16_t kGlobalGantryStraightness = 113;
inline constexpr std::uint16_t kGlobalOriginSigma = 114;
inline constexpr std::uint16_t kGlobalAngleSigmaX = 115;
inline constexpr std::uint16_t kGlobalSubMachines = 118;
inline constexpr std::uint16_t kGlobalIdMask = 119;
inline constexpr std::uint16_t kGlobalBedFlatnessFloor = 120;
inline constexpr std::uint16_t kGlobalGantryStraightnessFloor = 121;
inline constexpr std::uint16_t kGlobalBedFormError = 122;
inline constexpr std::uint16_t kGlobalBedFormErrorSigma = 123;
inline constexpr std::uint16_t kGlobalGantryFormError = 124;
inline constexpr std::uint16_t kGlobalGantryFormErrorSigma = 125;
// 9825
inline constexpr std::uint16_t kGantryPointX = 100;
// 9826
inline constexpr std::uint16_t kSubOriginX = 100;
inline constexpr std::uint16_t kSubOriginSigma = 103;
inline constexpr std::uint16_t kSubXX = 104;
inline constexpr std::uint16_t kSubYX = 107;
inline constexpr std::uint16_t kSubZX = 110;
inline constexpr std::uint16_t kSubMasterAxis = 113;
inline constexpr std::uint16_t kSubSquarenessXY = 114;
inline constexpr std::uint16_t kSubACOffset = 117;
inline constexpr std::uint16_t kSubACAngle = 118;
inline constexpr std::uint16_t kSubAngleSigmaX = 119;
inline constexpr std::uint16_t kSubStraightnessX = 122;
inline constexpr std::uint16_t kSubCCircleRms = 125;
inline constexpr std::uint16_t kSubACircleRms = 126;
inline constexpr std::uint16_t kSubSquarenessSigmaXY = 127;
inline constexpr std::uint16_t kSubACOffsetSigma = 130;
inline constexpr std::uint16_t kSubACAngleSigma = 131;
}  // namespace var

namespace gantry {

// Its macros, named once: the descriptor (kMacros, kSession, kCheck), the
// host's flows and plans use these names (docs/INTERFACE.md has the numbers).
inline constexpr std::uint16_t kMacroSessionClear = 9820;
inline constexpr std::uint16_t kMacroSessionAdd = 9821;
inline constexpr std::uint16_t kMacroSubMachine = 9822;
inline constexpr std::uint16_t kMacroBuild = 9823;
inline constexpr std::uint16_t kMacroGlobal = 9824;
inline constexpr std::uint16_t kMacroConvert = 9825;
inline constexpr std::uint16_t kMacroSubReport = 9826;
inline constexpr std::uint16_t kMacroCheck = 9827;

inline constexpr MethodBlock kBlock{"gantry", 700, 799, 3000, 3999};

// Q = #17 of 9821.
enum class GroupKind : std::uint8_t {
  kBed = 1,
  kSide1 = 2,
  kSide2 = 3,
  kGantryPass = 4,
  kXPass = 5,
  kYPass = 6,
  kZPass = 7,
  kCCircle = 8,
  kACircle = 9,
};

// Tracker points the session holds, all groups together.
inline constexpr std::uint16_t kSessionCapacity = 2048;
// Points one group may hold: one group is one fit, one step of 9823, and these
// keep a step inside Module::kStepBoundInstructions (bench_gantry.cpp measures it).
inline constexpr std::uint16_t kMaxPlanePoints = 128;   // bed, side_1, side_2
inline constexpr std::uint16_t kMaxPassPoints = 64;     // one pass of the gantry or of an axis
inline constexpr std::uint16_t kMaxCirclePoints = 30;   // a C or an A circle
inline constexpr std::uint16_t kMaxPasses = 4;          // passes of one axis (of the gantry)
// The defaults of #701 and #702: an AT960-class tracker's MPE +-(15 um + 6 um/m)
// read as 2 sigma, the simulator's transverse noise (host_sim laser_tracker.hpp
// convention 3, across the line of sight); a point's sigma is a + b r
// (core::PointNoise::additive), r its distance from the tracker.
inline constexpr double kDefaultTrackerNoiseMm = 0.0075;
inline constexpr double kDefaultTrackerNoisePerMMm = 0.003;
// The gates' defaults (gates.hpp): a gantry bed spans metres (in metres its
// points span a few units); a sub-machine's origin and axes measured again move
// by their noise (origin sigma ~20 um, angles ~10"), far less than these.
inline constexpr double kDefaultMinBedSpanMm = 100.0;
inline constexpr double kDefaultMaxOriginChangeMm = 0.25;
inline constexpr double kDefaultMaxNominalOffsetMm = 10.0;
inline constexpr double kDefaultMinSwingMm = 10.0;
inline constexpr double kDefaultMaxAngleChangeArcsec = 120.0;
// The check's tolerances' defaults (check.hpp): a sub-machine's origin and
// its axes against the stored frame.
inline constexpr double kDefaultCheckOriginMm = 0.100;
inline constexpr double kDefaultCheckAngleArcsec = 45.0;
// The check's figures (check.hpp convention 1), one of each per sub-machine
// both the computation and the stored frames hold (item: its id).
inline constexpr std::uint16_t kCheckOrigin = 1;
inline constexpr std::uint16_t kCheckAngle = 2;
// What a build logs (measuring_log.hpp).
inline constexpr std::uint16_t kLogBedForm = 1;
inline constexpr std::uint16_t kLogGantryForm = 2;

// Its status codes (block 1200..1299).
inline constexpr core::Status kBedSpanImplausible = static_cast<core::Status>(1200);
inline constexpr core::Status kSwingImplausible = static_cast<core::Status>(1201);
inline constexpr core::Status kOriginOffNominal = static_cast<core::Status>(1202);

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(var::kGantryMinArc, 1.0, 360.0, 30.0, "gantry_min_arc", "deg",
               "Gantry: a C or A circle whose points span a shorter arc is refused (arc_too_short)."),
  rows::config(var::kGantryTrackerNoise, 0.0, 1.0, kDefaultTrackerNoiseMm, "gantry_tracker_noise", "mm",
               "Gantry: the tracker's stated noise, 1 sigma per axis, its constant part a (a point's sigma is a + b r, r its distance from the tracker in m; an AT960's MPE +-(15 um + 6 um/m) read as 2 sigma); the bed's and the gantry's noise floors and form errors come from it (#701 and #702 both 0: not stated, each fit's own residuals instead)."),
  rows::config(var::kGantryTrackerNoisePerM, 0.0, 1.0, kDefaultTrackerNoisePerMMm, "gantry_tracker_noise_per_m", "mm/m",
               "Gantry: the tracker's stated noise, its part b per metre of distance from the tracker (1 sigma per axis; the tracker at the origin of the points' frame)."),
  rows::config(var::kGantryMinBedSpan, 0.0, 1e5, kDefaultMinBedSpanMm, "gantry_min_bed_span", "mm",
               "Gantry: a computation whose bed points span less than this (the largest distance from the first) is refused (bed_span_implausible: points in metres?); 0 switches the gate off."),
  rows::config(var::kGantryMaxOriginChange, 0.0, 1e5, kDefaultMaxOriginChangeMm, "gantry_max_origin_change", "mm",
               "Gantry: a store that moves a stored sub-machine's origin (global frame) by more than this is refused unless M = 1 (change_beyond_limit)."),
  rows::config(var::kGantryMaxAngleChange, 0.0, 1e6, kDefaultMaxAngleChangeArcsec, "gantry_max_angle_change", "arcsec",
               "Gantry: a store that turns a stored sub-machine's axes by more than this is refused unless M = 1 (change_beyond_limit)."),
  rows::config(var::kGantryCheckOrigin, 1e-6, 1e5, kDefaultCheckOriginMm, "gantry_check_origin_tolerance", "mm",
               "Gantry check (9827): the tolerance of a sub-machine's origin (global frame) against the stored frame's: the length of the difference."),
  rows::config(var::kGantryCheckAngle, 1e-3, 1e6, kDefaultCheckAngleArcsec, "gantry_check_angle_tolerance", "arcsec",
               "Gantry check (9827): the tolerance of a sub-machine's axes against the stored frame's: the angle they turned."),
  rows::config(var::kGantryMaxNominalOffset, 0.0, 1e5, kDefaultMaxNominalOffsetMm, "gantry_max_nominal_offset", "mm",
               "Gantry: a computation whose sub-machine origin lies farther than this from the nominal origin its 9822 gave (MACHINE's origin_x_mm .. origin_z_mm, global frame) is refused (origin_off_nominal: a swing length or tool direction typed wrong?); sub-machines without a nominal origin are taken as given."),
  rows::config(var::kGantryMinSwing, 0.0, 1e5, kDefaultMinSwingMm, "gantry_min_swing", "mm",
               "Gantry: a computation with a sub-machine's swing length below this is refused (swing_implausible: MACHINE in metres?); 0 switches the gate off."),
};

inline constexpr CheckFigureInfo kLogFigureKinds[] = {
  {kLogBedForm, "bed_form_error", "mm", "The bed's noise-corrected RMS form error (global bed_form_error_mm) with its 1-sigma."},
  {kLogGantryForm, "gantry_form_error", "mm", "The gantry's noise-corrected RMS form error (global gantry_form_error_mm) with its 1-sigma."},
};

inline constexpr CheckFigureInfo kCheckFigureKinds[] = {
  {kCheckOrigin, "origin_change", "mm", "A sub-machine's origin (global frame) against the stored frame's: the length of the difference; stored and measured are the origins' distances from the global origin. Its sigma: one direction's share of both origins' 3-D sigmas, sqrt((s_new^2 + s_stored^2) / 3)."},
  {kCheckAngle, "axes_turn", "arcsec", "The angle a sub-machine's axes turned from the stored frame's; stored 0, measured the turn. Its sigma: sqrt((|s_new|^2 + |s_stored|^2) / 3) of the frames' three angle sigmas."},
};

inline constexpr OutputInfo kSessionOutputs[] = {
  {var::kGantrySessionCount, "gantry_session_count", "", "Tracker points in the gantry session after this macro."},
  {var::kGantrySessionCapacity, "gantry_session_capacity", "", "Tracker points the gantry session holds at most."},
  {var::kGantryGroupCount, "gantry_session_groups", "", "Groups with at least one point in the session."},
};

inline constexpr OutputInfo kBuildOutputs[] = {
  {var::kGantryBuilt, "gantry_built", "", "Sub-machines whose frames were computed."},
  {var::kGantryWorstOriginSigma, "gantry_worst_origin_sigma", "mm", "Largest origin_sigma_mm of a computed sub-machine."},
  {var::kGantryBuildFlatness, "gantry_bed_flatness", "mm", "Bed flatness: peak-to-valley of the pads' distances from their plane."},
  {var::kGantryBuildStraightness, "gantry_straightness", "mm", "Gantry straightness: twice the largest distance of a pass from its line, worst pass."},
  {var::kGantryOriginChange, "gantry_origin_change", "mm", "The change against the stored frames: the largest move of a sub-machine's origin (global frame) from its stored one; 0 when none of them is stored."},
  {var::kGantryOriginChangeId, "gantry_origin_change_sub_machine", "", "The sub-machine of that largest move (0: none stored)."},
  {var::kGantryAngleChange, "gantry_angle_change", "arcsec", "The largest turn of a sub-machine's axes from its stored ones; 0 when none is stored."},
  {var::kGantryAngleChangeId, "gantry_angle_change_sub_machine", "", "The sub-machine of that largest turn (0: none stored)."},
  {var::kGantryBedSpan, "gantry_bed_span", "mm", "The bed points' span (the largest distance from the first): #703 at least."},
  {var::kGantryFitRatio, "gantry_fit_ratio", "", "The fit gate's figure: the largest chi-square statistic of a sub-machine's C or A circle (the tracker's noise #701 + #702 r at its points) over its quantile at #901 (refused above 1); 0 when #701 and #702 are 0."},
  {var::kGantryFitSubMachine, "gantry_fit_sub_machine", "", "The sub-machine of that largest figure."},
};

inline constexpr OutputInfo kGlobalOutputs[] = {
  {var::kGlobalOriginX, "global_origin_x", "mm", "X of the global origin O (tracker frame)."},
  {var::kGlobalOriginX + 1, "global_origin_y", "mm", "Y of O."},
  {var::kGlobalOriginX + 2, "global_origin_z", "mm", "Z of O."},
  {var::kGlobalXX, "global_x_x", "", "X of the global X axis (tracker frame)."},
  {var::kGlobalXX + 1, "global_x_y", "", "Y of the global X axis."},
  {var::kGlobalXX + 2, "global_x_z", "", "Z of the global X axis."},
  {var::kGlobalYX, "global_y_x", "", "X of the global Y axis."},
  {var::kGlobalYX + 1, "global_y_y", "", "Y of the global Y axis."},
  {var::kGlobalYX + 2, "global_y_z", "", "Z of the global Y axis."},
  {var::kGlobalZX, "global_z_x", "", "X of the global Z axis."},
  {var::kGlobalZX + 1, "global_z_y", "", "Y of the global Z axis."},
  {var::kGlobalZX + 2, "global_z_z", "", "Z of the global Z axis."},
  {var::kGlobalBedFlatness, "global_bed_flatness", "mm", "Bed flatness (peak-to-valley)."},
  {var::kGlobalGantryStraightness, "global_gantry_straightness", "mm", "Gantry straightness (twice the largest distance from a pass's line)."},
  {var::kGlobalOriginSigma, "global_origin_sigma", "mm", "1-sigma radial uncertainty of O."},
  {var::kGlobalAngleSigmaX, "global_angle_sigma_x", "arcsec", "1-sigma uncertainty of the frame's rotation about its X axis."},
  {var::kGlobalAngleSigmaX + 1, "global_angle_sigma_y", "arcsec", "... about its Y axis."},
  {var::kGlobalAngleSigmaX + 2, "global_angle_sigma_z", "arcsec", "... about its Z axis."},
  {var::kGlobalSubMachines, "global_sub_machines", "", "Sub-machines in that set of frames."},
  {var::kGlobalIdMask, "global_id_mask", "", "Their ids as a bit mask: bit N-1 set for sub-machine N."},
  {var::kGlobalBedFlatnessFloor, "global_bed_flatness_noise_floor", "mm", "The bed flatness (peak-to-valley) the tracker's noise (#701, #702) alone would give at the bed's point count: a flatness near it is noise, not form. -1: not stored (a table stored before it)."},
  {var::kGlobalGantryStraightnessFloor, "global_gantry_straightness_noise_floor", "mm", "The gantry straightness the tracker's noise alone would give at the passes' point counts. -1: not stored."},
  {var::kGlobalBedFormError, "global_bed_form_error", "mm", "The bed's noise-corrected form error: RMS of its points' distances from their plane with the tracker's noise taken out (0 on a flat bed within 3 sigma). -1: not stored."},
  {var::kGlobalBedFormErrorSigma, "global_bed_form_error_sigma", "mm", "1-sigma uncertainty of the bed's form error. -1: not stored."},
  {var::kGlobalGantryFormError, "global_gantry_form_error", "mm", "The gantry's noise-corrected form error: RMS distance of the passes' points from their lines, the tracker's noise taken out (0 on a straight gantry within 3 sigma). -1: not stored."},
  {var::kGlobalGantryFormErrorSigma, "global_gantry_form_error_sigma", "mm", "1-sigma uncertainty of the gantry's form error. -1: not stored."},
};

inline constexpr OutputInfo kPointOutputs[] = {
  {var::kGantryPointX, "sub_point_x", "mm", "X of the point in the sub-machine's frame."},
  {var::kGantryPointX + 1, "sub_point_y", "mm", "Y of the point in the sub-machine's frame."},
  {var::kGantryPointX + 2, "sub_point_z", "mm", "Z of the point in the sub-machine's frame."},
};

inline constexpr OutputInfo kSubOutputs[] = {
  {var::kSubOriginX, "sub_origin_x", "mm", "X of the sub-machine's origin O_sp (global frame)."},
  {var::kSubOriginX + 1, "sub_origin_y", "mm", "Y of O_sp."},
  {var::kSubOriginX + 2, "sub_origin_z", "mm", "Z of O_sp."},
  {var::kSubOriginSigma, "sub_origin_sigma", "mm", "1-sigma radial uncertainty of O_sp, the global frame's included."},
  {var::kSubXX, "sub_x_x", "", "X of the sub-machine's x' axis (global frame)."},
  {var::kSubXX + 1, "sub_x_y", "", "Y of x'."},
  {var::kSubXX + 2, "sub_x_z", "", "Z of x'."},
  {var::kSubYX, "sub_y_x", "", "X of the sub-machine's y' axis."},
  {var::kSubYX + 1, "sub_y_y", "", "Y of y'."},
  {var::kSubYX + 2, "sub_y_z", "", "Z of y'."},
  {var::kSubZX, "sub_z_x", "", "X of the sub-machine's z' axis."},
  {var::kSubZX + 1, "sub_z_y", "", "Y of z'."},
  {var::kSubZX + 2, "sub_z_z", "", "Z of z'."},
  {var::kSubMasterAxis, "sub_master_axis", "", "The axis kept exactly: 0 x, 1 y, 2 z (the longest stroke)."},
  {var::kSubSquarenessXY, "sub_squareness_xy", "arcsec", "Measured angle between x and y minus 90 deg, before orthonormalisation."},
  {var::kSubSquarenessXY + 1, "sub_squareness_yz", "arcsec", "... between y and z."},
  {var::kSubSquarenessXY + 2, "sub_squareness_zx", "arcsec", "... between z and x."},
  {var::kSubACOffset, "sub_a_c_offset", "mm", "Length of the common perpendicular of the A and C axes."},
  {var::kSubACAngle, "sub_a_c_angle", "deg", "Angle between the A and C directions (0..180)."},
  {var::kSubAngleSigmaX, "sub_angle_sigma_x", "arcsec", "1-sigma uncertainty of the frame's rotation about x'."},
  {var::kSubAngleSigmaX + 1, "sub_angle_sigma_y", "arcsec", "... about y'."},
  {var::kSubAngleSigmaX + 2, "sub_angle_sigma_z", "arcsec", "... about z'."},
  {var::kSubStraightnessX, "sub_straightness_x", "mm", "Straightness of the x axis: twice the largest distance of a pass from its line, worst pass."},
  {var::kSubStraightnessX + 1, "sub_straightness_y", "mm", "... of the y axis."},
  {var::kSubStraightnessX + 2, "sub_straightness_z", "mm", "... of the z axis."},
  {var::kSubCCircleRms, "sub_c_circle_rms", "mm", "RMS distance of the C circle's points from their fitted circle."},
  {var::kSubACircleRms, "sub_a_circle_rms", "mm", "RMS distance of the A circle's points from their fitted circle."},
  {var::kSubSquarenessSigmaXY, "sub_squareness_sigma_xy", "arcsec", "1-sigma uncertainty of the xy squareness, from the passes' fits. -1: not stored (a table stored before it)."},
  {var::kSubSquarenessSigmaXY + 1, "sub_squareness_sigma_yz", "arcsec", "1-sigma uncertainty of the yz squareness. -1: not stored."},
  {var::kSubSquarenessSigmaXY + 2, "sub_squareness_sigma_zx", "arcsec", "1-sigma uncertainty of the zx squareness. -1: not stored."},
  {var::kSubACOffsetSigma, "sub_a_c_offset_sigma", "mm", "1-sigma uncertainty of the A-to-C offset (of the signed offset, so honest at an offset near 0), from the circles' fits. -1: not stored."},
  {var::kSubACAngleSigma, "sub_a_c_angle_sigma", "deg", "1-sigma uncertainty of the A-to-C angle, from the circles' fits. -1: not stored."},
};

inline constexpr core::StatusInfo kStatuses[] = {
  {core::Status::kGroupNotContiguous, "group_not_contiguous", "A point was added to a group after other groups' points: send each group's points together, in measuring order (clear the session and send them again)."},
  {core::Status::kAxesParallel, "axes_parallel", "Two axes that must cross at an angle are parallel or nearly so (A and C of a head, two linear axes, or the gantry and the bed normal): their common perpendicular is undefined."},
  {core::Status::kPlanesDegenerate, "planes_degenerate", "The three planes do not meet in one well-defined point: two of them are parallel or nearly so (the bed and the two side faces)."},
  {core::Status::kAxisOppositeGantry, "axis_opposite_gantry", "A sub-machine's X axis points against the gantry's positive X: check the order in which its passes were measured."},
  {core::Status::kPassesDisagree, "passes_disagree", "The passes of one axis run in opposite directions: every pass must be measured moving the axis in its positive direction."},
  {core::Status::kToolDirectionAmbiguous, "tool_direction_ambiguous", "The nominal tool direction is perpendicular to the measured C axis: it cannot say which way the C axis points towards the tool tip."},
  {kBedSpanImplausible, "bed_span_implausible", "The bed points span less than #703 (#9013 their span in mm): were the points given in metres instead of millimetres? Nothing was published or stored."},
  {kSwingImplausible, "swing_implausible", "A sub-machine's swing length (9822's D, MACHINE's swing_mm) is shorter than #709 (#9012 the sub-machine, #9013 the length in mm): was MACHINE given in metres instead of millimetres? Nothing was published or stored."},
  {kOriginOffNominal, "origin_off_nominal", "A sub-machine's measured origin lies farther than #708 from the nominal origin its 9822 gave (#9012 the sub-machine, #9013 the distance in mm): a swing length typed wrong (a digit twice, metres), a tool direction with its sign flipped, or a nominal origin in another frame? Nothing was published or stored."},
  {core::Status::kBedNotLevel, "bed_not_level", "The bed plane's normal is far from the measurement's +Z: the tracker data must be levelled (+Z up)."},
};
// clang-format on

}  // namespace gantry
}  // namespace trueaxis::macros
