// M4's outputs: the screw error of the tool axis against the ideal axis and the
// tool-tip correction, per spindle angle and over a revolution (docs/INTERFACE.md
// "M4 spindle"), from the identified model (spindle_model.hpp), with their
// 1-sigma uncertainties; and the stored model (its record's byte layout).
//
// Conventions
//  1. Everything is written relative to O1 (o cancels: both lines pass near it
//     and both tips are measured from it), in the analyser's frame, whose axes
//     are the machine's. The ideal axis is the line through O1 along -Z
//     (docs/INTERFACE.md: the machine's Z direction through O1, towards the tool).
//  2. The tool line at spindle angle phi (spindle_model.hpp convention 2), with
//     R(phi) x = cos(phi) x + sin(phi) (a x x) for x normal to a:
//         point at the gauge plane  q(phi) = G a + R(phi) e,
//         direction                 d(phi) = unit(a + R(phi) w).
//     theta_e, d_e: screw_error (screw.hpp) from the ideal line to it; theta_e
//     in [0, pi], d_e >= 0 the length of the common perpendicular.
//  3. Tool tip at tool length L below the gauge line (the model's point at depth
//     L, the balls' law): actual  t(phi) = (G + L) a + R(phi) (e + L w);
//     ideal (G + L) (0, 0, -1); tip error = actual - ideal. Over a revolution
//     R(phi) averages to zero: the mean tip error is (G + L) (a + Z).
//  4. Uncertainties (spindle_correction_sigma): first-order propagation of the
//     model's covariance, the Jacobian by central differences (steps 1e-9 in
//     the dimensionless a, w; 1e-7 mm in e). theta_e and d_e are magnitudes:
//     their linearised sigma holds while they exceed a few sigma (a figure near
//     zero is a distance from zero, not a Gaussian).
//  5. Stored model, layout version 1 (little-endian, byte_order.hpp):
//       0    2        layout version = 1
//       2    2        flags: bit 0 noise_from_repeats
//       4    4        samples (u32)
//       8    4, 4     angles of ball 1, ball 2 (u32)
//       16   4        evaluations (u32)
//       20   4        reserved, 0
//       24   9 x 8    params
//       96   45 x 8   covariance, upper triangle row by row
//       456  3 x 8    geometry: gauge_mm, ball_mm[0], ball_mm[1]
//       480  4 x 8    rms_mm, synchronous_rms_mm, noise_sigma_mm,
//                     smallest_eigenvalue_ratio
//     Size 512 bytes (kSpindleModelBytes). The axes (spindle_axes) are not
//     stored: decode recomputes them with the same code.
//     Decode refuses (kTableInvalid, `out` untouched): a size other than
//     kSpindleModelBytes, another version, flags above bit 0, reserved bytes
//     not 0, a non-finite real, |a_x, a_y| >= 1 or a_z not clearly negative
//     (|(a_x, a_y)| above sin 30 deg), a negative variance, figure or ratio,
//     b_2 <= b_1, no samples.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::core {

struct SpindleCorrection {
  double theta_e_rad = 0.0;
  double d_e_mm = 0.0;
  Vec3 tip_error_mm = Vec3::Zero();
};

// A spindle angle in degrees as radians within one turn, fmod's result (its
// sign) bit for bit, without fmod's cost below 2^44 deg: what 9843 and every
// direct caller of the correction turn an angle into.
double spindle_phi_rad(double phi_deg);

// Conventions 2-3 at one angle (rad) and tool length (mm below the gauge line).
[[nodiscard]] Result<SpindleCorrection> spindle_correction(const SpindleAxes& axes, double gauge_mm,
                                                           double tool_mm, double phi_rad);

// Convention 3: the tip error averaged over a revolution.
Vec3 spindle_mean_tip_error_mm(const SpindleAxes& axes, double gauge_mm, double tool_mm);

struct SpindleCorrectionSigma {
  double theta_e_rad = 0.0;
  double d_e_mm = 0.0;
  Vec3 tip_error_mm = Vec3::Zero();       // per axis
  Vec3 mean_tip_error_mm = Vec3::Zero();  // per axis
};

// Convention 4.
[[nodiscard]] Result<SpindleCorrectionSigma> spindle_correction_sigma(const SpindleParams& p,
                                                                      const SpindleCovariance& covariance,
                                                                      double gauge_mm, double tool_mm,
                                                                      double phi_rad);

// The model a controller keeps (convention 5).
struct SpindleModel {
  SpindleFit fit;
  SpindleGeometry geometry;
  SpindleAxes axes;  // spindle_axes(fit.params)
};

inline constexpr std::uint16_t kSpindleLayoutVersion = 1;
inline constexpr std::size_t kSpindleModelBytes = 512;

SpindleModel make_spindle_model(const SpindleFit& fit, const SpindleGeometry& geometry);
std::size_t encode_spindle_model(const SpindleModel& model, std::uint8_t* out, std::size_t capacity);
[[nodiscard]] Status decode_spindle_model(const std::uint8_t* bytes, std::size_t size, SpindleModel& out);

}  // namespace trueaxis::core
