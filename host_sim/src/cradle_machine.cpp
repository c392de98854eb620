#include "trueaxis/sim/cradle_machine.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::sim {

std::uint64_t SimRng::next_u64() {
  state_ += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double SimRng::uniform01() {
  // 53 random bits, shifted by one so the result is never 0 (log below).
  return (static_cast<double>(next_u64() >> 11) + 1.0) * 0x1.0p-53;
}

double SimRng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double r = std::sqrt(-2.0 * std::log(uniform01()));
  const double phi = 2.0 * core::kPi * uniform01();
  spare_ = r * std::sin(phi);
  has_spare_ = true;
  return r * std::cos(phi);
}

CradleMachine::CradleMachine(const FaceConfig& face) : face_(face) {
  const double t = core::deg_to_rad(face.tilt_deg);
  const double az = core::deg_to_rad(face.azimuth_deg);
  normal_table_ = core::Vec3(std::sin(t) * std::cos(az), std::sin(t) * std::sin(az), std::cos(t));
}

core::Mat3 CradleMachine::table_rotation(double a_deg, double c_deg) {
  const double a = core::deg_to_rad(a_deg);
  const double c = core::deg_to_rad(c_deg);
  core::Mat3 rx;
  rx << 1.0, 0.0, 0.0,
        0.0, std::cos(a), -std::sin(a),
        0.0, std::sin(a), std::cos(a);
  core::Mat3 rz;
  rz << std::cos(c), -std::sin(c), 0.0,
        std::sin(c), std::cos(c), 0.0,
        0.0, 0.0, 1.0;
  return rx * rz;
}

double CradleMachine::tilt_deg_at(double a_deg, double c_deg) const {
  const core::Vec3 n_machine = table_rotation(a_deg, c_deg) * normal_table_;
  // atan2 of the horizontal and vertical parts stays accurate near 0, where acos does not.
  const double horizontal = std::hypot(n_machine.x(), n_machine.y());
  return core::rad_to_deg(std::atan2(horizontal, n_machine.z()));
}

bool CradleMachine::touch(double a_deg, double c_deg, double x_mm, double y_mm, core::Vec3& p_machine) const {
  if (tilt_deg_at(a_deg, c_deg) > kMaxProbeTiltDeg) return false;
  const core::Mat3 R_machine_table = table_rotation(a_deg, c_deg);
  const core::Vec3 n_machine = R_machine_table * normal_table_;
  const core::Vec3 origin_machine = R_machine_table * core::Vec3(0.0, 0.0, face_.height_mm);
  // The plane n . (p - o) = 0 solved for z at the probe's (x, y).
  const double z_mm = origin_machine.z() -
                      (n_machine.x() * (x_mm - origin_machine.x()) + n_machine.y() * (y_mm - origin_machine.y())) /
                          n_machine.z();
  p_machine = core::Vec3(x_mm, y_mm, z_mm);
  return true;
}

}  // namespace trueaxis::sim
