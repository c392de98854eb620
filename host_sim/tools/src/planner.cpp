// trueaxis-calibrate plan: the linearised prediction, the suggestions and the
// texts (planner.hpp contracts 2-5).
#include "trueaxis/sim/tools/planner.hpp"

#include "trueaxis/sim/tools/plan_options.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/sim/sim_math.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"

namespace trueaxis::sim {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  return plan_text("%.9g", v);
}

// The 95th percentile of |d|, d the normal vector of the outputs `members`
// (at most 3) with their block of the covariance: from its eigenvalues,
// |d|^2 = sum lambda_i z_i^2, by a fixed-seed Monte Carlo of 40,000 draws
// (the percentile's standard error about 0.3 %, the same every run).
double length_q95(const std::vector<double>& cov, std::size_t n, const std::vector<std::size_t>& members) {
  const std::size_t k = std::min<std::size_t>(members.size(), 3);
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = cov[members[i] * n + members[j]];
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(block, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = eigen.eigenvalues().cwiseMax(0.0);
  SimRng rng(0x9E3779B97F4A7C15ull);
  std::vector<double> r2(40000);
  for (double& x : r2) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double z = rng.normal();
      sum += lambda(i) * z * z;
    }
    x = sum;
  }
  const std::size_t at = r2.size() * 95 / 100;
  std::nth_element(r2.begin(), r2.begin() + static_cast<std::ptrdiff_t>(at), r2.end());
  return std::sqrt(r2[at]);
}

// The module's clock in this process: a millisecond a call, so that no
// interface hold or unlock runs out between the plan's macros.
class StepClock final : public hal::Clock {
  std::uint64_t us_ = 0;
  std::uint64_t do_now_us() override { return us_ += 1000; }
};

}  // namespace

std::string module_refusal(const PlanModel& model) {
  namespace var = macros::var;
  // One draw of the instrument's noise on every reading (contract 6).
  const std::vector<PlanReading>& readings = model.readings();
  std::vector<core::Vec3> values(readings.size());
  SimRng rng(0x7A5E5EEDull);
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const core::Vec3 z(rng.normal(), rng.normal(), rng.normal());
    values[i] = readings[i].value + readings[i].noise_factor * z;
  }
  std::vector<std::uint8_t> bytes(macros::kRequiredStorageBytes, 0);
  hal::RamNvStorage storage(bytes.data(), bytes.size());
  StepClock clock;
  const auto module = std::make_unique<macros::Module>(storage, clock);
  if (module->start() != core::Status::kOk) return "the planner's module did not start";
  const auto write = [&module](std::uint16_t number, double value) { return module->write(number, 1, &value); };
  const auto refused_write = [](std::uint16_t number, double value, macros::AccessFault f) {
    std::string text = "the module refuses #" + std::to_string(number) + plan_text(" = %.9g", value);
    for (const macros::AccessFaultInfo& info : macros::kAccessFaultTable) {
      if (info.fault == f) text += std::string(": ") + info.name + ": " + info.message;
    }
    return text;
  };
  const auto configuration = model.module_configuration();
  if (!configuration.empty()) {
    if (write(var::kUnlock, macros::kUnlockCode) != macros::AccessFault::kNone) return "the planner's module did not unlock";
    for (const auto& [number, value] : configuration) {
      const macros::AccessFault f = write(number, value);
      if (f != macros::AccessFault::kNone) return "the plan's configuration: " + refused_write(number, value, f);
    }
    static_cast<void>(write(var::kUnlock, 0.0));
  }
  for (const PlanMacro& m : model.module_macros(values)) {
    const std::string what = m.what.empty() ? "" : m.what + ": ";
    for (const auto& [number, value] : m.arguments) {
      const macros::AccessFault f = write(number, value);
      if (f != macros::AccessFault::kNone) return what + refused_write(number, value, f);
    }
    if (write(var::kCmd, m.macro) != macros::AccessFault::kNone) return what + "macro " + std::to_string(m.macro) + " not started";
    for (long steps = 0; module->busy(); ++steps) {
      if (steps > 100000000L) return what + "macro " + std::to_string(m.macro) + " did not finish";
      module->step();
    }
    if (module->value(var::kStatus) == 3.0) {
      const double item = module->value(var::kGateItem);
      const double value = module->value(var::kGateValue);
      const double limit = module->value(var::kGateLimit);
      std::string gate;
      if (item != 0.0 || value != 0.0 || limit != 0.0) {
        gate = item != 0.0 ? plan_text("; item %g (#9012): %.6g (#9013) against the limit %.6g (#9014)", item, value, limit)
                           : plan_text("; %.6g (#9013) against the limit %.6g (#9014)", value, limit);
      }
      return what + module_error_text(static_cast<int>(module->value(var::kError))) + " (macro " +
             std::to_string(m.macro) + gate + ")";
    }
  }
  return "";
}

