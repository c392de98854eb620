// The methods' plans (planner.hpp contract 1): each one's readings on the
// simulator's machine, its outputs, its evaluation by the method's own
// firmware_core routine (the module's code, called directly), and its
// one-pose changes (contract 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "trueaxis/core/gantry_frames.hpp"
#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/so3.hpp"
#include "trueaxis/core/spindle_model.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/instruments/laser_tracker.hpp"
#include "trueaxis/sim/instruments/spindle_analyser.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/machines/gantry_machine.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"
#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

namespace {

using core::Mat3;
using core::Vec3;

using core::kArcsecPerRad;

std::string refusal(core::Status s) { return module_error_text(static_cast<int>(s)); }

namespace var = macros::var;

// #X, #Y, #Z = p, after `first` (planner.hpp contract 6).
std::vector<std::pair<std::uint16_t, double>> with_xyz(std::vector<std::pair<std::uint16_t, double>> first, const Vec3& p) {
  first.push_back({var::kArgX, p.x()});
  first.push_back({static_cast<std::uint16_t>(var::kArgX + 1), p.y()});
  first.push_back({static_cast<std::uint16_t>(var::kArgX + 2), p.z()});
  return first;
}

// ---- M3 -----------------------------------------------------------------------------

class RigidityModel final : public PlanModel {
 public:
  explicit RigidityModel(RigidityPlan plan) : plan_(std::move(plan)), builder_(std::make_unique<core::RigidityBuilder>()) {
    const CradleMachine machine(FaceConfig{}, realistic_errors(), plan_.pivot);
    std::vector<double> poses;
    for (const auto& pose : plan_.poses) {
      for (const double c : pose.second) {
        readings_.push_back({machine.machine_T_table(pose.first, c).apply(plan_.ball_table_mm),
                             Mat3::Identity() * plan_.sigma_mm});
        samples_.push_back({pose.first, c, Vec3::Zero()});
      }
      poses.push_back(pose.first);
    }
    std::sort(poses.begin(), poses.end());
    int group = 0;
    for (const double a : poses) {
      if (std::fabs(a) <= core::kPoseAToleranceDeg) continue;
      const std::string at = plan_text("A=%g ", a);
      const double rot = macros::rigidity::kDefaultCheckRotationArcsec;
      ++group;  // the check judges the rotation vector's change by its length
      outputs_.push_back({at + "rotation_vector_x", "arcsec", rot, false, group});
      outputs_.push_back({at + "rotation_vector_y", "arcsec", rot, false, group});
      outputs_.push_back({at + "rotation_vector_z", "arcsec", rot, false, group});
      outputs_.push_back({at + "a_positioning_error", "arcsec", macros::rigidity::kDefaultCheckAErrorArcsec});
    }
    for (const char* k : {"x", "y", "z"}) outputs_.push_back({std::string("a_axis_point_") + k, "mm", 0.0});
    outputs_.push_back({"a_axis_direction_y", "arcsec", 0.0});
    outputs_.push_back({"a_axis_direction_z", "arcsec", 0.0});
    // Signed along the nominal n_ref x nA: the length the table holds folds at 0.
    outputs_.push_back({"c_to_a_offset_signed", "mm", 0.0});
    outputs_.push_back({"c_to_a_squareness", "arcsec", 0.0});
    std::vector<Vec3> values;
    for (const PlanReading& r : readings_) values.push_back(r.value);
    std::vector<double> ignored;
    std::string error;
    if (evaluate(values, ignored, error)) {
      const core::RigidityTable& t = builder_->table();
      const Vec3 across = t.poses[t.reference].c_direction.cross(t.a_axis_direction);
      if (across.norm() > 0.0) offset_direction_ = across.normalized();
    }
  }

