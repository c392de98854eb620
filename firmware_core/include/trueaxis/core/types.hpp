// Fixed-size linear-algebra types and angle helpers used across trueaxis.
//
// Conventions
//  1. Double precision everywhere: micrometres over metres of gantry need it.
//  2. Only fixed-size Eigen types; EIGEN_NO_MALLOC is defined for every build, so a
//     heap allocation inside Eigen is a programming error caught at once.
//  3. Frames: `a_T_b` maps points written in frame b into frame a; `R_a_b` likewise
//     for rotations; `p_a` is a point written in frame a.
//  4. Angles are radians inside the math, degrees at the register interface
//     (suffixes _rad and _deg where the unit is not obvious).
#pragma once

#ifndef EIGEN_NO_MALLOC
#define EIGEN_NO_MALLOC
#endif
#ifndef EIGEN_NO_IO
#define EIGEN_NO_IO
#endif
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace trueaxis::core {

using Vec2 = Eigen::Matrix<double, 2, 1>;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;
using Mat3 = Eigen::Matrix<double, 3, 3>;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kArcsecPerRad = 180.0 * 3600.0 / kPi;

constexpr double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
constexpr double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

// True when every component is finite (neither NaN nor infinite).
template <typename Derived>
bool all_finite(const Eigen::MatrixBase<Derived>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    if (!std::isfinite(m.coeff(i))) return false;
  }
  return true;
}

// The bits of a double, and whether two doubles are the same bit for bit
// (0.0 and -0.0 differ; a NaN equals only its own bits): how a session tells
// a sample given twice from a measurement repeated (macros' duplicate_sample).
inline std::uint64_t bits_of(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
inline bool same_bits(double a, double b) { return bits_of(a) == bits_of(b); }
inline bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

// Rotation about +X by `angle_rad` (right-hand rule), as written in docs/METHODS.md M1.
inline Mat3 rot_x(double angle_rad) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  Mat3 r;
  r << 1.0, 0.0, 0.0,
       0.0, c,  -s,
       0.0, s,   c;
  return r;
}

// Rotation about +Z by `angle_rad` (right-hand rule), as written in docs/METHODS.md M1.
inline Mat3 rot_z(double angle_rad) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  Mat3 r;
  r <<  c, -s,  0.0,
        s,  c,  0.0,
       0.0, 0.0, 1.0;
  return r;
}

// Angle between two non-zero vectors in [0, pi], accurate at 0 and at pi
// (atan2 of |a x b| and a.b, not acos of a cosine).
inline double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// `angle_deg` wrapped into (-180, 180].
inline double wrap_deg_180(double angle_deg) {
  double w = std::fmod(angle_deg, 360.0);
  if (w <= -180.0) w += 360.0;
  if (w > 180.0) w -= 360.0;
  return w;
}

}  // namespace trueaxis::core