std::string plan_text(const char* format, ...) {
  char buf[256];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return buf;
}

PlanPrediction predict_plan(const PlanModel& model, const std::function<void(std::size_t, std::size_t)>& progress) {
  PlanPrediction p;
  p.outputs = model.outputs();
  const std::vector<PlanReading>& readings = model.readings();
  p.readings = readings.size();
  if (readings.size() > kMaxPlanReadings) {
    p.error = "the plan has " + std::to_string(readings.size()) + " readings, more than the planner's " +
              std::to_string(kMaxPlanReadings) + " (its 3 n evaluations each run the method over all n): plan fewer " +
              "(repeated revolutions or passes average as 1/sqrt(n): predict a shorter plan and scale)";
    return p;
  }
  // Contract 6: what the module would refuse is refused first, in its words.
  p.error = module_refusal(model);
  if (!p.error.empty()) return p;
  std::vector<core::Vec3> values(readings.size());
  for (std::size_t i = 0; i < readings.size(); ++i) values[i] = readings[i].value;
  if (!model.evaluate(values, p.value, p.error)) return p;
  ++p.evaluations;
  const std::size_t n = p.outputs.size();
  if (p.value.size() != n) {
    p.error = "the method gave " + std::to_string(p.value.size()) + " outputs, not " + std::to_string(n);
    return p;
  }
  p.covariance.assign(n * n, 0.0);
  // Forward differences of one sigma: the methods are smooth on the scale of
  // their noise (micrometres against the plan's millimetres), so the step's
  // second-order error is ~1e-5 of the derivative, and half the evaluations
  // of central differences.
  const std::vector<double> nominal = p.value;
  std::vector<double> moved, g(n);
  const std::size_t total = 1 + 3 * readings.size();
  for (std::size_t i = 0; i < readings.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const core::Vec3 step = readings[i].noise_factor.col(k);
      if (step.squaredNorm() == 0.0) continue;
      values[i] = readings[i].value + step;
      const bool ok = model.evaluate(values, moved, p.error);
      values[i] = readings[i].value;
      ++p.evaluations;
      if (!ok) {
        p.error = "one sigma of noise on reading " + std::to_string(i + 1) + " makes the method refuse: " + p.error;
        return p;
      }
      for (std::size_t a = 0; a < n; ++a) {
        g[a] = moved[a] - nominal[a];
        if (!std::isfinite(g[a])) {
          p.error = "output " + p.outputs[a].name + " is not finite at reading " + std::to_string(i + 1) +
                    " moved by one sigma: the plan is at a singularity of the method";
          return p;
        }
      }
      for (std::size_t a = 0; a < n; ++a) {
        for (std::size_t b = 0; b < n; ++b) p.covariance[a * n + b] += g[a] * g[b];
      }
    }
    if (progress) progress(p.evaluations, total);
  }
  p.sigma.resize(n);
  for (std::size_t a = 0; a < n; ++a) p.sigma[a] = std::sqrt(p.covariance[a * n + a]);
  // Contract 3: each judged figure's 95th percentile, a group's from its block.
  p.q95.assign(n, 0.0);
  for (std::size_t a = 0; a < n; ++a) {
    if (p.outputs[a].tolerance <= 0.0) continue;
    if (p.outputs[a].group == 0) {
      p.q95[a] = 1.959963984540054 * p.sigma[a];
      continue;
    }
    if (a > 0 && p.outputs[a - 1].group == p.outputs[a].group) {
      p.q95[a] = p.q95[a - 1];
      continue;
    }
    std::vector<std::size_t> members;
    for (std::size_t b = a; b < n && p.outputs[b].group == p.outputs[a].group; ++b) members.push_back(b);
    p.q95[a] = length_q95(p.covariance, n, members);
  }
  p.valuation = 0.0;
  bool judged = false;
  for (std::size_t a = 0; a < n; ++a) {
    if (p.outputs[a].tolerance <= 0.0) continue;
    if (a > 0 && p.outputs[a].group != 0 && p.outputs[a - 1].group == p.outputs[a].group) continue;
    const double v = p.q95[a] / p.outputs[a].tolerance;
    if (!judged || v > p.valuation) {
      p.valuation = v;
      p.worst = a;
      judged = true;
    }
  }
  // Contract 4. Outputs that do not move (a reference pose's zeros) have no
  // correlation.
  // An output that does not move (sigma 0 to rounding against the largest
  // sigma of its own unit) correlates with nothing.
  const auto moves = [&p, n](std::size_t a) {
    double largest = 0.0;
    for (std::size_t b = 0; b < n; ++b) {
      if (p.outputs[b].unit == p.outputs[a].unit) largest = std::max(largest, p.sigma[b]);
    }
    return p.sigma[a] > 1e-12 * largest;
  };
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      if (!moves(a) || !moves(b)) continue;
      if (p.outputs[a].derived || p.outputs[b].derived) continue;
      const double rho = p.covariance[a * n + b] / (p.sigma[a] * p.sigma[b]);
      if (std::fabs(rho) > kInseparable) p.inseparable.push_back({a, b, rho});
    }
  }
  p.ok = true;
  return p;
}

