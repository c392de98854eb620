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
//  3. Start (spindle_start): per ball the centre m_k and the first harmonic
//     v_k of convention 4's exact harmonic fit (any sampling), then
//     a = (m_2 - m_1) / |m_2 - m_1|, o = m_1 - (G + b_1) a,
//     w = (v_2 - v_1) / (b_2 - b_1), e = v_1 - b_1 w, each v_k first made
//     normal to a.
//  4. The session keeps no samples, in memory that does not grow with them
//     (an analyser's encoder gives up to 4,096 samples a revolution, one
//     sampling on time gives angles that never repeat; any number of
//     revolutions), in two parts per ball:
//     - Sums (SpindleBallSums), exact for the fit: with d = p - (the ball's
//       first sample) and (c, s) = (cos phi, sin phi), the count, the sums of
//       c, s, cc, cs, ss, d, d c, d s and per axis d^2. Each ball's model is
//       M(phi) = m + c v + s u (convention 2: m = o + (G + b) a, v = e + b w,
//       u = a x v), so its sum of squared residuals is, per axis x with
//       z_x = (m_x, v_x, u_x), H = [[n, Sc, Ss], [Sc, Scc, Scs], [Ss, Scs, Sss]]
//       and g_x = (Sd_x, Sdc_x, Sds_x):
//           SSR_x = z_x^T H z_x - 2 z_x^T g_x + Sdd_x
//                 = |L^T z_x - y_x|^2 + (Sdd_x - |y_x|^2),  H = L L^T, y_x = L^-1 g_x.
//       The fit (convention 5) minimises exactly this: the same parameters,
//       cost and covariance as a fit to every sample. The harmonic fit
//       (spindle_harmonics) is z_x = L^-T y_x, its SSR Sdd_x - |y_x|^2.
//     - Angle bins (SpindleBin), kSpindleBins of kSpindleBinDeg (2 deg) per
//       ball, phi modulo 360, for the noise (convention 6), the coverage
//       (convention 7) and the duplicates: per bin the count, its first
//       sample's angle phi_0, and over delta = phi - phi_0 (deg) and d the
//       means, sum (delta - mean)^2, sum (delta - mean)(d - mean) and
//       sum |d - mean|^2 (Welford's update on d, small: the sums keep the
//       digits a centre 400 mm from the analyser's origin would cost). A bin's local line p = alpha +
//       beta delta leaves residuals that hold the noise (what does not
//       repeat at an angle: ISO 230-7's asynchronous error) and, of what
//       repeats (the balls' form error, synchronous error motion), only its
//       curvature across the bin: a harmonic of order k and amplitude A
//       leaves at most A k^2 w^2 / (12 sqrt 5) RMS across a bin of width w,
//       4.5e-5 A k^2 at 2 deg: 0.45 nm of a 10 um run-out (k = 1), 0.5 nm of
//       50 nm of form to k = 15, against 15 nm of probe noise.
//       A bin whose angles spread by no more than kSameAngleDeg (RMS) holds
//       repeats of one angle: its local mean, not a line.
//     A sample given twice (the same phi_deg as given, not reduced, and the
//     same centre, bit for bit) is no repeat of a measurement: it would count
//     the same error twice and shrink the sigmas. Each bin keeps a 32-bit
//     fingerprint of its first and of its latest sample (spindle_fingerprint),
//     and add() refuses a sample with either (kDuplicateSample): a file or a
//     revolution given twice at its first sample, a row given twice in a row.
//     A repeat of a bin's other samples passes unseen (the tools check their
//     files whole); a measured sample is refused only if its fingerprint
//     collides, with probability 2^-31 per sample.
//  5. Fit (SpindleBuilder, fit_spindle): per ball and axis the three residuals
//     L^T z_x(p) - y_x of convention 4 with their analytic Jacobian
//     (spindle_ball_terms; checked against central differences in the tests):
//     18 residuals whose sum of squares differs from the samples' by the
//     constant sum (Sdd_x - |y_x|^2), which moves no parameter (the solver's
//     statistical stop then judges by the 9 degrees of freedom the harmonic
//     fits have beyond the model: noise, as the samples' would);
//     Levenberg-Marquardt from the start of convention 3, with the
//     identifiability check of levenberg_marquardt.hpp convention 5. An
//     evaluation costs the same for 16 samples or 16 million.
//  6. Noise and covariance: the bins' local lines leave the noise alone
//     (convention 4). With at least kMinNoiseRepeats degrees of freedom in
//     them (sum over the bins of count - 2, or count - 1 for repeats of one
//     angle) the noise variance per axis is s^2 = their residuals' sum of
//     squares / (3 dof), and the covariance s^2 (J^T J)^-1: the harmonics 2
//     and up of a form error are orthogonal to the model's 0th and 1st at
//     evenly spaced angles and move no parameter, so they must not widen the
//     intervals either. With fewer (one revolution at steps of 2 deg or more)
//     s^2 = SSR / (3 n - 9) from every residual, form error included: the
//     intervals are then conservative (noise_from_repeats = false says so).
//     synchronous_rms_mm = sqrt((SSR - the bins' residuals) / n): what the
//     model leaves that is not noise.
//  7. Coverage: a ball's angle bins must leave no gap (circularly, between the
//     mean angles of the bins that hold samples) wider than kMaxSpindleGapDeg
//     (or the limit given), else kRevolutionIncomplete: a part of a revolution
//     cannot separate the run-out circle from its centre. Exact where each bin
//     holds one angle; otherwise up to a bin's width wider than the true gap.
//
// Status codes: kTooFewSamples (fewer than kMinSpindleSamples angle bins holding
// samples per ball), kMissingGroup (a ball with no samples: one height cannot separate e from
// w), kRevolutionIncomplete (convention 7), kNotFinite, kArgumentOutOfRange (a
// ball index other than 1 or 2, b_2 <= b_1, a coordinate beyond kSpindleBigMm),
// kSessionFull (a sample beyond kMaxBinCount in one angle bin),
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
inline constexpr std::size_t kMinSpindleSamples = 8;      // angle bins holding samples per ball
inline constexpr std::size_t kSpindleBins = 180;          // angle bins per ball (convention 4)
inline constexpr double kSpindleBinDeg = 360.0 / kSpindleBins;
inline constexpr double kSameAngleDeg = 1e-6;             // a bin's angles within this (RMS): one angle
inline constexpr double kMaxSpindleGapDeg = 45.0;         // convention 7
inline constexpr std::size_t kMinNoiseRepeats = 9;        // convention 6
inline constexpr double kSpindleBigMm = 1e5;              // a coordinate beyond this is refused
inline constexpr double kSpindleBigDeg = 1e6;             // an angle beyond this is refused
inline constexpr std::uint32_t kMaxBinCount = 1u << 23;   // samples one angle bin takes (all: < 2^32)
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
  double synchronous_rms_mm = 0.0;  // convention 6: RMS 3-D residual beyond the bins' noise
  double noise_sigma_mm = 0.0;      // s of convention 6, per axis
  bool noise_from_repeats = false;  // convention 6: s from the bins (true) or every residual
  std::uint32_t samples = 0;
  std::uint32_t angles[2] = {0, 0};  // angle bins holding samples, per ball
  double smallest_eigenvalue_ratio = 0.0;
  int evaluations = 0;              // residual-and-Jacobian passes of the solver
  double ball_ssr_mm2[2] = {0.0, 0.0};  // each ball's sum of squared 3-D residuals (not stored)
};

