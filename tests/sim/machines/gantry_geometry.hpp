// Closed forms the gantry tests check the virtual gantry with: angles between
// directions, the circle through three points, the distance from a line.
#pragma once

#include <algorithm>
#include <cmath>

#include "trueaxis/core/types.hpp"

namespace trueaxis::test::gantry {

using core::Vec3;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kRadPerArcsec = kPi / (180.0 * 3600.0);

inline double angle_arcsec(const Vec3& u, const Vec3& w) {
  return std::acos(std::max(-1.0, std::min(1.0, u.normalized().dot(w.normalized())))) / kRadPerArcsec;
}

// Centre and right-handed unit normal of the circle through p0, p1, p2 (in that order).
inline Vec3 circumcentre(const Vec3& p0, const Vec3& p1, const Vec3& p2, Vec3& normal) {
  const Vec3 u = p1 - p0;
  const Vec3 v = p2 - p0;
  const Vec3 w = u.cross(v);
  normal = w.normalized();
  return p0 + (u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u)) / (2.0 * w.squaredNorm());
}

inline double distance_to_line(const Vec3& p, const Vec3& point, const Vec3& dir) {
  const Vec3 d = p - point;
  return (d - d.dot(dir) * dir).norm();
}

}  // namespace trueaxis::test::gantry
