// Issue 7: M4's Levenberg-Marquardt identification (core::fit_spindle) against
// seed 002's particle swarm (particle_swarm.hpp) on the same 9-parameter model
// (spindle_model.hpp) and the same simulated analyser data. Prints model
// evaluations, time, final RMS residual and the worst parameter error in units
// of LM's sigma, and how often the swarm reaches a truth-level fit: a cost (sum
// of squared residuals) <= (1 + 1e-3) x the cost at the true parameters.
// One evaluation = one pass of spindle_ball_mm over the whole data set.
// docs/M4_BENCHMARK.md has the settings, the figures and their reading.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "particle_swarm.hpp"
#include "trueaxis/core/levenberg_marquardt.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/program.hpp"

namespace {

namespace core = trueaxis::core;
namespace bench = trueaxis::bench;
using core::SpindleParams;
using core::Vec3;
using Clock = std::chrono::steady_clock;

constexpr double kArcsec = core::kPi / (180.0 * 3600.0);
constexpr double kNoiseMm = 15e-6;    // per axis, 1 sigma
constexpr int kAnglesPerRev = 72;     // 5 deg steps
constexpr int kRevolutions = 3;
constexpr std::uint64_t kNoiseSeed = 20240607;
constexpr int kPsoRuns = 20;
constexpr long kPsoBudget = 200000;   // evaluations per run
constexpr double kTruthLevel = 1e-3;  // relative excess over the cost at the truth
constexpr int kLmTimingRepeats = 300;  // fit_spindle, timed as the median of this many
constexpr int kCentralTimingRepeats = 30;
// Forward passes per evaluation of the central-difference LM below: the
// residual pass plus 2 x 6 for the columns a_x ... w_y (the columns in o are
// the identity and cost nothing).
constexpr int kPassesPerCentralEvaluation = 1 + 2 * 6;

const core::SpindleGeometry kGeometry{350.0, {50.0, 150.0}};

SpindleParams truth() {
  SpindleParams p;
  p << 0.0123, -0.0087, 400.0042,  // o [mm]
      1.0e-4, -1.2e-4,             // a_x, a_y [rad]: 20.6", -24.8"
      0.0023, -0.0014,             // e [mm]
      -15.0 * kArcsec, 11.0 * kArcsec;  // w [rad]
  return p;
}

// The box a user would set from the nominal: spindle along -Z, analyser zeroed on
// ball 1 (o = (0, 0, G + b_1)), no errors; o within 0.05 mm, tilts within 100",
// run-out within 10 um.
void search_box(SpindleParams& lower, SpindleParams& upper) {
  SpindleParams centre;
  centre << 0.0, 0.0, kGeometry.gauge_mm + kGeometry.ball_mm[0], 0, 0, 0, 0, 0, 0;
  SpindleParams half;
  half << 0.05, 0.05, 0.05, 100 * kArcsec, 100 * kArcsec, 0.010, 0.010, 100 * kArcsec, 100 * kArcsec;
  lower = centre - half;
  upper = centre + half;
}

std::vector<core::SpindleSample> make_samples(const SpindleParams& p) {
  std::mt19937_64 rng(kNoiseSeed);
  std::normal_distribution<double> noise(0.0, kNoiseMm);
  std::vector<core::SpindleSample> s;
  for (int ball = 1; ball <= 2; ++ball) {
    for (int i = 0; i < kAnglesPerRev * kRevolutions; ++i) {
      const double phi_deg = 360.0 * i / kAnglesPerRev;
      Vec3 m = core::spindle_ball_mm(p, kGeometry, ball, core::deg_to_rad(phi_deg));
      for (int k = 0; k < 3; ++k) m(k) += noise(rng);
      s.push_back({phi_deg, ball, m});
    }
  }
  return s;
}

// The residuals LM uses (measured minus predicted), squared and summed.
double cost(const SpindleParams& p, const std::vector<core::SpindleSample>& s) {
  double sum = 0.0;
  for (const core::SpindleSample& x : s) {
    sum += (x.p_mm - core::spindle_ball_mm(p, kGeometry, x.ball, core::deg_to_rad(x.phi_deg))).squaredNorm();
  }
  return sum;
}

struct LmRun {
  core::Status status = core::Status::kOk;
  SpindleParams params = SpindleParams::Zero();
  int evaluations = 0;
  int to_level = -1;  // the evaluation whose accepted cost first met the truth level
  double seconds = 0.0;
};

// The same solver (levenberg_marquardt.hpp, default options) on every sample,
// with the Jacobian by central differences (steps 1e-7) in a_x ... w_y: each
// evaluation is exactly kPassesPerCentralEvaluation forward passes.
LmRun fit_central(const SpindleParams& p0, const std::vector<core::SpindleSample>& s, double target) {
  LmRun run;
  core::LevenbergMarquardt<core::kSpindleParams> lm;
  lm.start(p0);
  constexpr double kStep = 1e-7;
  core::LmStep step;
  do {
    const SpindleParams p = lm.point();
    lm.begin_evaluation();
    for (const core::SpindleSample& x : s) {
      const double phi = core::deg_to_rad(x.phi_deg);
      Eigen::Matrix<double, 3, core::kSpindleParams> j;
      j.leftCols<3>().setIdentity();
      for (int k = 3; k < core::kSpindleParams; ++k) {
        SpindleParams plus = p;
        SpindleParams minus = p;
        plus(k) += kStep;
        minus(k) -= kStep;
        j.col(k) = (core::spindle_ball_mm(plus, kGeometry, x.ball, phi) -
                    core::spindle_ball_mm(minus, kGeometry, x.ball, phi)) / (2 * kStep);
      }
      lm.add(Vec3(core::spindle_ball_mm(p, kGeometry, x.ball, phi) - x.p_mm), j);
    }
    step = lm.finish_evaluation();
    if (run.to_level < 0 && 2.0 * lm.cost() <= target) run.to_level = lm.evaluations();
  } while (step.more);
  run.status = lm.status();
  run.params = lm.solution();
  run.evaluations = lm.evaluations();
  return run;
}

// fit_central, timed as the median of kCentralTimingRepeats runs.
LmRun timed_central(const SpindleParams& p0, const std::vector<core::SpindleSample>& s, double target) {
  LmRun run;
  std::vector<double> t;
  for (int i = 0; i < kCentralTimingRepeats; ++i) {
    const Clock::time_point t0 = Clock::now();
    run = fit_central(p0, s, target);
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  run.seconds = t[t.size() / 2];
  return run;
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double rms_nm(double c, std::size_t count) { return 1e6 * std::sqrt(c / static_cast<double>(count)); }

// max_k |p_k - truth_k| / sigma_k, and the k where it is reached.
double worst_sigma(const SpindleParams& p, const SpindleParams& t, const SpindleParams& sigma, int* which = nullptr) {
  const SpindleParams z = (p - t).cwiseAbs().cwiseQuotient(sigma);
  Eigen::Index k = 0;
  const double worst = z.maxCoeff(&k);
  if (which != nullptr) *which = static_cast<int>(k);
  return worst;
}

volatile double g_sink = 0.0;  // keeps the timed loops' results alive

const char* const kNames[core::kSpindleParams] = {"o_x", "o_y", "o_z", "a_x", "a_y", "e_x", "e_y", "w_x", "w_y"};

struct PsoRun {
  long first = -1;       // evaluations to the truth-level fit, -1 never
  double first_s = 0.0;  // seconds to it
  double first_worst = 0.0;
  double final_cost = 0.0;
  double final_worst = 0.0;
  int final_worst_k = 0;
  double seconds = 0.0;
  long evaluations = 0;
  int on_wall = 0;  // parameters of the final best on a wall of the box
  SpindleParams final_sigma = SpindleParams::Zero();  // |error| / sigma per parameter
};

}  // namespace

constexpr const char* kHelp =
    "usage: bench_spindle_pso\n"
    "  M4's Levenberg-Marquardt identification against seed 002's particle swarm on the same\n"
    "  model and data: evaluations, time, RMS and how often the swarm reaches the fit\n"
    "  (docs/M4_BENCHMARK.md).\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_spindle_pso", kHelp)) return 0;
  const SpindleParams t = truth();
  const std::vector<core::SpindleSample> s = make_samples(t);
  const std::size_t n = s.size();
  const double cost_true = cost(t, s);
  const double target = (1.0 + kTruthLevel) * cost_true;
  SpindleParams lower, upper;
  search_box(lower, upper);

  // One evaluation (a forward pass over the data), timed.
  double sink = 0.0;
  constexpr int kPassRepeats = 2000;
  const Clock::time_point tp = Clock::now();
  for (int i = 0; i < kPassRepeats; ++i) sink += cost(t, s);
  const double pass_s = seconds_since(tp) / kPassRepeats;

  // LM as the firmware runs it.
  core::SpindleFit fit;
  const core::Status status = core::fit_spindle(s.data(), n, kGeometry, fit);
  if (status != core::Status::kOk) {
    std::printf("fit_spindle failed: %s\n", trueaxis::macros::status_name(status));
    return 1;
  }
  std::vector<double> lm_times;
  for (int i = 0; i < kLmTimingRepeats; ++i) {
    core::SpindleFit again;
    const Clock::time_point t0 = Clock::now();
    const core::Status st = core::fit_spindle(s.data(), n, kGeometry, again);
    lm_times.push_back(seconds_since(t0));
    if (st != core::Status::kOk) return 1;
    sink += again.rms_mm;
  }
  const double lm_s = median(lm_times);
  const double lm_time_passes = lm_s / pass_s;
  SpindleParams sigma;
  for (int k = 0; k < core::kSpindleParams; ++k) sigma(k) = std::sqrt(fit.covariance(k, k));
  if (!sigma.allFinite() || !(sigma.minCoeff() > 0.0)) {
    std::printf("fit_spindle returned no usable covariance\n");
    return 1;
  }
  const double lm_cost = cost(fit.params, s);

  // The same solver counted exactly in forward passes: central differences on
  // every sample, from the closed-form start and from the box's centre.
  static core::SpindleBins bins;  // 35 KB
  bins.clear();
  for (const core::SpindleSample& x : s) {
    if (bins.add(x) != core::Status::kOk) return 1;
  }
  const core::Result<SpindleParams> start = core::spindle_start(bins, kGeometry);
  if (!start.ok()) {
    std::printf("spindle_start failed: %s\n", trueaxis::macros::status_name(start.status()));
    return 1;
  }
  const LmRun cs = timed_central(start.value(), s, target);
  const LmRun cc = timed_central(0.5 * (lower + upper), s, target);
  for (const LmRun* r : {&cs, &cc}) {
    if (r->status != core::Status::kOk) {
      std::printf("central-difference LM failed: %s\n", trueaxis::macros::status_name(r->status));
      return 1;
    }
  }
  const int cs_passes = cs.evaluations * kPassesPerCentralEvaluation + 1;  // + the start's pass
  const int cc_passes = cc.evaluations * kPassesPerCentralEvaluation;

  // The swarm, kPsoRuns seeds.
  std::vector<PsoRun> runs;
  const Clock::time_point t_all = Clock::now();
  for (int r = 0; r < kPsoRuns; ++r) {
    PsoRun run;
    bench::PsoOptions opt;
    opt.seed = static_cast<std::uint64_t>(r + 1);
    opt.max_evaluations = kPsoBudget;
    opt.target_cost = target;
    bool hit = false;  // the evaluation count at the hit comes from the swarm's own bookkeeping
    const Clock::time_point t0 = Clock::now();
    const auto objective = [&](const SpindleParams& p) {
      const double c = cost(p, s);
      if (!hit && c <= target) {
        hit = true;
        run.first_s = seconds_since(t0);
        run.first_worst = worst_sigma(p, t, sigma);
      }
      return c;
    };
    const bench::PsoResult<core::kSpindleParams> res =
        bench::minimise_pso<core::kSpindleParams>(objective, lower, upper, opt);
    run.seconds = seconds_since(t0);
    run.first = res.first_target_evaluation;
    run.evaluations = res.evaluations;
    run.final_cost = res.best_cost;
    run.final_worst = worst_sigma(res.best, t, sigma, &run.final_worst_k);
    run.final_sigma = (res.best - t).cwiseAbs().cwiseQuotient(sigma);
    for (int k = 0; k < core::kSpindleParams; ++k) {
      if (res.best(k) == lower(k) || res.best(k) == upper(k)) ++run.on_wall;
    }
    runs.push_back(run);
  }
  const double pso_all_s = seconds_since(t_all);

  // Report.
  std::printf("M4 benchmark: Levenberg-Marquardt against seed 002's particle swarm, same model and data\n");
  std::printf("data: G = %.0f mm, balls %.0f and %.0f mm, %d angles x %d rev per ball = %zu samples, "
              "noise %.0f nm per axis (seed %llu)\n",
              kGeometry.gauge_mm, kGeometry.ball_mm[0], kGeometry.ball_mm[1], kAnglesPerRev, kRevolutions, n,
              kNoiseMm * 1e6, static_cast<unsigned long long>(kNoiseSeed));
  std::printf("cost (sum of squared residuals) at the truth %.6e mm^2, RMS %.2f nm per sample (3-D);\n"
              "truth-level fit: cost <= (1 + %.0e) x that = %.6e mm^2\n",
              cost_true, rms_nm(cost_true, n), kTruthLevel, target);
  std::printf("one evaluation = spindle_ball_mm over all %zu samples: %.2f us\n", n, pass_s * 1e6);
  std::printf("LM sigma: o %.2f %.2f %.2f nm, a %.4f %.4f\", e %.2f %.2f nm, w %.4f %.4f\"\n", sigma(0) * 1e6,
              sigma(1) * 1e6, sigma(2) * 1e6, sigma(3) / kArcsec, sigma(4) / kArcsec, sigma(5) * 1e6,
              sigma(6) * 1e6, sigma(7) / kArcsec, sigma(8) / kArcsec);
  const bench::PsoOptions defaults;
  std::printf("PSO: gbest, swarm %d, w %.4f, c1 = c2 = %.5f (Clerc-Kennedy constriction: the seed gives no\n"
              "settings), box o +-0.05 mm, a +-100\", e +-10 um, w +-100\" about the nominal, absorbing walls,\n"
              "%d runs (seeds 1..%d) of %ld evaluations each\n\n",
              defaults.swarm, defaults.inertia, defaults.c1, kPsoRuns, kPsoRuns, kPsoBudget);

  std::vector<double> first, first_s, first_worst, final_rms, final_worst, seconds, evals;
  int reached = 0;
  for (const PsoRun& r : runs) {
    if (r.first >= 0) {
      ++reached;
      first.push_back(static_cast<double>(r.first));
      first_s.push_back(r.first_s);
      first_worst.push_back(r.first_worst);
    }
    final_rms.push_back(rms_nm(r.final_cost, n));
    final_worst.push_back(r.final_worst);
    seconds.push_back(r.seconds);
    evals.push_back(static_cast<double>(r.evaluations));
  }

  std::printf("%-54s %12s %12s %10s %9s\n", "method", "evaluations", "time", "RMS [nm]", "worst [s]");
  std::printf("%-54s %12d %9.3f ms %10.3f %9.2f\n", "LM fit_spindle (bins, analytic J): LM passes", fit.evaluations,
              lm_s * 1e3, rms_nm(lm_cost, n), worst_sigma(fit.params, t, sigma));
  std::printf("%-54s %12.1f\n", "  as forward passes, by its time", lm_time_passes);
  std::printf("%-54s %12d %9.3f ms %10.3f %9.2f\n", "LM central differences, closed-form start: passes",
              cs_passes, cs.seconds * 1e3, rms_nm(cost(cs.params, s), n), worst_sigma(cs.params, t, sigma));
  std::printf("%-54s %12d\n", "  LM evaluations (13 passes each, + 1 for the start)", cs.evaluations);
  std::printf("%-54s %12d\n", "  passes to the truth-level fit", cs.to_level * kPassesPerCentralEvaluation + 1);
  std::printf("%-54s %12d %9.3f ms %10.3f %9.2f\n", "LM central differences, box centre start: passes", cc_passes,
              cc.seconds * 1e3, rms_nm(cost(cc.params, s), n), worst_sigma(cc.params, t, sigma));
  std::printf("%-54s %12d\n", "  LM evaluations (13 passes each)", cc.evaluations);
  std::printf("%-54s %12d\n", "  passes to the truth-level fit", cc.to_level * kPassesPerCentralEvaluation);
  if (reached > 0) {
    std::printf("%-54s %12.0f %10.3f s %10s %9.2f\n", "PSO to the truth level (median, runs that reach it)",
                median(first), median(first_s), "<= level", median(first_worst));
  } else {
    std::printf("%-54s %12s\n", "PSO to the truth-level fit", "never");
  }
  std::printf("%-54s %12.0f %10.3f s %10.3f %9.2f\n", "PSO at the end of its budget (median of all runs)",
              median(evals), median(seconds), median(final_rms), median(final_worst));
  std::printf("(worst [s]: the largest |parameter - truth| / LM sigma over the 9 parameters)\n");

  std::printf("\nPSO reached the truth-level fit in %d of %d runs.\n", reached, kPsoRuns);
  if (reached > 0) {
    const double best = *std::min_element(first.begin(), first.end());
    std::printf("PSO evaluations to it: median %.0f, min %.0f, max %.0f; time median %.3f s\n", median(first), best,
                *std::max_element(first.begin(), first.end()), median(first_s));
    std::printf("ratio PSO evaluations (median; PSO's best run) / LM forward passes:\n");
    const double lm_counts[4] = {lm_time_passes, static_cast<double>(cs_passes),
                                 static_cast<double>(cs.to_level * kPassesPerCentralEvaluation + 1),
                                 static_cast<double>(cc_passes)};
    const char* const lm_labels[4] = {"fit_spindle, by time", "central differences, closed-form start, to the end",
                                      "central differences, closed-form start, to the level",
                                      "central differences, box centre, to the end"};
    double smallest = 1e300;
    for (int i = 0; i < 4; ++i) {
      std::printf("  %-54s %8.1f passes: %7.0fx; %7.0fx\n", lm_labels[i], lm_counts[i], median(first) / lm_counts[i],
                  best / lm_counts[i]);
      smallest = std::fmin(smallest, best / lm_counts[i]);
    }
    std::printf("  the least of these: %.0fx (claim: >= 50x) %s\n", smallest, smallest >= 50.0 ? "holds" : "FAILS");
    std::printf("ratio PSO time to the level (median) / fit_spindle time: %.0fx\n", median(first_s) / lm_s);
  }
  std::printf("PSO final RMS [nm]: median %.3f, min %.3f, max %.3f\n", median(final_rms),
              *std::min_element(final_rms.begin(), final_rms.end()),
              *std::max_element(final_rms.begin(), final_rms.end()));
  std::printf("PSO final worst parameter error [LM sigma]: median %.2f, min %.2f, max %.2f\n", median(final_worst),
              *std::min_element(final_worst.begin(), final_worst.end()),
              *std::max_element(final_worst.begin(), final_worst.end()));
  std::printf("PSO total time for %d runs: %.1f s\n\n", kPsoRuns, pso_all_s);

  std::printf("%4s %9s %7s %9s %12s %13s %4s  |error| / sigma at the end: %s\n", "seed", "to level", "at [s]",
              "RMS [nm]", "cost/truth-1", "worst [sigma]", "wall", "o_x o_y o_z a_x a_y e_x e_y w_x w_y");
  for (int r = 0; r < kPsoRuns; ++r) {
    const PsoRun& x = runs[static_cast<std::size_t>(r)];
    char to_level[24];
    if (x.first >= 0) {
      std::snprintf(to_level, sizeof to_level, "%ld", x.first);
    } else {
      std::snprintf(to_level, sizeof to_level, "never");
    }
    std::printf("%4d %9s %7.2f %9.3f %12.2e %9.1f %-3s %4d ", r + 1, to_level, x.first >= 0 ? x.first_s : 0.0,
                rms_nm(x.final_cost, n), x.final_cost / cost_true - 1.0, x.final_worst, kNames[x.final_worst_k],
                x.on_wall);
    for (int k = 0; k < core::kSpindleParams; ++k) std::printf(" %.3g", x.final_sigma(k));
    std::printf("\n");
  }
  std::printf("LM cost/truth-1: %.2e (fit_spindle), %.2e (closed-form start), %.2e (box centre)\n",
              lm_cost / cost_true - 1.0, cost(cs.params, s) / cost_true - 1.0, cost(cc.params, s) / cost_true - 1.0);
  g_sink = sink;
  return 0;
}
