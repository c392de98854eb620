// A rigid transform a_T_b: rotation R_a_b and translation (frame b's origin in
// frame a, mm), so that p_a = R_a_b p_b + t_a (types.hpp convention 3).
#pragma once

#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

struct RigidTransform {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation_mm = Vec3::Zero();

  Vec3 point(const Vec3& p_mm) const { return rotation * p_mm + translation_mm; }
  Vec3 direction(const Vec3& v) const { return rotation * v; }
  // b_T_a.
  RigidTransform inverse() const {
    RigidTransform inv;
    inv.rotation = rotation.transpose();
    inv.translation_mm = -(inv.rotation * translation_mm);
    return inv;
  }
  // a_T_c = a_T_b * b_T_c.
  RigidTransform operator*(const RigidTransform& b_T_c) const {
    RigidTransform out;
    out.rotation = rotation * b_T_c.rotation;
    out.translation_mm = rotation * b_T_c.translation_mm + translation_mm;
    return out;
  }
};

}  // namespace trueaxis::core
