// The trueaxis-calibrate spindle tests' own support: the virtual spindle
// measured by trueaxis-measure-spindle, a file's physical lines, the module's
// 9843 answers, and the command's flow run without its files (the simulator in
// this process: in_process_sim.hpp).
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "calibrate_support.hpp"
#include "in_process_sim.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_spindle.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::test {

// ---- the virtual spindle's files -------------------------------------------------------

struct SpindleFiles {
  std::string samples, machine, truth;  // paths
};

// trueaxis-measure-spindle --seed SEED --revolutions R into w, files named after `tag`.
// `sampling`: further options of trueaxis-measure-spindle (--samples-per-rev N,
// --time-sampled, ...).
inline SpindleFiles measure_spindle(const Workspace& w, const std::string& tag, int seed, int revolutions,
                                    const std::vector<std::string>& sampling = {}) {
  const SpindleFiles f{w.file(tag + "_samples.csv"), w.file(tag + "_machine.csv"), w.file(tag + "_truth.json")};
  std::vector<std::string> args = {TRUEAXIS_MEASURE_SPINDLE_BINARY, "--out", f.samples, "--machine", f.machine,
                                   "--truth", f.truth, "--seed", std::to_string(seed), "--revolutions",
                                   std::to_string(revolutions)};
  args.insert(args.end(), sampling.begin(), sampling.end());
  const Run r = run(args, w.file("measure_err.txt"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return f;
}

// A text's physical lines: lines[i] is line i + 1.
inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

inline std::string text_of(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

// A line's comma-separated fields.
inline std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  return fields;
}

// ---- the module ------------------------------------------------------------------------------

inline const std::vector<double> kQueryAngles = {0.0, 45.0, 90.0, 135.0, 200.0, 270.0, 355.0};

// 9843 at `phi_deg` and tool length `tool_mm`: #100..#104, or {error code}.
inline std::vector<double> correction(sim::VariableClient& client, double phi_deg, double tool_mm) {
  REQUIRE(client.write_one(macros::var::kArgS, phi_deg));
  REQUIRE(client.write_one(macros::var::kArgZ, tool_mm));
  const sim::MacroOutcome o = client.run_macro(9843);
  REQUIRE(o.status >= 2);
  if (o.status == 3) return {static_cast<double>(o.error)};
  std::vector<double> c(5);
  REQUIRE(client.read(macros::var::kSpindleThetaE, 5, c.data()));
  return c;
}

// 9843 at kQueryAngles.
inline std::vector<std::vector<double>> corrections(sim::VariableClient& client, double tool_mm) {
  std::vector<std::vector<double>> out;
  for (double phi : kQueryAngles) out.push_back(correction(client, phi, tool_mm));
  REQUIRE(client.give_back_interface());  // for the commands the test runs next (module contract 8)
  return out;
}

// The command's flow as calibrate_main.cpp runs it, without the files: the
// flow, then (on success, with store) the store.
inline sim::FlowResult spindle_flow(sim::VariableClient& client, const std::string& in, const std::string& machine,
                                    bool store) {
  sim::CalibrateOptions o;
  o.method = "spindle";
  o.in_path = in;
  o.machine_path = machine;
  o.json_path = "unused.json";
  o.store = store;
  sim::FlowResult r = sim::calibrate_spindle(client, o);
  if (r.ok && store && !sim::store_spindle(client, r)) r.ok = false;
  return r;
}

}  // namespace trueaxis::test
