// A cradle whose every error is known in closed form, for M3's tests through
// the module: the C table turns on its own axis by a C positioning error that
// grows with A, psi(A) = kPsiPerDeg_arcsec * A, nothing else. The ball sits
// 200 mm out and 50 mm up on the table:
//     p(A, C) = Rx(A) Rz(psi(A)) Rz(C) (200, 0, 50)          (mm, deg, machine frame)
// Then (core/rigidity_table.hpp conventions 3-5) every pose's C circle is
// centred on the A axis at Rx(A) (0, 0, 50), the A axis is +X through the
// origin, theta_i = A_i, the A positioning error is 0, and the pose's rotation
// vector is
//     rv(A) = log(Rx(A) Rz(psi) Rx(A)^T) = psi(A) Rx(A) e_z = psi(A) (0, -sin A, cos A),
// its norm |psi(A)|. A ball position the ideal machine would give,
// Rx(A) Rz(C) b, is at p(A, C) on the real one (rigidity_compensation.hpp
// convention 5; any pivot on the C axis gives the same).
// The samples are exact: 5 poses A = -60..60 every 30 deg, C every 60 deg.
#pragma once

#include <cmath>
#include <cstdint>

#include "module_rig.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test::rigidity {

inline constexpr double kPsiPerDeg_arcsec = 20.0 / 60.0;  // 20" at A = 60
inline constexpr int kPoses = 5;
inline constexpr double kFirstA_deg = -60.0;
inline constexpr double kStepA_deg = 30.0;
inline constexpr int kCPositions = 6;
inline constexpr double kArcsecToRad = core::kPi / (180.0 * 3600.0);

inline double pose_a_deg(int i) { return kFirstA_deg + kStepA_deg * i; }

inline core::Vec3 rot_x(double a_deg, const core::Vec3& p) {
  const double a = core::deg_to_rad(a_deg);
  return core::Vec3(p.x(), std::cos(a) * p.y() - std::sin(a) * p.z(), std::sin(a) * p.y() + std::cos(a) * p.z());
}
inline core::Vec3 rot_z(double c_deg, const core::Vec3& p) {
  const double c = core::deg_to_rad(c_deg);
  return core::Vec3(std::cos(c) * p.x() - std::sin(c) * p.y(), std::sin(c) * p.x() + std::cos(c) * p.y(), p.z());
}

inline double psi_arcsec(double a_deg) { return kPsiPerDeg_arcsec * a_deg; }

inline const core::Vec3 kBall(200.0, 0.0, 50.0);

// The ball where the real machine puts it, and where the ideal one would.
inline core::Vec3 actual_ball(double a_deg, double c_deg) {
  return rot_x(a_deg, rot_z(psi_arcsec(a_deg) / 3600.0, rot_z(c_deg, kBall)));
}
inline core::Vec3 theory_ball(double a_deg, double c_deg) { return rot_x(a_deg, rot_z(c_deg, kBall)); }

// rv(A) in arcsec.
inline core::Vec3 rotvec_arcsec(double a_deg) {
  const double a = core::deg_to_rad(a_deg);
  return psi_arcsec(a_deg) * core::Vec3(0.0, -std::sin(a), std::cos(a));
}

// 9831 for one sample: its #9001.
inline double add(ModuleRig& rig, double a_deg, double c_deg, const core::Vec3& p) {
  rig.set(macros::var::kArgA, a_deg);
  rig.set(macros::var::kArgC, c_deg);
  rig.set3(macros::var::kArgX, p);
  return rig.run(9831);
}

// 9830, then every sample of the fixture (the first `poses` poses).
inline void stream(ModuleRig& rig, int poses = kPoses) {
  rig.done(9830);
  for (int i = 0; i < poses; ++i) {
    for (int k = 0; k < kCPositions; ++k) {
      const double c = 360.0 / kCPositions * k;
      add(rig, pose_a_deg(i), c, actual_ball(pose_a_deg(i), c));
    }
  }
}

// 9832 with R = 1 (unlocked first) or R = 0: its #9001.
inline double build(ModuleRig& rig, bool store) {
  if (store) rig.unlock();
  rig.set(macros::var::kArgR, store ? 1.0 : 0.0);
  return rig.run(9832);
}

// The fixture streamed and stored.
inline void stored(ModuleRig& rig) {
  stream(rig);
  if (build(rig, true) != kDone) {
    Line what;
    what.text("the rigidity fixture did not build: error ").integer(static_cast<int>(rig.code()));
    rig_failure(TA_HERE, what);
  }
}

}  // namespace trueaxis::test::rigidity
