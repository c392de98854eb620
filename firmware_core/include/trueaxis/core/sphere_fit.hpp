// Least-squares sphere through 4 to kMaxSpherePoints probe touches: the centre
// of a calibration ball from a touch probe, computed once here for every
// controller (the LinuxCNC rigidity program, an HMI) instead of in G-code.
//
// Conventions
//  1. Points are the probe tip's centre at each touch, in millimetres, in the
//     caller's frame; the centre is in that frame. The fitted radius is the
//     ball's radius plus the stylus tip's radius (plus the probe's mean
//     overshoot): leave it free unless it is known.
//  2. The fit minimises the sum of squared geometric distances
//     sum (|p_i - c| - r)^2. It starts from the algebraic fit (linear least
//     squares of |q|^2 = 2 q.c + k on the points q centred on their centroid)
//     and takes Gauss-Newton steps on the geometric residuals until a step
//     moves the centre by less than kSphereStepTolerance times the radius (or
//     1 mm, the larger): 1e-9 of it, far below any probe's noise and above the
//     rounding that an ill-conditioned cap leaves in a step (at most
//     kSphereMaxIterations, else kNoConvergence).
//  3. radius_mm > 0 fixes the radius (3 unknowns); 0 leaves it free (4).
//  4. Uncertainty: the touches' noise along the surface normal, sigma_mm
//     (1 sigma, independent), propagated by the fit's Jacobian at the
//     solution: cov = sigma^2 (J^T J)^-1. centre_sigma_mm are the square
//     roots of its diagonal, radius_sigma_mm its radius entry (0 when fixed).
//  5. Degenerate touches: all within kCoincidentSpan_mm of their centroid is
//     kPointsCoincident; touches in one plane (the smallest singular value of
//     the centred points below kCollinearRatio times the largest) do not
//     determine a ball, nor (with a fixed radius) the side of the plane it
//     is on: kNotIdentifiable (only these). A fit that cannot proceed
//     otherwise (a touch at the centre, no positive-definite J^T J) is
//     kNoConvergence.
// Status codes also: kTooFewPoints (< 4), kTooManyPoints, kNotFinite (a
// point, the radius or sigma), kArgumentOutOfRange (radius or sigma < 0).
#pragma once

#include <cstddef>

#include "trueaxis/core/plane_fit.hpp"  // kCoincidentSpan_mm, kCollinearRatio
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr std::size_t kMaxSpherePoints = 32;
inline constexpr double kSphereStepTolerance = 1e-9;  // of max(radius, 1 mm)
inline constexpr int kSphereMaxIterations = 50;

struct SphereFit {
  Vec3 centre_mm = Vec3::Zero();
  double radius_mm = 0.0;
  Vec3 centre_sigma_mm = Vec3::Zero();  // convention 4
  double radius_sigma_mm = 0.0;         // 0 when the radius was fixed
  double rms_residual_mm = 0.0;         // root mean square of |p_i - c| - r
  double max_residual_mm = 0.0;         // the largest |(|p_i - c| - r)|
  std::size_t count = 0;
  int iterations = 0;                   // Gauss-Newton steps taken
};

[[nodiscard]] Result<SphereFit> fit_sphere(const Vec3* points_mm, std::size_t count, double radius_mm,
                                           double sigma_mm);

}  // namespace trueaxis::core
