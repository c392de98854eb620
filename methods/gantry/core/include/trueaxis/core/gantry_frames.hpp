// The frames of a gantry multi-spindle machine from laser-tracker points
// (docs/METHODS.md M2 S1-S4, docs/INTERFACE.md "M2 gantry"), with diagnostics and the
// first-order uncertainty of every frame.
//
// Frames
//   tracker  the frame of the input points, levelled: +Z up.
//   global   O-XYZ of S1; tracker_T_global is written in the tracker's frame.
//   sub      sub-machine sp's program frame (O_sp; x', y', z'); global_T_sub maps
//            its coordinates into the global frame.
//
// Conventions
//  1. S1 (global_frame_from): z0 = the bed plane's unit normal oriented to the
//     tracker's +Z (refused with kBedNotLevel when z0 . Z < kMinBedNormalZ);
//     O = the point common to the bed and the two side planes (lines.hpp item 4);
//     x = the gantry's averaged pass direction (gantry_fits.hpp item 5);
//     y = z0 x x / |z0 x x|, z = x x y. X is kept exactly, Z is corrected.
//     kAxesParallel when sin(x, z0) < kMinLineSin.
//  2. S2-S3 (sub_frame_from), all in the tracker frame: x_sp, y_sp, z_sp the
//     averaged pass directions; c = the C circle's normal oriented to the side of
//     the nominal tool direction (kToolDirectionAmbiguous when |c . tool| <
//     kMinToolCos |tool|); a = the A circle's normal oriented by the measuring
//     order (increasing A). The wrist centre T is the foot on L_C of the common
//     perpendicular of L_C = (R_C, c) and L_A = (R_A, a) (lines.hpp item 2; refused
//     with kAxesParallel when sin(a, c) < options.min_ac_sin). O_sp = T + L_sp c.
//  3. S4: the master axis is the linear axis with the largest stroke (the
//     largest extent of one of its passes along its line; ties go to x, then y).
//     X master: x' = x, y' = z x x, z' = x' x y'; Y master: y' = y, x' = y x z,
//     z' = x' x y'; Z master: z' = z, x' = y x z, y' = z x x' (each normalised;
//     kAxesParallel when a cross product's sine is below kMinLineSin). x' and the
//     measured x must both have a positive component along the gantry's x, else
//     kAxisOppositeGantry.
//  4. Diagnostics: squareness_arcsec = (angle(x, y), angle(y, z), angle(z, x))
//     minus 90 deg, of the measured directions before orthonormalisation;
//     a_c_offset_mm = length of the common perpendicular, a_c_angle_deg = angle(a,
//     c) in [0, 180]; bed_flatness_mm = peak-to-valley of the pads' signed
//     distances from the fitted plane; straightness = twice the largest distance
//     from a pass's fitted line, worst pass.
//  5. Uncertainty, first order (FrameUncertainty): each fit's parameters have
//     the covariance of gantry_fits.hpp (point noise model or the residuals);
//     the fits are independent. The frame is recomputed with each fit's
//     parameters moved by +-sqrt(lambda_k) e_k along every eigenvector of the
//     fit's covariance (numeric central differences over the whole S1 or S2-S4
//     computation); cov = sum_k g_k g_k^T with g_k = (f(+) - f(-)) / 2. The
//     output f of a frame a_T_b is (t [mm], phi [rad]) with R' = R exp([phi]x): the
//     origin's displacement in the frame a, the rotation about the frame's own
//     axes. Included for the global frame: the bed, side_1 and side_2 planes
//     (offset and tilt) and the gantry passes' directions. For a sub-machine: its
//     three axes' pass directions, the C and A circles' centres and normals
//     (with their correlation), and the global frame's covariance, mapped to
//     first order through O_sp,g = R_g^T (O_sp - O_g), R_g,sub = R_g^T R_sub:
//         d(O_sp,g) = R_g^T dO_sp - R_g^T dO_g + [O_sp,g]x phi_g,
//         phi_sub += -R_g,sub^T phi_g.
//     Not included: the swing length L_sp and the nominal tool direction (taken
//     as exact), the choice of master axis, systematic tracker errors (scale,
//     station orientation), and anything beyond first order (the errors are
//     micrometres and micro-radians against metres: the second-order terms are
//     below 1e-6 of the first).
//     origin_sigma_mm = sqrt(trace of the origin block); angle_sigma_arcsec the
//     square roots of the rotation block's diagonal.
//  6. Capacities are compile-time: kMaxSubMachines, kMaxPasses, kMaxGroupPoints,
//     kMaxCirclePoints. Memory: GantryInput holds only spans; the computation
//     keeps one sub-machine's fits at a time, no heap.
//  7. The diagnostics' 1-sigma (SubMachineFrame *_sigma_*), from the same
//     central differences as convention 5 (the same fits' covariances, the
//     same steps; the global frame does not enter: they are angles and
//     distances between measured lines): squareness from the three axes'
//     directions, the A-to-C angle and offset from the two circles' centres and
//     normals. The offset is differentiated signed, along the nominal unit(a x
//     c) (its length has no derivative at 0); so its sigma is that of the
//     signed offset, honest at and near 0 where the length is folded.
//  8. Noise floors and form errors (GlobalFrame, form_noise.hpp) from the
//     stated noise options.instrument (options.noise when that is all zero):
//     s = the RMS of sigma_i (and q of form_noise.hpp item 5) over the bed's
//     points (over the gantry passes'
//     points), count and dof those of the bed's plane (count - 3) and of the
//     gantry's passes together (sum 2 n_k - 4), the RMS from the bed fit's
//     residuals (the passes' pooled residuals). With neither noise modelled
//     the floors and sigmas are 0 and the form error is the RMS itself.
//
// Status codes (compute_gantry_frames, first failure wins, sub-machines in input
// order): those of gantry_fits.hpp for every group; kMissingGroup (no
// sub-machine, or a sub-machine without a group); kTooManyPoints (more than
// kMaxSubMachines); kArgumentOutOfRange (an id outside 1..kMaxSubMachines or
// repeated, a negative swing length, a zero tool direction, a bad option);
// kNotFinite; kBedNotLevel, kPlanesDegenerate, kAxesParallel,
// kToolDirectionAmbiguous, kAxisOppositeGantry (conventions 1-3). On failure
// compute_gantry_frames resets `out` to an empty GantryFrames and GantryBuilder
// leaves out.sub_machine_count at 0: never a half result.
#pragma once

