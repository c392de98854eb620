// A virtual touch probe: it comes down along -Z and touches a face, and adds
// its repeatability to the touch point. It knows the face only as a plane in
// the machine frame (a machine's face_at gives one).
//
// Conventions
//  1. The probe comes down along machine -Z at (x_mm, y_mm) and touches the
//     face's plane (unbounded): the touch point is the plane point below
//     (x_mm, y_mm). It refuses, touching nothing, when the plane's normal is
//     tilted more than kMaxProbeTiltDeg from +Z: too steep to touch from above,
//     or facing down.
//  2. A reading is the touch point plus sigma_mm times a standard normal deviate
//     per coordinate, drawn from the caller's SimRng in the order x, y, z (three
//     draws, always, even when sigma_mm is 0).
#pragma once

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

inline constexpr double kMaxProbeTiltDeg = 75.0;

struct TouchProbe {
  double sigma_mm = 0.0;  // 1 sigma per coordinate (trueaxis-sim: sim_probe_sigma, #12008)

  // Convention 1: the noise-free touch point (machine frame); false, leaving
  // p_machine untouched, when the face is too steep.
  static bool touch(const Plane& face_machine, double x_mm, double y_mm, core::Vec3& p_machine);

  // Convention 2.
  core::Vec3 read(const core::Vec3& touch_machine, SimRng& rng) const;
};

}  // namespace trueaxis::sim
