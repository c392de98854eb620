// M4's tool-axis model as the identifiability study chose it
// (docs/M4_IDENTIFIABILITY.md, finding 3): 9 parameters the analyser data at two
// ball heights determine, the ball centres they predict, a closed-form start and
// the Levenberg-Marquardt fit (levenberg_marquardt.hpp) with its covariance.
//
// Conventions
//  1. Parameters p = (o_x, o_y, o_z [mm], a_x, a_y [rad], e_x, e_y [mm],
//     w_x, w_y [rad]): O1 in the analyser frame; the x, y of the unit spindle
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
//  4. Fit (fit_spindle): residuals measured minus predicted, 3 per sample,
//     equally weighted; the Jacobian analytic in o and by central differences
//     (steps 1e-7 rad, 1e-7 mm) in the rest; covariance from the residuals.
//
// Status codes: kTooFewSamples (fewer than kMinSpindleSamples per ball),
// kMissingGroup (a ball with no samples: one height cannot separate e from w),
// kNotFinite, kArgumentOutOfRange (a ball index other than 1 or 2, b_2 <= b_1),
// and those of the solver (kNotIdentifiable, kNoConvergence).
#pragma once

#include <cstddef>

#include "trueaxis/core/levenberg_marquardt.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

inline constexpr int kSpindleParams = 9;
inline constexpr std::size_t kMinSpindleSamples = 8;  // per ball: a revolution at 45 deg steps
using SpindleParams = Eigen::Matrix<double, kSpindleParams, 1>;
using SpindleCovariance = Eigen::Matrix<double, kSpindleParams, kSpindleParams>;

struct SpindleGeometry {
  double gauge_mm = 0.0;               // G: O1 to the gauge plane along the spindle
  double ball_mm[2] = {0.0, 0.0};      // b_1 < b_2: ball centres below the gauge plane
};

struct SpindleSample {
  double phi_deg = 0.0;
  int ball = 1;  // 1 or 2
  Vec3 p_mm = Vec3::Zero();
};

struct SpindleFit {
  SpindleParams params = SpindleParams::Zero();
  SpindleCovariance covariance = SpindleCovariance::Zero();
  double rms_mm = 0.0;  // RMS of the 3-D residual per sample
  int evaluations = 0;
};

// Convention 2.
Vec3 spindle_ball_mm(const SpindleParams& p, const SpindleGeometry& g, int ball, double phi_rad);

// Convention 3.
[[nodiscard]] Result<SpindleParams> spindle_start(const SpindleSample* samples, std::size_t count,
                                                  const SpindleGeometry& g);

// Conventions 3-4.
[[nodiscard]] Status fit_spindle(const SpindleSample* samples, std::size_t count, const SpindleGeometry& g,
                                 SpindleFit& out);

}  // namespace trueaxis::core
