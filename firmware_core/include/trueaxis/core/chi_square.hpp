// The chi-square test the gates run (docs/METHODS.md "Gates"): the bound a
// fit's weighted sum of squared residuals stays below with a given confidence
// when its residuals are the instrument's noise alone.
//
// Conventions
//  1. normal_upper_quantile(p): z with P(Z > z) = p for a standard normal Z,
//     by bisection on erfc (z in [-40, 40], 80 halvings: |error| < 1e-22 of
//     the interval, far below double rounding at the gates' p). p outside
//     (0, 1) gives 0.
//  2. chi_square_quantile(dof, confidence): x with P(X <= x) = confidence for
//     X ~ chi-square(dof), by the Wilson-Hilferty cube-root approximation
//         x = dof (1 - 2/(9 dof) + z sqrt(2/(9 dof)))^3,  z = quantile of 1 - confidence.
//     Against the exact quantile (tests/core/test_chi_square.cpp, an
//     independent incomplete-gamma inversion): at confidence 0.999 and above
//     (#901 allows 0.999 .. 1 - 1e-9) it is never below it, so a gate refuses less often
//     than its confidence says, never more; it is above it by at most 26 % at
//     dof 1 (confidence 1 - 1e-9), 4.2 % from dof 10 and 0.35 % from dof 100.
//     At 0.9..0.99 it errs by at most 2.5 % either side. dof 0 gives 0 (no
//     test: the caller passes everything).
//  3. A gate compares a statistic T = SSR / sigma^2 with the quantile; its
//     "ratio" T / quantile is > 1 when refused. Pure functions, no
//     allocation, no exceptions.
#pragma once

#include <cstddef>

namespace trueaxis::core {

[[nodiscard]] double normal_upper_quantile(double p);
[[nodiscard]] double chi_square_quantile(std::size_t dof, double confidence);
// The same with z = normal_upper_quantile(1 - confidence) given: the gates
// compute z once per macro and a quantile per pose or group.
[[nodiscard]] double chi_square_quantile_z(std::size_t dof, double z);

}  // namespace trueaxis::core
