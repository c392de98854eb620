// M2 uncertainties against Monte Carlo on the independent ground truth
// (gantry_truth.hpp) with an AT960-like tracker 2..6 m away: the reported
// origin_sigma_mm and angle sigmas against the spread of the actual errors, and
// the fraction of runs within 3 sigma. Set TRUEAXIS_FIGURES=1 to print the figures.
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>

#include <Eigen/Cholesky>

#include "gantry_truth.hpp"
#include "trueaxis/core/so3.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;
using t::Mat3L;
using t::Vec3L;
using Vec6 = Eigen::Matrix<double, 6, 1>;

namespace {

// Errors and reported sigmas of one frame over the runs.
struct FrameStats {
  int runs = 0;
  int origin_within = 0;        // |e| <= 3 origin_sigma_mm
  double origin_e2 = 0.0;       // sum |e|^2
  double origin_s2 = 0.0;       // sum origin_sigma_mm^2
  int angle_within[3] = {0, 0, 0};
  double angle_e2[3] = {0, 0, 0};  // arcsec^2
  double angle_s2[3] = {0, 0, 0};
  double mahalanobis = 0.0;     // sum e^T C^-1 e over the 6 components

  void add(const Vec3& e_origin, const Vec3& e_rot_rad, const core::FrameUncertainty& u) {
    ++runs;
    const double so = u.origin_sigma_mm;
    origin_within += e_origin.norm() <= 3.0 * so ? 1 : 0;
    origin_e2 += e_origin.squaredNorm();
    origin_s2 += so * so;
    for (int k = 0; k < 3; ++k) {
      const double e = e_rot_rad(k) * core::kArcsecPerRad;
      const double s = u.angle_sigma_arcsec(k);
      angle_within[k] += std::abs(e) <= 3.0 * s ? 1 : 0;
      angle_e2[k] += e * e;
      angle_s2[k] += s * s;
    }
    Vec6 e;
    e << e_origin, e_rot_rad;
    mahalanobis += e.dot(u.covariance.ldlt().solve(e));
  }
  // Monte-Carlo RMS error over the RMS reported sigma.
  double origin_ratio() const { return std::sqrt(origin_e2 / origin_s2); }
  double angle_ratio(int k) const { return std::sqrt(angle_e2[k] / angle_s2[k]); }
  double origin_fraction() const { return static_cast<double>(origin_within) / runs; }
  double angle_fraction(int k) const { return static_cast<double>(angle_within[k]) / runs; }
  double mean_mahalanobis() const { return mahalanobis / runs; }
};

struct McResult {
  FrameStats global;
  FrameStats subs[4];
};

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

McResult run_mc(std::uint64_t seed, int runs, t::NoiseSpec noise, const core::GantryOptions& options) {
  t::Rng rng(seed);
  const t::TrueGantry truth = t::make_truth(rng);
  t::Sampler sampler(truth, rng, noise);
  auto out = std::make_unique<core::GantryFrames>();
  McResult r;
  for (int run = 0; run < runs; ++run) {
    const t::Samples s = sampler.sample();
    const core::GantryInput in = t::make_input(truth, s);
    REQUIRE(core::compute_gantry_frames(in, options, *out) == core::Status::kOk);
    const core::Rigid3& g = out->global.tracker_T_global;
    r.global.add((g.t.cast<long double>() - truth.O_t).cast<double>(),
                 core::so3_log((truth.R_tg.transpose() * g.R.cast<long double>()).cast<double>()),
                 out->global.uncertainty);
    for (std::size_t i = 0; i < 4; ++i) {
      const core::SubMachineFrame& f = out->sub_machines[i];
      const t::TrueSub& ts = truth.subs[i];
      r.subs[i].add((f.global_T_sub.t.cast<long double>() - ts.origin).cast<double>(),
                    core::so3_log((ts.R.transpose() * f.global_T_sub.R.cast<long double>()).cast<double>()),
                    f.uncertainty);
    }
  }
  return r;
}

void report(const char* name, const FrameStats& s) {
  if (!print_figures()) return;
  std::printf("%-28s origin: sigma %.4f mm, MC rms %.4f mm, ratio %.3f, within 3 sigma %.3f | "
              "angles ratio %.3f %.3f %.3f, sigma %.2f %.2f %.2f arcsec, within %.3f %.3f %.3f | "
              "mean Mahalanobis^2 %.2f (6)\n",
              name, std::sqrt(s.origin_s2 / s.runs), std::sqrt(s.origin_e2 / s.runs), s.origin_ratio(),
              s.origin_fraction(), s.angle_ratio(0), s.angle_ratio(1), s.angle_ratio(2),
              std::sqrt(s.angle_s2[0] / s.runs), std::sqrt(s.angle_s2[1] / s.runs), std::sqrt(s.angle_s2[2] / s.runs),
              s.angle_fraction(0), s.angle_fraction(1), s.angle_fraction(2), s.mean_mahalanobis());
}

// Checks the Monte-Carlo figures of one frame. Within-3-sigma: for a 3-D
// Gaussian error, P(|e| <= 3 sqrt(trace C)) >= P(|z| <= 3) = 0.9973 (the 1-D
// limit, one dominant eigenvalue); per angle 0.9973 exactly. 0.98 leaves room for
// the binomial scatter of a few hundred runs and the first-order model.
void check_frame(const char* name, const FrameStats& s, double mahalanobis_lo, double mahalanobis_hi) {
  INFO(name);
  report(name, s);
  CHECK(s.origin_fraction() >= 0.98);
  CHECK(s.origin_ratio() > 1.0 / 1.5);
  CHECK(s.origin_ratio() < 1.5);
  for (int k = 0; k < 3; ++k) {
    INFO("angle about axis " << k);
    CHECK(s.angle_fraction(k) >= 0.98);
    CHECK(s.angle_ratio(k) > 1.0 / 1.5);
    CHECK(s.angle_ratio(k) < 1.5);
  }
  // The whole 6x6 covariance, correlations included: E[e^T C^-1 e] = 6.
  CHECK(s.mean_mahalanobis() > mahalanobis_lo);
  CHECK(s.mean_mahalanobis() < mahalanobis_hi);
}

const char* const kNames[4] = {"sub 1 (beam)", "sub 2 (left column)", "sub 3 (right column)", "sub 4 (floor bridge)"};

}  // namespace

