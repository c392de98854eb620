#include "trueaxis/sim/tools/gantry_measure.hpp"

#include <cstdio>

namespace trueaxis::sim {

namespace {

using core::Vec3;

// n values evenly from `from` to `to`, both included (n >= 2), or `from` alone.
std::vector<double> evenly(double from, double to, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(n < 2 ? from : from + (to - from) * i / (n - 1));
  return v;
}

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.15g", v == 0.0 ? 0.0 : v);  // no "-0"
  return text;
}

std::string vec(const Vec3& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; }

class Recorder {
 public:
  Recorder(const LaserTracker& tracker, SimRng& rng, std::vector<TrackerSample>& out)
      : tracker_(tracker), rng_(rng), out_(out) {}
  void add(const std::string& group, const Vec3& p_machine) {
    out_.push_back(TrackerSample{group, tracker_.measure(p_machine, rng_)});
  }

 private:
  const LaserTracker& tracker_;
  SimRng& rng_;
  std::vector<TrackerSample>& out_;
};

}  // namespace

LaserTracker place_tracker(const GantryMachine& machine, const TrackerPlacement& placement, const TrackerSpec& spec,
                           bool noise) {
  const GantryConfig& c = machine.config();
  return place_tracker(0.5 * c.bed_length_mm, c.front_y_mm, placement, spec, noise);
}

std::vector<double> gantry_stops(const GantryMachine& machine, const GantryPlan& plan) {
  return evenly(machine.config().gantry_travel_min_mm, machine.config().gantry_travel_max_mm, plan.pass_points);
}

std::vector<TrackerSample> measure_gantry(const GantryMachine& machine, const LaserTracker& tracker,
                                          const GantryPlan& plan, SimRng& rng) {
  std::vector<TrackerSample> out;
  Recorder rec(tracker, rng, out);
  const GantryConfig& c = machine.config();
  const double pad = c.pad_size_mm;
  const double corner_x[4] = {0.0, c.bed_length_mm - pad, c.bed_length_mm - pad, 0.0};
  const double corner_y[4] = {0.0, 0.0, c.bed_width_mm - pad, c.bed_width_mm - pad};
  for (int k = 0; k < 4; ++k) {
    for (double y : evenly(corner_y[k] + 10.0, corner_y[k] + pad - 10.0, plan.pad_grid)) {
      for (double x : evenly(corner_x[k] + 10.0, corner_x[k] + pad - 10.0, plan.pad_grid)) {
        rec.add("bed", Vec3(x, y, 0.0));
      }
    }
  }
  for (int side = 1; side <= 2; ++side) {
    for (double z : evenly(-10.0, 10.0 - c.pad_height_mm, plan.side_rows)) {
      for (double along : evenly(15.0, pad - 15.0, plan.side_cols)) {
        rec.add("side_" + std::to_string(side), machine.side_point(side, along, z));
      }
    }
  }
  const std::vector<double> stops = gantry_stops(machine, plan);
  for (int pass = 1; pass <= plan.passes; ++pass) {
    for (double u : stops) rec.add("gantry_" + std::to_string(pass), machine.gantry_target(u));
  }
  for (std::size_t i = 0; i < machine.sub_machine_count(); ++i) {
    const SubMachineConfig& s = c.sub_machines[i];
    const std::string sp = "sp" + std::to_string(s.id) + "_";
    const char* axis_names[3] = {"x_", "y_", "z_"};
    for (int k = 0; k < 3; ++k) {
      for (int pass = 1; pass <= plan.passes; ++pass) {
        for (double q : evenly(s.stroke_min_mm[k], s.stroke_max_mm[k], plan.pass_points)) {
          Vec3 axes = Vec3::Zero();
          axes[k] = q;
          rec.add(sp + axis_names[k] + std::to_string(pass), machine.smr(i, axes, 0.0, 0.0));
        }
      }
    }
    for (double angle : evenly(plan.c_from_deg, plan.c_to_deg, plan.circle_points)) {
      rec.add(sp + "c", machine.smr(i, Vec3::Zero(), 0.0, angle));
    }
    for (double angle : evenly(plan.a_from_deg, plan.a_to_deg, plan.circle_points)) {
      rec.add(sp + "a", machine.smr(i, Vec3::Zero(), angle, 0.0));
    }
  }
  return out;
}

