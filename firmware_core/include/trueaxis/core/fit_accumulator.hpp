// Streaming plane and 3-D line fits (docs/METHODS.md M1, M2): points arrive one at a
// time, only running sums are kept, so the number of points is not limited by
// memory. Fixed size, no heap, fixed time per point.
//
// Conventions
//  1. Points are in millimetres, in whatever frame the caller uses; every output
//     vector is in that same frame. Points carry a sample index 0, 1, 2, ... in
//     the order they were added.
//  2. PointAccumulator keeps the count n, the first point o, the mean m (held
//     as m - o) and the centred scatter
//         S = sum_i (p_i - m)(p_i - m)^T
//     with Welford's one-pass update (Welford 1962) on the shifted points
//     q = p - o (Chan, Golub, LeVeque 1983, "shifted data"):
//         d = q - (m - o)_old,   (m - o) += d / n,   S += d (q - (m - o))^T.
//     Why the distance from the origin costs no digits: every quantity rounded
//     in the update is a difference from o or from the running mean, of the
//     size of the cloud, never a raw coordinate, and no raw coordinate is
//     squared. The textbook S = sum p p^T - n m m^T squares the offset: at 1e3 mm
//     with 1 um spread its two terms are 1e6 mm^2 per point and agree to 12
//     digits, leaving ~4 of 16 (tests: 1e5 times the error of this update on
//     clouds 1e3..1e4 mm out). The offset returns once, when mean_mm() adds o
//     back: half an ulp of |m|, 1e-13 mm at 1e3 mm, the resolution of the input
//     coordinates themselves.
//  3. Index co-moment: with k the sample index, kbar = (n - 1) / 2,
//         t = sum_i (k_i - kbar)(p_i - m)   (mm),  updated t += (n / 2)(p - m_new),
//     is what tells the order of the points: a line's direction is oriented so
//     that the position along it grows with the sample index (for M2, the pass
//     is measured moving the axis in its positive direction).
//  4. merge(other) appends `other`'s points after this one's (sample indices of
//     `other` continue after this one's), by the pairwise rule of Chan et al.:
//         S = S_a + S_b + (n_a n_b / n) (m_b - m_a)(m_b - m_a)^T,
//         t = t_a + t_b + (n_a n_b / 2) (m_b - m_a).
//  5. A non-finite point is not added; it makes the accumulator fail every fit
//     with kNotFinite until reset() (sticky: a session with one NaN is spoiled).
//  6. Eigen-decomposition of S (Eigen::SelfAdjointEigenSolver<Matrix3d>:
//     Householder tridiagonalisation and implicit QR, fixed size, no heap):
//     eigenvalues l1 >= l2 >= l3 >= 0 with unit eigenvectors e1, e2, e3; the
//     spreads s_k = sqrt(l_k) are the singular values of the centred point matrix.
//     Accuracy (what forming S costs, whatever the offset): every eigenvalue is
//     exact to about C eps l1 and the eigenvector of l_k to C eps l1 / gap_k,
//     with C ~ 2 for tens of points, growing to ~30 at 1e5 points (measured,
//     tests). So a small spread is exact to about eps (s1 / s_small)^2
//     relatively; the batch fit (plane_fit.hpp, Givens QR of the points) keeps
//     that ratio linear. In numbers: a 4 m line with 1 um residual gives its
//     RMS residual to ~2e-3 relative (a few nm) at 1e5 points; an exact line reads an
//     RMS residual up to sqrt(C eps) s_along / sqrt(n) (a few nm over metres);
//     a plane at the collinear limit kCollinearRatio has its normal to ~1e-4 rad
//     (the batch fit: 1e-10 rad), an ordinary one (s2 / s1 > 1e-3) to 1e-9 rad.
//  7. Coincidence is judged on the root-mean-square distance of the points from
//     their centroid, sqrt(trace(S) / n) (the batch fit uses the largest
//     distance, which sums cannot give).
//  8. Uncertainty, to first order in an isotropic point noise sigma (mm, 1 sigma
//     per axis, independent points), with the fitted spreads standing for the
//     true ones:
//       plane: normal error in (axis_u, axis_v): covariance
//                  sigma^2 diag(1 / s_u^2, 1 / s_v^2)
//              (the eigenvector perturbation e_k^T dS e3 / (l_k - l3) with l3 = 0
//              for the true points; in-plane noise enters only at second order;
//              the same result as plane_fit.hpp item 4).
//       line:  direction error in (axis_1, axis_2): covariance
//                  sigma^2 / s_along^2 * I
//              (e_k^T dS e1 / (l1 - l_k) with l_k = 0 for the true points);
//              centroid: covariance sigma^2 / n * I (mm^2); the two are
//              uncorrelated (sum_i (p_i - m) = 0), so the line's perpendicular
//              offset at distance a along it from the centroid has variance
//              sigma^2 (1 / n + a^2 / s_along^2) per perpendicular axis.
//
// Status codes (both fits, checked in this order): kNotFinite (a non-finite
// point was added, or the sums overflowed), kTooFewPoints (plane < 3, line < 2),
// kPointsCoincident (item 7 below kCoincidentSpan_mm); then for the plane
// kPointsCollinear (s_v / s_u < kCollinearRatio), for the line kPointsNotOnLine
// (s_1 / s_along > kLineWidthRatio).
#pragma once

