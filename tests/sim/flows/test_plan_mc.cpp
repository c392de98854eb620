// The planner (issue "The calibration lifecycle", item 4; planner.hpp): its
// predicted 1-sigma of every output against the spread of the same outputs
// over Monte-Carlo measurements, within a factor 1.2 for three plans per
// method. The measurements are the simulator's instruments on the simulator's
// machines (the ball, the laser tracker with its radial and transverse noise,
// the spindle analyser with its form error, the touch probe), drawn in the
// order of the plan; the outputs are the method's own routine on them (the
// plan's evaluate, which calls the firmware_core routine the module runs).
// TRUEAXIS_FIGURES=1 prints each plan's valuation and the range of
// predicted / observed (the table of docs/GUIDE.md "The plan").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "module_rig.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/instruments/laser_tracker.hpp"
#include "trueaxis/sim/instruments/spindle_analyser.hpp"
#include "trueaxis/sim/instruments/touch_probe.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"
#include "trueaxis/sim/tools/gantry_plan.hpp"
#include "trueaxis/sim/tools/level_plan.hpp"
#include "trueaxis/sim/tools/planner.hpp"
#include "trueaxis/sim/tools/rigidity_plan.hpp"
#include "trueaxis/sim/tools/spindle_plan.hpp"

namespace {

namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
using core::Vec3;

constexpr int kRuns = 400;  // the spread's relative standard error 1 / sqrt(2 kRuns) = 3.5 %

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

// One measurement of the plan by the simulator's instrument, readings in the
// plan's order; `rng` null: noise-free.
using Measure = std::function<std::vector<Vec3>(sim::SimRng* rng)>;

// The plan's readings are the instrument's noise-free readings; then kRuns
// measurements, and every output's predicted sigma within x1.2 of its
// observed standard deviation.
void check_plan(const char* what, const sim::PlanModel& model, const Measure& measure, std::uint64_t seed) {
  const sim::PlanPrediction p = sim::predict_plan(model);
  INFO(what << ": " << model.description() << ": " << p.error);
  REQUIRE(p.ok);
  const std::vector<Vec3> exact = measure(nullptr);
  REQUIRE(exact.size() == model.readings().size());
  for (std::size_t i = 0; i < exact.size(); ++i) {
    INFO("reading " << i);
    REQUIRE((exact[i] - model.readings()[i].value).norm() < 1e-9);
  }
  const std::size_t n = p.outputs.size();
  std::vector<double> sum(n, 0.0), sum2(n, 0.0);
  sim::SimRng rng(seed);
  std::vector<double> out;
  std::string error;
  std::vector<std::vector<double>> runs;
  for (int run = 0; run < kRuns; ++run) {
    const std::vector<Vec3> values = measure(&rng);
    REQUIRE(model.evaluate(values, out, error));
    for (std::size_t k = 0; k < n; ++k) {
      const double d = out[k] - p.value[k];  // about the nominal: no cancellation
      sum[k] += d;
      sum2[k] += d * d;
    }
    runs.push_back(out);
  }
  // The valuation's percentile (planner.hpp contract 3): how often each judged
  // figure's noise (a group's length, about the runs' mean: the balls' fixed
  // form error moves M4's mean, not its spread) exceeds its q95, pooled.
  int judged = 0, beyond = 0;
  for (const std::vector<double>& r : runs) {
    for (std::size_t k = 0; k < n; ++k) {
      if (p.outputs[k].tolerance <= 0.0) continue;
      const int g = p.outputs[k].group;
      if (g != 0 && k > 0 && p.outputs[k - 1].group == g) continue;
      double length2 = 0.0;
      for (std::size_t m = k; m < n && (m == k || (g != 0 && p.outputs[m].group == g)); ++m) {
        const double d = r[m] - p.value[m] - sum[m] / kRuns;
        length2 += d * d;
      }
      ++judged;
      beyond += std::sqrt(length2) > p.q95[k] ? 1 : 0;
    }
  }
  const double fraction = static_cast<double>(beyond) / judged;
  INFO("judged figures beyond their q95: " << beyond << " of " << judged);
  const double se = std::sqrt(0.05 * 0.95 / judged);  // binomial, as if the figures were independent
  CHECK(fraction > 0.05 - 4.0 * se);
  CHECK(fraction < 0.05 + 4.0 * se);
  double low = 1e300, high = 0.0;
  std::string low_name, high_name;
  for (std::size_t k = 0; k < n; ++k) {
    const double mean = sum[k] / kRuns;
    const double observed = std::sqrt((sum2[k] - kRuns * mean * mean) / (kRuns - 1));
    INFO(p.outputs[k].name << ": predicted " << p.sigma[k] << ", observed " << observed << " " << p.outputs[k].unit);
    REQUIRE(observed > 0.0);
    const double ratio = p.sigma[k] / observed;
    CHECK(ratio > 1.0 / 1.2);
    CHECK(ratio < 1.2);
    if (ratio < low) low = ratio, low_name = p.outputs[k].name;
    if (ratio > high) high = ratio, high_name = p.outputs[k].name;
  }
  if (print_figures()) {
    std::printf("%s: %s\n  valuation %.3f (worst %s); predicted / observed over %zu outputs: %.3f (%s) .. %.3f (%s); "
                "beyond q95: %.1f %%\n",
                what, model.description().c_str(), p.valuation, p.outputs[p.worst].name.c_str(), n, low,
                low_name.c_str(), high, high_name.c_str(), 100.0 * fraction);
  }
}

// ---- the instruments, in each plan's order --------------------------------------------

Measure ball_measure(const sim::RigidityPlan& plan) {
  return [plan](sim::SimRng* rng) {
    const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors(), plan.pivot);
    sim::CalibrationBall ball;
    ball.centre_table_mm = plan.ball_table_mm;
    ball.sigma_mm = plan.sigma_mm;
    std::vector<Vec3> v;
    for (const auto& pose : plan.poses) {
      for (const double c : pose.second) {
        v.push_back(rng != nullptr ? ball.measure(machine.machine_T_table(pose.first, c), *rng)
                                   : ball.centre_mm(machine.machine_T_table(pose.first, c)));
      }
    }
    return v;
  };
}

