// A virtual spindle error analyser (docs/INTERFACE.md "M4 spindle"): two balls
// on the tool, read by capacitive probes as the spindle turns. It knows the
// spindle only by where the balls' centres are at each spindle angle
// (BallCentres); tools/spindle_measure.hpp points it at the virtual spindle.
// Host only: it allocates.
//
// Conventions (lengths mm, angles degrees)
//  1. Balls 1 and 2 on the tool (1 nearer the spindle), read by capacitive
//     probes along the analyser's +X, +Y and -Z. Order: revolution r = 0..R-1,
//     angle i = 0..360/S - 1, ball 1 then ball 2, phi_deg = 360 r + i S (it keeps
//     growing, as a controller logs its spindle encoder; the module takes phi
//     modulo 360). A reading is the ball's true centre (the caller's BallCentres,
//     analyser frame) + the form error f_k(phi) + noise_sigma (n_x, n_y, n_z),
//     three standard normal deviates from the caller's SimRng in that order
//     (none when noise_sigma = 0).
//  2. Form error of ball k: its equator's radius deviates by
//         rho_k(beta) = sum_{n=2..15} (A_kn cos n beta + B_kn sin n beta),
//     beta the azimuth on the ball about +Z from +X at phi = 0. A, B are drawn
//     normal from SimRng(form_seed ^ kFormStream) (ball 1's A2 B2 .. A15 B15,
//     then ball 2's) and scaled so the RMS of rho_k over beta is form_rms_mm
//     exactly. The spindle angle grows in the M03 sense (docs/INTERFACE.md "M4
//     spindle"): the tool turns clockwise seen from above (axis ~ -Z), so the
//     probe at azimuth gamma faces beta = gamma + phi, and the apparent centre moves
//     by +rho there: f_k(phi) = (rho_k(phi), rho_k(phi + 90 deg), 0). The z probe
//     faces the pole, which stays on the axis: no form error in z. f_k repeats
//     every revolution (synchronous error, ISO 230-7) and has no 0th or 1st
//     harmonic, so over whole revolutions at even steps it is orthogonal to the
//     model's terms.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

// The true centre of ball 1 or 2 at spindle angle phi_deg, analyser frame.
using BallCentres = std::function<core::Vec3(int ball, double phi_deg)>;

// Conventions 1-2.
struct AnalyserConfig {
  int revolutions = 3;
  double step_deg = 5.0;                 // 360 / step_deg whole
  double noise_sigma_mm = 15e-6;         // per axis, 1 sigma, white
  double form_rms_mm = 50e-6;            // per ball, harmonics 2..15
  std::uint64_t form_seed = 1;
};

inline constexpr int kFormFirstHarmonic = 2;
inline constexpr int kFormLastHarmonic = 15;
inline constexpr std::uint64_t kFormStream = 0x6A09E667F3BCC909ull;

class VirtualAnalyser {
 public:
  explicit VirtualAnalyser(const AnalyserConfig& config);

  const AnalyserConfig& config() const { return config_; }
  // Angles per revolution (360 / step_deg rounded; the tool checks it is whole).
  int steps_per_revolution() const;
  // Convention 2: rho_k at beta, and the apparent centre shift f_k at phi.
  double form_radius_mm(int ball, double beta_deg) const;
  core::Vec3 form_error_mm(int ball, double phi_deg) const;
  // Convention 1: every reading in order.
  std::vector<core::SpindleSample> measure(const BallCentres& centres, SimRng& noise) const;

 private:
  static constexpr int kHarmonics = kFormLastHarmonic - kFormFirstHarmonic + 1;
  AnalyserConfig config_;
  double cos_[2][kHarmonics] = {};
  double sin_[2][kHarmonics] = {};
};

}  // namespace trueaxis::sim
