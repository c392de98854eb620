// The gantry plan (M2; planner.hpp contract 1): its readings on the simulator's machine, its
// outputs, its evaluation by the method's own firmware_core routine (the module's code, called
// directly), and its one-pose changes (contract 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "trueaxis/core/gantry_frames.hpp"
#include "trueaxis/core/so3.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/sim/instruments/laser_tracker.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"
#include "trueaxis/sim/tools/plan_parts.hpp"
#include "trueaxis/sim/tools/gantry_plan.hpp"
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

// A samples group's place in GantryInput (docs/INTERFACE.md "M2 gantry").
struct GroupRange {
  std::string name;
  std::size_t begin = 0;
  std::size_t count = 0;
};

class GantryModel final : public PlanModel {
 public:
  explicit GantryModel(const GantryPlanSpec& spec)
      : spec_(spec), machine_(realistic_gantry()), frames_(std::make_unique<core::GantryFrames>()) {
    const LaserTracker tracker =
        place_tracker(machine_, gantry_tracker_placement(spec), gantry_tracker_spec(spec), false);
    const GantryPlan plan = gantry_measuring_plan(spec);
    SimRng rng(1);  // no noise: no draws
    for (const TrackerSample& s : measure_gantry(machine_, tracker, plan, rng)) {
      const double range = s.p_mm.norm();
      const Vec3 scale(tracker.radial_sigma_mm(range), tracker.transverse_sigma_mm(range),
                       tracker.transverse_sigma_mm(range));
      readings_.push_back({s.p_mm, LaserTracker::sight_basis(s.p_mm) * scale.asDiagonal()});
      if (groups_.empty() || groups_.back().name != s.group) groups_.push_back({s.group, readings_.size() - 1, 0});
      ++groups_.back().count;
    }
    points_.resize(readings_.size());
    for (std::size_t i = 0; i < machine_.sub_machine_count(); ++i) {
      const SubMachineConfig& c = machine_.config().sub_machines[i];
      tools_.push_back(tracker.tracker_T_machine().rotation * c.tool_nominal);
      const std::string sp = "sp" + std::to_string(c.id) + " ";
      // The check judges the origin's move and the frame's turn by their lengths.
      const int origin_group = 2 * static_cast<int>(i) + 1;
      for (const char* k : {"x", "y", "z"}) {
        outputs_.push_back({sp + "origin_" + k, "mm", macros::gantry::kDefaultCheckOriginMm, false, origin_group});
      }
      for (const char* k : {"x", "y", "z"}) {
        outputs_.push_back(
            {sp + "axes_turn_" + k, "arcsec", macros::gantry::kDefaultCheckAngleArcsec, false, origin_group + 1});
      }
      for (const char* k : {"xy", "yz", "zx"}) outputs_.push_back({sp + "squareness_" + k, "arcsec", 0.0});
      // Signed along the nominal c x a: the length OUT.json reports folds at 0,
      // and a few sigma from it its spread is not the linear one.
      outputs_.push_back({sp + "a_c_offset_signed", "mm", 0.0});
      outputs_.push_back({sp + "a_c_angle_minus_90", "arcsec", 0.0});
    }
    // The nominal frames' axes, the reference of each frame's turn.
    std::vector<Vec3> values(readings_.size());
    for (std::size_t i = 0; i < readings_.size(); ++i) values[i] = readings_[i].value;
    nominal_ok_ = compute(values, nominal_error_);
    if (nominal_ok_) {
      for (std::size_t i = 0; i < frames_->sub_machine_count; ++i) {
        const core::SubMachineFrame& f = frames_->sub_machines[i];
        nominal_R_.push_back(f.global_T_sub.R);
        nominal_ca_.push_back(f.c_circle.normal.cross(f.a_circle.normal).normalized());
      }
    }
  }

  const char* method() const override { return "gantry"; }
  std::string description() const override {
    return std::to_string(machine_.sub_machine_count()) + " sub-machines of the simulator's gantry; pads " +
           plan_text("%d x %d points, ", spec_.pad_grid, spec_.pad_grid) + std::to_string(spec_.passes) +
           " passes of " + std::to_string(spec_.pass_points) + " points per axis, C circle " +
           std::to_string(spec_.circle_points) + plan_text(" points %g..%g deg, A circle ", spec_.c_from_deg, spec_.c_to_deg) +
           std::to_string(spec_.circle_points) + plan_text(" points %g..%g deg", spec_.a_from_deg, spec_.a_to_deg) +
           plan_text("; tracker %g m in front, MPE +-(%g um + %g um/m), distance meter +-%g um, read as 2 sigma",
                spec_.tracker_distance_m, spec_.transverse_mpe_mm * 1000.0, spec_.transverse_mpe_per_m_mm * 1000.0,
                spec_.radial_mpe_mm * 1000.0);
  }
  const std::vector<PlanReading>& readings() const override { return readings_; }
  const std::vector<PlanOutput>& outputs() const override { return outputs_; }