Measure tracker_measure(const sim::GantryPlanSpec& spec) {
  return [spec](sim::SimRng* rng) {
    const sim::GantryMachine machine(sim::realistic_gantry());
    const sim::LaserTracker tracker = sim::place_tracker(machine, sim::gantry_tracker_placement(spec),
                                                         sim::gantry_tracker_spec(spec), rng != nullptr);
    const sim::GantryPlan plan = sim::gantry_measuring_plan(spec);
    sim::SimRng none(1);
    std::vector<Vec3> v;
    for (const sim::TrackerSample& s : sim::measure_gantry(machine, tracker, plan, rng != nullptr ? *rng : none)) {
      v.push_back(s.p_mm);
    }
    return v;
  };
}

Measure analyser_measure(const sim::SpindlePlan& plan) {
  return [plan](sim::SimRng* rng) {
    sim::SpindleConfig config = sim::realistic_spindle();
    config.ball_mm[0] = plan.ball_mm[0];
    config.ball_mm[1] = plan.ball_mm[1];
    const sim::VirtualSpindle spindle(config);
    sim::AnalyserConfig analyser;
    analyser.revolutions = plan.revolutions;
    analyser.samples_per_revolution = plan.samples_per_revolution;
    analyser.noise_sigma_mm = rng != nullptr ? plan.sigma_mm : 0.0;
    // The balls' form error (50 nm RMS, fixed) stays in the noisy runs: a
    // synchronous error the plan does not know moves the values, not the spread.
    analyser.form_rms_mm = rng != nullptr ? 50e-6 : 0.0;
    sim::SimRng none(1);
    std::vector<Vec3> v;
    for (const core::SpindleSample& s : sim::VirtualAnalyser(analyser).measure(
             [&spindle](int ball, double phi) { return spindle.ball_mm(ball, phi); }, rng != nullptr ? *rng : none)) {
      v.push_back(s.p_mm);
    }
    return v;
  };
}

Measure probe_measure(const sim::LevelPlan& plan) {
  return [plan](sim::SimRng* rng) {
    const sim::CradleMachine machine{sim::FaceConfig{}};
    const sim::TouchProbe probe{plan.sigma_mm};
    std::vector<Vec3> v;
    for (const auto& xy : plan.points) {
      Vec3 touch = Vec3::Zero();
      REQUIRE(sim::TouchProbe::touch(machine.face_at(0.0, 0.0), xy.first, xy.second, touch));
      v.push_back(rng != nullptr ? probe.read(touch, *rng) : touch);
    }
    return v;
  };
}

}  // namespace

