// The newcomer's mistakes of issue "Nothing wrong reaches the machine", each
// through `trueaxis-calibrate --store --report` against a trueaxis-sim (child
// processes, argv, no shell): A in radians, ball positions in metres, spindle
// samples in metres, a spindle MACHINE in metres, a ball distance typed wrong.
// Each is refused by a gate of the module: exit 1, one stderr line naming the
// likely cause, no OUT.json, no report, nothing stored, the controller locked
// again. And the change gate: a calibration far from the stored one is stored
// only with --accept-change.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "calibrate_gantry_support.hpp"
#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"

namespace {

namespace v = trueaxis::macros::var;
using trueaxis::sim::VariableClient;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

constexpr double kPi = 3.14159265358979323846;

// A CSV's text with the named columns rewritten by f (comments and the header kept).
template <typename F>
std::string rewrite(const std::string& csv, const std::vector<std::string>& columns, F f) {
  std::istringstream in(csv);
  std::string line, out;
  std::vector<bool> change;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out += line + "\n";
      continue;
    }
    const std::vector<std::string> fields = fields_of(line);
    if (header) {
      for (const std::string& name : fields) {
        bool named = false;
        for (const std::string& c : columns) named = named || c == name;
        change.push_back(named);
      }
      header = false;
      out += line + "\n";
      continue;
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      char buf[40];
      if (change[i]) std::snprintf(buf, sizeof buf, "%.17g", f(std::stod(fields[i])));
      out += (i ? "," : "") + (change[i] ? std::string(buf) : fields[i]);
    }
    out += "\n";
  }
  return out;
}

// 9833 at A = 60 (R = 1 clamps): 2 done, or 3 and its code in `code`.
int rigidity_query(VariableClient& client, int& code) {
  REQUIRE(client.write_one(v::kArgA, 60.0));
  REQUIRE(client.write_one(v::kArgR, 1.0));
  const trueaxis::sim::MacroOutcome o = client.run_macro(9833);
  code = o.error;
  REQUIRE(client.give_back_interface());
  return o.status;
}

// A refused run: exit 1, one line holding every `words`, nothing written.
void check_refused(const Run& r, const Workspace& w, const std::vector<std::string>& words) {
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.out.empty());
  CHECK(r.err.find('\n') == r.err.size() - 1);
  for (const std::string& word : words) CHECK(r.err.find(word) != std::string::npos);
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK_FALSE(exists(w.file("report")));
}

Run calibrate(const std::string& method, int port, const Workspace& w, const std::string& in,
              const std::string& machine = "", bool accept = false) {
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, method, "--in", in, "--json", w.file("out.json"),
                                   "--report", w.file("report"), "--store", "--port", std::to_string(port)};
  if (!machine.empty()) argv.insert(argv.end(), {"--machine", machine});
  if (accept) argv.emplace_back("--accept-change");
  return run(argv, w.file("calibrate.err"));
}

}  // namespace

TEST_CASE("calibrate rigidity: A or A and C in radians, ball positions in metres: refused by a gate, nothing stored",
          "[calibrate][gates]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-gates");
  const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("samples.csv")},
                    w.file("measure.err"));
  REQUIRE(m.exit_code == 0);
  const std::string good = slurp(w.file("samples.csv"));
  const auto radians = [](double deg) { return deg * kPi / 180.0; };
  w.write("a_radians.csv", rewrite(good, {"a_deg"}, radians));
  w.write("ac_radians.csv", rewrite(good, {"a_deg", "c_deg"}, radians));
  w.write("metres.csv", rewrite(good, {"x_mm", "y_mm", "z_mm"}, [](double mm) { return mm / 1000.0; }));
  struct Case {
    const char* file;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"a_radians.csv", {"a_error_implausible", "radians", "gate a_error (each pose's A positioning error) at pose 1 (A = -1.5708 deg)",
        "against the limit 1800 arcsec (#602 rigidity_max_a_error)"}},
      {"ac_radians.csv", {"c_phase_inconsistent", "radians"}},
      {"metres.csv", {"c_radius_implausible", "metres", "against the limit 5 mm (#603 rigidity_min_c_radius)"}},
  };
  for (const Case& c : cases) {
    INFO(c.file);
    check_refused(calibrate("rigidity", sim.port(), w, w.file(c.file)), w, c.words);
    int code = 0;
    CHECK(rigidity_query(sim.client(), code) == 3);
    CHECK(code == static_cast<int>(trueaxis::core::Status::kNoTable));
    CHECK(read_var(sim.client(), v::kUnlock) == 0.0);
  }
}

