// M4's tool-axis model as the identifiability study chose it
// (docs/M4_IDENTIFIABILITY.md, finding 3): 9 parameters the analyser data at two
// ball heights determine, the ball centres they predict, a closed-form start and
// the Levenberg-Marquardt fit (levenberg_marquardt.hpp) with its covariance.
//
// Conventions
//  1. Parameters p = (o_x, o_y, o_z [mm], a_x, a_y, e_x, e_y [mm], w_x, w_y;
//     a and w dimensionless, radians for small angles): O1 in the analyser frame; the x, y of the unit spindle
//     axis a through O1, pointing to the tool (a_z < 0); the tool line minus the
//     spindle axis at the gauge plane at phi = 0 (e, normal to a); the tool
//     direction minus a per unit depth (w, normal to a):
//         a = (a_x, a_y, -sqrt(1 - a_x^2 - a_y^2)),
//         e = (e_x, e_y, -(a_x e_x + a_y e_y) / a_z), w likewise.
//  2. Ball k (0: nearer the spindle) at depth b_k below the gauge plane, the
//     gauge plane G below O1 (SpindleGeometry), spindle angle phi (rad, M03
//     positive, right-handed about a):
//         M_k(phi) = o + (G + b_k) a + cos(phi) v_k + sin(phi) (a x v_k),
//         v_k = e + b_k w.
//  3. Start (spindle_start): per ball the mean m_k and the first harmonic
//     v_k = (2 / N_k) sum (M - m_k) cos(phi) (exact for whole revolutions at even
//     steps; otherwise only a start), then a = (m_2 - m_1) / |m_2 - m_1|,
//     o = m_1 - (G + b_1) a, w = (v_2 - v_1) / (b_2 - b_1), e = v_1 - b_1 w, each
//     v_k first made normal to a.
//  4. Angle bins (SpindleBins): an analyser repeats its angles revolution after
//     revolution, so samples are kept per ball and per distinct angle (phi
//     modulo 360 within kSameAngleDeg): the count, the mean and the scatter
//     sum |p - mean|^2 (Welford's update). The least-squares fit to the samples
//     equals the fit to the bin means weighted by their counts (the scatter is
//     a constant of it), so the session costs memory per angle, not per
//     sample, and any number of revolutions. Bins are kept sorted by angle.
//     A sample given twice (the same phi_deg as given, not reduced, and the
//     same centre, bit for bit) is no repeat of a measurement: it would
//     count the same error twice and shrink the sigmas (convention 6). As
//     the bins keep no samples, each keeps a 32-bit fingerprint of its first
//     and of its latest sample (spindle_fingerprint), and add() refuses a
//     sample with either (kDuplicateSample): a file or a revolution given
//     twice at its first sample, a row given twice in a row. A repeat of a
//     bin's other samples passes unseen (the tools check their files whole);
//     a measured sample is refused only if its fingerprint collides, with
//     probability 2^-31 per sample. A later revolution differs in phi
//     (phi + 360) or in its measured centre, and is a bin's repeat.
//  5. Fit (SpindleBuilder, fit_spindle): residuals predicted minus bin mean, 3 per
//     bin, weighted by the bin's count; the Jacobian analytic
//     (spindle_ball_jacobian; checked against central differences in the
//     tests); Levenberg-Marquardt from the start of convention 3, with the
//     identifiability check of levenberg_marquardt.hpp convention 5.
//  6. Noise and covariance: the repeats of an angle differ only by what does
//     not repeat each revolution (asynchronous error: probe noise), while a
//     ball's form error and any error motion that repeats (synchronous) stays
//     in the bin means. With at least kMinNoiseRepeats repeats (samples minus
//     bins, both balls) the noise variance per axis is the pooled
//     s^2 = scatter / (3 repeats), and the covariance s^2 (J^T W J)^-1: the
//     harmonics 2 and up of a form error are orthogonal to the model's 0th
//     and 1st at evenly spaced angles and move no parameter, so they must not
//     widen the intervals either. With fewer repeats (one revolution) s^2 =
//     (2F + scatter) / (3 n - 9) from every residual, form error included: the
//     intervals are then conservative (noise_from_repeats = false says so).
//  7. Coverage: a ball's angles must leave no gap (circularly) wider than
//     kMaxSpindleGapDeg (or the limit given), else kRevolutionIncomplete: a part of a revolution
//     cannot separate the run-out circle from its centre.
//
// Status codes: kTooFewSamples (fewer than kMinSpindleSamples distinct angles per
// ball), kMissingGroup (a ball with no samples: one height cannot separate e from
// w), kRevolutionIncomplete (convention 7), kNotFinite, kArgumentOutOfRange (a
// ball index other than 1 or 2, b_2 <= b_1, a coordinate beyond kSpindleBigMm),
// kSessionFull (a ball's kMaxSpindleAngles-th + 1 distinct angle),
// kDuplicateSample (convention 4), and those of
// the solver (kNotIdentifiable, kNoConvergence: also for an iteration whose
// model values overflow, as lengths in metres against samples in mm drive
// the axis horizontal; finite data never give kNotFinite from the fit); a fit whose axis lies more than
// 30 deg from -Z (kMaxSpindleTilt) is kArgumentOutOfRange.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/levenberg_marquardt.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr int kSpindleParams = 9;
inline constexpr std::size_t kMinSpindleSamples = 8;      // distinct angles per ball: a revolution at 45 deg
inline constexpr std::size_t kMaxSpindleAngles = 360;     // distinct angles per ball the bins hold
inline constexpr double kSameAngleDeg = 1e-6;             // angles closer than this (mod 360) share a bin
inline constexpr double kMaxSpindleGapDeg = 45.0;         // convention 7
inline constexpr std::size_t kMinNoiseRepeats = 9;        // convention 6
inline constexpr double kSpindleBigMm = 1e5;              // a coordinate beyond this is refused
inline constexpr double kSpindleBigDeg = 1e6;             // an angle beyond this is refused
inline constexpr std::uint32_t kMaxBinCount = 1u << 24;   // samples one angle bin takes
// The spindle axis within 30 deg of the machine's -Z (|(a_x, a_y)| <= sin 30):
// a fit beyond it is refused (kArgumentOutOfRange), and so is a stored model.
inline constexpr double kMaxSpindleTilt = 0.5;
using SpindleParams = Eigen::Matrix<double, kSpindleParams, 1>;
using SpindleCovariance = Eigen::Matrix<double, kSpindleParams, kSpindleParams>;
using SpindleJacobian = Eigen::Matrix<double, 3, kSpindleParams>;