#include <cstddef>

#include "trueaxis/core/plane_fit.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

// A "line" whose largest perpendicular spread s_1 exceeds this fraction of its
// spread along it, s_along, is rejected: such points are not an axis's pass (a
// tracker pass is micrometres wide over a stroke of millimetres or more), and as
// the ratio nears 1 the direction is undefined (its sensitivity to the points
// grows as 1 / (1 - ratio^2)). 0.1 leaves room for a short pass with a noisy
// instrument.
inline constexpr double kLineWidthRatio = 0.1;

class PointAccumulator {
 public:
  // Adds one point (mm). A non-finite point is not added and makes the
  // accumulator non-finite until reset().
  void add(const Vec3& p_mm);
  // Appends `other`'s points after this one's (convention 4).
  void merge(const PointAccumulator& other);
  void reset() { *this = PointAccumulator(); }

  std::size_t count() const { return count_; }  // finite points added
  bool finite() const { return finite_; }       // false once a non-finite point came, until reset()
  Vec3 mean_mm() const { return origin_mm_ + shifted_mean_mm_; }
  const Mat3& scatter_mm2() const { return scatter_mm2_; }       // S, convention 2
  const Vec3& index_moment_mm() const { return index_moment_mm_; }  // t, convention 3

 private:
  std::size_t count_ = 0;
  bool finite_ = true;
  Vec3 origin_mm_ = Vec3::Zero();         // the first point added, o
  Vec3 shifted_mean_mm_ = Vec3::Zero();   // m - o
  Mat3 scatter_mm2_ = Mat3::Zero();
  Vec3 index_moment_mm_ = Vec3::Zero();
};

// The plane fit that sums allow: plane_fit.hpp's PlaneFit without the flatness
// (a peak-to-valley needs the points again).
struct StreamPlaneFit {
  Vec3 centroid_mm = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, e3; (axis_u, axis_v, normal) is right-handed
  Vec3 axis_u = Vec3::UnitX();  // in-plane unit axis of the largest spread, e1
  Vec3 axis_v = Vec3::UnitY();  // in-plane unit axis of the smaller spread, e2
  double spread_u_mm = 0.0;     // s1
  double spread_v_mm = 0.0;     // s2
  double rms_residual_mm = 0.0;  // sqrt(l3 / n): RMS signed distance to the plane
  std::size_t count = 0;
};

struct LineFit {
  Vec3 point_mm = Vec3::Zero();     // the centroid, a point on the line
  Vec3 direction = Vec3::UnitX();   // unit, e1, oriented along growing sample index
  Vec3 axis_1 = Vec3::UnitY();      // perpendicular unit axis of the larger spread, e2
  Vec3 axis_2 = Vec3::UnitZ();      // direction x axis_1 (right-handed frame)
  double spread_along_mm = 0.0;     // s1
  double spread_1_mm = 0.0;         // s2, along axis_1
  double spread_2_mm = 0.0;         // s3, along axis_2
  double rms_residual_mm = 0.0;     // sqrt((l2 + l3) / n): RMS perpendicular distance
  // Least-squares slope of the position along `direction` against the sample
  // index, t . direction / sum (k - kbar)^2 (mm per sample), >= 0. Near zero the
  // order of the points says nothing and the sign of `direction` is arbitrary:
  // compare it with the expected step before trusting the orientation.
  double advance_per_sample_mm = 0.0;
  std::size_t count = 0;
};

// Least-squares plane (orthogonal distance) of the accumulated points.
[[nodiscard]] Result<StreamPlaneFit> fit_plane(const PointAccumulator& acc);

// Least-squares 3-D line (orthogonal distance) of the accumulated points.
[[nodiscard]] Result<LineFit> fit_line(const PointAccumulator& acc);

// The covariances take a fit that succeeded (its spreads are then > 0).
//
// Covariance (rad^2) of the normal's direction error in (axis_u, axis_v) for an
// isotropic point noise sigma_mm (convention 8).
Mat2 normal_covariance_rad2(const StreamPlaneFit& fit, double sigma_mm);

// Covariance (rad^2) of the direction error in (axis_1, axis_2) for an isotropic
// point noise sigma_mm (convention 8).
Mat2 direction_covariance_rad2(const LineFit& fit, double sigma_mm);

// Covariance (mm^2) of the centroid (point_mm) for an isotropic point noise sigma_mm.
Mat3 centroid_covariance_mm2(const LineFit& fit, double sigma_mm);

// `direction` or its negative, whichever has a non-negative dot product with
// `hint` (`direction` itself when they are perpendicular).
inline Vec3 orient(const Vec3& direction, const Vec3& hint) {
  return direction.dot(hint) < 0.0 ? Vec3(-direction) : direction;
}

}  // namespace trueaxis::core
