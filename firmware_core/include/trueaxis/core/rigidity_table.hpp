// M3, AC-axis connection rigidity: the table built from ball-centre samples
// (docs/METHODS.md M3 S100-S200, docs/INTERFACE.md "M3 rigidity", docs/METHODS.md "M3 design notes").
//
// Conventions
//  1. Machine frame: the instrument's XYZ, mm. Angles are degrees at this
//     interface (a_deg, c_deg: commanded) and radians in the table's results.
//     Rotation vectors are written in machine coordinates.
//  2. Poses. Samples whose commanded A agree within kPoseAToleranceDeg with the
//     first sample of a pose (in input order) belong to that pose; its a_deg is
//     that first sample's A. Poses are sorted by A. The reference pose is the
//     one with |A| <= kPoseAToleranceDeg. Required: kMinAPoses..kMaxAPoses poses,
//     each with at least kMinCPositions distinct C (modulo 360, distinct = more
//     than kPoseAToleranceDeg apart) and at most kMaxCirclePoints samples. A C
//     repeated within a pose is a repeat measurement and is kept.
//  3. Per pose i: the geometric circle fit of its ball centres, oriented by the
//     commanded C (circle_fit.hpp convention 4), gives the centre c_i, the unit
//     normal n_i (c_direction: right-hand rule about the ball's motion for
//     increasing C) and the rms distance; delta_i = circular mean of
//     (phase(p_k) - C_k) (circle_phase_offset_rad); X_i = circle_direction(fit,
//     delta_i), the direction from c_i towards the circle's point at commanded
//     C = 0. Actual frame: E_i = [X_i, n_i x X_i, n_i] (columns), origin c_i.
//  4. A axis: the circle through c_1..c_m oriented by the commanded A: centre a0
//     (a_axis_point_mm), unit normal nA (a_axis_direction, right-hand rule for
//     increasing A).
//  5. theta_i (disAngle): the signed angle about nA from (c_ref - a0) to
//     (c_i - a0), both projected on the plane normal to nA, taken on the branch
//     nearest deg2rad(A_i - A_ref). Theory frame ET_i = R(nA, theta_i) E_ref with
//     origin o_i = a0 + R(nA, theta_i)(c_ref - a0), R(n, t) = exp(t n).
//     rotvec_i = log(E_i ET_i^T) (so3_log), rigidity_i = |rotvec_i|,
//     a_error_i = theta_i - deg2rad(A_i - A_ref), origin_offset_i = c_i - o_i.
//     The reference pose has rotvec 0, a_error 0, origin_offset 0 and sigmas 0
//     exactly.
//  6. C-to-A location errors (ISO 230-1 style, at the reference pose):
//     offset = length of the common perpendicular of the lines (c_ref, n_ref)
//     and (a0, nA) (their distance when parallel); squareness =
//     angle(n_ref, nA) - pi / 2, signed.
//  7. Sigmas (1 sigma, from the data's own scatter): first-order propagation of
//     each pose's fit uncertainty through the whole of 3-6 (the A-axis circle and
//     the reference pose included) by a numeric Jacobian. Per pose the
//     independent inputs are (a) the circle fit's joint covariance of centre and
//     normal (5x5: c_x, c_y, c_z and the normal's tangent angles along axis_u,
//     axis_v; the joint block, so a short arc's centre-normal correlation is
//     kept), taken along its eigenvectors, and (b) the phase offset's standard
//     error (a turn of X_i about n_i). A perturbed normal carries X_i along by the
//     smallest rotation (X projected on the new plane): the phases are measured
//     in the circle's plane. Each direction is a central difference of step
//     max(sigma, kJacobianMinStep) scaled to sigma:
//         Sigma_out = sum_j J_j Sigma_j J_j^T.
//     Per-component sigma = sqrt(diag); rigidity sigma = sqrt(u^T Sigma u),
//     u = rotvec / |rotvec|, except where |rotvec| is below that figure (the norm
//     is not differentiable at 0): sqrt(trace(Sigma) / 3). Neglected: the
//     correlation of the phase offset with the centre (zero for C positions
//     spread evenly over a turn).
//  8. Derived data (computed by build and by decode, never serialized): E_ref,
//     exp(rotvec_i), log(exp(rotvec_i)^T exp(rotvec_{i+1})) for the geodesic
//     blend, and the cubic splines' second derivatives over A: of the rotation
//     vector (per component) with natural and with not-a-knot end conditions,
//     and of the A positioning error and the origin offset (not-a-knot) for the
//     cubic blends (rigidity_compensation.hpp convention 3).
//
// Bounded work: RigidityBuilder::step() does one of: grouping kGroupChunk
// samples, one pose's circle fit (the fit is not resumable, so its cost grows
// with the pose's samples: about 3.4k Cortex-M7 instructions each; the caller
// bounds it with options.max_pose_samples), the nominal evaluation of 4-6, one
// side of one Jacobian column (an A-axis circle fit of <= 16 points plus the
// frames), the finish. The module's figure is Module::kStepBoundInstructions.
//
// Status codes: kNotFinite (a sample or an option), kArgumentOutOfRange
// (samples null with count > 0, min_c_arc_deg or min_a_arc_deg outside
// [0, 360)), kTooManyPoints (more than kMaxRigiditySamples samples, or more than
// kMaxCirclePoints or options.max_pose_samples in one pose), kTooManyPoses, kTooFewPoses, kNoReferencePose,
// kTooFewCPositions, from a pose's circle fit: kArcTooShort (its C arc below
// min_c_arc_deg), kPointsCoincident, kPointsCollinear, kNoConvergence;
// kCPhaseInconsistent (the phase offsets' resultant length below
// kMinPhaseResultant: the commanded C do not match the ball's motion);
// kAAxisUndetermined (the A-axis circle fit failed: centres coincident or
// collinear, A arc below min_a_arc_deg, no convergence). failed_pose() names
// the pose (1-based, in A order) for the per-pose codes.
#pragma once

