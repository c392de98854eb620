// What the leveling tests share: faces built in long double with their truth,
// configurations, and the residual of a solution against +Z.
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "reference.hpp"
#include "trueaxis/core/leveling.hpp"

namespace trueaxis::test::leveling {

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

// A face with outward normal n_table (table at zero), probed at `pose`: three
// well-spread points, built and rotated in long double.
struct Face {
  t::Vec3L n_table;
  std::array<Vec3, 3> machine_points;
  Vec3 n_machine;
};

inline t::Mat3L table_rotation_l(const core::TablePose& pose, const core::LevelConfig& cfg) {
  return t::rot_x_l(cfg.a_sign * t::deg_l(pose.a_deg)) * t::rot_z_l(cfg.c_sign * t::deg_l(pose.c_deg));
}

inline Face make_face(double tilt_rad, double azimuth_rad, const core::TablePose& pose, const core::LevelConfig& cfg,
               t::Rng& rng) {
  Face f;
  const long double tl = tilt_rad;
  const long double al = azimuth_rad;
  f.n_table = t::Vec3L(std::sin(tl) * std::cos(al), std::sin(tl) * std::sin(al), std::cos(tl));
  t::Vec3L u = f.n_table.cross(t::Vec3L::UnitX());
  if (u.norm() < 0.5L) u = f.n_table.cross(t::Vec3L::UnitY());
  u.normalize();
  const t::Vec3L v = f.n_table.cross(u);
  const t::Vec3L centre(rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(0, 150));
  const t::Mat3L r = table_rotation_l(pose, cfg);
  const long double angles[3] = {0.0L, 2.0L * t::kPiL / 3.0L, 4.0L * t::kPiL / 3.0L};
  const long double phase = rng.uniform(0, 6.28);
  const long double radius = rng.uniform(30, 150);
  for (int k = 0; k < 3; ++k) {
    const long double a = angles[k] + phase + rng.uniform(-0.3, 0.3);
    const t::Vec3L p = centre + radius * (std::cos(a) * u + std::sin(a) * v);
    f.machine_points[static_cast<std::size_t>(k)] = (r * p).cast<double>();
  }
  f.n_machine = (r * f.n_table).cast<double>();
  return f;
}

// Angle between +Z and the face normal turned by the commanded (C, A), long double.
inline long double residual_rad(const t::Vec3L& n_table, double c_deg, double a_deg, const core::LevelConfig& cfg) {
  const t::Vec3L turned = table_rotation_l({a_deg, c_deg}, cfg) * n_table;
  return t::angle_l(turned, t::Vec3L::UnitZ());
}

inline core::LevelInput input_for(const Face& f, const core::TablePose& pose) {
  core::LevelInput in;
  in.points_mm = f.machine_points.data();
  in.count = 3;
  in.probe_pose = pose;
  in.current_pose = pose;
  in.outward_hint_machine = f.n_machine;
  return in;
}

// Root mean square spread of `value(result)` about its value for the noise-free
// face, over `trials` probings with isotropic Gaussian noise of cfg.probe_sigma_mm.
template <typename Value>
inline double monte_carlo_sd(const Face& f, const core::LevelConfig& cfg, t::Rng& rng, int trials, Value value) {
  const auto nominal = core::level_face(input_for(f, {}), cfg);
  REQUIRE(nominal.ok());
  const double centre = value(nominal.value());
  double sum_sq = 0;
  for (int k = 0; k < trials; ++k) {
    Face noisy = f;
    for (auto& p : noisy.machine_points) p += cfg.probe_sigma_mm * Vec3(rng.normal(), rng.normal(), rng.normal());
    const auto r = core::level_face(input_for(noisy, {}), cfg);
    REQUIRE(r.ok());
    const double d = value(r.value()) - centre;
    sum_sq += d * d;
  }
  return std::sqrt(sum_sq / trials);
}

}  // namespace trueaxis::test::leveling