// Convention 2.
Vec3 spindle_ball_mm(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad);

// Convention 2 and its Jacobian d M / d p.
Vec3 spindle_ball_jacobian(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad,
                           SpindleJacobian& j);

// Convention 4: a ball's model M(phi) = m + cos(phi) v + sin(phi) u, with the
// Jacobians of m, v and u.
struct SpindleBallTerms {
  Vec3 m = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 u = Vec3::Zero();
  SpindleJacobian jm = SpindleJacobian::Zero();
  SpindleJacobian jv = SpindleJacobian::Zero();
  SpindleJacobian ju = SpindleJacobian::Zero();
};
void spindle_ball_terms(const SpindleParams& p, const SpindleGeometry& g, int ball, SpindleBallTerms& out);

// Convention 4's sums over one ball's samples.
struct SpindleBallSums {
  std::uint64_t count = 0;
  Vec3 origin_mm = Vec3::Zero();  // the ball's first sample; d = p - origin_mm
  double c = 0.0, s = 0.0, cc = 0.0, cs = 0.0, ss = 0.0;
  Vec3 d = Vec3::Zero();
  Vec3 dc = Vec3::Zero();
  Vec3 ds = Vec3::Zero();
  Vec3 dd = Vec3::Zero();  // per axis
  // The plain mean of the ball's samples (zero for none).
  Vec3 mean_mm() const;
};

// Convention 4's harmonic fit of one ball: H = L L^T, y_x = L^-1 g_x (one
// column per axis), its centre m = origin + z's first row, first harmonic v,
// second u, and the sum of squared residuals it leaves.
struct SpindleHarmonics {
  Mat3 l = Mat3::Zero();
  Mat3 y = Mat3::Zero();
  Vec3 centre_mm = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 u = Vec3::Zero();
  double ssr_mm2 = 0.0;
};
// kNotIdentifiable when H is not positive definite (fewer than three angles).
[[nodiscard]] Status spindle_harmonics(const SpindleBallSums& sums, SpindleHarmonics& out);