TEST_CASE("plan rigidity: predicted sigmas within x1.2 of the Monte-Carlo spread, three plans", "[plan][mc]") {
  const sim::RigidityPlan standard = sim::rigidity_plan(-90.0, 90.0, 30.0, 10.0);
  check_plan("M3 default", *sim::rigidity_model(standard), ball_measure(standard), 31);

  sim::RigidityPlan narrow = sim::rigidity_plan(-30.0, 30.0, 30.0, 30.0);
  check_plan("M3 three poses x 12 C", *sim::rigidity_model(narrow), ball_measure(narrow), 32);

  // Uneven: a short C arc at one pose, the ball elsewhere, a noisier probe,
  // the cradle about a pivot off the origin (the A axis 80 mm below the table).
  sim::RigidityPlan uneven = sim::rigidity_plan(-60.0, 75.0, 15.0, 45.0);
  uneven.poses[2].second = {0.0, 20.0, 40.0, 60.0, 80.0};
  uneven.ball_table_mm = Vec3(150.0, 40.0, 80.0);
  uneven.sigma_mm = 0.002;
  uneven.pivot.c_point_mm = Vec3(35.0, -25.0, 0.0);
  uneven.pivot.a_offset_z_mm = -80.0;
  check_plan("M3 uneven", *sim::rigidity_model(uneven), ball_measure(uneven), 33);
}

TEST_CASE("plan gantry: predicted sigmas within x1.2 of the Monte-Carlo spread, three plans", "[plan][mc]") {
  const sim::GantryPlanSpec standard;
  check_plan("M2 default", *sim::gantry_model(standard), tracker_measure(standard), 41);

  sim::GantryPlanSpec short_arcs;
  short_arcs.passes = 2;
  short_arcs.pass_points = 10;
  short_arcs.circle_points = 12;
  short_arcs.c_to_deg = 165.0;
  short_arcs.a_from_deg = -45.0;
  short_arcs.a_to_deg = 45.0;
  check_plan("M2 short arcs", *sim::gantry_model(short_arcs), tracker_measure(short_arcs), 42);

  sim::GantryPlanSpec dense;
  dense.pad_grid = 3;
  dense.passes = 4;
  dense.circle_points = 30;  // a circle holds 30 in the module
  dense.transverse_mpe_mm = 0.025;
  check_plan("M2 dense circles, a worse tracker", *sim::gantry_model(dense), tracker_measure(dense), 43);
}

TEST_CASE("plan spindle: predicted sigmas within x1.2 of the Monte-Carlo spread, three plans", "[plan][mc]") {
  const sim::SpindlePlan standard;
  check_plan("M4 default", *sim::spindle_model(standard), analyser_measure(standard), 51);

  sim::SpindlePlan sparse;
  sparse.revolutions = 1;
  sparse.samples_per_revolution = 16;
  sparse.ball_mm[0] = 40.0;
  sparse.ball_mm[1] = 100.0;
  check_plan("M4 one revolution x 16", *sim::spindle_model(sparse), analyser_measure(sparse), 52);

  sim::SpindlePlan fine;
  fine.revolutions = 5;
  fine.samples_per_revolution = 360;
  fine.sigma_mm = 20e-6;
  check_plan("M4 5 revolutions x 360", *sim::spindle_model(fine), analyser_measure(fine), 53);
}

TEST_CASE("plan level: predicted sigmas within x1.2 of the Monte-Carlo spread, three plans", "[plan][mc]") {
  const sim::LevelPlan standard = sim::level_plan(100.0);
  check_plan("M1 default", *sim::level_model(standard), probe_measure(standard), 61);

  sim::LevelPlan small = sim::level_plan(30.0);
  small.sigma_mm = 0.001;
  check_plan("M1 30 mm triangle", *sim::level_model(small), probe_measure(small), 62);

  sim::LevelPlan five;
  five.points = {{-40.0, -40.0}, {40.0, -40.0}, {40.0, 40.0}, {-40.0, 40.0}, {0.0, 0.0}};
  check_plan("M1 five points", *sim::level_model(five), probe_measure(five), 63);
}

