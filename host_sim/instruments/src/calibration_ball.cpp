#include "trueaxis/sim/instruments/calibration_ball.hpp"

namespace trueaxis::sim {

core::Vec3 CalibrationBall::measure(const RigidTransform& machine_T_table, SimRng& rng) const {
  core::Vec3 p = centre_mm(machine_T_table);
  for (int i = 0; i < 3; ++i) p[i] += sigma_mm * rng.normal();
  return p;
}

}  // namespace trueaxis::sim
