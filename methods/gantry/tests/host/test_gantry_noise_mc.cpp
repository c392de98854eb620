// M2's noise floors, form errors and diagnostic sigmas (issue 17, item 6) on
// the simulator, by Monte Carlo: the PERFECT virtual gantry (ideal_gantry():
// a flat bed, a straight gantry, square axes, A and C crossing at 90 deg)
// measured by the virtual AT960-class tracker (laser_tracker.hpp: 5 um radial,
// 7.5 um + 3 um/m transverse, anisotropic, which the module's isotropic
// hypot(a, b r) model of #701/#702 does not match exactly), streamed through
// the module's registers (9820..9823, defaults of #701 and #702) and reported
// (9824, 9826), kRuns times with new noise each run. Per run the noise-corrected
// bed and gantry form errors must be 0 within 3 of their own sigmas in at least
// 99 % of the runs (issue 17: "on a perfect virtual machine the corrected
// figures are 0 within 3 sigma in >= 99 % of Monte-Carlo runs"); over the runs
// each new sub-machine sigma (the A-to-C offset at its true 0, the A-to-C
// angle, the squareness of each pair of axes) must be within x1.5 of the
// observed RMS error about the truth.
// TRUEAXIS_FIGURES=1 prints the figures.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"

namespace {

namespace m = trueaxis::macros;
namespace g = trueaxis::macros::gantry;
namespace v = trueaxis::macros::var;
namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
using core::Vec3;
using F = m::AccessFault;
using trueaxis::test::kDone;

constexpr int kRuns = 2000;  // about 8 s in a Release host build (2 shared cores)
// The squareness sigmas come from each pass fit's perpendicular residuals,
// one noise per perpendicular axis (gantry_fits.hpp convention 4): the
// simulated tracker is 3 to 4 times noisier across its line of sight than
// along it. Pooled over both axes (isotropic) they were up to 1.57 x the
// observed spread here; per axis 0.97..1.03 over these 2,000 runs.

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

// A samples group name as (T, Q, D) (gantry_map.hpp convention 3).
struct Group {
  int t = 0;
  g::GroupKind q = g::GroupKind::kBed;
  int d = 0;
};

Group group_of(const std::string& name) {
  if (name == "bed") return {0, g::GroupKind::kBed, 0};
  if (name == "side_1") return {0, g::GroupKind::kSide1, 0};
  if (name == "side_2") return {0, g::GroupKind::kSide2, 0};
  if (name.rfind("gantry_", 0) == 0) return {0, g::GroupKind::kGantryPass, std::atoi(name.c_str() + 7)};
  const std::size_t us = name.find('_');
  const int t = std::atoi(name.substr(2, us - 2).c_str());
  const std::string rest = name.substr(us + 1);
  if (rest == "c") return {t, g::GroupKind::kCCircle, 0};
  if (rest == "a") return {t, g::GroupKind::kACircle, 0};
  const auto q = static_cast<g::GroupKind>(static_cast<int>(g::GroupKind::kXPass) + (rest[0] - 'x'));
  return {t, q, std::atoi(rest.c_str() + 2)};
}

struct Rig : trueaxis::test::ModuleRig {
  double add(const Group& at, const Vec3& p) {
    set(v::kArgT, at.t);
    set(v::kArgQ, static_cast<double>(at.q));
    set(v::kArgD, at.d);
    const double xyz[3] = {p.x(), p.y(), p.z()};
    REQUIRE(module().write(v::kArgX, 3, xyz) == F::kNone);
    return run(9821);
  }
};

// Running sums of an estimate's error about its truth and of its stated sigma.
struct Spread {
  double err2 = 0.0, sigma2 = 0.0;
  int n = 0;
  void add(double error, double sigma) {
    err2 += error * error;
    sigma2 += sigma * sigma;
    ++n;
  }
  // RMS stated sigma / RMS observed error.
  double ratio() const { return std::sqrt(sigma2 / err2); }
};

}  // namespace