struct SpindleGeometry {
  double gauge_mm = 0.0;               // G: O1 to the gauge plane along the spindle
  double ball_mm[2] = {0.0, 0.0};      // b_1 < b_2: ball centres below the gauge plane
};

struct SpindleSample {
  double phi_deg = 0.0;
  int ball = 1;  // 1 or 2
  Vec3 p_mm = Vec3::Zero();
};

// The vectors of convention 1.
struct SpindleAxes {
  Vec3 a = -Vec3::UnitZ();  // unit spindle axis, towards the tool
  Vec3 e = Vec3::Zero();    // tool line minus spindle axis at the gauge plane, phi = 0
  Vec3 w = Vec3::Zero();    // tool direction minus a per unit depth, phi = 0
};
SpindleAxes spindle_axes(const SpindleParams& p);

struct SpindleFit {
  SpindleParams params = SpindleParams::Zero();
  SpindleCovariance covariance = SpindleCovariance::Zero();
  double rms_mm = 0.0;              // RMS of the 3-D residual per sample, every sample
  double synchronous_rms_mm = 0.0;  // RMS (weighted by count) of the 3-D residual of the angle means
  double noise_sigma_mm = 0.0;      // s of convention 6, per axis
  bool noise_from_repeats = false;  // convention 6: s from the repeats (true) or every residual
  std::uint32_t samples = 0;
  std::uint32_t angles[2] = {0, 0};
  double smallest_eigenvalue_ratio = 0.0;
  int evaluations = 0;              // residual-and-Jacobian passes of the solver
};