#include <Eigen/Eigenvalues>
#include <cstddef>
#include <cstdint>

#include "trueaxis/core/circle_fit.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr std::size_t kMaxAPoses = 16;
inline constexpr std::size_t kMaxRigiditySamples = 512;
inline constexpr std::size_t kMinAPoses = 3;
inline constexpr std::size_t kMinCPositions = 4;
inline constexpr double kPoseAToleranceDeg = 1e-6;
inline constexpr double kDefaultMinCArcDeg = 45.0;
inline constexpr double kDefaultMinAArcDeg = 5.0;
inline constexpr double kMinPhaseResultant = 0.99984769515639124;  // cos(1 deg)
inline constexpr double kJacobianMinStep = 1e-7;                   // mm or rad
inline constexpr std::size_t kGroupChunk = 64;

struct RigiditySample {
  double a_deg = 0.0;  // commanded
  double c_deg = 0.0;  // commanded
  Vec3 p_mm = Vec3::Zero();  // ball centre, machine frame
};

struct RigidityOptions {
  double min_c_arc_deg = kDefaultMinCArcDeg;  // a pose's C arc shorter than this: kArcTooShort
  double min_a_arc_deg = kDefaultMinAArcDeg;  // the poses' A arc shorter than this: kAAxisUndetermined
  // A pose with more samples: kTooManyPoints. A pose's circle fit is one step,
  // so this bounds the longest step (the module passes kMaxPoseSamples).
  std::size_t max_pose_samples = kMaxCirclePoints;
  // The machine's home identity the table records (RigidityTable::home_identity).
  std::uint16_t home_identity = 0;
};

