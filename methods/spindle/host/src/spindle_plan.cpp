// The spindle plan (M4; planner.hpp contract 1): its readings on the simulator's machine, its
// outputs, its evaluation by the method's own firmware_core routine (the module's code, called
// directly), and its one-pose changes (contract 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "trueaxis/core/so3.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/instruments/spindle_analyser.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/plan_parts.hpp"
#include "trueaxis/sim/tools/spindle_plan.hpp"
#include "trueaxis/sim/tools/planner.hpp"
#include "trueaxis/sim/tools/plan_options.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

namespace {

using core::Mat3;
using core::Vec3;
using core::kArcsecPerRad;
using plan_parts::refusal;
using plan_parts::with_xyz;
namespace var = macros::var;

class SpindleModel final : public PlanModel {
 public:
  explicit SpindleModel(const SpindlePlan& plan) : plan_(plan) {
    SpindleConfig config = realistic_spindle();
    config.ball_mm[0] = plan.ball_mm[0];
    config.ball_mm[1] = plan.ball_mm[1];
    const VirtualSpindle spindle(config);
    geometry_ = spindle.geometry();
    AnalyserConfig analyser;
    analyser.revolutions = plan.revolutions;
    analyser.samples_per_revolution = plan.samples_per_revolution;
    analyser.noise_sigma_mm = 0.0;
    analyser.form_rms_mm = 0.0;
    SimRng rng(1);
    samples_ = VirtualAnalyser(analyser).measure(
        [&spindle](int ball, double phi_deg) { return spindle.ball_mm(ball, phi_deg); }, rng);
    for (const core::SpindleSample& s : samples_) readings_.push_back({s.p_mm, Mat3::Identity() * plan.sigma_mm});
    const double tilt = macros::spindle::kDefaultCheckTiltArcsec;
    const double offset = macros::spindle::kDefaultCheckOffsetMm;
    outputs_ = {{"o_x", "mm", 0.0},        {"o_y", "mm", 0.0},        {"o_z", "mm", 0.0},
                {"a_x", "arcsec", tilt},   {"a_y", "arcsec", tilt},   {"e_x", "mm", offset},
                {"e_y", "mm", offset},     {"w_x", "arcsec", tilt},   {"w_y", "arcsec", tilt}};
  }

  const char* method() const override { return "spindle"; }
  std::string description() const override {
    return std::to_string(plan_.revolutions) + " revolutions x " + std::to_string(plan_.samples_per_revolution) +
           plan_text(" angles, balls %g and %g mm below the gauge line, read to %g nm (1 sigma per axis)", plan_.ball_mm[0],
                plan_.ball_mm[1], plan_.sigma_mm * 1e6);
  }
  const std::vector<PlanReading>& readings() const override { return readings_; }
  const std::vector<PlanOutput>& outputs() const override { return outputs_; }

  bool evaluate(const std::vector<Vec3>& values, std::vector<double>& out, std::string& error) const override {
    for (std::size_t i = 0; i < values.size(); ++i) samples_[i].p_mm = values[i];
    core::SpindleFit fit;
    const core::Status s = core::fit_spindle(samples_.data(), samples_.size(), geometry_, fit);
    if (s != core::Status::kOk) {
      error = refusal(s);
      return false;
    }
    out.resize(core::kSpindleParams);
    for (int k = 0; k < core::kSpindleParams; ++k) {
      const bool angle = k == 3 || k == 4 || k == 7 || k == 8;
      out[static_cast<std::size_t>(k)] = fit.params(k) * (angle ? kArcsecPerRad : 1.0);
    }
    return true;
  }

  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override {
    return {{var::kSpindleProbeNoise, plan_.sigma_mm}};
  }
  // As trueaxis-calibrate spindle: 9840, a 9841 per reading, 9842 with the lengths and R = 0.
  std::vector<PlanMacro> module_macros(const std::vector<Vec3>& values) const override {
    std::vector<PlanMacro> out = {{macros::spindle::kMacroSessionClear, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const core::SpindleSample& s = samples_[i];
      out.push_back({macros::spindle::kMacroSessionAdd, with_xyz({{var::kArgS, s.phi_deg}, {var::kArgT, static_cast<double>(s.ball)}}, values[i]),
                     plan_text("reading %zu (ball %d at %g deg)", i + 1, s.ball, s.phi_deg)});
    }
    out.push_back({macros::spindle::kMacroBuild,
                   {{var::kArgD, geometry_.gauge_mm}, {var::kArgU, geometry_.ball_mm[0]}, {var::kArgV, geometry_.ball_mm[1]},
                    {var::kArgR, 0.0}},
                   ""});
    return out;
  }

  std::vector<PlanChange> candidates() const override {
    std::vector<PlanChange> out;
    SpindlePlan next = plan_;
    next.revolutions += 1;
    out.push_back({plan_text("one more revolution (%d)", next.revolutions), std::make_shared<SpindleModel>(next)});
    if (plan_.samples_per_revolution * 2 <= kMaxSamplesPerRevolution) {
      next = plan_;
      next.samples_per_revolution *= 2;
      out.push_back({plan_text("twice the angles a revolution (%d)", next.samples_per_revolution),
                     std::make_shared<SpindleModel>(next)});
    }
    next = plan_;
    next.ball_mm[1] += 50.0;
    out.push_back({plan_text("ball 2 50 mm farther along the tool (%g mm)", next.ball_mm[1]),
                   std::make_shared<SpindleModel>(next)});
    return out;
  }

 private:
  SpindlePlan plan_;
  core::SpindleGeometry geometry_;
  mutable std::vector<core::SpindleSample> samples_;
  std::vector<PlanReading> readings_;
  std::vector<PlanOutput> outputs_;
};

}  // namespace

std::shared_ptr<const PlanModel> spindle_model(const SpindlePlan& plan) {
  return std::make_shared<SpindleModel>(plan);
}

namespace {

class SpindlePlanOptions final : public PlanOptions {
 public:
  const char* help() const override {
    return "  spindle   --revolutions R (3) --angles N (a revolution, 8..4096; 72) --balls B1,B2 (mm below\n"
           "            the gauge line; 50,150) --noise-nm S (1 sigma per axis; 15)\n";
  }

  Take take(const std::string& arg, const std::string& value, bool has, std::string& form) override {
    std::vector<double> v;
    bool ok = has;
    if (arg == "--revolutions") {
      form = "1..100";
      ok = ok && plan_whole(value, 1, 100, plan_.revolutions);
    } else if (arg == "--angles") {
      form = "8..4096 a revolution";
      ok = ok && plan_whole(value, 8, 4096, plan_.samples_per_revolution);
    } else if (arg == "--balls") {
      form = "B1,B2 in mm below the gauge line, 0 < B1 < B2";
      ok = ok && plan_numbers(value, 2, v) && v[0] > 0.0 && v[1] > v[0];
      if (ok) plan_.ball_mm[0] = v[0], plan_.ball_mm[1] = v[1];
    } else if (arg == "--noise-nm") {
      form = "nanometres, > 0";
      double nm = 0.0;
      ok = ok && plan_positive(value, nm);
      plan_.sigma_mm = nm * 1e-6;
    } else {
      return Take::kNotMine;
    }
    return ok ? Take::kTaken : Take::kBad;
  }

  std::shared_ptr<const PlanModel> finish(std::string&, bool&) override { return spindle_model(plan_); }

 private:
  SpindlePlan plan_;
};

}  // namespace

std::unique_ptr<PlanOptions> plan_options_spindle() { return std::make_unique<SpindlePlanOptions>(); }

}  // namespace trueaxis::sim