TEST_CASE("uncertainties from the tracker model match the Monte-Carlo spread", "[gantry][mc]") {
  core::GantryOptions options;
  options.noise = {t::kTracker.a_mm, t::kTracker.b_per_mm, Vec3::Zero()};  // the tracker at the origin
  const McResult r = run_mc(801, 300, t::kTracker, options);
  // 300 runs: the mean of a chi-square with 6 degrees of freedom has a standard
  // error of sqrt(12 / 300) = 0.2.
  check_frame("model: global", r.global, 5.0, 7.0);
  for (int i = 0; i < 4; ++i) check_frame(kNames[i], r.subs[i], 5.0, 7.0);
}

TEST_CASE("uncertainties from the fits' residuals match the Monte-Carlo spread", "[gantry][mc]") {
  const McResult r = run_mc(802, 300, t::kTracker, core::GantryOptions{});
  // Sigmas estimated from a dozen to a few hundred residuals scatter: the
  // quadratic form's mean grows a little above 6 (Student rather than Gaussian).
  check_frame("residuals: global", r.global, 5.0, 7.5);
  for (int i = 0; i < 4; ++i) check_frame(kNames[i], r.subs[i], 5.0, 7.5);
}

TEST_CASE("the global frame's uncertainty reaches every sub-machine", "[gantry][mc]") {
  // Noise on the bed, the sides and the gantry only, sigmas from the residuals:
  // the sub-machines' own fits are exact and add nothing, so all of their
  // reported uncertainty is the global frame's, mapped through the first-order
  // chain of gantry_frames.hpp item 5.
  t::NoiseSpec noise = t::kTracker;
  noise.global_only = true;
  const McResult r = run_mc(803, 300, noise, core::GantryOptions{});
  // The side faces' 12 points leave 9 degrees of freedom for their sigma: the
  // quadratic form's mean is then about 6 * 9 / 7 = 7.7 in the planes' share.
  check_frame("global only: global", r.global, 5.0, 8.0);
  for (int i = 0; i < 4; ++i) check_frame(kNames[i], r.subs[i], 5.0, 8.0);
}