// Convention 2.
Vec3 spindle_ball_mm(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad);

// Convention 2 and its Jacobian d M / d p.
Vec3 spindle_ball_jacobian(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad,
                           SpindleJacobian& j);

struct SpindleBin {
  double phi_deg = 0.0;  // [0, 360)
  std::uint32_t count = 0;
  std::uint32_t first_fingerprint = 0;  // convention 4: the bin's first sample's
  Vec3 mean_mm = Vec3::Zero();
  double scatter_mm2 = 0.0;  // sum of |p - mean|^2 over the bin's samples
  std::uint32_t last_fingerprint = 0;   // the latest sample's
};

// Convention 4: a 32-bit digest of a sample's bits as given (phi_deg before
// any reduction, the centre); the ball is the bin's.
std::uint32_t spindle_fingerprint(const SpindleSample& s);

// Convention 4. add() checks a sample whole before it changes anything.
class SpindleBins {
 public:
  void clear();
  [[nodiscard]] Status add(const SpindleSample& s);
  std::size_t angles(int ball) const { return angles_[index(ball)]; }
  std::size_t samples(int ball) const { return samples_[index(ball)]; }
  std::size_t samples() const { return samples_[0] + samples_[1]; }
  const SpindleBin& bin(int ball, std::size_t i) const { return bins_[index(ball)][i]; }
  // The widest circular gap between a ball's angles (360 for one angle or none).
  double largest_gap_deg(int ball) const;
  double scatter_mm2() const;

 private:
  static std::size_t index(int ball) { return ball == 2 ? 1 : 0; }
  SpindleBin bins_[2][kMaxSpindleAngles];
  std::size_t angles_[2] = {0, 0};
  std::size_t samples_[2] = {0, 0};
};

// Convention 3 on the bins (each angle once, whatever its count), after the
// checks of conventions 4 and 7.
[[nodiscard]] Result<SpindleParams> spindle_start(const SpindleBins& bins, const SpindleGeometry& g,
                                                  double max_gap_deg = kMaxSpindleGapDeg);

struct SpindleStep {
  Status status = Status::kOk;
  bool more = false;
};

// The fit of conventions 5-6 in bounded steps: the checks and the start in the
// first, then at most kBinsPerStep bins of an evaluation per step, the
// solver's decision in a step of its own, and the covariance in the last. The
// bins must not change between start() and the last step.
class SpindleBuilder {
 public:
  static constexpr std::size_t kBinsPerStep = 48;

  // max_gap_deg: convention 7's limit (kMaxSpindleGapDeg unless configured).
  void start(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg = kMaxSpindleGapDeg,
             const LmOptions& options = LmOptions());
  SpindleStep step();
  // Complete after a step that returned kOk without more.
  const SpindleFit& fit() const { return fit_; }

 private:
  enum class Phase : std::uint8_t { kStart, kEvaluate, kDecide, kFinish, kDone };
  SpindleStep fail(Status s);

  const SpindleBins* bins_ = nullptr;
  SpindleGeometry geometry_;
  double max_gap_deg_ = kMaxSpindleGapDeg;
  LmOptions options_;
  LevenbergMarquardt<kSpindleParams> lm_;
  SpindleFit fit_;
  SpindleCovariance factor_ = SpindleCovariance::Zero();  // the covariance's Cholesky factor (scratch)
  Phase phase_ = Phase::kDone;
  Status status_ = Status::kOk;
  std::size_t cursor_ = 0;  // the next bin of the evaluation under way, both balls in a row
};

// Conventions 4-6 on a set of samples, the builder run to its end (host and
// tests: its SpindleBins, 35 KB, live on the stack).
[[nodiscard]] Status fit_spindle(const SpindleSample* samples, std::size_t count, const SpindleGeometry& g,
                                 SpindleFit& out);

}  // namespace trueaxis::core
