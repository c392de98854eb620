#include "trueaxis/sim/instruments/touch_probe.hpp"

#include <cmath>

namespace trueaxis::sim {

bool TouchProbe::touch(const Plane& face_machine, double x_mm, double y_mm, core::Vec3& p_machine) {
  const core::Vec3& n = face_machine.normal;
  const core::Vec3& o = face_machine.point_mm;
  // atan2 of the horizontal and vertical parts stays accurate near 0, where acos does not.
  if (core::rad_to_deg(std::atan2(std::hypot(n.x(), n.y()), n.z())) > kMaxProbeTiltDeg) return false;
  // The plane n . (p - o) = 0 solved for z at the probe's (x, y).
  const double z_mm = o.z() - (n.x() * (x_mm - o.x()) + n.y() * (y_mm - o.y())) / n.z();
  p_machine = core::Vec3(x_mm, y_mm, z_mm);
  return true;
}

core::Vec3 TouchProbe::read(const core::Vec3& touch_machine, SimRng& rng) const {
  core::Vec3 p = touch_machine;
  for (int i = 0; i < 3; ++i) p[i] += sigma_mm * rng.normal();
  return p;
}

}  // namespace trueaxis::sim
