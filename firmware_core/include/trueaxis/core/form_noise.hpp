// What instrument noise alone does to M2's peak-to-valley figures (bed
// flatness, gantry straightness) and the form error left when it is taken out
// (docs/INTERFACE.md "M2 gantry"; docs/GUIDE.md "M2: what flatness and
// straightness mean").
//
// Conventions
//  1. A least-squares fit of `count` points leaves `dof` residual degrees of
//     freedom: a plane count - 3 (one height per point), a line 2 count - 4
//     (two perpendicular components per point), summed over a group's passes.
//     noise_sigma_mm is the instrument's stated noise: 1 sigma per axis,
//     Gaussian, independent between points and axes (for a range-dependent
//     noise the caller passes the RMS of the points' sigmas).
//  2. Residual model: each residual component is approximated as independent
//     with variance s^2 dof / (count components): the exact variance of
//     residual i is s^2 (1 - h_ii), whose mean over the points is exactly that;
//     the small correlation between residuals is neglected (the test checks the
//     result against simulated fits: within 3 % from 8 points a group or a
//     pass on; one pass of 4 points reads 3.5 % high).
//  3. Flatness noise floor: the expected peak-to-valley of count such heights,
//         s sqrt(dof / count) d2(count),  d2(n) = E[range of n N(0, 1)]
//                                              = 2 int_0^inf 1 - Phi(x)^n - Phi(-x)^n dx.
//     Straightness noise floor: straightness is twice the largest distance from
//     a pass's line, worst pass, so the largest of all count 2-D distances:
//         2 s sqrt(dof / (2 count)) m2(count),
//         m2(n) = E[max of n Rayleigh(1)] = int_0^inf 1 - (1 - exp(-r^2 / 2))^n dr.
//     Both integrals by composite Simpson over [0, 9] in kQuadratureIntervals
//     steps (the integrands are smooth; beyond 9 they are below n 1e-18); the
//     results are within 1e-9 of the tabulated d2 (2: 1.1284, 10: 3.0775)
//     and of m2(1) = sqrt(pi / 2).
//  4. Form error (the noise-corrected RMS): SSR = count rms^2 is s^2 times a
//     noncentral chi-square of dof degrees of freedom (residual_noise.hpp item
//     2), E[SSR] = |r|^2 + dof s^2. The RMS form error is |r| / sqrt(count),
//     estimated by F = sqrt(max(0, (SSR - dof s^2) / count)).
//  5. Its sigma: V(f2) = (4 s^2 count f2 + 2 dof q^4) / count^2 is Var[F^2]
//     at a true form^2 f2 (q^4 = the mean of sigma_i^4: unequal sigmas
//     scatter the SSR more than their RMS would; the gantry's points 2.7 to
//     6.5 m from the tracker read 1.5 % beyond 3 sigma with s^4 there); D = max(0, F^2 - 2 sqrt(V(F^2))) the part of F^2
//     resolved from no form, and
//         sigma_F^2 = V(D) / (4 D + sqrt(2 pi V(D))).
//     Where form dominates this is the first-order sqrt(V) / (2 F) (-> s /
//     sqrt(count)). At no form F^2 is a clipped Gaussian of spread sqrt(V(0))
//     and sigma_F is the RMS of F about the true 0, (V(0) / (2 pi))^(1/4).
//     Within 2 spreads of 0 (where the data cannot tell a form from none) the
//     sigma stays near that, so a perfect machine reads 0 within 3 sigma in
//     99.7 % of runs; with D = F^2 instead (the plain first-order blend) in
//     only 89 %. A simulation of the chi-square (36 points) gives
//     predicted / observed RMS error 0.97..1.19 from no form to 30 x the
//     noise; the test's Monte Carlo of plane fits checks it within 1.5.
//  6. Degenerate input gives zeros, never NaN: s = 0 (no stated noise) gives
//     floors and sigmas of 0 and F = rms; count or dof 0 gives zeros.
#pragma once

#include <cstddef>

namespace trueaxis::core {

inline constexpr int kQuadratureIntervals = 96;  // even

// Convention 3: E[range of n independent N(0, 1)]; 0 for n < 2.
[[nodiscard]] double expected_normal_range(std::size_t n);

// Convention 3: E[largest of n independent 2-D distances |N(0, I_2)|]; 0 for n = 0.
[[nodiscard]] double expected_max_rayleigh(std::size_t n);

// Convention 3.
[[nodiscard]] double flatness_noise_floor_mm(std::size_t count, std::size_t dof, double noise_sigma_mm);
[[nodiscard]] double straightness_noise_floor_mm(std::size_t count, std::size_t dof, double noise_sigma_mm);

struct FormError {
  double form_mm = 0.0;   // convention 4
  double sigma_mm = 0.0;  // convention 5
};

// noise_quartic_mm: (mean sigma_i^4)^(1/4) where the points' sigmas differ
// (convention 5); 0 or less: noise_sigma_mm.
[[nodiscard]] FormError form_error(double rms_mm, std::size_t count, std::size_t dof, double noise_sigma_mm,
                                   double noise_quartic_mm = 0.0);

// Residual degrees of freedom (convention 1); 0 for too few points.
constexpr std::size_t plane_residual_dof(std::size_t count) { return count > 3 ? count - 3 : 0; }
constexpr std::size_t line_residual_dof(std::size_t count) { return count > 2 ? 2 * count - 4 : 0; }

}  // namespace trueaxis::core
