#include "trueaxis/core/form_noise.hpp"

#include <algorithm>
#include <cmath>

#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

namespace {

constexpr double kUpper = 9.0;
constexpr double kResolved = 2.0;  // spreads of F^2, convention 5

// Composite Simpson over [0, kUpper].
template <typename F>
double simpson(F f) {
  const double h = kUpper / kQuadratureIntervals;
  double sum = f(0.0) + f(kUpper);
  for (int i = 1; i < kQuadratureIntervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(h * i);
  return sum * h / 3.0;
}

// Q(x) = 1 - Phi(x).
double upper_tail(double x) { return 0.5 * std::erfc(x / std::sqrt(2.0)); }

}  // namespace

double expected_normal_range(std::size_t n) {
  if (n < 2) return 0.0;
  const double k = static_cast<double>(n);
  // Phi(x)^n = exp(n log1p(-Q(x))): exact where Phi is within an ulp of 1.
  return 2.0 * simpson([k](double x) {
           const double q = upper_tail(x);
           return 1.0 - std::exp(k * std::log1p(-q)) - std::pow(q, k);
         });
}

double expected_max_rayleigh(std::size_t n) {
  if (n == 0) return 0.0;
  const double k = static_cast<double>(n);
  return simpson([k](double r) {
    const double tail = std::exp(-0.5 * r * r);
    return tail >= 1.0 ? 1.0 : -std::expm1(k * std::log1p(-tail));
  });
}

double flatness_noise_floor_mm(std::size_t count, std::size_t dof, double noise_sigma_mm) {
  if (count == 0 || dof == 0 || !(noise_sigma_mm > 0.0)) return 0.0;
  return noise_sigma_mm * std::sqrt(static_cast<double>(dof) / static_cast<double>(count)) *
         expected_normal_range(count);
}

double straightness_noise_floor_mm(std::size_t count, std::size_t dof, double noise_sigma_mm) {
  if (count == 0 || dof == 0 || !(noise_sigma_mm > 0.0)) return 0.0;
  return 2.0 * noise_sigma_mm * std::sqrt(static_cast<double>(dof) / (2.0 * static_cast<double>(count))) *
         expected_max_rayleigh(count);
}

FormError form_error(double rms_mm, std::size_t count, std::size_t dof, double noise_sigma_mm,
                     double noise_quartic_mm) {
  FormError out;
  if (count == 0 || dof == 0) return out;
  if (!(noise_sigma_mm > 0.0)) {
    out.form_mm = rms_mm;
    return out;
  }
  const double n = static_cast<double>(count);
  const double k = static_cast<double>(dof);
  const double s2 = noise_sigma_mm * noise_sigma_mm;
  const double q = std::max(noise_quartic_mm, noise_sigma_mm);
  const double s4 = q * q * q * q;
  const double form2 = std::max(0.0, (n * rms_mm * rms_mm - k * s2) / n);
  const auto var_of = [&](double f2) { return (4.0 * s2 * n * f2 + 2.0 * k * s4) / (n * n); };
  out.form_mm = std::sqrt(form2);
  // F^2 within kResolved spreads of 0 cannot be told from no form: only the
  // part beyond counts as form in its sigma (form_noise.hpp convention 5).
  const double resolved = std::max(0.0, form2 - kResolved * std::sqrt(var_of(form2)));
  const double v = var_of(resolved);
  out.sigma_mm = std::sqrt(v / (4.0 * resolved + std::sqrt(2.0 * kPi * v)));
  return out;
}

}  // namespace trueaxis::core
