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

int VirtualAnalyser::steps_per_revolution() const { return static_cast<int>(std::lround(360.0 / config_.step_deg)); }

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
  for (int r = 0; r < config_.revolutions; ++r) {
    for (int i = 0; i < steps; ++i) {
      const double phi = 360.0 * r + config_.step_deg * i;
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
    }
  }
  return out;
}

}  // namespace trueaxis::sim
