// The trueaxis-calibrate gantry tests' own support: the virtual gantry
// measured, samples rows, the module's 9825 conversions, and the command's flow
// run without its files (the simulator in this process: in_process_sim.hpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "calibrate_support.hpp"
#include "in_process_sim.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_gantry.hpp"
#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"

namespace trueaxis::test {

// ---- the virtual gantry's files ------------------------------------------------------

// The virtual gantry measured by the virtual tracker: the three files' texts.
struct Measured {
  std::string samples, machine, truth;
  std::string machine_nominal;  // MACHINE with the nominal origins a drawing gives (to 0.1 mm)
};

inline Measured measure(const sim::GantryPlan& plan, std::uint64_t seed) {
  const sim::GantryMachine machine(sim::realistic_gantry());
  const sim::LaserTracker tracker = sim::place_tracker(machine, sim::TrackerPlacement{});
  sim::SimRng rng(seed);
  return {sim::samples_csv_text(sim::measure_gantry(machine, tracker, plan, rng), {"measured"}),
          sim::machine_csv_text(machine, tracker), sim::truth_json_text(machine, tracker, plan),
          sim::machine_csv_text(machine, tracker, true)};
}

// A plan of fewer points: the bad inputs need a whole stream, not its precision.
inline sim::GantryPlan small_plan() {
  sim::GantryPlan p;
  p.pad_grid = 3;
  p.side_rows = 3;
  p.side_cols = 3;
  p.passes = 2;
  p.pass_points = 8;
  p.circle_points = 12;
  return p;
}

// A samples file as its data rows (group, the whole line); comments and the header dropped.
struct Row {
  std::string group, text;
};
inline const std::string kHeader = "group,x_mm,y_mm,z_mm\n";

inline std::vector<Row> rows_of(const std::string& csv) {
  std::vector<Row> rows;
  std::istringstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("group,", 0) == 0) continue;
    rows.push_back({line.substr(0, line.find(',')), line});
  }
  return rows;
}

inline std::string text_of(const std::vector<Row>& rows) {
  std::string out = kHeader;
  for (const Row& r : rows) out += r.text + "\n";
  return out;
}

// ---- OUT.json ----------------------------------------------------------------------------

inline const Json& sub_of(const Json& doc, int id) {
  for (const Json& s : doc["sub_machines"].items) {
    if (s["id"].number == id) return s;
  }
  FAIL("no sub-machine " << id);
  return doc;
}

inline double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < 3; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum);
}

// A global point into sub-machine coordinates through global_T_sub (row-major).
inline std::vector<double> to_sub(const std::vector<double>& t, const std::vector<double>& p) {
  std::vector<double> q(3, 0.0);
  for (std::size_t j = 0; j < 3; ++j) {
    for (std::size_t i = 0; i < 3; ++i) q[j] += t[4 * i + j] * (p[i] - t[4 * i + 3]);
  }
  return q;
}

// ---- the module ------------------------------------------------------------------------------

inline const std::vector<double> kPoint = {400.0, 1100.0, 150.0};  // a workpiece point, global frame

// 9825 for sub-machines 1..4 at kPoint: each #100..#102 or {error code}.
inline std::vector<std::vector<double>> conversions(sim::VariableClient& client) {
  std::vector<std::vector<double>> out;
  for (int n = 1; n <= 4; ++n) {
    REQUIRE(client.write_one(macros::var::kArgT, n));
    REQUIRE(client.write(macros::var::kArgX, 3, kPoint.data()));
    const sim::MacroOutcome o = client.run_macro(9825);
    REQUIRE(o.status >= 2);
    if (o.status == 3) {
      out.push_back({static_cast<double>(o.error)});
      continue;
    }
    std::vector<double> p(3);
    REQUIRE(client.read(macros::var::kGantryPointX, 3, p.data()));
    out.push_back(p);
  }
  REQUIRE(client.give_back_interface());  // for the commands the test runs next (module contract 8)
  return out;
}

// The command's flow as calibrate_main.cpp runs it, without the files: the
// flow, then (on success, with store) the store; `sub_machines` is --sub-machines.
inline sim::FlowResult flow(sim::VariableClient& client, const std::string& in, const std::string& machine,
                            bool store, const std::vector<int>& sub_machines = {}) {
  sim::CalibrateOptions o;
  o.method = "gantry";
  o.in_path = in;
  o.machine_path = machine;
  o.sub_machines = sub_machines;
  o.json_path = "unused.json";
  o.store = store;
  sim::FlowResult r = sim::calibrate_gantry(client, o);
  if (r.ok && store) {
    sim::FlowResult s;
    if (!sim::store_gantry(client, s)) return s;
  }
  return r;
}

}  // namespace trueaxis::test
