#include "trueaxis/core/circle_fit.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::core {

namespace {

template <typename AngleAt>
CircularMean circular_mean(std::size_t count, AngleAt angle_at) {
  double sum_sin = 0.0;
  double sum_cos = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    sum_sin += std::sin(angle_at(i));
    sum_cos += std::cos(angle_at(i));
  }
  CircularMean m;
  const double n = static_cast<double>(count);
  m.resultant_length = std::min(1.0, std::hypot(sum_sin, sum_cos) / n);
  if (m.resultant_length == 0.0) return m;
  m.mean_rad = std::atan2(sum_sin, sum_cos);
  if (count > 1) {
    double sum_sq = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      const double s = std::sin(angle_at(i) - m.mean_rad);
      sum_sq += s * s;
    }
    m.standard_error_rad = std::sqrt(sum_sq / (n * (n - 1.0)));
  }
  return m;
}

}  // namespace

double circle_phase_rad(const CircleFit& fit, const Vec3& p_mm) {
  const Vec3 d = p_mm - fit.centre_mm;
  const double phase = std::atan2(fit.axis_v.dot(d), fit.axis_u.dot(d));
  return phase <= -kPi ? kPi : phase;  // atan2(-0, x < 0) is -pi
}

Result<CircularMean> circular_mean_rad(const double* angles_rad, std::size_t count) {
  if (count == 0) return Status::kTooFewPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(angles_rad[i])) return Status::kNotFinite;
  }
  return circular_mean(count, [angles_rad](std::size_t i) { return angles_rad[i]; });
}

Result<CircularMean> circle_phase_offset_rad(const CircleFit& fit, const Vec3* points_mm, const double* angles_deg,
                                             std::size_t count) {
  if (count == 0) return Status::kTooFewPoints;
  for (std::size_t i = 0; i < count; ++i) {
    if (!all_finite(points_mm[i]) || !std::isfinite(angles_deg[i])) return Status::kNotFinite;
  }
  return circular_mean(count, [&](std::size_t i) {
    return circle_phase_rad(fit, points_mm[i]) - deg_to_rad(angles_deg[i]);
  });
}

}  // namespace trueaxis::core
