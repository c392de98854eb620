// The simulator's small shared math: the random generator every noisy
// instrument draws from, a rigid transform, a line and a plane. Every machine
// and every instrument includes this header, and neither includes the other:
// a machine gives poses, lines and planes; an instrument turns them into readings.
// Host only (it is used by code that allocates), but nothing here allocates.
//
// Conventions
//  1. Frames as everywhere in trueaxis: a_T_b maps points written in frame b
//     into frame a, p_a = a_T_b.rotation * p_b + a_T_b.translation_mm. Lengths mm,
//     angles radians unless a name says deg or arcsec.
//  2. SimRng is splitmix64 (Steele, Lea, Flood 2014) for the 64-bit stream and
//     Box-Muller (polar form avoided: it consumes a variable number of draws)
//     for normal deviates, so the same seed gives the same sequence on every
//     platform and standard library. Each normal() after the first of a pair
//     returns the pair's spare; a copy carries the spare with it.
//  3. A Line's direction and a Plane's normal are unit vectors; nothing here
//     checks it.
#pragma once

#include <cstdint>

#include <Eigen/Geometry>

#include "trueaxis/core/types.hpp"

namespace trueaxis::sim {

using core::kArcsecPerRad;  // firmware_core/types.hpp

inline double arcsec_to_rad(double arcsec) { return arcsec / kArcsecPerRad; }

// The rotation by angle_rad about the unit vector `axis`, right-handed.
inline core::Mat3 turn(const core::Vec3& axis, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, axis).toRotationMatrix();
}

// Convention 2. Copyable, so a caller can draw on a copy and keep it only when
// the operation that drew succeeds.
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

// A rigid transform (convention 1): p_to = rotation * p_from + translation_mm.
struct RigidTransform {
  core::Mat3 rotation = core::Mat3::Identity();
  core::Vec3 translation_mm = core::Vec3::Zero();

  core::Vec3 apply(const core::Vec3& p) const { return translation_mm + rotation * p; }
  // The transform the other way: b_T_a from a_T_b.
  RigidTransform inverse() const {
    RigidTransform back;
    back.rotation = rotation.transpose();
    back.translation_mm = -(back.rotation * translation_mm);
    return back;
  }
};

// A directed line: a point on it and a unit direction (convention 3).
struct Line {
  core::Vec3 point_mm = core::Vec3::Zero();
  core::Vec3 direction = core::Vec3::UnitZ();
};

// A plane: a point on it and its unit normal (convention 3).
struct Plane {
  core::Vec3 point_mm = core::Vec3::Zero();
  core::Vec3 normal = core::Vec3::UnitZ();
};

}  // namespace trueaxis::sim