std::vector<PlanSuggestion> suggest_changes(const PlanModel& model, const PlanPrediction& base, int count,
                                            const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<PlanSuggestion> out;
  if (!base.ok) return out;
  std::shared_ptr<const PlanModel> current;
  const PlanModel* from = &model;
  double valuation = base.valuation;
  for (int round = 0; round < count; ++round) {
    const std::vector<PlanChange> changes = from->candidates();
    double best = valuation;
    std::size_t best_index = changes.size();
    PlanPrediction best_prediction;
    for (std::size_t i = 0; i < changes.size(); ++i) {
      const PlanPrediction p = predict_plan(*changes[i].plan);
      if (progress) progress(i + 1, changes.size());
      if (p.ok && p.valuation < best) {
        best = p.valuation;
        best_index = i;
        best_prediction = p;
      }
    }
    if (best_index == changes.size()) break;
    PlanSuggestion s;
    s.what = changes[best_index].what;
    s.valuation = best;
    s.worst = best_prediction.outputs[best_prediction.worst].name;
    s.description = changes[best_index].plan->description();
    out.push_back(s);
    current = changes[best_index].plan;
    from = current.get();
    valuation = best;
  }
  return out;
}

std::string plan_table(const PlanModel& model, const PlanPrediction& p, const std::vector<PlanSuggestion>& s,
                       bool searched) {
  std::string t = std::string("plan ") + model.method() + ": " + model.description() + "\n";
  if (!p.ok) return t + "the method refuses this plan: " + p.error + "\n";
  t += std::to_string(p.readings) + " readings, " + std::to_string(p.evaluations) + " evaluations of the method\n";
  t += "output                                      value        1-sigma      tolerance    q95 / tol\n";
  for (std::size_t i = 0; i < p.outputs.size(); ++i) {
    const PlanOutput& o = p.outputs[i];
    char line[256];
    if (o.tolerance > 0.0) {
      std::snprintf(line, sizeof line, "%-40s %12.6g %12.4g %-6s %8.4g %10.3g%s%s\n", o.name.c_str(), p.value[i],
                    p.sigma[i], o.unit.c_str(), o.tolerance, p.q95[i] / o.tolerance, o.group != 0 ? " (length)" : "",
                    i == p.worst ? "  <- worst" : "");
    } else {
      std::snprintf(line, sizeof line, "%-40s %12.6g %12.4g %-6s %8s %10s\n", o.name.c_str(), p.value[i], p.sigma[i],
                    o.unit.c_str(), "-", "-");
    }
    t += line;
  }
  t += plan_text("valuation %.3g", p.valuation) + " (the worst figure's 95th percentile / tolerance: " +
       p.outputs[p.worst].name +
       "; below 1 the plan's noise stays within every tolerance 95 % of the time; an unchanged machine passes "
       "a check against a table from the same plan 95 % of the time below about 0.35)\n";
  if (p.inseparable.empty()) {
    t += "every output separated (no correlation beyond 0.99)\n";
  } else {
    for (const PlanInseparable& q : p.inseparable) {
      t += "not separated: " + p.outputs[q.first].name + " and " + p.outputs[q.second].name +
           plan_text(" (rho %+.4f)\n", q.rho);
    }
  }
  if (s.empty() && searched) t += "no change of one pose lowers the valuation\n";
  for (std::size_t i = 0; i < s.size(); ++i) {
    t += "suggestion " + std::to_string(i + 1) + ": " + s[i].what + plan_text(": valuation %.3g", s[i].valuation) +
         " (worst " + s[i].worst + ")\n";
  }
  return t;
}

