// Geometric least-squares circle in 3-D through 3 to kMaxCirclePoints points,
// with its covariance, the arc the points span, and the phase helpers that M3
// needs to place a frame's X axis at commanded angle zero (docs/METHODS.md M2 S2, M3
// S100; docs/INTERFACE.md "M3 rigidity").
//
// Conventions
//  1. Points in millimetres, in any frame; every output vector is in that frame.
//     A circle is (centre c, unit normal n, radius r > 0).
//  2. The fit is GEOMETRIC: it minimises the sum over the points of the squared
//     3-D orthogonal distance to the circle,
//         e_i^2 = h_i^2 + (rho_i - r)^2,   d_i = p_i - c,  h_i = n . d_i,
//         rho_i = |d_i - h_i n|,
//     i.e. the maximum-likelihood circle under isotropic Gaussian point noise
//     (the model p_i = c + r (cos t_i u + sin t_i v) + noise with the phases t_i
//     eliminated). Initial guess: the points' scatter-matrix plane, then the
//     Kasa circle in that plane; then Levenberg-Marquardt on the 2n residuals
//     (h_i, sgn(k) (rho_i - r)) in coordinates centred on the centroid and
//     scaled by the points' RMS extent. The solver's 6 parameters are not
//     (c, n, r), whose centre and radius run off together along a flat valley on
//     short arcs, but an anchor point m on the circle near the points, the frame
//     (tangent t, towards-centre w, normal n) there, turned by a small rotation
//     (3), m moved along w and n (2), and the signed curvature k = 1/r (1), with
//         sgn(k) (rho - r) = (k s^2 - 2 y) / (1 + sqrt(k^2 x^2 + (k y - 1)^2)),
//     (x, y, z) the point in the anchor frame, s^2 = x^2 + y^2: no cancellation
//     for large radii, smooth through k = 0 (a line). Near the minimum,
//     undamped Gauss-Newton steps finish the job (the cost's decrease is then
//     below its rounding). The covariance (convention 5) is in (c, n, r).
//  3. In-plane basis: axis_u is the unit vector from the centre towards the
//     first point's projection on the circle's plane; axis_v = normal x axis_u,
//     so (axis_u, axis_v, normal) is right-handed. Phases are angles about the
//     normal (right-hand rule), measured from axis_u, in (-pi, pi].
//  4. Orientation of the normal (right-hand rule about the motion):
//     - with commanded angles (options.angles_deg, one per point): increasing
//       angle is a positive rotation about the normal. The evidence is
//       S = sum over consecutive samples k, k+1 (in the order given) of
//       sin(angle_{k+1} - angle_k) sin(phase_{k+1} - phase_k); the normal is
//       flipped when S < 0. Samples may come in any order; steps of exactly 0 or
//       180 deg carry no evidence.
//     - without: increasing sample order is a positive rotation; S = sum of
//       sin(phase_{k+1} - phase_k) (consecutive samples less than 180 deg apart).
//     When S is exactly 0 the sign of the initial plane fit's normal is kept.
//  5. Covariance of the parameters x = (c_x, c_y, c_z, a, b, r) at the solution:
//         cov = sigma^2 (J^T J)^-1,
//     J the Jacobian of the 2n residuals (h_i, rho_i - r) with respect to x, the
//     normal's tangent parameters (a, b) taken along (axis_u, axis_v): to first
//     order the normal's error is a axis_u + b axis_v (radians). sigma is the
//     per-axis point noise: options.point_sigma_mm when > 0, otherwise the
//     data's own scatter sigma^2 = SSR / (2n - 6), SSR = sum e_i^2. The
//     denominator is 2n - 6, not 3n - 6: of each point's three noise components
//     the one along the circle's tangent is absorbed by its phase, so the
//     residuals have 2n - 6 degrees of freedom (E[SSR] = (2n - 6) sigma^2 to first
//     order). With 3 points there is none: sigma from the data is 0 and the
//     covariance is zero; dof tells the caller (who should demand 4 or more).
//  6. Arc span: 360 deg minus the largest angular gap between the points'
//     phases (sorted), in [0, 360).
//
// Status codes: kTooFewPoints (< 3 points; or max_centre_sigma_mm set with the
// sigma taken from 3 points, which have no residual), kTooManyPoints
// (> kMaxCirclePoints), kNotFinite (a coordinate, an angle, or an option),
// kArgumentOutOfRange (an option negative), kPointsCoincident (all points within
// kCircleCoincidentSpan_mm of their centroid), kPointsCollinear (the second
// in-plane spread below kCircleCollinearRatio times the first), kArcTooShort
// (arc_deg < options.min_arc_deg, or centre_sigma_mm > options.max_centre_sigma_mm
// when that is > 0, or a radius above 1e12 times the points' extent: a line, or a
// fit that did not converge with its centre_sigma_mm above its radius: the data
// hardly define a circle), kNoConvergence (not converged in
// kCircleMaxIterations for another reason).
#pragma once

#include <cstddef>

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

using Mat6 = Eigen::Matrix<double, 6, 6>;

