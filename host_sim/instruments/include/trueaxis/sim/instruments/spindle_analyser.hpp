// A virtual spindle error analyser (docs/INTERFACE.md "M4 spindle"): two balls
// on the tool, read by capacitive probes as the spindle turns. It knows the
// spindle only by where the balls' centres are at each spindle angle
// (BallCentres); tools/spindle_measure.hpp points it at the virtual spindle.
// Host only: it allocates.
//
// Conventions (lengths mm, angles degrees)
//  1. Encoder-synchronous sampling (time_sampled false, the default). Balls 1
//     and 2 on the tool (1 nearer the spindle), read by capacitive probes along
//     the analyser's +X, +Y and -Z. Order: revolution r = 0..R-1, angle
//     i = 0..N-1, ball 1 then ball 2, where
//       - samples_per_revolution = 0 (the default): N = 360/S rounded, S =
//         step_deg, and phi_deg = 360 r + i S, computed so (a config that
//         leaves the three newer fields at their defaults reads as before the
//         issue-18 modes, bit for bit);
//       - samples_per_revolution = N (8..4096): step_deg is not used, and
//         phi_deg = 360 r + 360 i / N (computed so).
//     phi keeps growing, as a controller logs its spindle encoder; the module
//     takes phi modulo 360. The N angles of one revolution repeat in every
//     revolution (to the rounding of 360 r + x, < 4e-12 deg at 100 revolutions).
//     A reading is the ball's true centre (the caller's BallCentres, analyser
//     frame) + the form error f_k(phi) + noise_sigma (n_x, n_y, n_z), three
//     standard normal deviates from the caller's SimRng in that order (none when
//     noise_sigma = 0): no draws at all when noise_sigma = 0.
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
//     model's terms (in convention 3 only nearly: its angles are not even).
//  3. Time-sampled (asynchronous) sampling (time_sampled true): the analyser
//     samples on a fixed clock, unsynchronised with the spindle, while the
//     spindle's speed drifts, so the angles do not repeat from one revolution to
//     the next. N = samples_per_revolution, or 1024 (kTimeSampledDefaultSamples)
//     when 0; step_deg is not used. Time t counts nominal revolution periods,
//     from t = 0 to t = R over the measurement. The speed, in nominal speeds,
//     rises linearly, D = speed_drift (0 <= D < 2; 0.01 is 1 %):
//         s(t) = 1 - D/2 + D t / R,   from 1 - D/2 at t = 0 to 1 + D/2 at t = R,
//     so its mean is the nominal speed and the spindle turns R revolutions in
//     t = R exactly. Its angle is
//         phi(t) = phi0 + theta(t),  theta(t) = 360 (t (1 - D/2) + D t^2 / (2 R))  deg.
//     Two draws on the caller's SimRng come first, before any noise (drawn even
//     when noise_sigma = 0), u1 then u2 = uniform01():
//         phi0 = 360 (1 - u1) in [0, 360), the spindle's angle at t = 0;
//         tau  = 1 - u2 in [0, 1), the clock's phase: it ticks at t_k = (k + tau) / N,
//     N ticks a nominal revolution, k = 0 .. N R - 1: N R instants in all, every
//     one in [0, R) (the clock gives N R whatever tau). At each instant ball 1
//     then ball 2 are read (both at the same phi, one reading each, noise as in
//     convention 1), and phi_deg = phi(t_k): the spindle's true angle at that
//     instant (the controller's encoder logged on the analyser's clock), growing
//     across revolutions from about phi0 to below phi0 + 360 R. Consecutive
//     angles are
//         360 / N (1 - D/2 + D (2k + 1 + 2 tau) / (2 N R))  apart,
//     strictly between 360/N (1 - D/2) and 360/N (1 + D/2); a revolution of the
//     spindle therefore holds between N / (1 + D/2) and N / (1 - D/2) samples
//     (to one). Why tau: were the ticks at k / N, instants symmetric about R/2
//     and a whole number of nominal periods apart would see exactly the nominal
//     mean speed, and R pairs of angles would coincide modulo 360. With tau drawn,
//     two angles coincide modulo 360 only by chance, never systematically; as
//     for any unsynchronised sampling, the closest two of all N R (about 360 /
//     (N R)^2 deg apart at random) come within 1e-6 deg for some seeds (tests/sim
//     checks that its seeds have none). D = 0 gives convention 1's angles at N
//     (to rounding), all shifted by phi0 + 360 tau / N.
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

// Conventions 1-3.
struct AnalyserConfig {
  int revolutions = 3;
  double step_deg = 5.0;                 // 360 / step_deg whole; used only when samples_per_revolution = 0
  double noise_sigma_mm = 15e-6;         // per axis, 1 sigma, white
  double form_rms_mm = 50e-6;            // per ball, harmonics 2..15
  std::uint64_t form_seed = 1;
  // Convention 1: 0, angles every step_deg; 8..4096, N angles a revolution.
  // Convention 3: N, the nominal samples a revolution (0: 1024).
  int samples_per_revolution = 0;
  bool time_sampled = false;             // convention 3, else convention 1
  double speed_drift = 0.01;             // convention 3's D, relative (0.01 = 1 %); 0 <= D < 2
};

inline constexpr int kMinSamplesPerRevolution = 8;
inline constexpr int kMaxSamplesPerRevolution = 4096;
inline constexpr int kTimeSampledDefaultSamples = 1024;

inline constexpr int kFormFirstHarmonic = 2;
inline constexpr int kFormLastHarmonic = 15;
inline constexpr std::uint64_t kFormStream = 0x6A09E667F3BCC909ull;

class VirtualAnalyser {
 public:
  explicit VirtualAnalyser(const AnalyserConfig& config);

  const AnalyserConfig& config() const { return config_; }
  // N: samples_per_revolution when not 0; else 1024 when time_sampled; else
  // 360 / step_deg rounded (the tool checks it is whole). Convention 3: nominal.
  int steps_per_revolution() const;
  // Convention 3: theta(t) = phi(t) - phi0, t in nominal revolution periods
  // (from this config's R and D, whether or not time_sampled).
  double time_sampled_angle_deg(double t) const;
  // Convention 2: rho_k at beta, and the apparent centre shift f_k at phi.
  double form_radius_mm(int ball, double beta_deg) const;
  core::Vec3 form_error_mm(int ball, double phi_deg) const;
  // Convention 1 or 3: every reading in order. Convention 3 draws phi0 and tau first.
  std::vector<core::SpindleSample> measure(const BallCentres& centres, SimRng& noise) const;

 private:
  static constexpr int kHarmonics = kFormLastHarmonic - kFormFirstHarmonic + 1;
  AnalyserConfig config_;
  double cos_[2][kHarmonics] = {};
  double sin_[2][kHarmonics] = {};
};

}  // namespace trueaxis::sim
