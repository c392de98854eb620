// A gantry whose frames are known in closed form, for M2's tests through the
// module (the construction of tests/target/bench_gantry.cpp, small and exact):
// the bed is z = 0, side_1 the plane x = 0, side_2 y = 0, the gantry runs
// along +X, so the global frame is the tracker's. Sub-machine N has ideal
// axes: its wrist centre at W_N = (1000 N, 1500, 1800), its C axis vertical
// and its A axis along X through W_N, the tool pointing down (-Z) and a swing
// of 300 mm, so its origin is O_N = W_N - (0, 0, 300), its axes the global
// ones, and a global point p is p - O_N in its frame (gantry_frames.hpp).
// Every group has a few more points than its fit needs, without noise.
//
// A Variation breaks one thing, for the refusals of 9823.
#pragma once

#include <cmath>
#include <cstdint>

#include "module_rig.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test::gantry {

inline constexpr double kSwingMm = 300.0;
inline constexpr int kSubMachines = 2;

// Group kinds, Q of 9821 (gantry_map.hpp convention 3).
enum Kind : int { kBed = 1, kSide1, kSide2, kGantryPass, kXPass, kYPass, kZPass, kCCircle, kACircle };

inline core::Vec3 wrist(int id) { return core::Vec3(1000.0 * id, 1500.0, 1800.0); }
inline core::Vec3 origin(int id) { return wrist(id) - core::Vec3(0.0, 0.0, kSwingMm); }

struct Variation {
  int bed_points = 8;
  int c_points = 6;         // of sub-machine 1
  int a_points = 6;         // of sub-machine 1 (0: none)
  bool a_about_c = false;   // sub-machine 1's A circle turns about its C axis
  int x_passes = 1;         // of sub-machine 1
  int reversed_x = 0;       // of sub-machine 1's x passes, measured backwards
  bool parameters_1 = true;  // 9822 for sub-machine 1
  double turn_deg = 0.0;     // sub-machine 1's points turned about the vertical through W_1: its axes turn by it
  double c_bump_mm = 0.0;    // sub-machine 1's first C point moved out from the C axis by this
};

// 9821 for one point: its #9001.
inline double add(ModuleRig& rig, int t, int q, int d, const core::Vec3& p) {
  rig.set(macros::var::kArgT, t);
  rig.set(macros::var::kArgQ, q);
  rig.set(macros::var::kArgD, d);
  rig.set3(macros::var::kArgX, p);
  return rig.run(9821);
}

// 9822 for sub-machine `id`: its #9001.
inline double parameters(ModuleRig& rig, int id, double swing_mm, const core::Vec3& tool) {
  rig.set(macros::var::kArgT, id);
  rig.set(macros::var::kArgD, swing_mm);
  rig.set3(macros::var::kArgI, tool);
  return rig.run(9822);
}

// 9825 for sub-machine `id`: its #9001.
inline double convert(ModuleRig& rig, double id, const core::Vec3& p) {
  rig.set(macros::var::kArgT, id);
  rig.set3(macros::var::kArgX, p);
  return rig.run(9825);
}

namespace detail {
inline void must(ModuleRig& rig, double status, Where where) {
  if (status == kDone) return;
  Line what;
  what.text("the gantry fixture: a macro failed, error ").integer(static_cast<int>(rig.code()));
  rig_failure(where, what);
}
}  // namespace detail

inline void stream_machine(ModuleRig& rig, const Variation& v = {}, Where where = TA_HERE) {
  for (int i = 0; i < v.bed_points; ++i) {
    const double x = i % 2 == 0 ? 100.0 + 50.0 * i : 5000.0 - 40.0 * i;
    const double y = i < 4 ? 200.0 + 30.0 * i : 2500.0 - 20.0 * i;
    detail::must(rig, add(rig, 0, kBed, 0, core::Vec3(x, y, 0.0)), where);
  }
  for (int i = 0; i < 6; ++i) {
    const core::Vec3 p(0.0, 100.0 + 150.0 * (i % 3), -50.0 - 80.0 * (i / 3));
    detail::must(rig, add(rig, 0, kSide1, 0, p), where);
  }
  for (int i = 0; i < 6; ++i) {
    const core::Vec3 p(100.0 + 150.0 * (i % 3), 0.0, -50.0 - 80.0 * (i / 3));
    detail::must(rig, add(rig, 0, kSide2, 0, p), where);
  }
  for (int i = 0; i < 4; ++i) {
    detail::must(rig, add(rig, 0, kGantryPass, 1, core::Vec3(200.0 + 1000.0 * i, 1500.0, 2300.0)), where);
  }
}