  const char* method() const override { return "rigidity"; }
  // The nominal pivot when it is not the machine origin's.
  std::string pivot_text() const {
    const CradlePivot& p = plan_.pivot;
    if (p.c_point_mm == Vec3::Zero() && p.a_offset_y_mm == 0.0 && p.a_offset_z_mm == 0.0) return "";
    return plan_text(", C about (%g, %g, %g) mm, A %g, %g mm from it", p.c_point_mm.x(), p.c_point_mm.y(),
                     p.c_point_mm.z(), p.a_offset_y_mm, p.a_offset_z_mm);
  }
  std::string description() const override {
    std::vector<double> a;
    std::size_t c = 0;
    for (const auto& p : plan_.poses) {
      a.push_back(p.first);
      c = std::max(c, p.second.size());
    }
    std::sort(a.begin(), a.end());
    std::string poses;
    for (const double x : a) poses += (poses.empty() ? "" : ", ") + plan_text("%g", x);
    return std::to_string(a.size()) + " A poses (" + poses + ") x up to " + std::to_string(c) +
           plan_text(" C positions, ball at (%g, %g, %g) mm on the table", plan_.ball_table_mm.x(), plan_.ball_table_mm.y(),
                plan_.ball_table_mm.z()) +
           plan_text(", read to %g um (1 sigma per axis)", plan_.sigma_mm * 1000.0) + pivot_text();
  }
  const std::vector<PlanReading>& readings() const override { return readings_; }
  const std::vector<PlanOutput>& outputs() const override { return outputs_; }

  bool evaluate(const std::vector<Vec3>& values, std::vector<double>& out, std::string& error) const override {
    for (std::size_t i = 0; i < values.size(); ++i) samples_[i].p_mm = values[i];
    core::RigidityOptions options;
    options.min_c_arc_deg = 45.0;  // #600's default
    const core::Status s = core::build_rigidity_table(samples_.data(), samples_.size(), options, *builder_);
    if (s != core::Status::kOk) {
      error = refusal(s);
      return false;
    }
    const core::RigidityTable& t = builder_->table();
    out.clear();
    for (std::size_t i = 0; i < t.pose_count; ++i) {
      if (i == t.reference) continue;
      for (int k = 0; k < 3; ++k) out.push_back(t.poses[i].rotvec_rad(k) * kArcsecPerRad);
      out.push_back(t.poses[i].a_error_rad * kArcsecPerRad);
    }
    for (int k = 0; k < 3; ++k) out.push_back(t.a_axis_point_mm(k));
    out.push_back(t.a_axis_direction.y() * kArcsecPerRad);
    out.push_back(t.a_axis_direction.z() * kArcsecPerRad);
    out.push_back((t.a_axis_point_mm - t.poses[t.reference].c_centre_mm).dot(offset_direction_));
    out.push_back(t.c_to_a_squareness_rad * kArcsecPerRad);
    return true;
  }