#include <Eigen/Eigenvalues>
#include <cstddef>
#include <cstdint>

#include "trueaxis/core/circle_fit.hpp"
#include "trueaxis/core/gantry_fits.hpp"
#include "trueaxis/core/lines.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr std::size_t kMaxSubMachines = 8;
inline constexpr double kMinBedNormalZ = 0.5;  // the bed within 60 deg of level
inline constexpr double kMinToolCos = 0.1;     // the tool within 84 deg of the C axis

enum class Axis : std::uint8_t { kX = 0, kY = 1, kZ = 2 };

struct SubMachineInput {
  int id = 0;                         // 1..kMaxSubMachines
  PointSpan passes[3][kMaxPasses];    // [x, y, z][pass], each in measuring order
  std::size_t pass_count[3] = {0, 0, 0};
  PointSpan c_circle;                 // head target while C turns, increasing C
  PointSpan a_circle;                 // head target while A turns (C at zero), increasing A
  double swing_mm = 0.0;              // L_sp, wrist centre to tool tip, >= 0
  Vec3 tool_direction = Vec3::Zero(); // nominal, tracker frame; only its sense is used
};

struct GantryInput {
  PointSpan bed;     // all four pads' top faces
  PointSpan side_1;  // the two side faces at the origin corner
  PointSpan side_2;
  PointSpan gantry_passes[kMaxPasses];
  std::size_t gantry_pass_count = 0;
  SubMachineInput sub_machines[kMaxSubMachines];
  std::size_t sub_machine_count = 0;
};

struct GantryOptions {
  PointNoise noise;  // gantry_fits.hpp item 2; all zero: each fit's own residuals
  double min_arc_deg = kDefaultMinArcDeg;
  double min_ac_sin = kMinLineSin;
  PointNoise instrument;  // convention 8: the tracker's stated noise; all zero: `noise`
};

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec5 = Eigen::Matrix<double, 5, 1>;  // squareness xy, yz, zx [rad], A-to-C offset [mm], angle [rad]

// Convention 5.
struct FrameUncertainty {
  Mat6 covariance = Mat6::Zero();  // (origin mm, rotation rad)
  double origin_sigma_mm = 0.0;
  Vec3 angle_sigma_arcsec = Vec3::Zero();  // about the frame's own x, y, z
};

struct CircleSummary {
  Vec3 centre_mm = Vec3::Zero();  // global frame
  Vec3 normal = Vec3::UnitZ();    // global frame, oriented as the axis (c or a)
  double radius_mm = 0.0;
  double rms_distance_mm = 0.0;
  double max_distance_mm = 0.0;
  double arc_deg = 0.0;
};

struct GlobalFrame {
  Rigid3 tracker_T_global;
  double bed_flatness_mm = 0.0;
  double gantry_straightness_mm = 0.0;
  double side_1_flatness_mm = 0.0;
  double side_2_flatness_mm = 0.0;
  double bed_flatness_noise_floor_mm = 0.0;         // convention 8
  double gantry_straightness_noise_floor_mm = 0.0;
  double bed_form_error_mm = 0.0;                   // noise-corrected RMS
  double bed_form_error_sigma_mm = 0.0;
  double gantry_form_error_mm = 0.0;
  double gantry_form_error_sigma_mm = 0.0;
  FrameUncertainty uncertainty;  // origin in the tracker frame, rotation about the global axes
};

