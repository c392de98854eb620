// The gates: what a method's compute macro checks before it publishes or
// stores a result, so that nothing wrong reaches the machine whichever client
// runs it (calibrate command, HMI, G-code). docs/INTERFACE.md "Gates".
//
// Conventions
//  1. Three kinds, each refused with its own code and the item, value and
//     limit in #9012 .. #9014 (method_context.hpp contract 8):
//       fit          the residuals against the instrument's stated noise (a
//                    configuration row of the method): fit_beyond_noise (500);
//       plausibility a figure against the configured nominal sizes, with a
//                    code of the method's whose message names the likely
//                    cause (metres for millimetres, radians for degrees);
//       change       against the stored table (Heidenhain's "maximum
//                    modification"): change_beyond_limit (501) when storing
//                    without M = 1; the change is published either way (an
//                    output of the compute macro; #9013 when refused).
//  2. The fit gate is a chi-square test: T = SSR / s^2 for each pose or group
//     (s the stated noise per axis, dof the fit's residual degrees of
//     freedom) against chi_square_quantile(dof, #901). Pure noise is refused
//     with probability 1 - #901 per item (1e-6 by default; the quantile errs
//     high, chi_square.hpp convention 2). A stated noise of 0 switches the
//     gate off. The item named is the one with the largest T / quantile.
//  3. A method lists its gates in its descriptor (kGates, optional): the JSON
//     map publishes each with its code and the configuration rows that set
//     its thresholds.
//  No allocation, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/chi_square.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::macros {

// Convention 3.
struct GateInfo {
  const char* name;                // "fit", "a_error", "change"
  core::Status status;             // the code it refuses with
  std::uint16_t thresholds[3];     // the configuration rows that set it (0: none)
  const char* what;
};

// Convention 2: the worst item of a fit gate.
class FitGate {
 public:
  explicit FitGate(double confidence) : z_(core::normal_upper_quantile(1.0 - confidence)) {}

  // One pose or group: SSR / s^2 with `dof` residual degrees of freedom; item is 1-based.
  void consider(std::size_t item, double statistic, std::size_t dof) {
    const double q = core::chi_square_quantile_z(dof, z_);
    if (!(q > 0.0)) return;
    const double ratio = statistic / q;
    if (ratio > ratio_ || item_ == 0) {
      ratio_ = ratio;
      item_ = item;
    }
  }
  bool refused() const { return ratio_ > 1.0; }
  std::size_t item() const { return item_; }
  double ratio() const { return ratio_; }

 private:
  double z_;
  double ratio_ = 0.0;
  std::size_t item_ = 0;
};

}  // namespace trueaxis::macros