  bool evaluate(const std::vector<Vec3>& values, std::vector<double>& out, std::string& error) const override {
    if (!nominal_ok_) {
      error = nominal_error_;
      return false;
    }
    if (!compute(values, error)) return false;
    out.clear();
    for (std::size_t i = 0; i < frames_->sub_machine_count; ++i) {
      const core::SubMachineFrame& f = frames_->sub_machines[i];
      for (int k = 0; k < 3; ++k) out.push_back(f.global_T_sub.t(k));
      const Vec3 turn = core::so3_log(nominal_R_[i].transpose() * f.global_T_sub.R) * kArcsecPerRad;
      for (int k = 0; k < 3; ++k) out.push_back(turn(k));
      for (int k = 0; k < 3; ++k) out.push_back(f.squareness_arcsec(k));
      out.push_back((f.a_circle.centre_mm - f.c_circle.centre_mm).dot(nominal_ca_[i]));
      out.push_back((f.a_c_angle_deg - 90.0) * 3600.0);
    }
    return true;
  }

  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override {
    // The tracker's transverse MPE read as 2 sigma, as the plan reads it (#701 + #702 r).
    return {{var::kGantryTrackerNoise, spec_.transverse_mpe_mm / 2.0},
            {var::kGantryTrackerNoisePerM, spec_.transverse_mpe_per_m_mm / 2.0}};
  }
  // As trueaxis-calibrate gantry: 9820, a 9821 per reading in group order,
  // a 9822 per sub-machine (its swing length and nominal tool direction), 9823 with R = 0.
  std::vector<PlanMacro> module_macros(const std::vector<Vec3>& values) const override {
    std::vector<PlanMacro> out = {{macros::gantry::kMacroSessionClear, {}, ""}};
    for (const GroupRange& g : groups_) {
      int t = 0, q = 0, d = 0;
      if (g.name == "bed" || g.name == "side_1" || g.name == "side_2") {
        q = g.name == "bed" ? 1 : g.name == "side_1" ? 2 : 3;
      } else if (g.name.rfind("gantry_", 0) == 0) {
        q = 4;
        d = std::atoi(g.name.c_str() + 7);
      } else {
        t = std::atoi(g.name.c_str() + 2);
        const std::string rest = g.name.substr(g.name.find('_') + 1);
        q = rest == "c" ? 8 : rest == "a" ? 9 : 5 + (rest[0] - 'x');
        d = rest.size() > 2 ? std::atoi(rest.c_str() + 2) : 0;
      }
      for (std::size_t i = g.begin; i < g.begin + g.count; ++i) {
        out.push_back({macros::gantry::kMacroSessionAdd,
                       with_xyz({{var::kArgT, static_cast<double>(t)}, {var::kArgQ, static_cast<double>(q)},
                                 {var::kArgD, static_cast<double>(d)}},
                                values[i]),
                       plan_text("reading %zu (group %s)", i + 1, g.name.c_str())});
      }
    }
    for (std::size_t k = 0; k < machine_.sub_machine_count(); ++k) {
      const SubMachineConfig& c = machine_.config().sub_machines[k];
      out.push_back({macros::gantry::kMacroSubMachine,
                     {{var::kArgT, static_cast<double>(c.id)}, {var::kArgD, c.swing_mm}, {var::kArgI, tools_[k].x()},
                      {static_cast<std::uint16_t>(var::kArgI + 1), tools_[k].y()},
                      {static_cast<std::uint16_t>(var::kArgI + 2), tools_[k].z()}},
                     plan_text("sub-machine %d's swing length and tool direction", c.id)});
    }
    out.push_back({macros::gantry::kMacroBuild, {{var::kArgR, 0.0}}, ""});
    return out;
  }