TEST_CASE("a perfect virtual gantry: the corrected form errors are 0 within 3 sigma and the new sigmas are honest",
          "[gantry][flow][mc]") {
  const auto started = std::chrono::steady_clock::now();
  const sim::GantryMachine machine(sim::ideal_gantry());
  const sim::LaserTracker tracker = sim::place_tracker(machine, sim::TrackerPlacement{});
  const sim::GantryPlan plan;
  const std::size_t subs = machine.sub_machine_count();
  REQUIRE(subs == 4);
  Rig rig;

  int bed_within = 0, gantry_within = 0;
  double bed_z2 = 0.0, gantry_z2 = 0.0, flatness = 0.0, bed_floor = 0.0, straightness = 0.0, gantry_floor = 0.0;
  std::vector<Spread> squareness(3 * subs), offset(subs), angle(subs);
  for (int run = 0; run < kRuns; ++run) {
    sim::SimRng rng(static_cast<std::uint64_t>(7000 + run));
    const std::vector<sim::TrackerSample> samples = sim::measure_gantry(machine, tracker, plan, rng);
    REQUIRE(rig.run(9820) == kDone);
    for (const sim::TrackerSample& s : samples) REQUIRE(rig.add(group_of(s.group), s.p_mm) == kDone);
    for (std::size_t i = 0; i < subs; ++i) {
      const sim::SubMachineConfig& c = machine.config().sub_machines[i];
      rig.set(v::kArgT, c.id);
      rig.set(v::kArgD, c.swing_mm);
      rig.set3(v::kArgI, tracker.tracker_T_machine().rotation * c.tool_nominal);
      REQUIRE(rig.run(9822) == kDone);
    }
    rig.set(v::kArgR, 0.0);
    REQUIRE(rig.run(9823) == kDone);
    REQUIRE(rig.get(v::kGantryBuilt) == static_cast<double>(subs));

    rig.set(v::kArgR, 0.0);
    REQUIRE(rig.run(9824) == kDone);
    const double bed = rig.get(v::kGlobalBedFormError), bed_sigma = rig.get(v::kGlobalBedFormErrorSigma);
    const double gantry = rig.get(v::kGlobalGantryFormError), gantry_sigma = rig.get(v::kGlobalGantryFormErrorSigma);
    REQUIRE(bed_sigma > 0.0);
    REQUIRE(gantry_sigma > 0.0);
    bed_within += bed <= 3.0 * bed_sigma ? 1 : 0;
    gantry_within += gantry <= 3.0 * gantry_sigma ? 1 : 0;
    bed_z2 += (bed / bed_sigma) * (bed / bed_sigma);
    gantry_z2 += (gantry / gantry_sigma) * (gantry / gantry_sigma);
    flatness += rig.get(v::kGlobalBedFlatness);
    bed_floor += rig.get(v::kGlobalBedFlatnessFloor);
    straightness += rig.get(v::kGlobalGantryStraightness);
    gantry_floor += rig.get(v::kGlobalGantryStraightnessFloor);

    for (std::size_t i = 0; i < subs; ++i) {
      rig.set(v::kArgT, machine.config().sub_machines[i].id);
      rig.set(v::kArgR, 0.0);
      REQUIRE(rig.run(9826) == kDone);
      const Vec3 sq = rig.get3(v::kSubSquarenessXY), sq_sigma = rig.get3(v::kSubSquarenessSigmaXY);
      for (int k = 0; k < 3; ++k) squareness[3 * i + static_cast<std::size_t>(k)].add(sq(k), sq_sigma(k));
      offset[i].add(rig.get(v::kSubACOffset), rig.get(v::kSubACOffsetSigma));  // true offset 0: RMS = signed RMS
      angle[i].add(rig.get(v::kSubACAngle) - 90.0, rig.get(v::kSubACAngleSigma));
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  const double bed_rate = static_cast<double>(bed_within) / kRuns;
  const double gantry_rate = static_cast<double>(gantry_within) / kRuns;
  INFO("bed " << bed_within << " / " << kRuns << ", gantry " << gantry_within << " / " << kRuns);
  CHECK(bed_rate >= 0.99);
  CHECK(gantry_rate >= 0.99);
  const char* pair[3] = {"xy", "yz", "zx"};
  double lo = 1e9, hi = 0.0;
  for (std::size_t i = 0; i < subs; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double r = squareness[3 * i + static_cast<std::size_t>(k)].ratio();
      INFO("sub-machine " << i + 1 << " squareness " << pair[k] << ": sigma / observed " << r);
      CHECK(r >= 1.0 / 1.5);
      CHECK(r <= 1.5);
      lo = std::fmin(lo, r);
      hi = std::fmax(hi, r);
    }
    INFO("sub-machine " << i + 1 << " A-to-C offset " << offset[i].ratio() << ", angle " << angle[i].ratio());
    CHECK(offset[i].ratio() >= 1.0 / 1.5);
    CHECK(offset[i].ratio() <= 1.5);
    CHECK(angle[i].ratio() >= 1.0 / 1.5);
    CHECK(angle[i].ratio() <= 1.5);
  }
  if (print_figures()) {
    std::printf("perfect gantry, %d runs, %.1f s: bed form error within 3 sigma %.2f %%, gantry %.2f %%; "
                "RMS z bed %.2f, gantry %.2f\n",
                kRuns, seconds, 100.0 * bed_rate, 100.0 * gantry_rate, std::sqrt(bed_z2 / kRuns),
                std::sqrt(gantry_z2 / kRuns));
    std::printf("  mean flatness %.4f mm (floor %.4f), mean straightness %.4f mm (floor %.4f)\n", flatness / kRuns,
                bed_floor / kRuns, straightness / kRuns, gantry_floor / kRuns);
    std::printf("  squareness sigma / observed %.2f..%.2f\n", lo, hi);
    for (std::size_t i = 0; i < subs; ++i) {
      std::printf("  sp%zu: squareness %.2f %.2f %.2f, A-to-C offset %.2f, angle %.2f\n", i + 1,
                  squareness[3 * i].ratio(), squareness[3 * i + 1].ratio(), squareness[3 * i + 2].ratio(),
                  offset[i].ratio(), angle[i].ratio());
    }
  }
}
