// The level plan (M1; planner.hpp contract 1): its readings on the simulator's machine, its
// outputs, its evaluation by the method's own firmware_core routine (the module's code, called
// directly), and its one-pose changes (contract 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/so3.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/plan_parts.hpp"
#include "trueaxis/sim/tools/level_plan.hpp"
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

class LevelModel final : public PlanModel {
 public:
  explicit LevelModel(LevelPlan plan) : plan_(std::move(plan)) {
    const FaceConfig face;
    const double t = face.tilt_deg * core::kPi / 180.0;
    const double az = face.azimuth_deg * core::kPi / 180.0;
    normal_ = Vec3(std::sin(t) * std::cos(az), std::sin(t) * std::sin(az), std::cos(t));
    for (const auto& p : plan_.points) {
      const double z = face.height_mm - (normal_.x() * p.first + normal_.y() * p.second) / normal_.z();
      readings_.push_back({Vec3(p.first, p.second, z), Mat3::Identity() * plan_.sigma_mm});
    }
    // The normal's turn across and along the face's slope: e_slope turns the
    // tilt, e_level (the face's level line) swings it about the vertical.
    e_level_ = normal_.cross(Vec3::UnitZ()).normalized();
    e_slope_ = normal_.cross(e_level_);
    // 9816 judges the tilt left, the normal's whole turn: one length.
    outputs_ = {{"normal_turn_tilt", "arcsec", macros::level::kDefaultCheckToleranceArcsec, false, 1},
                {"normal_turn_level_line", "arcsec", macros::level::kDefaultCheckToleranceArcsec, false, 1},
                {"level_a", "arcsec", 0.0, true},
                {"level_c", "arcsec", 0.0, true}};
  }

  const char* method() const override { return "level"; }
  std::string description() const override {
    std::string p;
    for (const auto& q : plan_.points) p += (p.empty() ? "" : ", ") + plan_text("(%.1f, %.1f)", q.first + 0.0, q.second + 0.0);
    return std::to_string(plan_.points.size()) + " probe points " + p +
           plan_text(" mm on the simulator's face, read to %g um (1 sigma per axis)", plan_.sigma_mm * 1000.0);
  }
  const std::vector<PlanReading>& readings() const override { return readings_; }
  const std::vector<PlanOutput>& outputs() const override { return outputs_; }

  bool evaluate(const std::vector<Vec3>& values, std::vector<double>& out, std::string& error) const override {
    core::LevelInput in;
    in.points_mm = values.data();
    in.count = values.size();
    core::LevelConfig config;
    config.probe_sigma_mm = plan_.sigma_mm;
    const core::Result<core::LevelResult> r = core::level_face(in, config);
    if (!r.ok()) {
      error = refusal(r.status());
      return false;
    }
    const Vec3 turn = normal_.cross(r.value().normal_table);
    out = {turn.dot(e_level_) * kArcsecPerRad, turn.dot(e_slope_) * kArcsecPerRad,
           r.value().chosen.a_deg * 3600.0, r.value().chosen.c_deg * 3600.0};
    return true;
  }

  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override {
    return {{var::kProbeSigma, plan_.sigma_mm}};
  }
  // The operator's session: 9812, a 9813 per probe point, 9814 with the table at zero.
  std::vector<PlanMacro> module_macros(const std::vector<Vec3>& values) const override {
    std::vector<PlanMacro> out = {{macros::level::kMacroSessionClear, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      out.push_back({macros::level::kMacroSessionAdd, with_xyz({}, values[i]),
                     plan_text("probe point %zu (%g, %g mm)", i + 1, plan_.points[i].first, plan_.points[i].second)});
    }
    out.push_back({macros::level::kMacroSessionCompute, {{var::kArgA, 0.0}, {var::kArgC, 0.0}}, ""});
    return out;
  }

  std::vector<PlanChange> candidates() const override {
    std::vector<PlanChange> out;
    if (plan_.points.empty()) return out;
    double cx = 0.0, cy = 0.0, r = 0.0;
    for (const auto& p : plan_.points) {
      cx += p.first / static_cast<double>(plan_.points.size());
      cy += p.second / static_cast<double>(plan_.points.size());
    }
    for (const auto& p : plan_.points) r = std::max(r, std::hypot(p.first - cx, p.second - cy));
    for (int k = 0; k < 8; ++k) {
      const double angle = k * core::kPi / 4.0;
      LevelPlan next = plan_;
      // Rounded to 0.1 mm, as an operator would write it (and no -0.0).
      next.points.emplace_back(std::round(10.0 * (cx + 1.5 * r * std::cos(angle))) / 10.0 + 0.0,
                               std::round(10.0 * (cy + 1.5 * r * std::sin(angle))) / 10.0 + 0.0);
      out.push_back({plan_text("add the probe point (%.1f, %.1f) mm", next.points.back().first, next.points.back().second),
                     std::make_shared<LevelModel>(next)});
    }
    return out;
  }

 private:
  LevelPlan plan_;
  Vec3 normal_ = Vec3::UnitZ();
  Vec3 e_level_ = Vec3::UnitX();
  Vec3 e_slope_ = Vec3::UnitY();
  std::vector<PlanReading> readings_;
  std::vector<PlanOutput> outputs_;
};

}  // namespace

LevelPlan level_plan(double side_mm) {
  LevelPlan plan;
  const double r = side_mm / std::sqrt(3.0);
  for (int i = 0; i < 3; ++i) {
    const double angle = core::kPi / 2.0 + 2.0 * core::kPi * i / 3.0;
    plan.points.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  return plan;
}
std::shared_ptr<const PlanModel> level_model(const LevelPlan& plan) { return std::make_shared<LevelModel>(plan); }

namespace {

class LevelPlanOptions final : public PlanOptions {
 public:
  const char* help() const override {
    return "  level     --side MM (the probing triangle's side; 100) or --points X,Y;X,Y;... (mm),\n"
           "            --noise-um U (1 sigma per axis; 0.5)\n";
  }

  Take take(const std::string& arg, const std::string& value, bool has, std::string& form) override {
    std::vector<double> v;
    bool ok = has;
    if (arg == "--noise-um") {
      form = "micrometres, > 0";
      double um = 0.0;
      ok = ok && plan_positive(value, um);
      plan_.sigma_mm = um / 1000.0;
    } else if (arg == "--side") {
      form = "millimetres, > 0";
      double side = 0.0;
      ok = ok && plan_positive(value, side);
      if (ok) plan_.points = level_plan(side).points;
    } else if (arg == "--points") {
      form = "X,Y;X,Y;X,Y... in mm, at least 3 points";
      plan_.points.clear();
      std::size_t from = 0;
      while (ok && from < value.size()) {
        const std::size_t semi = value.find(';', from);
        const std::string point = value.substr(from, semi == std::string::npos ? std::string::npos : semi - from);
        ok = plan_numbers(point, 2, v);
        if (ok) plan_.points.emplace_back(v[0], v[1]);
        if (semi == std::string::npos) break;
        from = semi + 1;  // a trailing ';' ends the list
      }
      ok = ok && plan_.points.size() >= 3;
    } else {
      return Take::kNotMine;
    }
    return ok ? Take::kTaken : Take::kBad;
  }

  std::shared_ptr<const PlanModel> finish(std::string&, bool&) override { return level_model(plan_); }

 private:
  LevelPlan plan_ = level_plan(100.0);
};

}  // namespace

std::unique_ptr<PlanOptions> plan_options_level() { return std::make_unique<LevelPlanOptions>(); }

}  // namespace trueaxis::sim
