// M4, the spindle's tool-axis model: its rows of the register map, its outputs,
// its blocks and its status codes (docs/METHODS.md M4, docs/INTERFACE.md "M4
// spindle"). Its descriptor is method.hpp.
//
// Conventions
//  1. Configuration #800.. (block #800..#899); no data rows: the analyser's
//     samples stream through the session (9840, 9841).
//  2. Lengths in mm, the spindle angle in degrees (M19 zero, growing in the M03
//     direction: right-handed about the axis towards the tool tip), theta_e and
//     the angles' sigmas in arc-seconds. Vectors are in the analyser's frame
//     (axes parallel to the machine's).
//  3. The model's parameters (9845, Q = 1..9) in the order of
//     core::SpindleParams (spindle_model.hpp convention 1): o_x, o_y, o_z (mm),
//     a_x, a_y, e_x, e_y (mm), w_x, w_y; a and w dimensionless (radians for
//     small angles). kParameterNames lists the names OUT.json uses.
//  4. Status codes: block 1300..1399; those it owned before the block (221,
//     222) keep their numbers.
#pragma once

#include <cstdint>

#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kSpindleMaxGap = 800;
inline constexpr std::uint16_t kSpindleProbeNoise = 801;
inline constexpr std::uint16_t kSpindleFormAllowance = 802;
inline constexpr std::uint16_t kSpindleMaxSpacingError = 803;
inline constexpr std::uint16_t kSpindleMaxChange = 804;
inline constexpr std::uint16_t kSpindleCheckTilt = 805;
inline constexpr std::uint16_t kSpindleCheckOffset = 806;
inline constexpr std::uint16_t kSpindleMinBallSpacing = 807;

// 9840, 9841
inline constexpr std::uint16_t kSpindleSessionSamples = 100;
inline constexpr std::uint16_t kSpindleSessionAngles1 = 101;
inline constexpr std::uint16_t kSpindleSessionAngles2 = 102;
inline constexpr std::uint16_t kSpindleSessionCapacity = 103;
// 9842
inline constexpr std::uint16_t kSpindleEvaluations = 100;
inline constexpr std::uint16_t kSpindleNoiseSigma = 101;
inline constexpr std::uint16_t kSpindleSynchronousRms = 102;
inline constexpr std::uint16_t kSpindleNoiseFromRepeats = 103;
inline constexpr std::uint16_t kSpindleSamplesUsed = 104;
inline constexpr std::uint16_t kSpindleFitRatio = 105;
inline constexpr std::uint16_t kSpindleFitBall = 106;
inline constexpr std::uint16_t kSpindleChange = 107;
inline constexpr std::uint16_t kSpindleChangeAngle = 108;
inline constexpr std::uint16_t kSpindleBallSpacing = 109;
// 9843, 9844
inline constexpr std::uint16_t kSpindleThetaE = 100;
inline constexpr std::uint16_t kSpindleDE = 101;
inline constexpr std::uint16_t kSpindleTipX = 102;
inline constexpr std::uint16_t kSpindleThetaESigma = 105;
inline constexpr std::uint16_t kSpindleDESigma = 106;
inline constexpr std::uint16_t kSpindleTipSigmaX = 107;
inline constexpr std::uint16_t kSpindleMeanTipX = 110;
inline constexpr std::uint16_t kSpindleMeanTipSigmaX = 113;
// 9845
inline constexpr std::uint16_t kSpindleParamValue = 100;
inline constexpr std::uint16_t kSpindleParamSigma = 101;
inline constexpr std::uint16_t kSpindleRms = 102;
inline constexpr std::uint16_t kSpindleModelSynchronousRms = 103;
inline constexpr std::uint16_t kSpindleModelNoiseSigma = 104;
inline constexpr std::uint16_t kSpindleModelNoiseFromRepeats = 105;
inline constexpr std::uint16_t kSpindleModelSamples = 106;
inline constexpr std::uint16_t kSpindleModelEvaluations = 107;
inline constexpr std::uint16_t kSpindleModelGauge = 108;
inline constexpr std::uint16_t kSpindleModelBall1 = 109;
inline constexpr std::uint16_t kSpindleModelBall2 = 110;
inline constexpr std::uint16_t kSpindleModelEigenRatio = 111;
// 9847
inline constexpr std::uint16_t kSpindleWordsBytes = 100;
inline constexpr std::uint16_t kSpindleWordsCount = 101;
inline constexpr std::uint16_t kSpindleWordsFirst = 102;
}  // namespace var