std::string samples_csv_text(const std::vector<TrackerSample>& samples, const std::vector<std::string>& comment) {
  std::string text;
  for (const std::string& line : comment) text += "# " + line + "\n";
  text += "group,x_mm,y_mm,z_mm\n";
  for (const TrackerSample& s : samples) {
    char line[160];
    std::snprintf(line, sizeof line, ",%.9f,%.9f,%.9f\n", s.p_mm.x(), s.p_mm.y(), s.p_mm.z());
    text += s.group + line;
  }
  return text;
}

std::string machine_csv_text(const GantryMachine& machine, const LaserTracker& tracker, bool nominal_origins) {
  std::string text = nominal_origins
                         ? "# nominal tool directions in the tracker frame; nominal origins (the tool tip at home, "
                           "global frame) as a drawing gives them, to 0.1 mm\n"
                           "sub_machine,swing_mm,tool_x,tool_y,tool_z,origin_x_mm,origin_y_mm,origin_z_mm\n"
                         : "# nominal tool directions in the tracker frame\nsub_machine,swing_mm,tool_x,tool_y,tool_z\n";
  for (std::size_t i = 0; i < machine.sub_machine_count(); ++i) {
    const SubMachineConfig& s = machine.config().sub_machines[i];
    const Vec3 tool = tracker.tracker_T_machine().rotation * s.tool_nominal;
    char line[240];
    std::snprintf(line, sizeof line, "%d,%.9f,%.9f,%.9f,%.9f", s.id, s.swing_mm, tool.x(), tool.y(), tool.z());
    text += line;
    if (nominal_origins) {
      const Vec3 o = machine.truth(i).origin_global_mm;
      std::snprintf(line, sizeof line, ",%.1f,%.1f,%.1f", o.x(), o.y(), o.z());
      text += line;
    }
    text += "\n";
  }
  return text;
}

std::string truth_json_text(const GantryMachine& machine, const LaserTracker& tracker, const GantryPlan& plan) {
  const RigidTransform& m_T_g = machine.machine_T_global();
  const RigidTransform& t_T_m = tracker.tracker_T_machine();
  std::string json = "{\n  \"method\": \"gantry\",\n  \"truth\": true,\n  \"global\": { \"origin_mm\": " +
                     vec(t_T_m.apply(m_T_g.translation_mm));
  const char* axis_names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    json += std::string(", \"") + axis_names[k] + "\": " + vec(t_T_m.rotation * m_T_g.rotation.col(k));
  }
  json += ",\n    \"bed_flatness_mm\": 0, \"gantry_straightness_mm\": " +
          number(machine.gantry_straightness_mm(gantry_stops(machine, plan))) + " },\n  \"sub_machines\": [";
  for (std::size_t i = 0; i < machine.sub_machine_count(); ++i) {
    const SubMachineTruth& t = machine.truth(i);
    json += i > 0 ? ",\n" : "\n";
    json += "    { \"id\": " + std::to_string(t.id) + ", \"origin_mm\": " + vec(t.origin_global_mm) +
            ", \"origin_sigma_mm\": 0,\n      ";
    for (int k = 0; k < 3; ++k) {
      json += std::string("\"") + axis_names[k] + "\": " + vec(t.axes_global.col(k)) + ", ";
    }
    json += std::string("\"master_axis\": \"") + master_axis_name(t.master) + "\",\n";
    json += "      \"squareness_arcsec\": { \"xy\": " + number(t.squareness_xy_arcsec) +
            ", \"yz\": " + number(t.squareness_yz_arcsec) + ", \"zx\": " + number(t.squareness_zx_arcsec) +
            " },\n      \"a_c_offset_mm\": " + number(t.a_c_offset_mm) + ", \"a_c_angle_deg\": " +
            number(t.a_c_angle_deg) + ",\n      \"global_T_sub\": [";
    for (int r = 0; r < 4; ++r) {
      for (int col = 0; col < 4; ++col) json += (r + col > 0 ? ", " : "") + number(t.global_T_sub(r, col));
    }
    json += "] }";
  }
  json += "\n  ]\n}\n";
  return json;
}

}  // namespace trueaxis::sim
