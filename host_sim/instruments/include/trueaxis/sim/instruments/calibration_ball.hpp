// A calibration ball fixed to a machine's table, and the instrument that
// reports its centre (M3's samples). It knows the table only by its pose
// machine_T_table (a machine gives it), so it measures on any table.
//
// Conventions
//  1. The ball's centre is centre_table_mm in table coordinates (origin on the
//     C axis, Z along it, axes turning with C); in the machine frame it is
//     machine_T_table.apply(centre_table_mm).
//  2. A reading is that centre plus sigma_mm times a standard normal deviate per
//     coordinate, drawn from the caller's SimRng in the order x, y, z (three
//     draws, always).
#pragma once

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

inline constexpr double kDefaultBallXMm = 200.0;
inline constexpr double kDefaultBallYMm = 0.0;
inline constexpr double kDefaultBallZMm = 50.0;
inline constexpr double kDefaultBallSigmaMm = 0.001;

// By default 200 mm from the C axis, 50 mm above the table, measured to 1 um.
struct CalibrationBall {
  core::Vec3 centre_table_mm = core::Vec3(kDefaultBallXMm, kDefaultBallYMm, kDefaultBallZMm);
  double sigma_mm = kDefaultBallSigmaMm;

  // Convention 1: the true centre, machine frame.
  core::Vec3 centre_mm(const RigidTransform& machine_T_table) const { return machine_T_table.apply(centre_table_mm); }

  // Convention 2: one measurement of it.
  core::Vec3 measure(const RigidTransform& machine_T_table, SimRng& rng) const;
};

}  // namespace trueaxis::sim