struct SubMachineFrame {
  int id = 0;
  Rigid3 global_T_sub;  // origin O_sp and axes x', y', z' in the global frame
  Axis master_axis = Axis::kX;
  Vec3 measured_axes[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};  // x, y, z, global frame
  Vec3 squareness_arcsec = Vec3::Zero();  // (xy, yz, zx), convention 4
  double a_c_offset_mm = 0.0;
  double a_c_angle_deg = 0.0;
  Vec3 squareness_sigma_arcsec = Vec3::Zero();  // convention 7
  double a_c_offset_sigma_mm = 0.0;
  double a_c_angle_sigma_deg = 0.0;
  Vec3 wrist_centre_mm = Vec3::Zero();  // T, global frame
  double stroke_mm[3] = {0.0, 0.0, 0.0};
  double straightness_mm[3] = {0.0, 0.0, 0.0};
  CircleSummary c_circle;
  CircleSummary a_circle;
  FrameUncertainty uncertainty;  // origin in the global frame, rotation about x', y', z'
};

struct GantryFrames {
  GlobalFrame global;
  SubMachineFrame sub_machines[kMaxSubMachines];  // in input order
  std::size_t sub_machine_count = 0;
};

// S1 from the fitted geometry (convention 1): tracker_T_global.
[[nodiscard]] Result<Rigid3> global_frame_from(const Plane3& bed, const Plane3& side_1, const Plane3& side_2,
                                               const Vec3& gantry_x);

// S2-S4 result in the tracker frame.
struct SubGeometry {
  Rigid3 tracker_T_sub;
  Vec3 wrist_centre_mm = Vec3::Zero();
  Vec3 c = Vec3::UnitZ();  // oriented C axis direction
  Vec3 a = Vec3::UnitX();  // oriented A axis direction
  double a_c_offset_mm = 0.0;
  double a_c_angle_deg = 0.0;
};

// S2-S4 from fitted geometry, all in the tracker frame (conventions 2, 3): axes
// = measured x, y, z directions; c_axis and a_axis = the circles' centres and
// normals (c is oriented here by tool_direction, a used as given).
[[nodiscard]] Result<SubGeometry> sub_frame_from(const Vec3 axes[3], Axis master, const Line3& c_axis,
                                                 const Vec3& tool_direction, const Line3& a_axis, double swing_mm,
                                                 const Vec3& gantry_x, double min_ac_sin);

// The whole of M2: fits, frames, diagnostics, uncertainties (a GantryBuilder
// run to its end).
[[nodiscard]] Status compute_gantry_frames(const GantryInput& input, const GantryOptions& options,
                                           GantryFrames& out);

struct GantryStep {
  Status status = Status::kOk;
  bool more = false;  // true: call step() again; status is kOk then
};

// M2 in bounded steps, for a controller's background task: one fit, or one
// frame with its uncertainty, per step(). The order of the work, and so which
// failure wins, is compute_gantry_frames's: the checks, the bed, side_1,
// side_2 and gantry fits, the global frame, then per sub-machine in input order
// its x, y, z passes, its C and A circles and its frame. No heap; about 4 kB
// besides the frames it writes.
class GantryBuilder {
 public:
  // Begins a build into `out`. `input`, the points its spans name and `out`
  // must outlive the build; restarting discards a build under way.
  // out.sub_machine_count is 0 until the last step succeeds.
  void start(const GantryInput& input, const GantryOptions& options, GantryFrames& out);

  // {kOk, true} while more remains, {kOk, false} when `out` is complete,
  // {error, false} on failure (out.sub_machine_count stays 0).
  GantryStep step();

  // The sub-machine (its id) a failure refers to; 0 for the global groups.
  int failed_sub_machine() const { return failed_id_; }

  std::size_t steps() const { return steps_; }

 private:
  enum class Phase : std::uint8_t { kIdle, kCheck, kBed, kSide1, kSide2, kGantry, kGlobal,
                                    kAxisX, kAxisY, kAxisZ, kCircleC, kCircleA, kSub, kDone, kFailed };
  GantryStep fail(Status status);

  const GantryInput* in_ = nullptr;
  GantryOptions options_;
  GantryFrames* out_ = nullptr;
  Phase phase_ = Phase::kIdle;
  std::size_t sub_ = 0;
  std::size_t steps_ = 0;
  int failed_id_ = 0;
  PlaneEstimate bed_, side_1_, side_2_;
  AxisEstimate gantry_;
  AxisEstimate axes_[3];
  CircleFit c_fit_, a_fit_;
  // Scratch: in the builder, not on the stack of step() (docs/FIGURES.md "Stack").
  CircleFitWork circle_work_;
  Eigen::SelfAdjointEigenSolver<Mat3> eigen3_;  // a fit's covariance (convention 5)
  Eigen::SelfAdjointEigenSolver<Mat6> eigen6_;
  Mat6 own_ = Mat6::Zero();  // a sub-machine's covariance before the global frame's
  Vec5 figure_var_ = Vec5::Zero();  // its diagnostics' variances (convention 7)
};

// A point in the global frame written in sub-machine `frame`'s coordinates.
inline Vec3 global_to_sub_mm(const SubMachineFrame& frame, const Vec3& p_global_mm) {
  return apply_point(inverse(frame.global_T_sub), p_global_mm);
}

}  // namespace trueaxis::core
