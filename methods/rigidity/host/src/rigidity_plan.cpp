// The rigidity plan (M3; planner.hpp contract 1): its readings on the simulator's machine, its
// outputs, its evaluation by the method's own firmware_core routine (the module's code, called
// directly), and its one-pose changes (contract 5).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/so3.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/plan_parts.hpp"
#include "trueaxis/sim/tools/rigidity_plan.hpp"
#include "trueaxis/sim/tools/planner.hpp"
#include "trueaxis/sim/tools/csv.hpp"
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
    std::vector<PlanMacro> out = {{macros::rigidity::kMacroSessionClear, {}, ""}};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const core::RigiditySample& s = samples_[i];
      out.push_back({macros::rigidity::kMacroSessionAdd, with_xyz({{var::kArgA, s.a_deg}, {var::kArgC, s.c_deg}}, values[i]),
                     plan_text("reading %zu (A = %g, C = %g deg)", i + 1, s.a_deg, s.c_deg)});
    }
    out.push_back({macros::rigidity::kMacroBuild, {{var::kArgR, 0.0}}, ""});
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

namespace {

// A rigidity plan from a CSV of a_deg, c_deg rows: one pose per A (within
// 1e-6 deg, as the module groups them), its C positions in file order.
bool read_rigidity_plan(const std::string& path, RigidityPlan& plan, std::string& error) {
  const CsvResult csv = read_csv(path, {{"a_deg"}, {"c_deg"}});
  if (!csv.ok) {
    error = csv.error;
    return false;
  }
  plan.poses.clear();
  for (const CsvRow& row : csv.rows) {
    auto pose = plan.poses.begin();
    while (pose != plan.poses.end() && std::fabs(pose->first - row.numbers[0]) > 1e-6) ++pose;
    if (pose == plan.poses.end()) {
      plan.poses.emplace_back(row.numbers[0], std::vector<double>{});
      pose = plan.poses.end() - 1;
    }
    pose->second.push_back(row.numbers[1]);
  }
  if (plan.poses.empty()) {
    error = path + ": no rows";
    return false;
  }
  return true;
}

class RigidityPlanOptions final : public PlanOptions {
 public:
  const char* help() const override {
    return "  rigidity  --a FROM,TO,STEP (deg; -90,90,30) --c-step DEG (10) or --in PLAN.csv (a_deg,c_deg:\n"
           "            a pose per A, its C positions; other columns ignored), --ball X,Y,Z (mm, table\n"
           "            coordinates: from the C axis at the table's top, not the machine's; 200,0,50),\n"
           "            --noise-um U (ball centre, 1 sigma per axis; 1),\n"
           "            --a-limits MIN,MAX (deg; the suggested poses' range; -120,120), --pivot X,Y,Z and\n"
           "            --a-offset DY,DZ (mm: the cradle's nominal pivot, as [TRUEAXIS] PIVOT_* and\n"
           "            A_OFFSET_*; 0,0,0 and 0,0: the ball's lever about A is Z + its height above A)\n";
  }

  Take take(const std::string& arg, const std::string& value, bool has, std::string& form) override {
    std::vector<double> v;
    bool ok = has;
    if (arg == "--a") {
      form = "FROM,TO,STEP in degrees, -360 <= FROM <= 0 <= TO <= 360, STEP > 0";
      ok = ok && plan_numbers(value, 3, a_range_) && a_range_[2] > 0.0 && a_range_[0] <= 0.0 && a_range_[1] >= 0.0 &&
           a_range_[0] >= -360.0 && a_range_[1] <= 360.0;
      poses_described_ = true;
    } else if (arg == "--c-step") {
      form = "degrees, 10..90 (a pose takes 4..36 C positions)";
      ok = ok && plan_positive(value, c_step_) && c_step_ >= 10.0 && c_step_ <= 90.0;
      poses_described_ = true;
    } else if (arg == "--in") {
      form = "a value";
      in_path_ = value;
    } else if (arg == "--ball") {
      form = "X,Y,Z in mm (table coordinates)";
      ok = ok && plan_numbers(value, 3, v);
      if (ok) plan_.ball_table_mm = Vec3(v[0], v[1], v[2]);
    } else if (arg == "--noise-um") {
      form = "micrometres, > 0";
      double um = 0.0;
      ok = ok && plan_positive(value, um);
      plan_.sigma_mm = um / 1000.0;
    } else if (arg == "--pivot") {
      form = "X,Y,Z in mm (machine coordinates)";
      ok = ok && plan_numbers(value, 3, v);
      if (ok) plan_.pivot.c_point_mm = Vec3(v[0], v[1], v[2]);
    } else if (arg == "--a-offset") {
      form = "DY,DZ in mm (the A axis from the pivot)";
      ok = ok && plan_numbers(value, 2, v);
      if (ok) plan_.pivot.a_offset_y_mm = v[0], plan_.pivot.a_offset_z_mm = v[1];
    } else if (arg == "--a-limits") {
      form = "MIN,MAX in degrees, MIN < MAX";
      ok = ok && plan_numbers(value, 2, v) && v[0] < v[1];
      if (ok) plan_.a_min_deg = v[0], plan_.a_max_deg = v[1];
    } else {
      return Take::kNotMine;
    }
    return ok ? Take::kTaken : Take::kBad;
  }

  std::shared_ptr<const PlanModel> finish(std::string& error, bool& usage) override {
    usage = !in_path_.empty() && poses_described_;
    if (usage) {
      error = "plan rigidity: --in gives the poses: not with --a or --c-step";
      return nullptr;
    }
    if (!in_path_.empty()) {
      if (!read_rigidity_plan(in_path_, plan_, error)) return nullptr;
    } else {
      plan_.poses = rigidity_plan(a_range_[0], a_range_[1], a_range_[2], c_step_).poses;
    }
    return rigidity_model(plan_);
  }

  // C positions given in radians span at most 2 pi and refuse as too short an arc.
  std::string hint(const PlanPrediction& p) const override {
    if (p.ok || p.error.find("arc_too_short") == std::string::npos) return "";
    double widest = 0.0;
    for (const auto& pose : plan_.poses) {
      const auto [lo, hi] = std::minmax_element(pose.second.begin(), pose.second.end());
      widest = std::max(widest, *hi - *lo);
    }
    if (widest > 2.0 * core::kPi + 1e-9) return "";
    return "(every pose's C positions span at most 2 pi: are they in radians? the columns are degrees)\n";
  }

 private:
  RigidityPlan plan_ = rigidity_plan(-90.0, 90.0, 30.0, 10.0);
  std::vector<double> a_range_ = {-90.0, 90.0, 30.0};
  double c_step_ = 10.0;
  std::string in_path_;
  bool poses_described_ = false;  // --a or --c-step given
};

}  // namespace

std::unique_ptr<PlanOptions> plan_options_rigidity() { return std::make_unique<RigidityPlanOptions>(); }

}  // namespace trueaxis::sim