TEST_CASE("calibrate rigidity: a table far from the stored one is refused by the change gate, stored with --accept-change",
          "[calibrate][gates]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-gates");
  const auto measure = [&](const std::string& name) {
    const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file(name)},
                      w.file("measure.err"));
    REQUIRE(m.exit_code == 0);
  };
  measure("realistic.csv");
  REQUIRE(calibrate("rigidity", sim.port(), w, w.file("realistic.csv")).exit_code == 0);
  REQUIRE(std::rename(w.file("out.json").c_str(), w.file("first.json").c_str()) == 0);
  REQUIRE(std::rename(w.file("report").c_str(), w.file("first_report").c_str()) == 0);
  REQUIRE(sim.client().write_one(12020, 0.0));  // the ideal machine: some 50" less rigidity error at A = +-60, 90
  REQUIRE(sim.client().give_back_interface());
  measure("ideal.csv");
  const Run refused = calibrate("rigidity", sim.port(), w, w.file("ideal.csv"));
  check_refused(refused, w, {"change_beyond_limit", "at pose 1 (A = -90 deg)", "against the limit 30 arcsec (#604 rigidity_max_change)",
                                 "--accept-change"});
  int code = 0;
  REQUIRE(rigidity_query(sim.client(), code) == 2);  // the realistic table is still the live one
  double rotvec[4] = {0, 0, 0, 0};
  REQUIRE(sim.client().read(v::kRigidityRotvecX, 4, rotvec));
  CHECK(rotvec[3] > 1.0);
  const Run accepted = calibrate("rigidity", sim.port(), w, w.file("ideal.csv"), "", true);
  INFO(accepted.err);
  CHECK(accepted.exit_code == 0);
  REQUIRE(rigidity_query(sim.client(), code) == 2);
  REQUIRE(sim.client().read(v::kRigidityRotvecX, 4, rotvec));
  CHECK(rotvec[3] < 5.0);  // the ideal machine's table: noise only
  const Run usage = run({TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", w.file("ideal.csv"), "--json",
                         w.file("x.json"), "--accept-change"},
                        w.file("usage.err"));
  CHECK(usage.exit_code != 0);
  CHECK(usage.err.find("--accept-change goes with --store") != std::string::npos);
}

TEST_CASE("calibrate spindle: samples in metres, MACHINE in metres, ball 2 typed 140 for 150: refused, nothing stored",
          "[calibrate][gates]") {
  SimFixture sim;
  Workspace w("trueaxis-calibrate-gates");
  const SpindleFiles f = measure_spindle(w, "s", 3, 3);
  const std::string samples = slurp(f.samples);
  const std::string machine = slurp(f.machine);
  w.write("samples_m.csv", rewrite(samples, {"x_mm", "y_mm", "z_mm"}, [](double mm) { return mm / 1000.0; }));
  w.write("machine_m.csv", rewrite(machine, {"value"}, [](double mm) { return mm / 1000.0; }));
  std::string typo = machine;
  const std::size_t at = typo.find("ball_2_mm,150");
  REQUIRE(at != std::string::npos);
  typo.replace(at, 13, "ball_2_mm,140");
  w.write("machine_typo.csv", typo);
  struct Case {
    std::string in, machine;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {f.samples, w.file("machine_m.csv"), {"ball_spacing_implausible", "metres"}},
      {w.file("samples_m.csv"), f.machine, {"ball_spacing_implausible", "metres", "lie 0.1 mm apart"}},
      {f.samples, w.file("machine_typo.csv"), {"ball_spacing_implausible", "typed wrong", "is 90"}},
  };
  for (const Case& c : cases) {
    INFO(c.in << " with " << c.machine);
    check_refused(calibrate("spindle", sim.port(), w, c.in, c.machine), w, c.words);
    const std::vector<double> answer = correction(sim.client(), 0.0, 100.0);
    REQUIRE(sim.client().give_back_interface());
    CHECK(answer.size() == 1);
    CHECK(answer[0] == static_cast<double>(trueaxis::core::Status::kNoTable));
    CHECK(read_var(sim.client(), v::kUnlock) == 0.0);
  }
  CHECK(calibrate("spindle", sim.port(), w, f.samples, f.machine).exit_code == 0);  // and the right files pass
}

TEST_CASE("calibrate gantry: points in metres are refused by the bed-span gate, nothing stored", "[calibrate][gates]") {
  SimFixture sim;
  Workspace w("trueaxis-calibrate-gates");
  const Measured measured = trueaxis::test::measure(small_plan(), 5);
  w.write("machine.csv", measured.machine);
  w.write("points.csv", measured.samples);
  w.write("points_m.csv", rewrite(measured.samples, {"x_mm", "y_mm", "z_mm"}, [](double mm) { return mm / 1000.0; }));
  check_refused(calibrate("gantry", sim.port(), w, w.file("points_m.csv"), w.file("machine.csv")), w,
                {"bed_span_implausible", "metres", "against the limit 100 mm (#703 gantry_min_bed_span)"});
  // Nothing stored: 9825 has no frames to convert with.
  REQUIRE(sim.client().write_one(v::kArgT, 1.0));
  const trueaxis::sim::MacroOutcome o = sim.client().run_macro(9825);
  REQUIRE(sim.client().give_back_interface());
  CHECK(o.status == 3);
  CHECK(o.error == static_cast<int>(trueaxis::core::Status::kNoTable));
  CHECK(read_var(sim.client(), v::kUnlock) == 0.0);
  CHECK(calibrate("gantry", sim.port(), w, w.file("points.csv"), w.file("machine.csv")).exit_code == 0);
}