TEST_CASE("plan rigidity: the pivot's A offset is the ball's lever: the A positioning error's sigma scales as its "
          "C centres' radius about A",
          "[plan]") {
  const sim::RigidityPlan at_origin = sim::rigidity_plan(-90.0, 90.0, 30.0, 10.0);
  sim::RigidityPlan below = at_origin;
  below.pivot.c_point_mm = Vec3(35.0, -25.0, 0.0);
  below.pivot.a_offset_z_mm = -80.0;
  const sim::PlanPrediction p0 = sim::predict_plan(*sim::rigidity_model(at_origin));
  const sim::PlanPrediction p1 = sim::predict_plan(*sim::rigidity_model(below));
  REQUIRE(p0.ok);
  REQUIRE(p1.ok);
  REQUIRE(p0.outputs.size() == p1.outputs.size());
  std::size_t seen = 0;
  for (std::size_t i = 0; i < p0.outputs.size(); ++i) {
    if (p0.outputs[i].name.find("a_positioning_error") == std::string::npos) continue;
    INFO(p0.outputs[i].name << ": " << p0.sigma[i] << " at the origin, " << p1.sigma[i] << " 80 mm below");
    // The ball 50 mm above A at the origin's cradle, 130 mm above it below.
    CHECK(p1.sigma[i] / p0.sigma[i] == Approx(50.0 / 130.0).epsilon(0.05));
    ++seen;
  }
  CHECK(seen == 6);
  // And the A axis' point where the pivot puts it.
  for (std::size_t i = 0; i < p1.outputs.size(); ++i) {
    if (p1.outputs[i].name == "a_axis_point_y") CHECK(p1.value[i] == Approx(-25.0 + 0.010).margin(1e-4));  // and the realistic errors
    if (p1.outputs[i].name == "a_axis_point_z") CHECK(p1.value[i] == Approx(-80.0 - 0.015).margin(1e-4));
  }
}

TEST_CASE("plan: a plan the method refuses is reported with the module's error", "[plan]") {
  sim::RigidityPlan no_reference = sim::rigidity_plan(-60.0, 60.0, 30.0, 30.0);
  no_reference.poses.erase(no_reference.poses.begin() + 2);  // A = 0
  REQUIRE(no_reference.poses.size() == 4);
  const sim::PlanPrediction p = sim::predict_plan(*sim::rigidity_model(no_reference));
  CHECK_FALSE(p.ok);
  CHECK(p.error.find("module error 209 no_reference_pose") != std::string::npos);
  CHECK(sim::suggest_changes(*sim::rigidity_model(no_reference), p, 2).empty());
  const std::string json = sim::plan_json(*sim::rigidity_model(no_reference), p, {});
  CHECK(json.find("\"refused\": \"module error 209 no_reference_pose") != std::string::npos);
}

TEST_CASE("plan: each suggestion is the candidate with the lowest valuation, after the one before", "[plan]") {
  const auto model = sim::level_model(sim::level_plan(100.0));
  const sim::PlanPrediction base = sim::predict_plan(*model);
  REQUIRE(base.ok);
  const std::vector<sim::PlanSuggestion> s = sim::suggest_changes(*model, base, 2);
  REQUIRE(s.size() == 2);
  // Round 1 by hand: every candidate predicted, the lowest valuation chosen.
  std::shared_ptr<const sim::PlanModel> chosen;
  double lowest = base.valuation;
  for (const sim::PlanChange& c : model->candidates()) {
    const sim::PlanPrediction p = sim::predict_plan(*c.plan);
    REQUIRE(p.ok);
    if (p.valuation < lowest) lowest = p.valuation, chosen = c.plan;
  }
  REQUIRE(chosen != nullptr);
  CHECK(s[0].valuation == lowest);
  CHECK(s[0].description == chosen->description());
  double second = lowest;
  for (const sim::PlanChange& c : chosen->candidates()) second = std::min(second, sim::predict_plan(*c.plan).valuation);
  CHECK(s[1].valuation == second);
  CHECK(s[1].valuation < s[0].valuation);
  CHECK(s[0].valuation < base.valuation);
}

