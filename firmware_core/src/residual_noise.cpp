#include "trueaxis/core/residual_noise.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::core {

ResidualNoise residual_rms_noise(double rms_mm, std::size_t count, std::size_t dof, double noise_sigma_mm) {
  ResidualNoise out;
  if (count == 0 || !(noise_sigma_mm > 0.0)) return out;
  const double n = static_cast<double>(count);
  const double k = static_cast<double>(dof);
  const double s2 = noise_sigma_mm * noise_sigma_mm;
  out.floor_mm = noise_sigma_mm * std::sqrt(k / n);
  const double form2 = std::max(0.0, n * rms_mm * rms_mm - k * s2);
  const double about = std::max(rms_mm, out.floor_mm);
  if (!(about > 0.0)) return out;
  out.sigma_mm = std::sqrt(4.0 * s2 * form2 + 2.0 * k * s2 * s2) / (2.0 * n * about);
  return out;
}

}  // namespace trueaxis::core
