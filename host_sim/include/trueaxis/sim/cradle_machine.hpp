// A virtual cradle (trunnion) table carrying a workpiece with one inclined flat
// face, and a virtual touch probe: the ground truth the host simulator measures.
//
// Conventions
//  1. Machine: A tilts the cradle about machine X, C turns the table about its own
//     Z. A point fixed to the table, written p_table with the table at zero, is at
//         p_machine = Rx(A) Rz(C) p_table
//     with both rotations about the machine origin and both signs +1 (commanded =
//     physical, right-handed), i.e. the module's configuration a_sign = c_sign = +1.
//  2. Face: a plane through (0, 0, height_mm) with the table at zero; its outward
//     (spindle-side) unit normal there is
//         n_table = (sin t cos az, sin t sin az, cos t),  t = tilt_deg, az = azimuth_deg,
//     so the face falls towards azimuth az (measured from +X towards +Y) and
//     rises towards az + 180 deg. 0 <= tilt_deg < 90.
//  3. Probe: comes down along -Z at machine (x, y) and touches the face's plane
//     (unbounded); the touch point is the plane point below (x, y), to which the
//     probe adds independent Gaussian noise of sigma_mm per coordinate. It
//     refuses, touching nothing, when the face at the present table position is
//     tilted by more than kMaxProbeTiltDeg from horizontal (too steep to touch
//     from above, or facing down).
//  4. Noise is drawn from SimRng (splitmix64 + Box-Muller): the same seed gives
//     the same sequence on every platform and standard library.
#pragma once

#include <cstdint>

#include "trueaxis/core/types.hpp"

namespace trueaxis::sim {

inline constexpr double kMaxProbeTiltDeg = 75.0;

struct FaceConfig {
  double tilt_deg = 12.5;
  double azimuth_deg = 30.0;
  double height_mm = 40.0;
};

// Deterministic normal deviates. Copyable, so a caller can draw on a copy and
// keep it only when the operation that drew succeeds.
class SimRng {
 public:
  explicit SimRng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next_u64();
  double uniform01();  // in (0, 1]
  double normal();     // mean 0, standard deviation 1

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

class CradleMachine {
 public:
  explicit CradleMachine(const FaceConfig& face);

  const FaceConfig& face() const { return face_; }

  // R_machine_table for the table at (a_deg, c_deg): convention 1.
  static core::Mat3 table_rotation(double a_deg, double c_deg);

  // The face's outward unit normal, table at zero (convention 2).
  const core::Vec3& normal_table() const { return normal_table_; }

  // The face's tilt from horizontal, degrees, with the table at (a_deg, c_deg).
  double tilt_deg_at(double a_deg, double c_deg) const;

  // The noise-free touch point (machine frame, mm) of a probe coming down at
  // machine (x_mm, y_mm) with the table at (a_deg, c_deg); false, leaving p_machine
  // untouched, when the face is too steep there (convention 3).
  bool touch(double a_deg, double c_deg, double x_mm, double y_mm, core::Vec3& p_machine) const;

 private:
  FaceConfig face_;
  core::Vec3 normal_table_;
};

}  // namespace trueaxis::sim
