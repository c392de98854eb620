// The fits of M2's point groups (docs/METHODS.md M2, docs/INTERFACE.md "M2 gantry"), each
// with the covariance of the parameters the frames are built from, for a point
// noise that can grow with the range from the tracker. gantry_frames.hpp builds
// the frames on them.
//
// Conventions
//  1. Points in millimetres, all in one frame (the tracker's); every output is in
//     that frame. A group is a PointSpan: a pointer to `count` points the caller
//     owns; nothing is copied or kept.
//  2. Point noise: independent, isotropic, zero-mean, per-axis standard
//     uncertainty
//         sigma_i^2 = a^2 + (b * |p_i - tracker|)^2,
//     a = distance_sigma_mm, b = range_sigma_per_mm (e.g. 3e-6 for 3 um/m), the
//     tracker's position given in the points' frame. An AT960-like MPE
//     +-(15 um + 6 um/m) read as 2 sigma is a = 0.0075, b = 3e-6. With a = b = 0
//     every fit takes sigma from its own residuals instead (a plane
//     sigma^2 = sum h_i^2 / (n - 3); a pass the covariance of its
//     perpendicular residuals q_i, sum q_i q_i^T / (n - 2), which follows a
//     tracker that is noisier across its line of sight than along it (convention
//     4); a circle as circle_fit.hpp item 5): pad unflatness and axis
//     straightness then count as noise. A stated model (a, b) is isotropic: the
//     real tracker's error is larger across the line of sight than along it, so
//     a stated model overstates the noise along it.
//     additive = true takes the MPE's own form instead,
//         sigma_i = a + b * |p_i - tracker|,
//     as a tracker's data sheet states it and the simulator's tracker draws
//     its noise across the line of sight (host_sim laser_tracker.hpp item 3):
//     the module's noise floors and form errors use it (gantry_frames.hpp
//     convention 8; #701, #702).
//  3. Plane (PlaneEstimate): fit_accumulator.hpp's streaming fit, then a second
//     pass over the points. With (x_i, y_i) the point's coordinates along
//     (axis_u, axis_v) from the centroid and h the height along the normal, the
//     fitted plane moves, to first order in the heights' noise e_i, to
//         h(x, y) = d + alpha x + beta y,   (d, alpha, beta) = sum_i g_i e_i,
//         g_i = (1 / n, x_i / Sxx, y_i / Syy),  Sxx = sum x^2, Syy = sum y^2
//     (sum x y = 0 on principal axes), so the covariance of (d [mm], alpha,
//     beta [rad]) is sum_i sigma_i^2 g_i g_i^T (the "sandwich" form: right for
//     unequal sigma_i although the fit is unweighted). perturbed_plane() turns
//     (d, alpha, beta) into the plane through centroid + d n with normal
//     (n - alpha u - beta v) normalised. flatness_mm = max - min of h_i.
//  4. Pass (one line fit, fit_accumulator.hpp): with t_i the position along the
//     fitted direction from the centroid, each perpendicular slope is
//     sum_i t_i e_i / Stt, Stt = sum t_i^2. With a stated model its variance is
//     v = sum sigma_i^2 t_i^2 / Stt^2, the same for both perpendicular axes and
//     uncorrelated, and the unit direction's error has covariance v (I - d d^T).
//     From the residuals (no model) it is S / Stt, S = sum q_i q_i^T / (n - 2)
//     the perpendicular residuals' covariance (rank 2, across d): each
//     perpendicular axis gets its own noise, so a pass lying across the line of
//     sight, whose one perpendicular axis is along it, is not given the larger
//     transverse noise on both (issue 17: squareness sigmas 1.57 x the spread on
//     the simulator's tracker when pooled isotropically). straightness_mm = twice the largest
//     perpendicular distance from the fitted line; stroke_mm = max t - min t.
//  5. Axis (AxisEstimate) from K passes: each pass's direction is oriented by the
//     order of its points (growing sample index = the axis's positive direction);
//     direction = m / |m|, m = (1 / K) sum_k d_k (docs/METHODS.md: "fit a line to each
//     pass and average"). Its covariance (rad^2, rank 2, perpendicular to it):
//         P (sum_k v_k (I - d_k d_k^T)) P / (K |m|)^2,  P = I - direction direction^T.
//     stroke_mm, straightness_mm and rms_residual_mm are the largest over the passes;
//     residual_ssr_mm2 and point_count are summed over them (form_noise.hpp).
//  6. Circle: circle_fit.hpp's geometric fit, normal oriented by the order of the
//     points (increasing axis angle); with a noise model its point_sigma_mm is the
//     RMS of the sigma_i (the points of one circle are nearly equidistant from the
//     tracker: a 200 mm circle 2 m away spans sigma_i within a few per cent).
//
// Status codes: kMissingGroup (a group or pass with no points, or no passes),
// kTooFewPoints (fewer than kMinPlanePoints, kMinPassPoints, kMinCirclePoints),
// kTooManyPoints (more than kMaxGroupPoints, or kMaxCirclePoints for a circle;
// more than kMaxPasses passes), kNotFinite (a point or a noise parameter),
// kArgumentOutOfRange (a negative noise parameter or min_arc_deg), kPassesDisagree
// (a pass whose oriented direction makes more than 90 deg with the first one's),
// and those of fit_plane / fit_line / fit_circle (kPointsCoincident,
// kPointsCollinear, kPointsNotOnLine, kArcTooShort, kNoConvergence).
#pragma once

