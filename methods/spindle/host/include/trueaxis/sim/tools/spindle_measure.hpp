// Measuring the virtual spindle (machines/virtual_spindle.hpp) with the virtual
// spindle analyser (instruments/spindle_analyser.hpp), as an operator would for
// M4: the analyser reads the spindle's balls in its own order and noise.
// Host only.
#pragma once

#include <vector>

#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/sim/instruments/spindle_analyser.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"

namespace trueaxis::sim {

// Every reading in the analyser's order (spindle_analyser.hpp convention 1) of
// the spindle's balls (virtual_spindle.hpp conventions 2-3), noise from `noise`.
inline std::vector<core::SpindleSample> measure_spindle(const VirtualAnalyser& analyser, const VirtualSpindle& spindle,
                                                        SimRng& noise) {
  return analyser.measure([&spindle](int ball, double phi_deg) { return spindle.ball_mm(ball, phi_deg); }, noise);
}

}  // namespace trueaxis::sim
