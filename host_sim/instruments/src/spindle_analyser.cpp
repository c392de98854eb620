#include "trueaxis/sim/instruments/spindle_analyser.hpp"

#include <cmath>

namespace trueaxis::sim {

using core::Vec3;

VirtualAnalyser::VirtualAnalyser(const AnalyserConfig& config) : config_(config) {
  SimRng rng(config.form_seed ^ kFormStream);
  for (int k = 0; k < 2; ++k) {
    for (int n = 0; n < kHarmonics; ++n) {
      cos_[k][n] = rng.normal();
      sin_[k][n] = rng.normal();
    }
  }
  for (int k = 0; k < 2; ++k) {
    double power = 0.0;  // mean of rho^2 over beta
    for (int n = 0; n < kHarmonics; ++n) power += 0.5 * (cos_[k][n] * cos_[k][n] + sin_[k][n] * sin_[k][n]);
    const double scale = config.form_rms_mm / std::sqrt(power);
    for (int n = 0; n < kHarmonics; ++n) {
      cos_[k][n] *= scale;
      sin_[k][n] *= scale;
    }
  }
}

int VirtualAnalyser::steps_per_revolution() const {
  if (config_.samples_per_revolution > 0) return config_.samples_per_revolution;
  if (config_.time_sampled) return kTimeSampledDefaultSamples;
  return static_cast<int>(std::lround(360.0 / config_.step_deg));
}

double VirtualAnalyser::time_sampled_angle_deg(double t) const {
  const double d = config_.speed_drift;
  const double r = static_cast<double>(config_.revolutions);
  return 360.0 * (t * ((1.0 - 0.5 * d) + d * t / (2.0 * r)));
}

double VirtualAnalyser::form_radius_mm(int ball, double beta_deg) const {
  const int k = ball == 2 ? 1 : 0;
  const double beta = core::deg_to_rad(beta_deg);
  double rho = 0.0;
  for (int n = 0; n < kHarmonics; ++n) {
    const double m = static_cast<double>(n + kFormFirstHarmonic);
    rho += cos_[k][n] * std::cos(m * beta) + sin_[k][n] * std::sin(m * beta);
  }
  return rho;
}

Vec3 VirtualAnalyser::form_error_mm(int ball, double phi_deg) const {
  return Vec3(form_radius_mm(ball, phi_deg), form_radius_mm(ball, phi_deg + 90.0), 0.0);
}

std::vector<core::SpindleSample> VirtualAnalyser::measure(const BallCentres& centres, SimRng& noise) const {
  std::vector<core::SpindleSample> out;
  const int steps = steps_per_revolution();
  const double sigma = config_.noise_sigma_mm;
  // Convention 1's (or 3's) reading of both balls at one angle.
  auto read_at = [&](double phi) {
    for (int ball = 1; ball <= 2; ++ball) {
      core::SpindleSample s;
      s.phi_deg = phi;
      s.ball = ball;
      s.p_mm = centres(ball, phi) + form_error_mm(ball, phi);
      if (sigma > 0.0) {
        const double nx = noise.normal();
        const double ny = noise.normal();
        const double nz = noise.normal();
        s.p_mm += sigma * Vec3(nx, ny, nz);
      }
      out.push_back(s);
    }
  };
  if (config_.revolutions <= 0 || steps <= 0) return out;
  out.reserve(2u * static_cast<std::size_t>(config_.revolutions) * static_cast<std::size_t>(steps));
  if (config_.time_sampled) {  // convention 3
    const double phi0 = 360.0 * (1.0 - noise.uniform01());
    const double tau = 1.0 - noise.uniform01();
    const long count = static_cast<long>(steps) * config_.revolutions;
    for (long k = 0; k < count; ++k) {
      read_at(phi0 + time_sampled_angle_deg((static_cast<double>(k) + tau) / steps));
    }
    return out;
  }
  for (int r = 0; r < config_.revolutions; ++r) {  // convention 1
    for (int i = 0; i < steps; ++i) {
      read_at(config_.samples_per_revolution > 0 ? 360.0 * r + 360.0 * i / steps
                                                 : 360.0 * r + config_.step_deg * i);
    }
  }
  return out;
}

}  // namespace trueaxis::sim
