// What instrument noise alone does to the RMS of a least-squares fit's
// residuals: the RMS it would give (the noise floor) and the 1-sigma
// uncertainty of an observed RMS (M3's C-circle RMS, docs/INTERFACE.md "M3
// rigidity"; docs/GUIDE.md "M3: what the C-circle RMS means").
//
// Conventions
//  1. A fit of `count` points leaves `dof` residual degrees of freedom (a 3-D
//     circle: 2 count - 6, circle_fit.hpp convention 5). rms_mm = sqrt(SSR /
//     count), SSR the sum of the squared 3-D distances from the fitted shape.
//     noise_sigma_mm is the instrument's stated noise: 1 sigma per axis,
//     Gaussian, independent between points and axes.
//  2. Model of the residuals: r + P eps, r the form the fitted shape cannot
//     follow (the machine's geometry), eps the noise, P the projection on the
//     dof residual directions (r lies in them at the solution). So SSR is
//     sigma^2 times a noncentral chi-square of dof degrees of freedom:
//         E[SSR] = |r|^2 + dof s^2,   Var[SSR] = 4 s^2 |r|^2 + 2 dof s^4.
//  3. Noise floor: the RMS noise alone gives, sqrt(E[SSR | r = 0] / count)
//         = s sqrt(dof / count).
//  4. Sigma of the RMS: Var[SSR] with |r|^2 estimated from the observed SSR,
//     max(0, SSR - dof s^2), carried to the RMS to first order about the
//     expected RMS: sigma = sqrt(Var[SSR]) / (2 count max(rms, floor)).
//     Its limits: form-dominated (|r|^2 >> dof s^2) s / sqrt(count); noise
//     only (r = 0) s / sqrt(2 count), where the RMS measures the noise, not
//     the machine: an RMS within a few of these sigmas of the floor says
//     nothing about the geometry.
//  5. Degenerate input gives zeros, never NaN: s = 0 (no stated noise) gives a
//     floor and a sigma of 0; count = 0 gives zeros. Inputs are not checked
//     for finiteness or sign (the callers pass a fit's figures and a
//     configuration value inside its map range).
#pragma once

#include <cstddef>

namespace trueaxis::core {

struct ResidualNoise {
  double floor_mm = 0.0;  // convention 3
  double sigma_mm = 0.0;  // convention 4: 1 sigma of rms_mm
};

[[nodiscard]] ResidualNoise residual_rms_noise(double rms_mm, std::size_t count, std::size_t dof,
                                               double noise_sigma_mm);

// A 3-D circle's residual degrees of freedom (circle_fit.hpp convention 5);
// 0 for fewer than 4 points.
constexpr std::size_t circle_residual_dof(std::size_t count) { return count > 3 ? 2 * count - 6 : 0; }

}  // namespace trueaxis::core