struct RigidityPose {
  double a_deg = 0.0;                         // commanded A of the pose
  Vec3 rotvec_rad = Vec3::Zero();             // log(E_i ET_i^T), machine frame
  Vec3 rotvec_sigma_rad = Vec3::Zero();       // per component, 1 sigma
  double rigidity_rad = 0.0;                  // |rotvec|
  double rigidity_sigma_rad = 0.0;
  double theta_rad = 0.0;                     // disAngle about nA from the reference
  double a_error_rad = 0.0;                   // theta - deg2rad(A - A_ref)
  double a_error_sigma_rad = 0.0;
  Vec3 origin_offset_mm = Vec3::Zero();       // d_i = c_i - o_i
  Vec3 c_centre_mm = Vec3::Zero();            // c_i
  Vec3 c_direction = Vec3::UnitZ();           // n_i, unit
  Vec3 c_x_axis = Vec3::UnitX();              // X_i, unit, normal to n_i
  double c_circle_rms_mm = 0.0;               // RMS 3-D distance of the samples from the circle
  double c_arc_deg = 0.0;                     // the arc the samples span
  std::size_t c_count = 0;                    // samples in the pose
};

struct RigidityTable {
  std::size_t pose_count = 0;
  std::size_t reference = 0;                  // index of the pose at A = 0
  RigidityPose poses[kMaxAPoses];             // sorted by a_deg, strictly increasing
  Vec3 a_axis_point_mm = Vec3::Zero();        // a0
  Vec3 a_axis_direction = Vec3::UnitX();      // nA, unit
  double c_to_a_offset_mm = 0.0;
  double c_to_a_offset_sigma_mm = 0.0;
  double c_to_a_squareness_rad = 0.0;
  double c_to_a_squareness_sigma_rad = 0.0;
  // The machine's home the poses were measured under, as a number its
  // integrator sets (the module's #904; 0: none recorded): the axes' zeros
  // the table's A, C and positions hold. Stored; not a measurement.
  std::uint16_t home_identity = 0;

  // Derived (convention 8).
  Mat3 reference_axes = Mat3::Identity();     // E_ref
  Mat3 rotation[kMaxAPoses];                  // exp(rotvec_i)
  Vec3 geodesic_step_rad[kMaxAPoses];         // log(R_i^T R_{i+1}); the last is 0
  Vec3 spline_m[kMaxAPoses];                  // d2 rotvec / dA^2, rad / deg^2 (natural)
  Vec3 spline_k[kMaxAPoses];                  // d2 rotvec / dA^2, rad / deg^2 (not-a-knot)
  double spline_e[kMaxAPoses];                // d2 a_error / dA^2, rad / deg^2
  Vec3 spline_d[kMaxAPoses];                  // d2 origin_offset / dA^2, mm / deg^2
};

// The scratch of prepare_rigidity_table: the not-a-knot splines' dense
// system, reduced (rigidity_pipeline.cpp).
struct RigiditySplineWork {
  double a[kMaxAPoses][kMaxAPoses];
  std::uint8_t pivot[kMaxAPoses];
};

// Fills the derived data of convention 8 from the stored fields (its 2 kB of
// scratch on the stack).
void prepare_rigidity_table(RigidityTable& table);

// The same with the caller's scratch (the builder's: docs/FIGURES.md "Stack").
void prepare_rigidity_table(RigidityTable& table, RigiditySplineWork& work);

namespace detail {

// One pose's measured frame: the input of conventions 4-6.
struct RigidityPoseFrame {
  double a_deg = 0.0;
  Vec3 centre = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 x_axis = Vec3::UnitX();
};

// Conventions 4-6 evaluated on a set of pose frames.
struct RigidityEvaluation {
  Vec3 a_point = Vec3::Zero();
  Vec3 a_direction = Vec3::UnitX();
  Vec3 rotvec[kMaxAPoses];
  double theta[kMaxAPoses];
  double a_error[kMaxAPoses];
  Vec3 origin_offset[kMaxAPoses];
  double offset_mm = 0.0;
  double squareness_rad = 0.0;
};

// The builder's scratch for the evaluations and the pose fits (conventions
// 3-6): in the builder, not on the stack of step() (docs/FIGURES.md "Stack").
struct RigidityScratch {
  RigidityPoseFrame frames[kMaxAPoses];
  Vec3 centres[kMaxAPoses];      // the A-axis circle's points
  double a_deg[kMaxAPoses];
  CircleFit circle;              // a pose's circle, or the A-axis circle
  CircleFitWork circle_work;
};

}  // namespace detail

struct RigidityStep {
  Status status = Status::kOk;
  bool more = false;  // true: call step() again; status is kOk then
};