#include <cstddef>

#include "trueaxis/core/circle_fit.hpp"
#include "trueaxis/core/fit_accumulator.hpp"
#include "trueaxis/core/lines.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr std::size_t kMaxGroupPoints = 1024;  // points of one plane group or one pass
inline constexpr std::size_t kMaxPasses = 8;          // passes per linear axis or of the gantry
inline constexpr std::size_t kMinPlanePoints = 4;     // n - 3 >= 1: a residual to judge by
inline constexpr std::size_t kMinPassPoints = 3;      // 2n - 4 >= 2
inline constexpr std::size_t kMinCirclePoints = 5;    // 2n - 6 >= 4

struct PointSpan {
  const Vec3* points_mm = nullptr;
  std::size_t count = 0;
};

// Convention 2.
struct PointNoise {
  double distance_sigma_mm = 0.0;   // a
  double range_sigma_per_mm = 0.0;  // b, mm of sigma per mm of range
  Vec3 tracker_mm = Vec3::Zero();   // the tracker's position, in the points' frame
  bool additive = false;            // a + b r, not hypot(a, b r) (convention 2)

  bool modelled() const { return distance_sigma_mm > 0.0 || range_sigma_per_mm > 0.0; }
  double sigma_mm(const Vec3& p_mm) const {
    const double range_term = range_sigma_per_mm * (p_mm - tracker_mm).norm();
    return additive ? distance_sigma_mm + range_term : std::hypot(distance_sigma_mm, range_term);
  }
};

// kNotFinite or kArgumentOutOfRange (negative) for a bad noise model, else kOk.
[[nodiscard]] Status check_noise(const PointNoise& noise);

struct PlaneEstimate {
  Vec3 centroid_mm = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit; sign as the caller oriented it (orient_plane)
  Vec3 axis_u = Vec3::UnitX();  // in-plane unit axes of the larger and smaller spread
  Vec3 axis_v = Vec3::UnitY();
  double flatness_mm = 0.0;      // peak-to-valley of the signed distances
  double rms_residual_mm = 0.0;
  Mat3 covariance = Mat3::Zero();  // of (d [mm], alpha, beta [rad]), convention 3
  std::size_t count = 0;
};

struct AxisEstimate {
  Vec3 direction = Vec3::UnitX();  // unit, convention 5
  Mat3 covariance = Mat3::Zero();  // rad^2 of the unit direction's error, convention 5
  double stroke_mm = 0.0;          // largest extent of a pass along its line
  double straightness_mm = 0.0;    // worst pass, twice the largest distance from its line
  double rms_residual_mm = 0.0;    // worst pass, RMS perpendicular distance
  std::size_t pass_count = 0;
  double residual_ssr_mm2 = 0.0;   // all passes, sum of squared perpendicular distances
  std::size_t point_count = 0;     // all passes
};

// Plane through a group (convention 3); the normal's sign is the fit's.
[[nodiscard]] Result<PlaneEstimate> fit_plane_group(PointSpan points, const PointNoise& noise);

// The plane with its normal turned to the side of `hint` (d, alpha, beta keep
// their covariance: all three change sign together).
PlaneEstimate orient_plane(const PlaneEstimate& plane, const Vec3& hint);

// The plane moved by delta = (d, alpha, beta) (convention 3).
Plane3 perturbed_plane(const PlaneEstimate& plane, const Vec3& delta);

// An axis's direction from its passes (conventions 4, 5).
[[nodiscard]] Result<AxisEstimate> fit_axis_passes(const PointSpan* passes, std::size_t pass_count,
                                                   const PointNoise& noise);

// A circle group (convention 6), into `out` with the caller's scratch
// (circle_fit.hpp); `out` is written only when kOk is returned.
[[nodiscard]] Status fit_circle_group(PointSpan points, const PointNoise& noise, double min_arc_deg,
                                      CircleFitWork& work, CircleFit& out);

// The circle's axis line moved by delta = (c_x, c_y, c_z, a, b, r) in the
// parameters of its covariance (circle_fit.hpp item 5): centre + (c_x, c_y, c_z),
// normal (n + a axis_u + b axis_v) normalised; r does not move the axis.
Line3 perturbed_circle_axis(const CircleFit& circle, const Eigen::Matrix<double, 6, 1>& delta);

}  // namespace trueaxis::core
