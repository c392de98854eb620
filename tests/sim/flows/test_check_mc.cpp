// The check (issue "The calibration lifecycle", check.hpp): a machine
// calibrated once and then measured again. An unchanged virtual machine must
// pass in >= 99 % of Monte-Carlo checks; a drift injected into the simulator's
// truth must fail in >= 99 %. Each run calibrates anew (stored, R = 1) and then
// checks a second measurement (R = 0, then the check macro), so that both the
// stored table's noise and the check's are in every run, as on a machine.
// TRUEAXIS_FIGURES=1 prints the verdict counts and the worst ratios (the
// table of docs/GUIDE.md "Check").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "virtual_streams.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/level/level_map.hpp"
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

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

// The verdicts of a series of checks, and the figure that decided the worst.
struct Verdicts {
  int runs = 0;
  int count[3] = {0, 0, 0};  // pass, warn, fail
  double ratio_min = 1e300;
  double ratio_max = 0.0;
  std::vector<double> ratios;
  void add(Rig& rig) {
    ratios.push_back(rig.get(v::kCheckWorstRatio));
    ++runs;
    const int verdict = static_cast<int>(rig.get(v::kCheckVerdict));
    REQUIRE((verdict >= 0 && verdict <= 2));
    ++count[verdict];
    ratio_min = std::min(ratio_min, rig.get(v::kCheckWorstRatio));
    ratio_max = std::max(ratio_max, rig.get(v::kCheckWorstRatio));
  }
  void print(const char* what) const {
    if (!print_figures()) return;
    std::printf("%s: %d checks: %d pass, %d warn, %d fail; worst ratio (|d| + 2 sigma) / tolerance %.3f .. %.3f\n",
                what, runs, count[0], count[1], count[2], ratio_min, ratio_max);
    std::vector<double> r = ratios;
    std::sort(r.begin(), r.end());
    std::printf("  worst ratio 1 %% %.3f, 50 %% %.3f, 99 %% %.3f\n", r[r.size() / 100], r[r.size() / 2],
                r[r.size() * 99 / 100]);
  }
};

// A vector figure's sigma (along the difference) against the spread of its
// length where a drift makes the difference's direction steady: the reported
// sigma's RMS over the observed standard deviation.
struct Spread {
  int n = 0;
  double sum = 0.0, sum2 = 0.0, sigma2 = 0.0;
  void add(Rig& rig) {
    const double d = rig.get(v::kCheckFigureDeviation);
    ++n;
    sum += d;
    sum2 += d * d;
    sigma2 += rig.get(v::kCheckFigureSigma) * rig.get(v::kCheckFigureSigma);
  }
  double honest() const {
    const double mean = sum / n;
    return std::sqrt(sigma2 / n) / std::sqrt((sum2 - n * mean * mean) / (n - 1));
  }
};

// The end of a method's series: the counts (printed with TRUEAXIS_FIGURES=1),
// the deviation sigma's honesty (x1.5 of the observed spread), >= 99 % pass
// unchanged and >= 99 % fail drifted.
void conclude(const Verdicts& same, const char* same_what, const Verdicts& moved, const char* moved_what,
              const char* figure, double honest) {
  same.print(same_what);
  moved.print(moved_what);
  if (print_figures()) std::printf("  %s deviation: sigma / observed RMS %.3f\n", figure, honest);
  CHECK(honest > 1.0 / 1.5);
  CHECK(honest < 1.5);
  CHECK(same.count[0] >= same.runs * 99 / 100);
  CHECK(moved.count[2] >= moved.runs * 99 / 100);
}

constexpr int kRigidityRuns = 1000;

}  // namespace

