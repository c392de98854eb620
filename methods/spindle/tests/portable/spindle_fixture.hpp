// A spindle whose tool axis is known in closed form, for M4's tests through
// the module: the spindle axis is exactly -Z through O1 = (0.01, -0.02, 400)
// (a = (0, 0, -1)); the tool line is offset at the gauge plane by e = (3 um, 0, 0)
// and tilted by w = (0, 15", 0) per unit depth, e normal to w
// (core/spindle_model.hpp convention 1). Gauge plane 350 mm below O1, balls
// 50 and 150 mm below it. Then (spindle_model.hpp convention 2, with
// a x x = (x_y, -x_x, 0) for x normal to a)
//     ball k at phi: o + (G + b_k) a + cos(phi) v_k + sin(phi) (v_k,y, -v_k,x, 0),  v_k = e + b_k w,
// and (spindle_correction.hpp conventions 2-3) at every angle the screw error
// is theta_e = atan(|w|) and d_e = |e| (the tool line stays in no plane
// through the ideal axis: its common perpendicular with it is R(phi) e), and
// the tool-tip error at tool length L is R(phi) (e + L w), in z exactly 0.
// The samples are exact: one revolution of each ball every 15 deg.
#pragma once

#include <cmath>
#include <cstdint>

#include "module_rig.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test::spindle {

inline constexpr double kArcsecToRad = core::kPi / (180.0 * 3600.0);
inline constexpr double kGaugeMm = 350.0;
inline constexpr double kBallMm[2] = {50.0, 150.0};
inline constexpr int kAngles = 24;  // per ball, every 15 deg
inline const core::Vec3 kO1(0.01, -0.02, 400.0);
inline const core::Vec3 kE(0.003, 0.0, 0.0);
inline const core::Vec3 kW(0.0, 15.0 * kArcsecToRad, 0.0);
// The nine parameters (o_x, o_y, o_z, a_x, a_y, e_x, e_y, w_x, w_y), Q = 1..9 of 9845.
inline const double kParams[9] = {0.01, -0.02, 400.0, 0.0, 0.0, 0.003, 0.0, 0.0, 15.0 * kArcsecToRad};

// R(phi) x for x normal to a = -Z.
inline core::Vec3 turn(double phi_deg, const core::Vec3& x) {
  const double phi = core::deg_to_rad(phi_deg);
  return std::cos(phi) * x + std::sin(phi) * core::Vec3(x.y(), -x.x(), 0.0);
}

// The centre of ball 1 or 2 at spindle angle phi (deg).
inline core::Vec3 ball(int k, double phi_deg) {
  const double b = kBallMm[k - 1];
  return kO1 + (kGaugeMm + b) * core::Vec3(0.0, 0.0, -1.0) + turn(phi_deg, kE + b * kW);
}

inline double theta_e_arcsec() { return std::atan(kW.norm()) / kArcsecToRad; }
inline double d_e_mm() { return kE.norm(); }
inline core::Vec3 tip_error_mm(double phi_deg, double tool_mm) { return turn(phi_deg, kE + tool_mm * kW); }

// 9841 for one sample: its #9001.
inline double add(ModuleRig& rig, double phi_deg, double k, const core::Vec3& p) {
  rig.set(macros::var::kArgS, phi_deg);
  rig.set(macros::var::kArgT, k);
  rig.set3(macros::var::kArgX, p);
  return rig.run(9841);
}

// 9840, then both balls at the first `angles` of the revolution's kAngles angles.
inline void stream(ModuleRig& rig, int angles = kAngles) {
  rig.done(9840);
  for (int k = 1; k <= 2; ++k) {
    for (int i = 0; i < angles; ++i) {
      const double phi = 360.0 / kAngles * i;
      add(rig, phi, k, ball(k, phi));
    }
  }
}

// 9842's arguments: geometry, R.
inline void arguments(ModuleRig& rig, double r, double gauge = kGaugeMm, double b1 = kBallMm[0],
                      double b2 = kBallMm[1]) {
  rig.set(macros::var::kArgR, r);
  rig.set(macros::var::kArgD, gauge);
  rig.set(macros::var::kArgU, b1);
  rig.set(macros::var::kArgV, b2);
}

// 9842 with R = 1 (unlocked first) or R = 0: its #9001.
inline double build(ModuleRig& rig, bool store) {
  if (store) rig.unlock();
  arguments(rig, store ? 1.0 : 0.0);
  return rig.run(9842);
}

// 9843 at (S, Z): its #9001.
inline double correction(ModuleRig& rig, double phi_deg, double tool_mm) {
  rig.set(macros::var::kArgS, phi_deg);
  rig.set(macros::var::kArgZ, tool_mm);
  return rig.run(9843);
}

// The fixture streamed and stored.
inline void stored(ModuleRig& rig, Where where = TA_HERE) {
  stream(rig);
  if (build(rig, true) != kDone) {
    Line what;
    what.text("the spindle fixture did not build: error ").integer(static_cast<int>(rig.code()));
    rig_failure(where, what);
  }
}

}  // namespace trueaxis::test::spindle
