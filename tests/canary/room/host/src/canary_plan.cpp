// The canary's plan (planner.hpp): N values read with a noise, the output the
// gain times their sum by the canary's own core function.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/canary_sum.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"
#include "trueaxis/sim/tools/plan_options.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

namespace {

constexpr double kGain = 2.0;  // #950's default

class CanaryModel final : public PlanModel {
 public:
  CanaryModel(int count, double sigma) : count_(count), sigma_(sigma) {
    for (int i = 0; i < count; ++i) {
      PlanReading r;
      r.value = core::Vec3(1.0 + i, 0.0, 0.0);
      r.noise_factor(0, 0) = sigma;
      readings_.push_back(r);
    }
    outputs_.push_back({"sum", "", 0.0, false, 0});
  }
  const char* method() const override { return "canary"; }
  std::string description() const override { return plan_text("%d values, noise %g", count_, sigma_); }
  const std::vector<PlanReading>& readings() const override { return readings_; }
  const std::vector<PlanOutput>& outputs() const override { return outputs_; }
  bool evaluate(const std::vector<core::Vec3>& values, std::vector<double>& out, std::string&) const override {
    double x[4] = {};
    for (std::size_t i = 0; i < values.size() && i < 4; ++i) x[i] = values[i].x();
    out = {kGain * core::canary_sum(x, values.size())};
    return true;
  }
  std::vector<PlanChange> candidates() const override {
    if (count_ >= 4) return {};
    return {{"add a value", std::make_shared<CanaryModel>(count_ + 1, sigma_)}};
  }
  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override { return {}; }
  std::vector<PlanMacro> module_macros(const std::vector<core::Vec3>& values) const override {
    std::vector<PlanMacro> m = {{9851, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      m.push_back({9852, {{macros::var::kArgA, values[i].x()}}, "value " + std::to_string(i + 1)});
    }
    m.push_back({9853, {{macros::var::kArgR, 0.0}}, ""});
    return m;
  }

 private:
  int count_;
  double sigma_;
  std::vector<PlanReading> readings_;
  std::vector<PlanOutput> outputs_;
};

class CanaryPlanOptions final : public PlanOptions {
 public:
  const char* help() const override { return "  canary    --values N (1..4; 3) --noise S (1 sigma; 0.1)\n"; }
  Take take(const std::string& arg, const std::string& value, bool has, std::string& form) override {
    bool ok = has;
    if (arg == "--values") {
      form = "1..4";
      ok = ok && plan_whole(value, 1, 4, count_);
    } else if (arg == "--noise") {
      form = "> 0";
      ok = ok && plan_positive(value, sigma_);
    } else {
      return Take::kNotMine;
    }
    return ok ? Take::kTaken : Take::kBad;
  }
  std::shared_ptr<const PlanModel> finish(std::string&, bool&) override {
    return std::make_shared<CanaryModel>(count_, sigma_);
  }

 private:
  int count_ = 3;
  double sigma_ = 0.1;
};

}  // namespace

std::unique_ptr<PlanOptions> plan_options_canary() { return std::make_unique<CanaryPlanOptions>(); }

}  // namespace trueaxis::sim