TEST_CASE("M3 check: an unchanged cradle passes, 20\" more rigidity at one pose fails, each in >= 99 %",
          "[check][mc]") {
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  sim::CradleErrors drifted_errors = sim::realistic_errors();
  drifted_errors.local_a_deg = 60.0;
  drifted_errors.local_arcsec = 20.0;
  const sim::CradleMachine drifted(sim::FaceConfig{}, drifted_errors);
  REQUIRE((drifted.rotation_vector_rad(60.0, 0.0) - machine.rotation_vector_rad(60.0, 0.0)).norm() * 206264.8 ==
          Approx(20.0).epsilon(0.01));
  Rig rig;
  Verdicts same;
  Verdicts moved;
  double d2 = 0.0;  // the unchanged A positioning errors' deviations, squared, and their sigmas
  double s2 = 0.0;
  Spread rotation;  // the drifted pose 7's rotation_change
  for (int run = 0; run < kRigidityRuns; ++run) {
    sim::SimRng rng(static_cast<std::uint64_t>(52000 + run));
    trueaxis::test::stream_rigidity(rig, machine, rng);
    REQUIRE(rig.unlock());
    rig.set(v::kArgR, 1.0);
    rig.set(v::kArgM, 1.0);
    REQUIRE(rig.done(9832));
    REQUIRE(rig.lock());
    for (const sim::CradleMachine* now : {&machine, &drifted}) {
      trueaxis::test::stream_rigidity(rig, *now, rng);
      REQUIRE(rig.done(9832));
      REQUIRE(rig.done(9836));
      REQUIRE(rig.get(v::kCheckFigures) == 12.0);  // 6 poses but the reference, 2 figures each
      (now == &machine ? same : moved).add(rig);
      if (now == &drifted) {  // pose 7 (A = 90): the rotation the drift moves most, steadily
        rig.set(v::kArgQ, 11.0);
        REQUIRE(rig.done(9836));
        REQUIRE((rig.get(v::kCheckFigureKind) == 1.0 && rig.get(v::kCheckFigureItem) == 7.0));
        rotation.add(rig);
      }
      for (int q = 2; now == &machine && q <= 12; q += 2) {
        rig.set(v::kArgQ, q);
        REQUIRE(rig.done(9836));
        REQUIRE(rig.get(v::kCheckFigureKind) == 2.0);
        d2 += rig.get(v::kCheckFigureDeviation) * rig.get(v::kCheckFigureDeviation);
        s2 += rig.get(v::kCheckFigureSigma) * rig.get(v::kCheckFigureSigma);
      }
    }
  }
  conclude(same, "M3 unchanged", moved, "M3 20\" at A = 60", "A positioning error", std::sqrt(s2 / d2));
  if (print_figures()) std::printf("  rotation_change at A = 90, drifted: sigma / observed spread %.3f\n", rotation.honest());
  CHECK(rotation.honest() > 1.0 / 1.5);
  CHECK(rotation.honest() < 1.5);
}

namespace {

constexpr int kSpindleRuns = 1000;

// One analyser session of `spindle` into the session and identified (R = 0 unless `store`).
void measure_spindle(Rig& rig, const sim::VirtualSpindle& spindle, std::uint64_t seed, bool store) {
  const core::SpindleGeometry g = spindle.geometry();
  sim::AnalyserConfig ac;  // 15 nm probes, 50 nm form error: the simulator's
  ac.form_seed = 500 + seed;
  sim::SimRng noise(90001 + seed);
  const auto samples = sim::measure_spindle(sim::VirtualAnalyser(ac), spindle, noise);
  REQUIRE(rig.run(9840) == 2.0);
  for (const core::SpindleSample& s : samples) {
    rig.set(v::kArgS, s.phi_deg);
    rig.set(v::kArgT, s.ball);
    const double xyz[3] = {s.p_mm.x(), s.p_mm.y(), s.p_mm.z()};
    REQUIRE(rig.module().write(v::kArgX, 3, xyz) == F::kNone);
    REQUIRE(rig.run(9841) == 2.0);
  }
  if (store) {
    REQUIRE(rig.unlock());
    rig.set(v::kArgR, 1.0);
    rig.set(v::kArgM, 1.0);
  }
  rig.set(v::kArgD, g.gauge_mm);
  rig.set(v::kArgU, g.ball_mm[0]);
  rig.set(v::kArgV, g.ball_mm[1]);
  REQUIRE(rig.done(9842));
  if (store) REQUIRE(rig.lock());
}

}  // namespace