TEST_CASE("plan: outputs the plan moves together are named, derived ones are not", "[plan]") {
  // M4: the analyser, 250 mm and more below O1, sees O1's place and the
  // axis' tilt almost only through their combination at the balls.
  const sim::PlanPrediction spindle = sim::predict_plan(*sim::spindle_model(sim::SpindlePlan{}));
  REQUIRE(spindle.ok);
  bool o_a = false;
  for (const sim::PlanInseparable& q : spindle.inseparable) {
    const std::size_t n = spindle.outputs.size();
    CHECK(std::fabs(q.rho) > sim::kInseparable);
    CHECK(q.rho == Approx(spindle.covariance[q.first * n + q.second] / (spindle.sigma[q.first] * spindle.sigma[q.second])));
    o_a = o_a || (spindle.outputs[q.first].name == "o_x" && spindle.outputs[q.second].name == "a_x");
  }
  CHECK(o_a);
  // M1: A is the normal's tilt and C its azimuth (rho = +-1), and not named.
  const sim::PlanPrediction level = sim::predict_plan(*sim::level_model(sim::level_plan(100.0)));
  REQUIRE(level.ok);
  CHECK(level.inseparable.empty());
  CHECK(std::fabs(level.covariance[0 * 4 + 2] / (level.sigma[0] * level.sigma[2])) > 0.999);
}

TEST_CASE("plan: each method's outputs are named for what they are: the noise-free plan gives the simulator's truth",
          "[plan]") {
  // The Monte Carlo compares a plan's outputs with themselves; here their
  // names and units meet the virtual machines' truth, so a swapped label, a
  // unit or a sub-machine out of order fails.
  const auto value = [](const sim::PlanPrediction& p, const std::string& name) {
    for (std::size_t k = 0; k < p.outputs.size(); ++k) {
      if (p.outputs[k].name == name) return p.value[k];
    }
    FAIL("no output " << name);
    return 0.0;
  };
  constexpr double kArcsec = 206264.80624709636;

  // M3: against the module's own report (9834) of the same noise-free
  // measurement (its rotation vector's definition differs from the
  // simulator's about its true A axis where the cradle bends: test_rigidity_flow).
  const sim::RigidityPlan rigidity = sim::rigidity_plan(-90.0, 90.0, 30.0, 10.0);
  const sim::PlanPrediction m3 = sim::predict_plan(*sim::rigidity_model(rigidity));
  REQUIRE(m3.ok);
  const std::vector<Vec3> exact = ball_measure(rigidity)(nullptr);
  trueaxis::test::ModuleRig rig;
  namespace v = trueaxis::macros::var;
  REQUIRE(rig.run(9830) == 2.0);
  std::size_t reading = 0;
  for (const auto& pose : rigidity.poses) {
    for (const double c : pose.second) {
      const double ac[3] = {pose.first, 0.0, c};
      const double xyz[3] = {exact[reading].x(), exact[reading].y(), exact[reading].z()};
      ++reading;
      REQUIRE(rig.module().write(v::kArgA, 3, ac) == trueaxis::macros::AccessFault::kNone);
      REQUIRE(rig.module().write(v::kArgX, 3, xyz) == trueaxis::macros::AccessFault::kNone);
      REQUIRE(rig.run(9831) == 2.0);
    }
  }
  REQUIRE(rig.run(9832) == 2.0);
  CHECK(value(m3, "a_axis_point_x") == Approx(rig.get(v::kRigidityAPointX)).margin(1e-12));
  CHECK(value(m3, "a_axis_point_y") == Approx(rig.get(v::kRigidityAPointX + 1)).margin(1e-12));
  CHECK(value(m3, "a_axis_point_z") == Approx(rig.get(v::kRigidityAPointX + 2)).margin(1e-12));
  CHECK(std::fabs(value(m3, "c_to_a_offset_signed")) == Approx(rig.get(v::kRigidityCToAOffset)).margin(1e-12));
  CHECK(value(m3, "c_to_a_squareness") == Approx(rig.get(v::kRigidityCToASquareness)).margin(1e-9));
  for (int q = 1; q <= 7; ++q) {
    rig.set(v::kArgQ, q);
    rig.set(v::kArgR, 0.0);
    REQUIRE(rig.run(9834) == 2.0);
    const double a = rig.get(v::kPoseA);
    if (a == 0.0) continue;
    INFO("A " << a);
    const std::string at = "A=" + std::to_string(static_cast<int>(a)) + " ";
    CHECK(value(m3, at + "rotation_vector_x") == Approx(rig.get(v::kPoseRotvecX)).margin(1e-9));
    CHECK(value(m3, at + "rotation_vector_y") == Approx(rig.get(v::kPoseRotvecX + 1)).margin(1e-9));
    CHECK(value(m3, at + "rotation_vector_z") == Approx(rig.get(v::kPoseRotvecX + 2)).margin(1e-9));
    CHECK(value(m3, at + "a_positioning_error") == Approx(rig.get(v::kPoseAError)).margin(1e-9));
  }

  const sim::PlanPrediction m4 = sim::predict_plan(*sim::spindle_model(sim::SpindlePlan{}));
  REQUIRE(m4.ok);
  const core::SpindleParams truth = sim::VirtualSpindle(sim::realistic_spindle()).identifiable_truth();
  const char* names[] = {"o_x", "o_y", "o_z", "a_x", "a_y", "e_x", "e_y", "w_x", "w_y"};
  for (int k = 0; k < 9; ++k) {
    INFO(names[k]);
    const bool angle = k == 3 || k == 4 || k == 7 || k == 8;
    CHECK(value(m4, names[k]) == Approx(truth(k) * (angle ? kArcsec : 1.0)).margin(angle ? 0.05 : 5e-5));
  }

  const sim::PlanPrediction m2 = sim::predict_plan(*sim::gantry_model(sim::GantryPlanSpec{}));
  REQUIRE(m2.ok);
  const sim::GantryMachine gantry(sim::realistic_gantry());
  for (std::size_t i = 0; i < gantry.sub_machine_count(); ++i) {
    const sim::SubMachineTruth& t = gantry.truth(i);
    const std::string sp = "sp" + std::to_string(t.id) + " ";
    INFO(sp);
    CHECK(value(m2, sp + "origin_x") == Approx(t.origin_global_mm.x()).margin(1e-6));
    CHECK(value(m2, sp + "origin_y") == Approx(t.origin_global_mm.y()).margin(1e-6));
    CHECK(value(m2, sp + "origin_z") == Approx(t.origin_global_mm.z()).margin(1e-6));
    CHECK(value(m2, sp + "squareness_xy") == Approx(t.squareness_xy_arcsec).margin(1e-3));
    CHECK(value(m2, sp + "a_c_angle_minus_90") == Approx((t.a_c_angle_deg - 90.0) * 3600.0).margin(1e-3));
    CHECK(std::fabs(value(m2, sp + "a_c_offset_signed")) == Approx(t.a_c_offset_mm).margin(1e-6));
  }

  const sim::PlanPrediction m1 = sim::predict_plan(*sim::level_model(sim::level_plan(100.0)));
  REQUIRE(m1.ok);
  CHECK(std::fabs(value(m1, "level_a")) == Approx(sim::FaceConfig{}.tilt_deg * 3600.0).margin(1e-6));
  CHECK(value(m1, "normal_turn_tilt") == Approx(0.0).margin(1e-6));
}

