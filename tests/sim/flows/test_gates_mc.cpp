// The gates must not refuse good data (issue "Nothing wrong reaches the
// machine"): 1,000 calibrations of each method on its virtual machine at the
// simulator's realistic noise, streamed into one module in process and each
// stored (R = 1) over the last, so that every gate runs, the change gate
// against the previous calibration of the same machine. At most 1 in 1,000 may
// be refused; the test states the margins (the largest fit figure against its
// limit 1, the largest change against its limit). TRUEAXIS_FIGURES=1 prints
// them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "virtual_streams.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"
#include "trueaxis/sim/tools/spindle_measure.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
using core::Vec3;
using F = m::AccessFault;
using Rig = trueaxis::test::ModuleRig;

constexpr int kRuns = 1000;
constexpr int kMaxRefused = 1;  // 1 in 1,000

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

struct Tally {
  int refused = 0;
  int codes[3] = {0, 0, 0};  // the first refusals' codes
  double worst_fit = 0.0;
  double worst_change = 0.0;
  void count(double status, Rig& rig, double fit, double change) {
    if (status != 2.0) {
      if (refused < 3) codes[refused] = static_cast<int>(rig.code());
      ++refused;
      return;
    }
    worst_fit = std::max(worst_fit, fit);
    worst_change = std::max(worst_change, change);
  }
};

void report(const char* method, const Tally& t, double change_limit, const char* unit, bool fit_gate = true) {
  if (print_figures()) {
    std::printf("%s: %d of %d calibrations refused; largest fit figure %.3f (limit 1); largest change %.4g %s (limit %g)\n",
                method, t.refused, kRuns, t.worst_fit, t.worst_change, unit, change_limit);
  }
  INFO(method << ": " << t.refused << " refused (codes " << t.codes[0] << ", " << t.codes[1] << ", " << t.codes[2]
              << "); largest fit figure " << t.worst_fit << ", largest change " << t.worst_change << " " << unit);
  CHECK(t.refused <= kMaxRefused);
  if (fit_gate) CHECK(t.worst_fit > 0.0);  // the fit gate ran
  CHECK(t.worst_change > 0.0);  // and the change gate
}

}  // namespace

TEST_CASE("M3: 1,000 realistic calibrations, each stored over the last: at most 1 refused by the gates", "[gates][mc]") {
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  Rig rig;
  Tally tally;
  for (int run = 0; run < kRuns; ++run) {
    sim::SimRng rng(7000 + static_cast<std::uint64_t>(run));
    trueaxis::test::stream_rigidity(rig, machine, rng);  // 7 poses x 36 C, 1 um
    rig.set(v::kUnlock, m::kUnlockCode);
    rig.set(v::kArgR, 1.0);
    const double status = rig.run(9832);
    tally.count(status, rig, rig.get(v::kRigidityFitRatio), rig.get(v::kRigidityChange));
  }
  report("M3 rigidity", tally, m::rigidity::kDefaultMaxChangeArcsec, "arcsec");
}

TEST_CASE("M4: 1,000 realistic analyser sessions, each stored over the last: at most 1 refused by the gates", "[gates][mc]") {
  const sim::VirtualSpindle spindle(sim::realistic_spindle());
  const core::SpindleGeometry g = spindle.geometry();
  Rig rig;
  Tally tally;
  for (int run = 0; run < kRuns; ++run) {
    sim::AnalyserConfig ac;  // 15 nm probes, 50 nm form error: the simulator's
    ac.form_seed = 500 + static_cast<std::uint64_t>(run);
    sim::SimRng noise(90001 + static_cast<std::uint64_t>(run));
    const auto samples = sim::measure_spindle(sim::VirtualAnalyser(ac), spindle, noise);
    REQUIRE(rig.run(9840) == 2.0);
    for (const core::SpindleSample& s : samples) {
      rig.set(v::kArgS, s.phi_deg);
      rig.set(v::kArgT, s.ball);
      const double xyz[3] = {s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
      REQUIRE(rig.module().write(v::kArgX, 3, xyz) == F::kNone);
      REQUIRE(rig.run(9841) == 2.0);
    }
    rig.set(v::kUnlock, m::kUnlockCode);
    rig.set(v::kArgR, 1.0);
    rig.set(v::kArgD, g.gauge_mm);
    rig.set(v::kArgU, g.ball_mm[0]);
    rig.set(v::kArgV, g.ball_mm[1]);
    const double status = rig.run(9842);
    tally.count(status, rig, rig.get(v::kSpindleFitRatio), rig.get(v::kSpindleChange));
  }
  report("M4 spindle", tally, m::spindle::kDefaultMaxChangeMm, "mm");
}

TEST_CASE("M2: 1,000 realistic gantry calibrations, each stored over the last: at most 1 refused by the gates", "[gates][mc]") {
  const sim::GantryMachine machine(sim::realistic_gantry());
  const sim::LaserTracker tracker = sim::place_tracker(machine, sim::TrackerPlacement{});
  const sim::GantryPlan plan;
  // Every other run gives each sub-machine a nominal origin as a drawing
  // would: 6.5 mm off the truth, within #708's 10 mm (the nominal gate runs).
  const Vec3 drawing(4.0, -3.0, 4.0);
  Rig rig;
  Tally tally;
  double worst_angle = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    sim::SimRng rng(static_cast<std::uint64_t>(31000 + run));
    trueaxis::test::stream_gantry(rig, machine, tracker, sim::measure_gantry(machine, tracker, plan, rng),
                                  run % 2 == 0 ? &drawing : nullptr);
    rig.set(v::kUnlock, m::kUnlockCode);
    rig.set(v::kArgR, 1.0);
    const double status = rig.run(9823);
    tally.count(status, rig, rig.get(v::kGantryFitRatio), rig.get(v::kGantryOriginChange));
    if (status == 2.0) worst_angle = std::max(worst_angle, rig.get(v::kGantryAngleChange));
  }
  if (print_figures()) {
    std::printf("M2 gantry: largest axes' turn %.3g arcsec (limit %g)\n", worst_angle,
                m::gantry::kDefaultMaxAngleChangeArcsec);
  }
  CHECK(worst_angle > 0.0);
  report("M2 gantry", tally, m::gantry::kDefaultMaxOriginChangeMm, "mm");
}