inline void stream_sub(ModuleRig& rig, int id, const Variation& v = {}, Where where = TA_HERE) {
  const core::Vec3 w = wrist(id);
  const bool first = id == 1;
  const double turn = first ? core::deg_to_rad(v.turn_deg) : 0.0;
  const auto turned = [&](const core::Vec3& p) {
    const core::Vec3 d = p - w;
    return core::Vec3(w.x() + std::cos(turn) * d.x() - std::sin(turn) * d.y(),
                      w.y() + std::sin(turn) * d.x() + std::cos(turn) * d.y(), p.z());
  };
  const double strokes[3] = {800.0, 600.0, 300.0};  // x longest: the master axis
  const int kinds[3] = {kXPass, kYPass, kZPass};
  for (int axis = 0; axis < 3; ++axis) {
    const int passes = first && axis == 0 ? v.x_passes : 1;
    for (int k = 1; k <= passes; ++k) {
      const bool backwards = first && axis == 0 && k <= v.reversed_x;
      for (int i = 0; i < 4; ++i) {
        const double s = -0.5 * strokes[axis] + strokes[axis] * (backwards ? 3 - i : i) / 3.0;
        const core::Vec3 offset = 10.0 * (k - 1) * core::Vec3::Unit((axis + 1) % 3);
        detail::must(rig, add(rig, id, kinds[axis], k, turned(w + s * core::Vec3::Unit(axis) + offset)), where);
      }
    }
  }
  const int c_points = first ? v.c_points : 6;
  for (int i = 0; i < c_points; ++i) {  // C: 0..300 deg about the vertical through W
    const double th = core::deg_to_rad(60.0 * i);
    const double radius = 120.0 + (first && i == 0 ? v.c_bump_mm : 0.0);
    detail::must(rig, add(rig, id, kCCircle, 0, turned(w + core::Vec3(radius * std::cos(th), radius * std::sin(th), -200))),
                 where);
  }
  const int a_points = first ? v.a_points : 6;
  for (int i = 0; i < a_points; ++i) {  // A: -90..90 deg about X through W
    const double th = core::deg_to_rad(-90.0 + 36.0 * i);
    const core::Vec3 p = first && v.a_about_c
                             ? w + core::Vec3(100 * std::cos(th), 100 * std::sin(th), -100)
                             : w + core::Vec3(50, 200 * std::sin(th), -200 * std::cos(th));
    detail::must(rig, add(rig, id, kACircle, 0, turned(p)), where);
  }
  if (!first || v.parameters_1) detail::must(rig, parameters(rig, id, kSwingMm, core::Vec3(0, 0, -1)), where);
}

// 9820, the machine's groups and sub-machines 1..subs.
inline void stream(ModuleRig& rig, const Variation& v = {}, int subs = kSubMachines, Where where = TA_HERE) {
  detail::must(rig, rig.run(9820), where);
  stream_machine(rig, v, where);
  for (int id = 1; id <= subs; ++id) stream_sub(rig, id, v, where);
}

// 9823 with R = 1 (unlocked first) or R = 0: its #9001.
inline double build(ModuleRig& rig, bool store) {
  if (store) rig.unlock();
  rig.set(macros::var::kArgR, store ? 1.0 : 0.0);
  return rig.run(9823);
}

// The fixture streamed and stored.
inline void stored(ModuleRig& rig, Where where = TA_HERE) {
  stream(rig, Variation{}, kSubMachines, where);
  detail::must(rig, build(rig, true), where);
}

}  // namespace trueaxis::test::gantry
