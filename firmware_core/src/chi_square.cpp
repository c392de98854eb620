#include "trueaxis/core/chi_square.hpp"

#include <cmath>

namespace trueaxis::core {

double normal_upper_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return 0.0;
  // P(Z > z) = erfc(z / sqrt 2) / 2 falls with z: bisect for it (convention 1).
  double lo = -40.0;
  double hi = 40.0;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(mid * 0.70710678118654752440) > p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

double chi_square_quantile(std::size_t dof, double confidence) {
  return chi_square_quantile_z(dof, normal_upper_quantile(1.0 - confidence));
}

double chi_square_quantile_z(std::size_t dof, double z) {
  if (dof == 0) return 0.0;
  const double k = static_cast<double>(dof);
  const double v = 2.0 / (9.0 * k);
  const double c = 1.0 - v + z * std::sqrt(v);
  return c > 0.0 ? k * c * c * c : 0.0;
}

}  // namespace trueaxis::core
