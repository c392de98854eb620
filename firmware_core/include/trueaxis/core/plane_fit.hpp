// Least-squares plane through 3 to kMaxPlanePoints points (orthogonal
// distance regression), with the diagnostics a metrology engineer reads.
//
// Conventions
//  1. Points are in millimetres, in whatever frame the caller uses; every output
//     vector is in that same frame.
//  2. The fit minimises the sum of squared orthogonal distances. It centres the
//     points on their centroid, reduces them to a 3x3 triangular factor with
//     Givens rotations (one row at a time, no normal equations, so the condition
//     number is not squared) and takes the SVD of that factor.
//  3. The normal's sign is arbitrary; callers orient it (see leveling.hpp).
//  4. spread_u_mm >= spread_v_mm are the singular values of the centred point
//     matrix: the root-sum-square extent of the points along the in-plane axes.
//     A probe noise of sigma (mm) along the normal tilts the fitted normal by a
//     zero-mean error with covariance sigma^2 diag(1/s_u^2, 1/s_v^2) in (u, v).
//
// Status codes: kTooFewPoints (< 3), kTooManyPoints (> kMaxPlanePoints),
// kNotFinite, kPointsCoincident (all points within kCoincidentSpan_mm of their
// centroid), kPointsCollinear (spread_v / spread_u < kCollinearRatio).
#pragma once

#include <cstddef>

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr std::size_t kMaxPlanePoints = 32;
inline constexpr double kCoincidentSpan_mm = 1e-6;  // 1 nm
inline constexpr double kCollinearRatio = 1e-6;     // 1 um of width per metre of length

struct PlaneFit {
  Vec3 centroid_mm = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit; (axis_u, axis_v, normal) is right-handed
  Vec3 axis_u = Vec3::UnitX();  // in-plane unit axis of the largest spread
  Vec3 axis_v = Vec3::UnitY();  // in-plane unit axis of the smaller spread
  double spread_u_mm = 0.0;
  double spread_v_mm = 0.0;
  double flatness_mm = 0.0;      // max minus min signed distance to the plane
  double rms_residual_mm = 0.0;  // root mean square of the signed distances
  std::size_t count = 0;
};

[[nodiscard]] Result<PlaneFit> fit_plane(const Vec3* points_mm, std::size_t count);

// Signed distance (mm) of a point from a fitted plane, positive along `normal`.
inline double plane_distance_mm(const PlaneFit& fit, const Vec3& p_mm) {
  return fit.normal.dot(p_mm - fit.centroid_mm);
}

}  // namespace trueaxis::core