TEST_CASE("plan rigidity: a candidate A pose at the A limit itself is offered, one ulp beyond it is not", "[plan]") {
  const auto offered = [](double a_min, double a_max) {
    sim::RigidityPlan plan = sim::rigidity_plan(-60.0, 60.0, 30.0, 30.0);
    plan.a_min_deg = a_min;
    plan.a_max_deg = a_max;
    std::vector<std::string> poses;
    for (const sim::PlanChange& c : sim::rigidity_model(plan)->candidates()) poses.push_back(c.what);
    return poses;
  };
  const auto has = [](const std::vector<std::string>& poses, const std::string& what) {
    return std::find(poses.begin(), poses.end(), what) != poses.end();
  };
  const std::vector<std::string> at = offered(-90.0, 90.0);
  CHECK(has(at, "add the A pose 90 deg (12 C positions)"));
  CHECK(has(at, "add the A pose -90 deg (12 C positions)"));
  CHECK(has(at, "add the A pose 75 deg (12 C positions)"));
  CHECK_FALSE(has(at, "add the A pose 105 deg (12 C positions)"));
  CHECK_FALSE(has(at, "add the A pose 60 deg (12 C positions)"));  // already planned
  const std::vector<std::string> inside = offered(std::nextafter(-90.0, 0.0), std::nextafter(90.0, 0.0));
  CHECK_FALSE(has(inside, "add the A pose 90 deg (12 C positions)"));
  CHECK_FALSE(has(inside, "add the A pose -90 deg (12 C positions)"));
  CHECK(has(inside, "add the A pose 75 deg (12 C positions)"));
  CHECK(has(inside, "add the A pose -75 deg (12 C positions)"));
}