TEST_CASE("M4 check: an unchanged spindle passes, 10\" more tool tilt fails, each in >= 99 %", "[check][mc]") {
  const sim::VirtualSpindle spindle(sim::realistic_spindle());
  sim::SpindleConfig tilted_config = sim::realistic_spindle();
  tilted_config.tilt_x_arcsec += 10.0;
  const sim::VirtualSpindle tilted(tilted_config);
  Rig rig;
  Verdicts same;
  Verdicts moved;
  double d2 = 0.0;  // the unchanged a_x's deviations, squared, and their sigmas
  double s2 = 0.0;
  for (int run = 0; run < kSpindleRuns; ++run) {
    const std::uint64_t seed = 3 * static_cast<std::uint64_t>(run);
    measure_spindle(rig, spindle, seed, true);
    for (const sim::VirtualSpindle* now : {&spindle, &tilted}) {
      measure_spindle(rig, *now, seed + (now == &spindle ? 1 : 2), false);
      REQUIRE(rig.done(9846));
      REQUIRE(rig.get(v::kCheckFigures) == 6.0);
      (now == &spindle ? same : moved).add(rig);
      if (now != &spindle) continue;
      rig.set(v::kArgQ, 1.0);
      REQUIRE(rig.done(9846));
      d2 += rig.get(v::kCheckFigureDeviation) * rig.get(v::kCheckFigureDeviation);
      s2 += rig.get(v::kCheckFigureSigma) * rig.get(v::kCheckFigureSigma);
    }
  }
  conclude(same, "M4 unchanged", moved, "M4 10\" more tilt", "a_x", std::sqrt(s2 / d2));
}

namespace {

// One gantry session of `machine` through `tracker` into the module and
// computed (R = 0 unless `store`).
void measure_gantry(Rig& rig, const sim::GantryMachine& machine, const sim::LaserTracker& tracker,
                    const sim::GantryPlan& plan, sim::SimRng& rng, bool store) {
  trueaxis::test::stream_gantry(rig, machine, tracker, sim::measure_gantry(machine, tracker, plan, rng));
  if (store) {
    REQUIRE(rig.unlock());
    rig.set(v::kArgR, 1.0);
    rig.set(v::kArgM, 1.0);
  }
  REQUIRE(rig.done(9823));
  if (store) REQUIRE(rig.lock());
}

int gantry_runs() {
  const char* runs = std::getenv("TRUEAXIS_CHECK_RUNS");
  return runs != nullptr ? std::atoi(runs) : 1000;
}

}  // namespace