  std::vector<PlanChange> candidates() const override {
    std::vector<PlanChange> out;
    auto add = [&](const std::string& what, const GantryPlanSpec& next) {
      out.push_back({what, std::make_shared<GantryModel>(next)});
    };
    GantryPlanSpec next = spec_;
    const double step = (spec_.a_to_deg - spec_.a_from_deg) / std::max(1, spec_.circle_points - 1);
    if (spec_.a_from_deg - step >= -spec_.a_limit_deg && spec_.a_to_deg + step <= spec_.a_limit_deg) {
      next = spec_;
      next.a_from_deg -= step;
      next.a_to_deg += step;
      next.circle_points = spec_.circle_points;
      add(plan_text("widen every A circle by one step at each end (%g..%g deg)", next.a_from_deg, next.a_to_deg), next);
    }
    if (spec_.c_to_deg - spec_.c_from_deg < 330.0) {
      next = spec_;
      next.c_to_deg = std::min(spec_.c_from_deg + 345.0, spec_.c_to_deg + 45.0);
      add(plan_text("widen every C circle to %g..%g deg", next.c_from_deg, next.c_to_deg), next);
    }
    // Within the module's session (a circle, a pass count): beyond it the module refuses the plan.
    if (spec_.circle_points + 4 <= static_cast<int>(macros::gantry::kMaxCirclePoints)) {
      next = spec_;
      next.circle_points += 4;
      add("4 more points on every C and A circle", next);
    }
    if (spec_.passes + 1 <= static_cast<int>(macros::gantry::kMaxPasses)) {
      next = spec_;
      next.passes += 1;
      add("one more pass of every linear axis and of the gantry", next);
    }
    next = spec_;
    next.pass_points += 5;
    add("5 more points on every pass", next);
    return out;
  }

 private:
  bool compute(const std::vector<Vec3>& values, std::string& error) const {
    std::copy(values.begin(), values.end(), points_.begin());
    core::GantryInput in;
    for (const GroupRange& g : groups_) {
      const core::PointSpan span{points_.data() + g.begin, g.count};
      if (g.name == "bed") {
        in.bed = span;
      } else if (g.name == "side_1") {
        in.side_1 = span;
      } else if (g.name == "side_2") {
        in.side_2 = span;
      } else if (g.name.rfind("gantry_", 0) == 0) {
        in.gantry_passes[in.gantry_pass_count++] = span;
      } else {
        const std::size_t us = g.name.find('_');
        const int id = std::atoi(g.name.c_str() + 2);
        std::size_t index = 0;
        while (index < in.sub_machine_count && in.sub_machines[index].id != id) ++index;
        core::SubMachineInput& sub = in.sub_machines[index];
        if (index == in.sub_machine_count) {
          ++in.sub_machine_count;
          sub.id = id;
          for (std::size_t k = 0; k < machine_.sub_machine_count(); ++k) {
            if (machine_.config().sub_machines[k].id != id) continue;
            sub.swing_mm = machine_.config().sub_machines[k].swing_mm;
            sub.tool_direction = tools_[k];
          }
        }
        const std::string rest = g.name.substr(us + 1);
        if (rest == "c") {
          sub.c_circle = span;
        } else if (rest == "a") {
          sub.a_circle = span;
        } else {
          const int axis = rest[0] - 'x';
          sub.passes[axis][sub.pass_count[axis]++] = span;
        }
      }
    }
    core::GantryOptions options;
    options.min_arc_deg = 30.0;  // #700's default
    const core::Status s = core::compute_gantry_frames(in, options, *frames_);
    if (s != core::Status::kOk) {
      error = refusal(s);
      return false;
    }
    return true;
  }

  GantryPlanSpec spec_;
  GantryMachine machine_;
  std::vector<PlanReading> readings_;
  std::vector<PlanOutput> outputs_;
  std::vector<GroupRange> groups_;
  std::vector<Vec3> tools_;
  std::vector<Mat3> nominal_R_;
  std::vector<Vec3> nominal_ca_;  // unit(c x a) of the nominal frames
  bool nominal_ok_ = false;
  std::string nominal_error_;
  mutable std::vector<Vec3> points_;
  std::unique_ptr<core::GantryFrames> frames_;
};

}  // namespace

GantryPlan gantry_measuring_plan(const GantryPlanSpec& spec) {
  GantryPlan plan;
  plan.pad_grid = spec.pad_grid;
  plan.side_rows = spec.side_rows;
  plan.side_cols = spec.side_cols;
  plan.passes = spec.passes;
  plan.pass_points = spec.pass_points;
  plan.circle_points = spec.circle_points;
  plan.c_from_deg = spec.c_from_deg;
  plan.c_to_deg = spec.c_to_deg;
  plan.a_from_deg = spec.a_from_deg;
  plan.a_to_deg = spec.a_to_deg;
  return plan;
}