// One per 10 deg of a full turn: the module's densest circles are a rigidity
// pose (36 C, rigidity_map.hpp kMaxPoseSamples) and a gantry circle (30).
inline constexpr std::size_t kMaxCirclePoints = 36;
inline constexpr double kCircleCoincidentSpan_mm = 1e-6;
inline constexpr double kCircleCollinearRatio = 1e-4;
inline constexpr double kDefaultMinArcDeg = 5.0;
inline constexpr int kCircleMaxIterations = 200;

struct CircleFitOptions {
  const double* angles_deg = nullptr;  // optional commanded angles, one per point (convention 4)
  double point_sigma_mm = 0.0;         // > 0: known per-axis point noise; 0: from the residuals
  double min_arc_deg = kDefaultMinArcDeg;
  double max_centre_sigma_mm = 0.0;  // > 0: refuse a centre less certain than this; 0: no limit
};

struct CircleFit {
  Vec3 centre_mm = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, oriented by convention 4
  Vec3 axis_u = Vec3::UnitX();  // convention 3
  Vec3 axis_v = Vec3::UnitY();
  double radius_mm = 0.0;
  double rms_distance_mm = 0.0;  // RMS of the 3-D distances e_i
  double max_distance_mm = 0.0;
  double arc_deg = 0.0;          // convention 6
  std::size_t count = 0;
  std::size_t dof = 0;           // 2n - 6
  double sigma_mm = 0.0;         // the per-axis point noise used in `covariance`
  // Order (c_x, c_y, c_z, a, b, r): mm^2, rad^2, mm^2; convention 5.
  Mat6 covariance = Mat6::Zero();
  double centre_sigma_mm = 0.0;  // sqrt of the largest eigenvalue of the centre block
  int iterations = 0;

  Mat3 centre_covariance_mm2() const { return covariance.topLeftCorner<3, 3>(); }
  Mat2 normal_covariance_rad2() const { return covariance.block<2, 2>(3, 3); }  // in (axis_u, axis_v)
  double radius_variance_mm2() const { return covariance(5, 5); }
};

// The scratch of a fit: its normal equations, the damped normal matrix and
// the covariance, the points' phases, the fit under way (1.3 kB). A firmware
// caller keeps one beside its data (a builder's member, in the module's work
// arena) so that they stay off its stack (docs/FIGURES.md "Stack"); it holds nothing
// between calls.
struct CircleFitWork {
  CircleFit fit;
  struct NormalEquations {
    Mat6 jtj;
    Eigen::Matrix<double, 6, 1> jtr;
    double cost;  // sum of squared 3-D distances
  };
  NormalEquations normal;
  Mat6 matrix;  // the damped normal matrix, then the covariance
  double phase_rad[kMaxCirclePoints];
};

// The circle through the points (convention 2), normal oriented by sample order.
[[nodiscard]] Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count);

// The same with commanded angles, a known point sigma and the short-arc rules.
[[nodiscard]] Result<CircleFit> fit_circle(const Vec3* points_mm, std::size_t count,
                                           const CircleFitOptions& options);

// The same into `out` with the caller's scratch: no large temporary on the
// stack. `out` is written only when kOk is returned.
[[nodiscard]] Status fit_circle(const Vec3* points_mm, std::size_t count, const CircleFitOptions& options,
                                CircleFitWork& work, CircleFit& out);

// Phase (rad, (-pi, pi]) of a point about the fitted circle's normal, from axis_u.
double circle_phase_rad(const CircleFit& fit, const Vec3& p_mm);

// Unit in-plane direction from the centre at `phase_rad` (convention 3).
inline Vec3 circle_direction(const CircleFit& fit, double phase_rad) {
  return std::cos(phase_rad) * fit.axis_u + std::sin(phase_rad) * fit.axis_v;
}

// The point of the fitted circle at `phase_rad` (mm).
inline Vec3 circle_point_mm(const CircleFit& fit, double phase_rad) {
  return fit.centre_mm + fit.radius_mm * circle_direction(fit, phase_rad);
}

struct CircularMean {
  double mean_rad = 0.0;           // atan2(sum sin, sum cos), in (-pi, pi]
  double resultant_length = 0.0;   // |mean unit vector| in [0, 1]; near 1 when the angles agree
  double standard_error_rad = 0.0; // sqrt(sum sin^2(x_k - mean) / (n (n - 1))); 0 for n = 1
};

// Circular mean of angles (rad). kTooFewPoints for count 0, kNotFinite. When the
// angles cancel (resultant exactly 0) the mean is 0 with resultant_length 0: a
// caller that needs a mean judges resultant_length.
[[nodiscard]] Result<CircularMean> circular_mean_rad(const double* angles_rad, std::size_t count);

// The circular mean of phase offsets x_k = phase(p_k) - angle_k (angle_k in
// degrees, converted): the phase at which the circle is at commanded angle 0,
// so circle_direction(fit, mean_rad) points from the centre towards it, whether
// or not angle 0 was sampled. The fit's normal must be oriented by the same
// angles (convention 4). Status codes as circular_mean_rad.
[[nodiscard]] Result<CircularMean> circle_phase_offset_rad(const CircleFit& fit, const Vec3* points_mm,
                                                           const double* angles_deg, std::size_t count);

}  // namespace trueaxis::core