// The table, built in bounded steps. No heap; about 26 kB (the table 6.3 kB).
class RigidityBuilder {
 public:
  // Begins a build. The samples (any order) must stay unchanged until step()
  // returns more == false. Restarting discards a build under way.
  void start(const RigiditySample* samples, std::size_t count, const RigidityOptions& options);

  // One bounded piece of work: {kOk, true} while more remains, {kOk, false} when
  // the table is complete, {error, false} on failure (then table() is not valid).
  RigidityStep step();

  // The table; complete only after step() returned {kOk, false}.
  const RigidityTable& table() const { return table_; }

  // The pose (1-based, in A order) a per-pose status refers to; 0 otherwise.
  std::size_t failed_pose() const { return failed_pose_; }

  // Steps taken since start().
  std::size_t steps() const { return steps_; }

 private:
  enum class Phase : std::uint8_t { kIdle, kGroup, kSort, kFit, kNominal, kJacobian, kFinish, kDone, kFailed };
  using Mat5 = Eigen::Matrix<double, 5, 5>;

  struct PoseFit {
    double a_deg = 0.0;
    std::size_t count = 0;
    Vec3 centre = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ();
    Vec3 x_axis = Vec3::UnitX();
    Vec3 axis_u = Vec3::UnitX();
    Vec3 axis_v = Vec3::UnitY();
    Mat5 covariance = Mat5::Zero();  // (c_x, c_y, c_z, a, b)
    double phase_sigma_rad = 0.0;
    double rms_mm = 0.0;
    double arc_deg = 0.0;
  };

  RigidityStep fail(Status s, std::size_t pose_index_plus_one = 0);
  RigidityStep step_group();
  RigidityStep step_sort();
  RigidityStep step_fit();
  RigidityStep step_nominal();
  RigidityStep step_jacobian();
  RigidityStep step_finish();
  Status evaluate_perturbed(double signed_step, detail::RigidityEvaluation& out);

  const RigiditySample* samples_ = nullptr;
  std::size_t count_ = 0;
  RigidityOptions options_;
  Phase phase_ = Phase::kIdle;
  std::size_t cursor_ = 0;        // sample (group), pose (fit), column (Jacobian)
  std::size_t steps_ = 0;
  std::size_t failed_pose_ = 0;
  Status final_status_ = Status::kOk;

  std::uint8_t pose_of_sample_[kMaxRigiditySamples] = {};  // in first-seen order
  double c_mod_360_[kMaxRigiditySamples] = {};              // C of each sample in [0, 360)
  std::uint16_t pose_samples_[kMaxCirclePoints] = {};       // the fitted pose's samples, by C
  Vec3 points_[kMaxCirclePoints];                           // ... their ball centres
  double angles_deg_[kMaxCirclePoints] = {};                // ... their commanded C
  std::size_t first_seen_count_ = 0;
  double first_seen_a_deg_[kMaxAPoses] = {};
  std::uint8_t sorted_of_first_seen_[kMaxAPoses] = {};
  PoseFit fits_[kMaxAPoses];

  // Jacobian: column = 6 * pose + direction; the + side is held until the - side.
  Eigen::SelfAdjointEigenSolver<Mat5> eigen_;
  std::size_t eigen_pose_ = kMaxAPoses;  // the pose whose covariance eigen_ holds
  bool plus_done_ = false;
  detail::RigidityEvaluation plus_;
  detail::RigidityEvaluation scratch_;
  detail::RigidityScratch work_;
  RigiditySplineWork spline_work_;
  Mat3 rotvec_cov_[kMaxAPoses];
  double a_error_var_[kMaxAPoses] = {};
  double offset_var_ = 0.0;
  double squareness_var_ = 0.0;

  RigidityTable table_;
};

// The whole build in one call (loops RigidityBuilder::step()); same status codes.
// `builder` holds the work space and the result: builder.table().
[[nodiscard]] Status build_rigidity_table(const RigiditySample* samples, std::size_t count,
                                          const RigidityOptions& options, RigidityBuilder& builder);

}  // namespace trueaxis::core