TrackerSpec gantry_tracker_spec(const GantryPlanSpec& spec) {
  TrackerSpec t;
  t.radial_mpe_mm = spec.radial_mpe_mm;
  t.transverse_mpe_mm = spec.transverse_mpe_mm;
  t.transverse_mpe_per_m_mm = spec.transverse_mpe_per_m_mm;
  return t;
}

TrackerPlacement gantry_tracker_placement(const GantryPlanSpec& spec) {
  TrackerPlacement p;
  p.distance_m = spec.tracker_distance_m;
  return p;
}

std::shared_ptr<const PlanModel> gantry_model(const GantryPlanSpec& plan) {
  return std::make_shared<GantryModel>(plan);
}

namespace {

class GantryPlanOptions final : public PlanOptions {
 public:
  const char* help() const override {
    return "  gantry    --pad-grid N (5) --side-grid ROWS,COLS (4,5) --passes N (3) --pass-points N (15) --circle-points N (5..36; 24)\n"
           "            --c-arc FROM,TO (0,345) --a-arc FROM,TO (-90,90) --mpe UM,UM_PER_M (15,6: the tracker's\n"
           "            point MPE, read as 2 sigma across the line of sight) --radial-mpe UM (10)\n"
           "            --tracker-distance M (in front of the machine's front; 2.5)\n";
  }

  Take take(const std::string& arg, const std::string& value, bool has, std::string& form) override {
    std::vector<double> v;
    bool ok = has;
    if (arg == "--pad-grid") {
      form = "2..11";
      ok = ok && plan_whole(value, 2, 11, spec_.pad_grid);
    } else if (arg == "--side-grid") {
      form = "ROWS,COLS: 2..20 each";
      ok = ok && plan_numbers(value, 2, v) && v[0] >= 2 && v[0] <= 20 && v[1] >= 2 && v[1] <= 20 &&
           v[0] == std::floor(v[0]) && v[1] == std::floor(v[1]);
      if (ok) spec_.side_rows = static_cast<int>(v[0]), spec_.side_cols = static_cast<int>(v[1]);
    } else if (arg == "--passes") {
      form = "1..8";
      ok = ok && plan_whole(value, 1, 8, spec_.passes);
    } else if (arg == "--pass-points") {
      form = "3..60";
      ok = ok && plan_whole(value, 3, 60, spec_.pass_points);
    } else if (arg == "--circle-points") {
      form = "5..36 (the module's session holds 30 a circle: more is refused as it refuses them)";
      ok = ok && plan_whole(value, 5, 36, spec_.circle_points);
    } else if (arg == "--c-arc" || arg == "--a-arc") {
      form = "FROM,TO in degrees, FROM < TO, less than a turn";
      ok = ok && plan_numbers(value, 2, v) && v[0] < v[1] && v[1] - v[0] < 360.0;
      if (ok && arg == "--c-arc") spec_.c_from_deg = v[0], spec_.c_to_deg = v[1];
      if (ok && arg == "--a-arc") spec_.a_from_deg = v[0], spec_.a_to_deg = v[1];
    } else if (arg == "--mpe") {
      form = "UM,UM_PER_M: micrometres > 0 and micrometres per metre >= 0";
      ok = ok && plan_numbers(value, 2, v) && v[0] > 0.0 && v[1] >= 0.0;
      if (ok) spec_.transverse_mpe_mm = v[0] / 1000.0, spec_.transverse_mpe_per_m_mm = v[1] / 1000.0;
    } else if (arg == "--tracker-distance") {
      form = "metres in front of the machine, 0 < M <= 30";
      ok = ok && plan_positive(value, spec_.tracker_distance_m) && spec_.tracker_distance_m <= 30.0;
    } else if (arg == "--radial-mpe") {
      form = "micrometres, > 0";
      double um = 0.0;
      ok = ok && plan_positive(value, um);
      spec_.radial_mpe_mm = um / 1000.0;
    } else {
      return Take::kNotMine;
    }
    return ok ? Take::kTaken : Take::kBad;
  }

  std::shared_ptr<const PlanModel> finish(std::string&, bool&) override { return gantry_model(spec_); }

 private:
  GantryPlanSpec spec_;
};

}  // namespace

std::unique_ptr<PlanOptions> plan_options_gantry() { return std::make_unique<GantryPlanOptions>(); }

}  // namespace trueaxis::sim