std::string plan_json(const PlanModel& model, const PlanPrediction& p, const std::vector<PlanSuggestion>& s) {
  std::string j = std::string("{\n  \"method\": ") + quoted(model.method()) + ",\n  \"plan\": " +
                  quoted(model.description()) + ",\n";
  if (!p.ok) return j + "  \"refused\": " + quoted(p.error) + "\n}\n";
  j += "  \"readings\": " + std::to_string(p.readings) + ",\n  \"evaluations\": " + std::to_string(p.evaluations) +
       ",\n  \"outputs\": [\n";
  for (std::size_t i = 0; i < p.outputs.size(); ++i) {
    const PlanOutput& o = p.outputs[i];
    j += "    { \"name\": " + quoted(o.name) + ", \"unit\": " + quoted(o.unit) + ", \"value\": " + number(p.value[i]) +
         ", \"sigma\": " + number(p.sigma[i]) + ", \"tolerance\": " + (o.tolerance > 0.0 ? number(o.tolerance) : "null") +
         ", \"q95\": " + (o.tolerance > 0.0 ? number(p.q95[i]) : "null") + ", \"length_group\": " + std::to_string(o.group) +
         " }" + (i + 1 < p.outputs.size() ? ",\n" : "\n");
  }
  j += "  ],\n  \"valuation\": " + number(p.valuation) + ",\n  \"worst\": " + quoted(p.outputs[p.worst].name) +
       ",\n  \"inseparable\": [";
  for (std::size_t i = 0; i < p.inseparable.size(); ++i) {
    const PlanInseparable& q = p.inseparable[i];
    j += std::string(i ? ", " : "") + "{ \"outputs\": [" + quoted(p.outputs[q.first].name) + ", " +
         quoted(p.outputs[q.second].name) + "], \"rho\": " + number(q.rho) + " }";
  }
  j += "],\n  \"suggestions\": [";
  for (std::size_t i = 0; i < s.size(); ++i) {
    j += std::string(i ? ",\n    " : "\n    ") + "{ \"change\": " + quoted(s[i].what) +
         ", \"valuation\": " + number(s[i].valuation) + ", \"worst\": " + quoted(s[i].worst) +
         ", \"plan\": " + quoted(s[i].description) + " }";
  }
  j += s.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return j;
}

bool plan_numbers(const std::string& text, std::size_t count, std::vector<double>& out) {
  out.clear();
  const char* p = text.c_str();
  while (true) {
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v)) return false;
    out.push_back(v);
    if (*end == '\0') break;
    if (*end != ',') return false;
    p = end + 1;
  }
  return out.size() == count;
}

bool plan_whole(const std::string& text, int low, int high, int& out) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < low || v > high) return false;
  out = static_cast<int>(v);
  return true;
}

bool plan_positive(const std::string& text, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v > 0.0) || !std::isfinite(v)) return false;
  out = v;
  return true;
}

}  // namespace trueaxis::sim