namespace spindle {

// Its macros, named once: the descriptor (kMacros, kSession, kCheck), the
// host's flows and plans use these names (docs/INTERFACE.md has the numbers).
inline constexpr std::uint16_t kMacroSessionClear = 9840;
inline constexpr std::uint16_t kMacroSessionAdd = 9841;
inline constexpr std::uint16_t kMacroBuild = 9842;
inline constexpr std::uint16_t kMacroCorrection = 9843;
inline constexpr std::uint16_t kMacroReport = 9844;
inline constexpr std::uint16_t kMacroModel = 9845;
inline constexpr std::uint16_t kMacroCheck = 9846;
inline constexpr std::uint16_t kMacroModelWords = 9847;

inline constexpr MethodBlock kBlock{"spindle", 800, 899, 4000, 4999};

// The gates' defaults (gates.hpp): the analyser's capacitive probes (15 nm,
// the simulator's), what the model may leave at an angle beyond the noise (the
// balls' form error, error motions that repeat: 50 nm balls leave ~75 nm), the
// balls' measured spacing against V - U (metres read 1000 times short, a
// typed ball distance by its typo), and a change of the tool tip at V.
inline constexpr double kDefaultProbeNoiseMm = 0.000015;
inline constexpr double kDefaultFormAllowanceMm = 0.0002;
inline constexpr double kDefaultMaxSpacingErrorMm = 1.0;
inline constexpr double kDefaultMinBallSpacingMm = 5.0;
inline constexpr double kDefaultMaxChangeMm = 0.005;
// The check's tolerances' defaults (check.hpp): the axis' and the tool's
// tilts, the tool line's offset at the gauge plane.
inline constexpr double kDefaultCheckTiltArcsec = 5.0;
inline constexpr double kDefaultCheckOffsetMm = 0.002;
// The check's figures (check.hpp convention 1): the model's parameters but O1
// (o_x, o_y, o_z place the analyser, not the spindle), each a kind of its own.
inline constexpr std::uint16_t kCheckAx = 1;
inline constexpr std::uint16_t kCheckAy = 2;
inline constexpr std::uint16_t kCheckEx = 3;
inline constexpr std::uint16_t kCheckEy = 4;
inline constexpr std::uint16_t kCheckWx = 5;
inline constexpr std::uint16_t kCheckWy = 6;
// The angles the change gate compares the tool tips at: every 10 deg.
inline constexpr int kChangeAngles = 36;
inline constexpr double kChangeStepDeg = 360.0 / kChangeAngles;
// The change gate's angle k * kChangeStepDeg as the measuring log keeps its
// item, a byte (measuring_log.hpp convention 1): its step k + 1, 1 .. 36; and back.
constexpr std::uint8_t change_log_step(int k) { return static_cast<std::uint8_t>(k + 1); }
constexpr double change_angle_of_step(int step) { return kChangeStepDeg * (step - 1); }

// Its status codes (block 1300..1399).
inline constexpr core::Status kBallSpacingImplausible = static_cast<core::Status>(1300);
inline constexpr core::Status kBallsTooClose = static_cast<core::Status>(1301);

// Convention 3.
inline constexpr const char* kParameterNames[core::kSpindleParams] = {
    "o_x_mm", "o_y_mm", "o_z_mm", "a_x", "a_y", "e_x_mm", "e_y_mm", "w_x", "w_y"};

// clang-format off
inline constexpr VarInfo kRows[] = {
  rows::config(var::kSpindleMaxGap, 1.0, 180.0, core::kMaxSpindleGapDeg, "spindle_max_gap", "deg",
               "Spindle: a ball whose angles leave a wider gap than this is refused (revolution_incomplete)."),
  rows::config(var::kSpindleProbeNoise, 0.0, 1.0, kDefaultProbeNoiseMm, "spindle_probe_noise", "mm",
               "Spindle: the analyser's stated probe noise, 1 sigma per axis, for the fit gate (0 with #802 0: no fit gate)."),
  rows::config(var::kSpindleFormAllowance, 0.0, 1.0, kDefaultFormAllowanceMm, "spindle_form_allowance", "mm",
               "Spindle: the RMS 3-D residual of the angle means the model may leave beyond the noise (the balls' form error, error motions that repeat), for the fit gate."),
  rows::config(var::kSpindleMaxSpacingError, 0.0, 1e5, kDefaultMaxSpacingErrorMm, "spindle_max_spacing_error", "mm",
               "Spindle: an identification whose balls' mean centres lie farther from V - U apart than this is refused (ball_spacing_implausible: samples in metres? a ball distance typed wrong?)."),
  rows::config(var::kSpindleMaxChange, 0.0, 1e5, kDefaultMaxChangeMm, "spindle_max_change", "mm",
               "Spindle: a store whose tool-tip error at ball 2's length (V) differs from the stored model's by more than this at some angle is refused unless M = 1 (change_beyond_limit)."),
  rows::config(var::kSpindleCheckTilt, 1e-3, 1e6, kDefaultCheckTiltArcsec, "spindle_check_tilt_tolerance", "arcsec",
               "Spindle check (9846): the tolerance of the axis' tilt (a_x, a_y) and the tool's tilt against it (w_x, w_y) against the stored model's."),
  rows::config(var::kSpindleCheckOffset, 1e-7, 1e3, kDefaultCheckOffsetMm, "spindle_check_offset_tolerance", "mm",
               "Spindle check (9846): the tolerance of the tool line's offset at the gauge plane (e_x, e_y) against the stored model's."),
  rows::config(var::kSpindleMinBallSpacing, 0.0, 1e5, kDefaultMinBallSpacingMm, "spindle_min_ball_spacing", "mm",
               "Spindle: an identification whose balls lie closer than this along the tool (V - U, MACHINE's ball_2_mm - ball_1_mm) is refused (balls_too_close: both files in metres? the spacing gate #803 cannot see them, as they agree); 0 switches the gate off."),
};

inline constexpr CheckFigureInfo kCheckFigureKinds[] = {
  {kCheckAx, "a_x", "arcsec", "The spindle axis' tilt towards +X (parameter a_x)."},
  {kCheckAy, "a_y", "arcsec", "The spindle axis' tilt towards +Y (a_y)."},
  {kCheckEx, "e_x", "mm", "The tool line's offset from the axis at the gauge plane, X (e_x)."},
  {kCheckEy, "e_y", "mm", "Its Y (e_y)."},
  {kCheckWx, "w_x", "arcsec", "The tool's tilt against the axis, X (w_x)."},
  {kCheckWy, "w_y", "arcsec", "Its Y (w_y)."},
};

inline constexpr OutputInfo kSessionOutputs[] = {
  {var::kSpindleSessionSamples, "spindle_session_samples", "", "Analyser samples in the spindle session after this macro."},
  {var::kSpindleSessionAngles1, "spindle_session_angles_1", "", "Angle bins (2 deg) of ball 1 that hold samples."},
  {var::kSpindleSessionAngles2, "spindle_session_angles_2", "", "Angle bins (2 deg) of ball 2 that hold samples."},
  {var::kSpindleSessionCapacity, "spindle_session_capacity", "", "Angle bins per ball: the session keeps sums per bin, not samples (any sampling, any number of revolutions)."},
};

inline constexpr OutputInfo kBuildOutputs[] = {
  {var::kSpindleEvaluations, "spindle_evaluations", "", "Residual-and-Jacobian passes of the identification."},
  {var::kSpindleNoiseSigma, "spindle_noise_sigma", "mm", "1-sigma probe noise per axis the intervals use: what the samples leave about a local line within each 2-deg bin (asynchronous error), when there are enough."},
  {var::kSpindleSynchronousRms, "spindle_synchronous_rms", "mm", "RMS 3-D residual beyond that noise: what repeats every revolution (form error, synchronous error motion) and the model does not hold."},
  {var::kSpindleNoiseFromRepeats, "spindle_noise_from_repeats", "", "1: the noise comes from within the angle bins; 0: from every residual (too few samples per bin: conservative)."},
  {var::kSpindleSamplesUsed, "spindle_samples", "", "Samples the identification used."},
  {var::kSpindleFitRatio, "spindle_fit_ratio", "", "The fit gate's figure: the larger ball's chi-square statistic of its residuals (per axis #801^2 + #802^2 / 3) over its quantile at #901 (refused above 1)."},
  {var::kSpindleFitBall, "spindle_fit_ball", "", "The ball (1 or 2) of that figure."},
  {var::kSpindleChange, "spindle_change", "mm", "The change against the stored model: the largest difference of the tool-tip error at V over the angles 0, 10, .. 350 deg; 0 without a stored model."},
  {var::kSpindleChangeAngle, "spindle_change_angle", "deg", "The spindle angle of that largest change."},
  {var::kSpindleBallSpacing, "spindle_ball_spacing", "mm", "The distance between the balls' mean centres: V - U within #803."},
};

inline constexpr OutputInfo kCorrectionOutputs[] = {
  {var::kSpindleThetaE, "spindle_theta_e", "arcsec", "theta_e: the angle between the ideal axis (machine -Z through O1) and the tool axis at that spindle angle."},
  {var::kSpindleDE, "spindle_d_e", "mm", "d_e: the length of their common perpendicular."},
  {var::kSpindleTipX, "spindle_tip_error_x", "mm", "X of the tool-tip error (actual minus ideal tip) at that tool length: the controller subtracts it."},
  {var::kSpindleTipX + 1, "spindle_tip_error_y", "mm", "Y of the tool-tip error."},
  {var::kSpindleTipX + 2, "spindle_tip_error_z", "mm", "Z of the tool-tip error."},
};

inline constexpr OutputInfo kReportOutputs[] = {
  {var::kSpindleThetaE, "spindle_theta_e", "arcsec", "theta_e (as 9843)."},
  {var::kSpindleDE, "spindle_d_e", "mm", "d_e (as 9843)."},
  {var::kSpindleTipX, "spindle_tip_error_x", "mm", "X of the tool-tip error (as 9843)."},
  {var::kSpindleTipX + 1, "spindle_tip_error_y", "mm", "Y of the tool-tip error."},
  {var::kSpindleTipX + 2, "spindle_tip_error_z", "mm", "Z of the tool-tip error."},
  {var::kSpindleThetaESigma, "spindle_theta_e_sigma", "arcsec", "1-sigma uncertainty of theta_e."},
  {var::kSpindleDESigma, "spindle_d_e_sigma", "mm", "1-sigma uncertainty of d_e."},
  {var::kSpindleTipSigmaX, "spindle_tip_error_sigma_x", "mm", "1-sigma uncertainty of the tool-tip error's X."},
  {var::kSpindleTipSigmaX + 1, "spindle_tip_error_sigma_y", "mm", "... of its Y."},
  {var::kSpindleTipSigmaX + 2, "spindle_tip_error_sigma_z", "mm", "... of its Z."},
  {var::kSpindleMeanTipX, "spindle_mean_tip_error_x", "mm", "X of the tool-tip error averaged over a revolution (a tool turning fast)."},
  {var::kSpindleMeanTipX + 1, "spindle_mean_tip_error_y", "mm", "Y of the mean tool-tip error."},
  {var::kSpindleMeanTipX + 2, "spindle_mean_tip_error_z", "mm", "Z of the mean tool-tip error."},
  {var::kSpindleMeanTipSigmaX, "spindle_mean_tip_error_sigma_x", "mm", "1-sigma uncertainty of the mean tool-tip error's X."},
  {var::kSpindleMeanTipSigmaX + 1, "spindle_mean_tip_error_sigma_y", "mm", "... of its Y."},
  {var::kSpindleMeanTipSigmaX + 2, "spindle_mean_tip_error_sigma_z", "mm", "... of its Z."},
};

// One text for all 98 words (one copy in flash): word k (1-based) of part Q
// is the record's bytes 4 (98 Q + k - 1) .. + 3.
inline constexpr char kWordText[] =
    "A word of the part: word k of part Q is the stored record's bytes 4 (98 Q + k - 1) .. + 3, little-endian, as a whole number (0 beyond the part).";
inline constexpr OutputInfo kWordsOutputs[] = {
  {var::kSpindleWordsBytes, "model_bytes", "", "The stored record's length in bytes (512)."},
  {var::kSpindleWordsCount, "model_words", "", "The 32-bit words in this part: 98 for Q = 0, 30 for Q = 1."},
  {var::kSpindleWordsFirst, "model_word_1", "", kWordText},
  {var::kSpindleWordsFirst + 1, "model_word_2", "", kWordText},
  {var::kSpindleWordsFirst + 2, "model_word_3", "", kWordText},
  {var::kSpindleWordsFirst + 3, "model_word_4", "", kWordText},
  {var::kSpindleWordsFirst + 4, "model_word_5", "", kWordText},
  {var::kSpindleWordsFirst + 5, "model_word_6", "", kWordText},
  {var::kSpindleWordsFirst + 6, "model_word_7", "", kWordText},
  {var::kSpindleWordsFirst + 7, "model_word_8", "", kWordText},
  {var::kSpindleWordsFirst + 8, "model_word_9", "", kWordText},
  {var::kSpindleWordsFirst + 9, "model_word_10", "", kWordText},
  {var::kSpindleWordsFirst + 10, "model_word_11", "", kWordText},
  {var::kSpindleWordsFirst + 11, "model_word_12", "", kWordText},
  {var::kSpindleWordsFirst + 12, "model_word_13", "", kWordText},
  {var::kSpindleWordsFirst + 13, "model_word_14", "", kWordText},
  {var::kSpindleWordsFirst + 14, "model_word_15", "", kWordText},
  {var::kSpindleWordsFirst + 15, "model_word_16", "", kWordText},
  {var::kSpindleWordsFirst + 16, "model_word_17", "", kWordText},
  {var::kSpindleWordsFirst + 17, "model_word_18", "", kWordText},
  {var::kSpindleWordsFirst + 18, "model_word_19", "", kWordText},
  {var::kSpindleWordsFirst + 19, "model_word_20", "", kWordText},
  {var::kSpindleWordsFirst + 20, "model_word_21", "", kWordText},
  {var::kSpindleWordsFirst + 21, "model_word_22", "", kWordText},
  {var::kSpindleWordsFirst + 22, "model_word_23", "", kWordText},
  {var::kSpindleWordsFirst + 23, "model_word_24", "", kWordText},
  {var::kSpindleWordsFirst + 24, "model_word_25", "", kWordText},
  {var::kSpindleWordsFirst + 25, "model_word_26", "", kWordText},
  {var::kSpindleWordsFirst + 26, "model_word_27", "", kWordText},
  {var::kSpindleWordsFirst + 27, "model_word_28", "", kWordText},
  {var::kSpindleWordsFirst + 28, "model_word_29", "", kWordText},
  {var::kSpindleWordsFirst + 29, "model_word_30", "", kWordText},
  {var::kSpindleWordsFirst + 30, "model_word_31", "", kWordText},
  {var::kSpindleWordsFirst + 31, "model_word_32", "", kWordText},
  {var::kSpindleWordsFirst + 32, "model_word_33", "", kWordText},
  {var::kSpindleWordsFirst + 33, "model_word_34", "", kWordText},
  {var::kSpindleWordsFirst + 34, "model_word_35", "", kWordText},
  {var::kSpindleWordsFirst + 35, "model_word_36", "", kWordText},
  {var::kSpindleWordsFirst + 36, "model_word_37", "", kWordText},
  {var::kSpindleWordsFirst + 37, "model_word_38", "", kWordText},
  {var::kSpindleWordsFirst + 38, "model_word_39", "", kWordText},
  {var::kSpindleWordsFirst + 39, "model_word_40", "", kWordText},
  {var::kSpindleWordsFirst + 40, "model_word_41", "", kWordText},
  {var::kSpindleWordsFirst + 41, "model_word_42", "", kWordText},
  {var::kSpindleWordsFirst + 42, "model_word_43", "", kWordText},
  {var::kSpindleWordsFirst + 43, "model_word_44", "", kWordText},
  {var::kSpindleWordsFirst + 44, "model_word_45", "", kWordText},
  {var::kSpindleWordsFirst + 45, "model_word_46", "", kWordText},
  {var::kSpindleWordsFirst + 46, "model_word_47", "", kWordText},
  {var::kSpindleWordsFirst + 47, "model_word_48", "", kWordText},
  {var::kSpindleWordsFirst + 48, "model_word_49", "", kWordText},
  {var::kSpindleWordsFirst + 49, "model_word_50", "", kWordText},
  {var::kSpindleWordsFirst + 50, "model_word_51", "", kWordText},
  {var::kSpindleWordsFirst + 51, "model_word_52", "", kWordText},
  {var::kSpindleWordsFirst + 52, "model_word_53", "", kWordText},
  {var::kSpindleWordsFirst + 53, "model_word_54", "", kWordText},
  {var::kSpindleWordsFirst + 54, "model_word_55", "", kWordText},
  {var::kSpindleWordsFirst + 55, "model_word_56", "", kWordText},
  {var::kSpindleWordsFirst + 56, "model_word_57", "", kWordText},
  {var::kSpindleWordsFirst + 57, "model_word_58", "", kWordText},
  {var::kSpindleWordsFirst + 58, "model_word_59", "", kWordText},
  {var::kSpindleWordsFirst + 59, "model_word_60", "", kWordText},
  {var::kSpindleWordsFirst + 60, "model_word_61", "", kWordText},
  {var::kSpindleWordsFirst + 61, "model_word_62", "", kWordText},
  {var::kSpindleWordsFirst + 62, "model_word_63", "", kWordText},
  {var::kSpindleWordsFirst + 63, "model_word_64", "", kWordText},
  {var::kSpindleWordsFirst + 64, "model_word_65", "", kWordText},
  {var::kSpindleWordsFirst + 65, "model_word_66", "", kWordText},
  {var::kSpindleWordsFirst + 66, "model_word_67", "", kWordText},
  {var::kSpindleWordsFirst + 67, "model_word_68", "", kWordText},
  {var::kSpindleWordsFirst + 68, "model_word_69", "", kWordText},
  {var::kSpindleWordsFirst + 69, "model_word_70", "", kWordText},
  {var::kSpindleWordsFirst + 70, "model_word_71", "", kWordText},
  {var::kSpindleWordsFirst + 71, "model_word_72", "", kWordText},
  {var::kSpindleWordsFirst + 72, "model_word_73", "", kWordText},
  {var::kSpindleWordsFirst + 73, "model_word_74", "", kWordText},
  {var::kSpindleWordsFirst + 74, "model_word_75", "", kWordText},
  {var::kSpindleWordsFirst + 75, "model_word_76", "", kWordText},
  {var::kSpindleWordsFirst + 76, "model_word_77", "", kWordText},
  {var::kSpindleWordsFirst + 77, "model_word_78", "", kWordText},
  {var::kSpindleWordsFirst + 78, "model_word_79", "", kWordText},
  {var::kSpindleWordsFirst + 79, "model_word_80", "", kWordText},
  {var::kSpindleWordsFirst + 80, "model_word_81", "", kWordText},
  {var::kSpindleWordsFirst + 81, "model_word_82", "", kWordText},
  {var::kSpindleWordsFirst + 82, "model_word_83", "", kWordText},
  {var::kSpindleWordsFirst + 83, "model_word_84", "", kWordText},
  {var::kSpindleWordsFirst + 84, "model_word_85", "", kWordText},
  {var::kSpindleWordsFirst + 85, "model_word_86", "", kWordText},
  {var::kSpindleWordsFirst + 86, "model_word_87", "", kWordText},
  {var::kSpindleWordsFirst + 87, "model_word_88", "", kWordText},
  {var::kSpindleWordsFirst + 88, "model_word_89", "", kWordText},
  {var::kSpindleWordsFirst + 89, "model_word_90", "", kWordText},
  {var::kSpindleWordsFirst + 90, "model_word_91", "", kWordText},
  {var::kSpindleWordsFirst + 91, "model_word_92", "", kWordText},
  {var::kSpindleWordsFirst + 92, "model_word_93", "", kWordText},
  {var::kSpindleWordsFirst + 93, "model_word_94", "", kWordText},
  {var::kSpindleWordsFirst + 94, "model_word_95", "", kWordText},
  {var::kSpindleWordsFirst + 95, "model_word_96", "", kWordText},
  {var::kSpindleWordsFirst + 96, "model_word_97", "", kWordText},
  {var::kSpindleWordsFirst + 97, "model_word_98", "", kWordText},
};

inline constexpr OutputInfo kModelOutputs[] = {
  {var::kSpindleParamValue, "spindle_parameter", "", "Value of parameter Q (spindle_map.hpp convention 3; mm or dimensionless)."},
  {var::kSpindleParamSigma, "spindle_parameter_sigma", "", "Its 1-sigma uncertainty."},
  {var::kSpindleRms, "spindle_rms", "mm", "RMS 3-D residual of every sample."},
  {var::kSpindleModelSynchronousRms, "spindle_model_synchronous_rms", "mm", "RMS 3-D residual beyond the noise (synchronous)."},
  {var::kSpindleModelNoiseSigma, "spindle_model_noise_sigma", "mm", "1-sigma noise per axis the intervals use."},
  {var::kSpindleModelNoiseFromRepeats, "spindle_model_noise_from_repeats", "", "1: noise from within the angle bins; 0: from every residual."},
  {var::kSpindleModelSamples, "spindle_model_samples", "", "Samples the model was identified from."},
  {var::kSpindleModelEvaluations, "spindle_model_evaluations", "", "Residual-and-Jacobian passes of its identification."},
  {var::kSpindleModelGauge, "spindle_model_gauge", "mm", "O1 to the gauge line along the spindle, as given to 9842."},
  {var::kSpindleModelBall1, "spindle_model_ball_1", "mm", "Ball 1's centre below the gauge line, as given."},
  {var::kSpindleModelBall2, "spindle_model_ball_2", "mm", "Ball 2's centre below the gauge line, as given."},
  {var::kSpindleModelEigenRatio, "spindle_model_eigen_ratio", "", "Smallest over largest eigenvalue of the normal matrix in correlation form (identifiability)."},
};

inline constexpr core::StatusInfo kStatuses[] = {
  {core::Status::kNotIdentifiable, "not_identifiable", "The data do not determine every parameter of the model: a combination of them leaves the measurements unchanged. Measure more (for the spindle: the ball at two heights, over a whole revolution)."},
  {kBallSpacingImplausible, "ball_spacing_implausible", "The balls' mean centres are not V - U apart within #803 (#9013 the measured spacing minus V - U, mm): were the samples given in metres instead of millimetres (the spacing reads 1000 times short), or a ball distance (U, V) typed wrong? Nothing was published or stored."},
  {kBallsTooClose, "balls_too_close", "The balls are closer than #807 along the tool (V - U, MACHINE's ball_2_mm - ball_1_mm; #9013 it in mm): were both the samples and MACHINE given in metres (the spacings then agree, 1000 times short)? Nothing was published or stored."},
  {core::Status::kRevolutionIncomplete, "revolution_incomplete", "The spindle angles of a ball leave a gap wider than #800 (45 degrees by default): measure the ball over a whole revolution. Were the angles given in radians? A revolution in radians spans only 6.3 degrees."},
};
// clang-format on

}  // namespace spindle
}  // namespace trueaxis::macros