TEST_CASE("plan gantry: widening the A circles to the A limit itself is offered, beyond it is not", "[plan]") {
  const auto widens = [](double limit) {
    sim::GantryPlanSpec spec;
    spec.a_limit_deg = limit;
    for (const sim::PlanChange& c : sim::gantry_model(spec)->candidates()) {
      if (c.what.find("widen every A circle") == 0) return true;
    }
    return false;
  };
  const sim::GantryPlanSpec spec;
  const double step = (spec.a_to_deg - spec.a_from_deg) / (spec.circle_points - 1);
  REQUIRE(spec.a_from_deg == -spec.a_to_deg);  // symmetric: a_to + step is the arc's new end at both sides
  CHECK(widens(spec.a_to_deg + step));
  CHECK_FALSE(widens(std::nextafter(spec.a_to_deg + step, 0.0)));
}

namespace {

// A plan with one reading of unit noise (mm) per axis and outputs
// x (mm), k x (mm), 1e-13 x (arcsec): k x is moved by the reading only at the
// scale k of x, and the arcsec output is the only one of its unit.
class ScaledOutputs final : public sim::PlanModel {
 public:
  explicit ScaledOutputs(double k) : k_(k) {
    readings_.push_back({Vec3::Zero(), core::Mat3::Identity()});
    outputs_ = {{"x", "mm", 0.0}, {"k_x", "mm", 0.0}, {"tiny_turn", "arcsec", 0.0}};
  }
  const char* method() const override { return "scaled"; }
  std::string description() const override { return "x, k x, 1e-13 x"; }
  const std::vector<sim::PlanReading>& readings() const override { return readings_; }
  const std::vector<sim::PlanOutput>& outputs() const override { return outputs_; }
  bool evaluate(const std::vector<Vec3>& values, std::vector<double>& out, std::string&) const override {
    out = {values[0].x(), k_ * values[0].x(), 1e-13 * values[0].x()};
    return true;
  }
  std::vector<sim::PlanChange> candidates() const override { return {}; }
  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override { return {}; }
  std::vector<sim::PlanMacro> module_macros(const std::vector<Vec3>&) const override { return {}; }

 private:
  double k_;
  std::vector<sim::PlanReading> readings_;
  std::vector<sim::PlanOutput> outputs_;
};

bool reported(const sim::PlanPrediction& p, std::size_t a, std::size_t b) {
  for (const sim::PlanInseparable& q : p.inseparable) {
    if (q.first == a && q.second == b) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("plan: an output moved only at rounding's scale (1e-12 of its unit's largest sigma) is never \"not separated\"",
          "[plan]") {
  // x and k x are perfectly correlated; k x counts as moving only above 1e-12
  // of the largest sigma among the mm outputs (x's, 1).
  const ScaledOutputs above(1e-12 * (1.0 + 1e-6));
  const sim::PlanPrediction pa = sim::predict_plan(above);
  REQUIRE(pa.ok);
  CHECK(pa.sigma[1] == Approx(1e-12 * (1.0 + 1e-6)).epsilon(1e-12));
  CHECK(reported(pa, 0, 1));
  CHECK(sim::plan_table(above, pa, {}, false).find("not separated: x and k_x") != std::string::npos);

  const ScaledOutputs below(1e-12 * (1.0 - 1e-6));
  const sim::PlanPrediction pb = sim::predict_plan(below);
  REQUIRE(pb.ok);
  CHECK_FALSE(reported(pb, 0, 1));
  CHECK_FALSE(reported(pb, 1, 2));
  CHECK(sim::plan_table(below, pb, {}, false).find("and k_x") == std::string::npos);
  // The arcsec output's sigma (1e-13) is compared with its own unit's largest
  // (itself), not with x's: it moves, and is as inseparable from x as it is.
  CHECK(reported(pb, 0, 2));
}