// Not yet the issue's >= 99 % / >= 99 %: with the simulator's plan and an
// AT960-class tracker at 2.5 m, an origin's deviation has a 1-sigma of about
// 15 um per direction (the global frame measured again dominates), so a 50 um
// move fails in about two thirds of the checks at a 50 um tolerance, and an
// unchanged gantry in one of ten (the planner, issue item 4, is to find a
// plan that resolves it). What this test holds: with a quiet tracker the
// check is exact (#706 at 30 um: unchanged passes, 50 um moved fails, every
// time); with the realistic one the origin deviation's sigma is honest
// (x1.5) and, at the default #706 of 0.1 mm that the plan resolves, an
// unchanged gantry passes in >= 99 % and a 0.2 mm move fails in >= 99 %.
TEST_CASE("M2 check: exact on a quiet tracker; honest sigmas and no false alarm on a realistic one", "[check][mc]") {
  const sim::GantryConfig config = sim::realistic_gantry();
  const sim::GantryMachine machine(config);
  const sim::GantryPlan plan;
  const auto series = [&](bool noise, int runs, double move_mm, double tolerance_mm, Verdicts& same, Verdicts& moved,
                          double& honest, Spread& origin) {
    sim::GantryConfig moved_config = config;
    moved_config.sub_machines[1].wrist_mm += Vec3(move_mm, 0.0, 0.0);
    const sim::GantryMachine moved_machine(moved_config);
    const sim::LaserTracker tracker = sim::place_tracker(machine, sim::TrackerPlacement{}, sim::TrackerSpec{}, noise);
    Rig rig;
    REQUIRE(rig.unlock());
    rig.set(v::kGantryCheckOrigin, tolerance_mm);
    REQUIRE(rig.lock());
    double d2 = 0.0;  // the unchanged origins' deviations, squared, and 3 sigma^2 (a 3-D length)
    double s2 = 0.0;
    for (int run = 0; run < runs; ++run) {
      sim::SimRng rng(static_cast<std::uint64_t>(61000 + run));
      measure_gantry(rig, machine, tracker, plan, rng, true);
      for (const sim::GantryMachine* now : {&machine, &moved_machine}) {
        measure_gantry(rig, *now, tracker, plan, rng, false);
        REQUIRE(rig.done(9827));
        REQUIRE(rig.get(v::kCheckFigures) == 8.0);  // 4 sub-machines, 2 figures each
        (now == &machine ? same : moved).add(rig);
        for (int q = 1; now == &machine && q <= 8; q += 2) {
          rig.set(v::kArgQ, q);
          REQUIRE(rig.done(9827));
          REQUIRE(rig.get(v::kCheckFigureKind) == 1.0);
          d2 += rig.get(v::kCheckFigureDeviation) * rig.get(v::kCheckFigureDeviation);
          s2 += 3.0 * rig.get(v::kCheckFigureSigma) * rig.get(v::kCheckFigureSigma);
        }
        if (now == &moved_machine) {  // the moved origin (sub-machine 2, figure 3): its length's spread
          rig.set(v::kArgQ, 3.0);
          REQUIRE(rig.done(9827));
          REQUIRE((rig.get(v::kCheckFigureKind) == 1.0 && rig.get(v::kCheckFigureItem) == 2.0));
          origin.add(rig);
        }
        if (now == &moved_machine && !noise) {  // the moved origin is the worst figure, 50 um
          REQUIRE(rig.get(v::kCheckFigureItem) == 2.0);
          CHECK(rig.get(v::kCheckFigureDeviation) == Approx(move_mm).margin(1e-5));
        }
      }
    }
    honest = std::sqrt(s2 / d2);
  };
  Verdicts quiet_same, quiet_moved;
  double quiet_honest = 0.0;
  Spread quiet_origin;
  series(false, 2, 0.050, 0.030, quiet_same, quiet_moved, quiet_honest, quiet_origin);
  CHECK(quiet_same.count[0] == 2);
  CHECK(quiet_moved.count[2] == 2);

  const int runs = gantry_runs();
  Verdicts same, moved;
  double honest = 0.0;
  Spread origin;  // the moved origin's length
  series(true, runs, 0.2, m::gantry::kDefaultCheckOriginMm, same, moved, honest, origin);
  conclude(same, "M2 unchanged", moved, "M2 sub-machine 2 moved 0.2 mm", "origin", honest);
  if (print_figures()) std::printf("  origin_change moved 0.2 mm: sigma / observed spread %.3f\n", origin.honest());
  CHECK(origin.honest() > 1.0 / 1.5);
  CHECK(origin.honest() < 1.5);
}

TEST_CASE("M1 check: a face probed level again passes, one left 30\" off fails, each in >= 99 %", "[check][mc]") {
  // Nine touches over a 100 mm square at the table's zero, the probe's noise
  // #506 (0.5 um, 1 sigma) on each: the re-probe after leveling (9812, 9813, 9816).
  constexpr int kRuns = 1000;
  const double sigma_mm = trueaxis::macros::level::kDefaults.probe_sigma_mm;
  Rig rig;
  Verdicts same;
  Verdicts moved;
  double d2 = 0.0;  // the 30" face's deviations from 30", squared, and their sigmas
  double s2 = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    sim::SimRng rng(static_cast<std::uint64_t>(71000 + run));
    for (const double tilt_arcsec : {0.0, 30.0}) {
      REQUIRE(rig.done(9812));
      const double slope = std::tan(tilt_arcsec / 206264.80624709636);
      for (int i = 0; i < 9; ++i) {
        const double x = 50.0 * (i % 3);
        const double y = 50.0 * (i / 3);
        rig.set3(v::kArgX, Vec3(x + sigma_mm * rng.normal(), y + sigma_mm * rng.normal(),
                                40.0 + slope * x + sigma_mm * rng.normal()));
        REQUIRE(rig.done(9813));
      }
      REQUIRE(rig.done(9816));
      (tilt_arcsec == 0.0 ? same : moved).add(rig);
      if (tilt_arcsec == 30.0) {
        d2 += (rig.get(v::kCheckFigureDeviation) - 30.0) * (rig.get(v::kCheckFigureDeviation) - 30.0);
        s2 += rig.get(v::kCheckFigureSigma) * rig.get(v::kCheckFigureSigma);
      }
    }
  }
  // The 30" face's tilt is a length along a steady direction: its spread is the sigma's.
  conclude(same, "M1 level", moved, "M1 30\" off", "tilt (30\" face)", std::sqrt(s2 / d2));
}
