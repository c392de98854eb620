// Fixtures shared by the portable tests: a seeded generator and random faces on a
// cradle table with their ground truth, built independently of firmware_core's
// formulas (Eigen::AngleAxisd for the rotations).
//
// Conventions (firmware_core/include/trueaxis/core/leveling.hpp)
//  1. p_machine = Rx(a_sign A) Rz(c_sign C) p_table, A and C commanded, in degrees.
//  2. A face's true outward normal n_table is drawn with its tilt from +Z spread
//     log-uniformly over [kMinTilt_rad, pi/2] and any azimuth; its three points
//     span a triangle of 20..150 mm radius around a centre anywhere in a 400 mm
//     cube, probed at any table pose.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "split_mix64.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::test {

inline constexpr double kMinTilt_rad = 1e-9;

// R_machine_table for commanded angles (deg) and sign conventions, by Eigen::AngleAxisd.
inline core::Mat3 reference_table_rotation(double a_deg, double c_deg, double a_sign, double c_sign) {
  const double a_rad = a_sign * core::deg_to_rad(a_deg);
  const double c_rad = c_sign * core::deg_to_rad(c_deg);
  return (Eigen::AngleAxisd(a_rad, core::Vec3::UnitX()) * Eigen::AngleAxisd(c_rad, core::Vec3::UnitZ()))
      .toRotationMatrix();
}

// Angle (rad) by which table angles (A, C) miss turning n_table to +Z.
inline double leveling_error_rad(const core::Vec3& n_table, double a_deg, double c_deg, double a_sign,
                                 double c_sign) {
  const core::Vec3 up = reference_table_rotation(a_deg, c_deg, a_sign, c_sign) * n_table;
  return std::atan2(up.cross(core::Vec3::UnitZ()).norm(), up.z());
}

struct Face {
  core::Vec3 normal_table;     // true outward unit normal, table at zero
  double tilt_rad;             // true angle between normal_table and +Z
  core::Vec3 points_machine[3];  // probed at (probe_a_deg, probe_c_deg)
  core::Vec3 hint_machine;     // normal_table as the probe saw it
  double probe_a_deg;
  double probe_c_deg;
  double a_sign;
  double c_sign;
};

inline Face random_face(SplitMix64& rng) {
  Face f{};
  f.tilt_rad = std::exp(rng.uniform(std::log(kMinTilt_rad), std::log(0.5 * core::kPi)));
  const double azimuth = rng.uniform(0.0, 2.0 * core::kPi);
  f.normal_table = core::Vec3(std::sin(f.tilt_rad) * std::cos(azimuth), std::sin(f.tilt_rad) * std::sin(azimuth),
                              std::cos(f.tilt_rad));
  const core::Vec3 u = f.normal_table.unitOrthogonal();
  const core::Vec3 v = f.normal_table.cross(u);
  const core::Vec3 centre(rng.uniform(-200.0, 200.0), rng.uniform(-200.0, 200.0), rng.uniform(-200.0, 200.0));
  f.a_sign = rng.sign();
  f.c_sign = rng.sign();
  f.probe_a_deg = rng.uniform(-120.0, 120.0);
  f.probe_c_deg = rng.uniform(-360.0, 360.0);
  const core::Mat3 R_machine_table = reference_table_rotation(f.probe_a_deg, f.probe_c_deg, f.a_sign, f.c_sign);
  const double base = rng.uniform(0.0, 2.0 * core::kPi);
  for (int k = 0; k < 3; ++k) {
    const double angle = base + 2.0 * core::kPi / 3.0 * k + rng.uniform(-0.5, 0.5);
    const double radius = rng.uniform(20.0, 150.0);
    const core::Vec3 p_table = centre + radius * (std::cos(angle) * u + std::sin(angle) * v);
    f.points_machine[k] = R_machine_table * p_table;
  }
  f.hint_machine = R_machine_table * f.normal_table;
  return f;
}

}  // namespace trueaxis::test