  std::vector<std::pair<std::uint16_t, double>> module_configuration() const override {
    return {{var::kRigidityBallNoise, plan_.sigma_mm}};
  }
  // As trueaxis-calibrate rigidity: 9830, a 9831 per reading, 9832 with R = 0.
  std::vector<PlanMacro> module_macros(const std::vector<Vec3>& values) const override {
    std::vector<PlanMacro> out = {{9830, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const core::RigiditySample& s = samples_[i];
      out.push_back({9831, with_xyz({{var::kArgA, s.a_deg}, {var::kArgC, s.c_deg}}, values[i]),
                     plan_text("reading %zu (A = %g, C = %g deg)", i + 1, s.a_deg, s.c_deg)});
    }
    out.push_back({9832, {{var::kArgR, 0.0}}, ""});
    return out;
  }

  std::vector<PlanChange> candidates() const override {
    std::vector<PlanChange> out;
    if (plan_.poses.empty() || plan_.poses.size() >= core::kMaxAPoses) return out;
    const std::vector<double>* cs = &plan_.poses.front().second;
    for (const auto& p : plan_.poses) {
      if (std::fabs(p.first) <= core::kPoseAToleranceDeg) cs = &p.second;
    }
    for (double a = std::ceil(plan_.a_min_deg / 15.0) * 15.0; a <= plan_.a_max_deg; a += 15.0) {
      bool present = false;
      for (const auto& p : plan_.poses) present = present || std::fabs(p.first - a) <= core::kPoseAToleranceDeg;
      if (present) continue;
      RigidityPlan next = plan_;
      next.poses.emplace_back(a, *cs);
      out.push_back({plan_text("add the A pose %g deg (%g C positions)", a, static_cast<double>(cs->size())),
                     std::make_shared<RigidityModel>(next)});
    }
    // Not a pose but a fixture: the ball's lever about the A axis.
    RigidityPlan higher = plan_;
    higher.ball_table_mm.z() += 50.0;
    out.push_back({plan_text("the ball 50 mm higher on the table (z %g mm: a longer stem)", higher.ball_table_mm.z()),
                   std::make_shared<RigidityModel>(higher)});
    return out;
  }

 private:
  RigidityPlan plan_;
  std::vector<PlanReading> readings_;
  std::vector<PlanOutput> outputs_;
  mutable std::vector<core::RigiditySample> samples_;
  std::unique_ptr<core::RigidityBuilder> builder_;  // about 26 kB
  Vec3 offset_direction_ = Vec3::UnitZ();  // unit(n_ref x nA) of the noise-free table
};

// ---- M2 -----------------------------------------------------------------------------

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
    std::vector<PlanMacro> out = {{9820, {}, ""}};
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
        out.push_back({9821,
                       with_xyz({{var::kArgT, static_cast<double>(t)}, {var::kArgQ, static_cast<double>(q)},
                                 {var::kArgD, static_cast<double>(d)}},
                                values[i]),
                       plan_text("reading %zu (group %s)", i + 1, g.name.c_str())});
      }
    }
    for (std::size_t k = 0; k < machine_.sub_machine_count(); ++k) {
      const SubMachineConfig& c = machine_.config().sub_machines[k];
      out.push_back({9822,
                     {{var::kArgT, static_cast<double>(c.id)}, {var::kArgD, c.swing_mm}, {var::kArgI, tools_[k].x()},
                      {static_cast<std::uint16_t>(var::kArgI + 1), tools_[k].y()},
                      {static_cast<std::uint16_t>(var::kArgI + 2), tools_[k].z()}},
                     plan_text("sub-machine %d's swing length and tool direction", c.id)});
    }
    out.push_back({9823, {{var::kArgR, 0.0}}, ""});
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

// ---- M4 -----------------------------------------------------------------------------

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
    std::vector<PlanMacro> out = {{9840, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const core::SpindleSample& s = samples_[i];
      out.push_back({9841, with_xyz({{var::kArgS, s.phi_deg}, {var::kArgT, static_cast<double>(s.ball)}}, values[i]),
                     plan_text("reading %zu (ball %d at %g deg)", i + 1, s.ball, s.phi_deg)});
    }
    out.push_back({9842,
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

// ---- M1 -----------------------------------------------------------------------------

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
    std::vector<PlanMacro> out = {{9812, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      out.push_back({9813, with_xyz({}, values[i]),
                     plan_text("probe point %zu (%g, %g mm)", i + 1, plan_.points[i].first, plan_.points[i].second)});
    }
    out.push_back({9814, {{var::kArgA, 0.0}, {var::kArgC, 0.0}}, ""});
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

RigidityPlan rigidity_plan(double a_from, double a_to, double a_step, double c_step) {
  RigidityPlan plan;
  std::vector<double> c;
  for (int k = 0; k * c_step < 360.0 - 1e-9; ++k) c.push_back(k * c_step);
  std::vector<double> a;
  for (double x = 0.0; x <= a_to + 1e-9; x += a_step) a.push_back(x);
  for (double x = -a_step; x >= a_from - 1e-9; x -= a_step) a.push_back(x);
  std::sort(a.begin(), a.end());
  for (const double x : a) plan.poses.emplace_back(x, c);
  return plan;
}

std::shared_ptr<const PlanModel> rigidity_model(const RigidityPlan& plan) {
  return std::make_shared<RigidityModel>(plan);
}
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
std::shared_ptr<const PlanModel> spindle_model(const SpindlePlan& plan) {
  return std::make_shared<SpindleModel>(plan);
}

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

}  // namespace trueaxis::sim
