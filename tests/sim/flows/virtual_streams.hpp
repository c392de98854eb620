// The virtual machines measured and streamed into a module in process, for the
// Monte-Carlo tests (test_gates_mc.cpp, test_check_mc.cpp): M3's ball at the
// gates' plan, a gantry samples group name as 9821's (T, Q, D) (gantry_map.hpp
// convention 3) and one gantry measurement as a session.
#pragma once

#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>
#include <vector>

#include "module_rig.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"

namespace trueaxis::test {

// A samples group name as (T, Q, D) (gantry_map.hpp convention 3).
inline void group_of(const std::string& name, double& t, double& q, double& d) {
  namespace g = trueaxis::macros::gantry;
  t = 0.0;
  d = 0.0;
  if (name == "bed") {
    q = static_cast<double>(g::GroupKind::kBed);
  } else if (name == "side_1") {
    q = static_cast<double>(g::GroupKind::kSide1);
  } else if (name == "side_2") {
    q = static_cast<double>(g::GroupKind::kSide2);
  } else if (name.rfind("gantry_", 0) == 0) {
    q = static_cast<double>(g::GroupKind::kGantryPass);
    d = std::atoi(name.c_str() + 7);
  } else {
    const std::size_t us = name.find('_');
    t = std::atoi(name.substr(2, us - 2).c_str());
    const std::string rest = name.substr(us + 1);
    if (rest == "c") {
      q = static_cast<double>(g::GroupKind::kCCircle);
    } else if (rest == "a") {
      q = static_cast<double>(g::GroupKind::kACircle);
    } else {
      q = static_cast<double>(static_cast<int>(g::GroupKind::kXPass) + (rest[0] - 'x'));
      d = std::atoi(rest.c_str() + 2);
    }
  }
}


// 9830, then the ball (1 um per axis, #601's default) at 7 A poses (-90 .. 90
// every 30) x 36 C (every 10 deg) into 9831: M3's session of one measurement.
inline void stream_rigidity(ModuleRig& rig, const sim::CradleMachine& machine, sim::SimRng& rng) {
  namespace v = trueaxis::macros::var;
  const sim::CalibrationBall ball;
  REQUIRE(rig.run(9830) == 2.0);
  for (const double a : {-90.0, -60.0, -30.0, 0.0, 30.0, 60.0, 90.0}) {
    for (int k = 0; k < 36; ++k) {
      const double c = 10.0 * k;
      const core::Vec3 p = ball.measure(machine.machine_T_table(a, c), rng);
      const double ac[3] = {a, 0.0, c};
      const double xyz[3] = {p.x(), p.y(), p.z()};
      REQUIRE(rig.module().write(v::kArgA, 3, ac) == trueaxis::macros::AccessFault::kNone);
      REQUIRE(rig.module().write(v::kArgX, 3, xyz) == trueaxis::macros::AccessFault::kNone);
      REQUIRE(rig.run(9831) == 2.0);
    }
  }
}

// 9820, every sample into 9821, then each sub-machine's 9822 (its swing and
// nominal tool direction in the tracker frame): the session of one measurement.
// With `drawing` (a nominal origin's error, mm, global frame), each 9822 also
// gives the nominal origin the machine's drawing would: the truth plus it.
inline void stream_gantry(ModuleRig& rig, const sim::GantryMachine& machine, const sim::LaserTracker& tracker,
                          const std::vector<sim::TrackerSample>& samples, const core::Vec3* drawing = nullptr) {
  namespace v = trueaxis::macros::var;
  REQUIRE(rig.run(9820) == 2.0);
  for (const sim::TrackerSample& s : samples) {
    double t = 0.0, q = 0.0, d = 0.0;
    group_of(s.group, t, q, d);
    rig.set(v::kArgT, t);
    rig.set(v::kArgQ, q);
    rig.set(v::kArgD, d);
    const double xyz[3] = {s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
    REQUIRE(rig.module().write(v::kArgX, 3, xyz) == trueaxis::macros::AccessFault::kNone);
    REQUIRE(rig.run(9821) == 2.0);
  }
  for (std::size_t i = 0; i < machine.sub_machine_count(); ++i) {
    const sim::SubMachineConfig& c = machine.config().sub_machines[i];
    rig.set(v::kArgT, c.id);
    rig.set(v::kArgD, c.swing_mm);
    rig.set3(v::kArgI, tracker.tracker_T_machine().rotation * c.tool_nominal);
    if (drawing != nullptr) {
      rig.set(v::kArgQ, 1.0);
      rig.set3(v::kArgX, machine.truth(i).origin_global_mm + *drawing);
    }
    REQUIRE(rig.run(9822) == 2.0);
  }
}

}  // namespace trueaxis::test