// Convention 4's angle bin.
struct SpindleBin {
  std::uint32_t count = 0;              // 0: empty
  std::uint32_t first_fingerprint = 0;  // the bin's first sample's
  std::uint32_t last_fingerprint = 0;   // the latest sample's
  double phi_deg = 0.0;                 // phi_0, the first sample's angle, [0, 360)
  double mean_delta_deg = 0.0;
  double delta_m2 = 0.0;                // sum (delta - mean)^2, deg^2
  Vec3 mean_offset_mm = Vec3::Zero();   // the mean of p - the ball's first sample (SpindleBallSums)
  Vec3 cross_mm = Vec3::Zero();         // sum (delta - mean)(p - mean), deg mm
  double scatter_mm2 = 0.0;             // sum |p - mean|^2
  double angle_deg() const { return phi_deg + mean_delta_deg; }
};

// Convention 6: the residuals' sum of squares the bins' local lines leave, and
// their degrees of freedom per axis.
struct SpindleNoise {
  double ssr_mm2 = 0.0;
  std::size_t dof = 0;
};
SpindleNoise spindle_bin_noise(const SpindleBin& b);

// Convention 4: a 32-bit digest of a sample's bits as given (phi_deg before
// any reduction, the centre); the ball is the bin's.
std::uint32_t spindle_fingerprint(const SpindleSample& s);

// Convention 4. add() checks a sample whole before it changes anything.
class SpindleBins {
 public:
  void clear();
  [[nodiscard]] Status add(const SpindleSample& s);
  // Angle bins holding samples.
  std::size_t angles(int ball) const { return angles_[index(ball)]; }
  std::size_t samples(int ball) const { return static_cast<std::size_t>(sums_[index(ball)].count); }
  std::size_t samples() const { return samples(1) + samples(2); }
  const SpindleBallSums& sums(int ball) const { return sums_[index(ball)]; }
  // Bin i < kSpindleBins of a ball (count 0: empty).
  const SpindleBin& bin(int ball, std::size_t i) const { return bins_[index(ball)][i]; }
  // Convention 7: the widest circular gap between a ball's bins (360 for one or none).
  double largest_gap_deg(int ball) const;
  // Convention 6 over both balls' bins.
  SpindleNoise noise() const;

 private:
  static std::size_t index(int ball) { return ball == 2 ? 1 : 0; }
  SpindleBin bins_[2][kSpindleBins];
  SpindleBallSums sums_[2];
  std::size_t angles_[2] = {0, 0};
};

// Convention 3 from the harmonic fits, after the checks of conventions 4 and 7;
// the two balls' harmonic fits into `harmonics` when given (the builder's
// residuals use them).
[[nodiscard]] Result<SpindleParams> spindle_start(const SpindleBins& bins, const SpindleGeometry& g,
                                                  double max_gap_deg = kMaxSpindleGapDeg,
                                                  SpindleHarmonics* harmonics = nullptr);

struct SpindleStep {
  Status status = Status::kOk;
  bool more = false;
};

// The fit of conventions 5-6 in bounded steps: the checks, the harmonic fits
// and the start in the first; the bins' noise in the second; then an
// evaluation a step (two balls' sums, whatever the sample count), the
// solver's decision in a step of its own, and the covariance in the last.
// The bins must not change between start() and the last step.
class SpindleBuilder {
 public:
  // max_gap_deg: convention 7's limit (kMaxSpindleGapDeg unless configured).
  void start(const SpindleBins& bins, const SpindleGeometry& g, double max_gap_deg = kMaxSpindleGapDeg,
             const LmOptions& options = LmOptions());
  SpindleStep step();
  // Complete after a step that returned kOk without more.
  const SpindleFit& fit() const { return fit_; }

 private:
  enum class Phase : std::uint8_t { kStart, kNoise, kEvaluate, kDecide, kFinish, kDone };
  SpindleStep fail(Status s);
  // Each ball's residuals of convention 5 at lm_.point() into lm_, or their
  // sum of squares at p into ssr (lm_ untouched).
  void evaluate(const SpindleParams& p, bool into_solver, double ssr[2]);

  const SpindleBins* bins_ = nullptr;
  SpindleGeometry geometry_;
  double max_gap_deg_ = kMaxSpindleGapDeg;
  LmOptions options_;
  LevenbergMarquardt<kSpindleParams> lm_;
  SpindleFit fit_;
  SpindleHarmonics harmonics_[2];
  SpindleBallTerms terms_;  // scratch (off the step's stack)
  SpindleNoise noise_;
  SpindleCovariance factor_ = SpindleCovariance::Zero();  // the covariance's Cholesky factor (scratch)
  Phase phase_ = Phase::kDone;
  Status status_ = Status::kOk;
};

// Conventions 4-6 on a set of samples, the builder run to its end (host and
// tests: its SpindleBins, 35 KB, live on the stack).
[[nodiscard]] Status fit_spindle(const SpindleSample* samples, std::size_t count, const SpindleGeometry& g,
                                 SpindleFit& out);

}  // namespace trueaxis::core
