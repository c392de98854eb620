// `trueaxis-calibrate spindle` (docs/INTERFACE.md "The integrator's command", "M4
// spindle"): its flow (calibrate_spindle, store_spindle) driven in this process
// against a simulator served in this process too (a thread, 127.0.0.1 port 0,
// RAM storage), on files trueaxis-measure-spindle measured off the virtual
// spindle, with that spindle's truth beside them:
//  1. good data: OUT.json parses with docs/INTERFACE.md's keys, the parameters and
//     the tool-tip errors within 3 sigma of the truth; after --store, 9843
//     answers every per_angle entry bit for bit; the header's order, extra
//     columns and comments change nothing; a later session replaces the model;
//  2. the command itself (its binary, against the same simulator) with --store
//     and --report: the page and its figures from simulator data.
// Every bad input: test_calibrate_spindle_inputs.cpp.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "in_process_sim.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"

namespace {

namespace v = trueaxis::macros::var;
namespace sim = trueaxis::sim;
using trueaxis::core::Status;
using namespace trueaxis::test;

const std::vector<double> kNoTable = {static_cast<double>(Status::kNoTable)};

// OUT.json's fixed shape (docs/INTERFACE.md) and what this command adds; the
// maxima are the per_angle maxima.
void check_shape(const Json& out, std::size_t samples) {
  CHECK(out["method"].text == "spindle");
  REQUIRE(out["parameters"].members.size() == 9);
  for (std::size_t k = 0; k < 9; ++k) {
    CAPTURE(k);
    CHECK(out["parameters"].members[k].first == trueaxis::macros::spindle::kParameterNames[k]);
    const Json& p = out["parameters"].members[k].second;
    REQUIRE(p["value"].kind == Json::kNumber);
    CHECK(p["sigma"].number > 0.0);
  }
  const std::vector<Json>& per = out["per_angle"].items;
  REQUIRE(per.size() == 72);
  double theta_max = 0.0;
  double d_e_max = 0.0;
  for (std::size_t i = 0; i < per.size(); ++i) {
    CAPTURE(i);
    for (const char* key : {"phi_deg", "theta_e_arcsec", "d_e_mm", "theta_e_sigma_arcsec", "d_e_sigma_mm"}) {
      CHECK(per[i][key].kind == Json::kNumber);
    }
    CHECK(per[i]["phi_deg"].number == 5.0 * static_cast<double>(i));
    CHECK(per[i]["theta_e_arcsec"].number >= 0.0);
    CHECK(per[i]["d_e_mm"].number >= 0.0);
    CHECK(per[i]["tool_tip_error_mm"].numbers().size() == 3);
    CHECK(per[i]["theta_e_sigma_arcsec"].number > 0.0);
    CHECK(per[i]["d_e_sigma_mm"].number > 0.0);
    for (double s : per[i]["tool_tip_error_sigma_mm"].numbers()) CHECK(s > 0.0);
    theta_max = std::max(theta_max, per[i]["theta_e_arcsec"].number);
    d_e_max = std::max(d_e_max, per[i]["d_e_mm"].number);
  }
  for (const char* key : {"theta_e_max_arcsec", "d_e_max_mm", "evaluations"}) CHECK(out[key].kind == Json::kNumber);
  CHECK(out["theta_e_max_arcsec"].number == theta_max);
  CHECK(out["d_e_max_mm"].number == d_e_max);
  CHECK(out["evaluations"].number >= 2.0);
  CHECK(out["evaluations"].number == std::floor(out["evaluations"].number));
  CHECK(out["fit"]["samples"].number == static_cast<double>(samples));
  CHECK(out["fit"]["noise_from_repeats"].kind == Json::kBool);
  CHECK(out["fit"]["noise_sigma_mm"].number > 0.0);
  CHECK(out["mean_tool_tip_error_mm"].numbers().size() == 3);
}

// 9843 at every per_angle entry: the same numbers, bit for bit.
void check_stored(sim::VariableClient& client, const Json& out) {
  const double tool = out["tool_length_mm"].number;
  for (const Json& p : out["per_angle"].items) {
    CAPTURE(p["phi_deg"].number);
    std::vector<double> want = {p["theta_e_arcsec"].number, p["d_e_mm"].number};
    for (double t : p["tool_tip_error_mm"].numbers()) want.push_back(t);
    CHECK(correction(client, p["phi_deg"].number, tool) == want);
  }
}

// The parameters within 3 sigma of the truth; the tool-tip errors within 3
// sigma of the truth's, less the axial error delta the analyser cannot see (it
// moves the identified O1 along a), and allowed the model's own second-order
// term m along the tool d (0.55 nm: virtual_spindle.hpp convention 4), far
// above z's sigma (pm).
void check_truth(const Json& out, const Json& truth, double tool) {
  for (const auto& [name, p] : out["parameters"].members) {
    CAPTURE(name, p["value"].number, p["sigma"].number);
    CHECK(std::fabs(p["value"].number - truth["parameters"][name]["value"].number) < 3.0 * p["sigma"].number);
  }
  const sim::VirtualSpindle spindle(sim::realistic_spindle());
  const double delta = truth["axial_error_mm"].number;
  REQUIRE(delta == Approx(spindle.axial_error_mm()).epsilon(1e-12));
  const trueaxis::core::Vec3 a = spindle.axis();
  const trueaxis::core::Vec3 d = spindle.tool_direction();
  const double m = spindle.mapping_error_mm(tool);
  REQUIRE(m < 1e-6);
  for (std::size_t i = 0; i < 72; ++i) {
    const Json& p = out["per_angle"].items[i];
    const Json& t = truth["per_angle"].items[i];
    REQUIRE(t["phi_deg"].number == p["phi_deg"].number);
    for (std::size_t k = 0; k < 3; ++k) {
      const double error = p["tool_tip_error_mm"].numbers()[k] -
                           (t["tool_tip_error_mm"].numbers()[k] - delta * a[static_cast<Eigen::Index>(k)]);
      const double sigma = p["tool_tip_error_sigma_mm"].numbers()[k];
      CAPTURE(i, k, error, sigma);
      CHECK(std::fabs(error) < 3.0 * sigma + m * std::fabs(d[static_cast<Eigen::Index>(k)]));
    }
    CHECK(std::fabs(p["theta_e_arcsec"].number - t["theta_e_arcsec"].number) < 3.0 * p["theta_e_sigma_arcsec"].number);
  }
}

std::size_t data_rows(const std::string& samples_path) {
  std::size_t n = 0;
  for (const std::string& l : lines_of(slurp(samples_path))) n += !l.empty() && l[0] != '#' && l[0] != 'p' ? 1u : 0u;
  return n;
}

}  // namespace

TEST_CASE("calibrate spindle: the virtual spindle's model within 3 sigma of its truth, stored and correcting",
          "[calibrate][spindle]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-spindle");
  const SpindleFiles f = measure_spindle(w, "good", 2, 3);
  const Json truth = parse(slurp(f.truth));
  const double tool = truth["tool_length_mm"].number;
  for (const auto& c : corrections(client, tool)) CHECK(c == kNoTable);

  // Without --store: computed, nothing stored.
  const sim::FlowResult dry = spindle_flow(client, f.samples, f.machine, false);
  INFO(dry.error);
  REQUIRE(dry.ok);
  for (const auto& c : corrections(client, tool)) CHECK(c == kNoTable);

  const sim::FlowResult r = spindle_flow(client, f.samples, f.machine, true);
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(r.json == dry.json);
  CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
  const Json out = parse(r.json);
  check_shape(out, data_rows(f.samples));
  CHECK(out["tool_length_mm"].number == tool);
  CHECK(out["fit"]["noise_from_repeats"].boolean);
  check_stored(client, out);
  // S counts revolutions: two more land on the same answer.
  CHECK(correction(client, 765.0, tool) == correction(client, 45.0, tool));

  check_truth(out, truth, tool);
  // What is stored is what OUT.json describes: 9845 on the stored model (R = 1).
  const double qr[2] = {1.0, 1.0};
  REQUIRE(client.write(v::kArgQ, 2, qr));
  REQUIRE(client.run_macro(9845).status == 2);
  CHECK(read_var(client, v::kSpindleParamValue) == out["parameters"]["o_x_mm"]["value"].number);
  CHECK(read_var(client, v::kSpindleParamSigma) == out["parameters"]["o_x_mm"]["sigma"].number);
  CHECK(r.json.find("bearing_spacing_mm") == std::string::npos);  // the report's, not OUT.json's
  CHECK(parse(r.report_extras)["bearing_spacing_mm"].number == 300.0);

  SECTION("the header in another order, an extra column and comments between rows: the same OUT.json") {
    // phi_deg,ball,x_mm,y_mm,z_mm -> z_mm,note,ball,x_mm,phi_deg,y_mm
    std::vector<std::string> lines = lines_of(slurp(f.samples));
    std::vector<std::string> mixed;
    for (std::size_t n = 0; n < lines.size(); ++n) {
      const std::vector<std::string> x = fields_of(lines[n]);
      if (x.size() != 5) {
        mixed.push_back(lines[n]);
        continue;
      }
      mixed.push_back(x[4] + "," + (n % 3 == 0 ? "a note" : "") + "," + x[1] + "," + x[2] + "," + x[0] + "," + x[3]);
      if (n % 50 == 0) mixed.push_back("# a comment between rows, " + std::to_string(n));
    }
    REQUIRE(mixed[2] == "z_mm,,ball,x_mm,phi_deg,y_mm");
    mixed[2] = "z_mm,note,ball,x_mm,phi_deg,y_mm";
    const sim::FlowResult again = spindle_flow(client, w.write("mixed.csv", text_of(mixed)), f.machine, false);
    INFO(again.error);
    REQUIRE(again.ok);
    CHECK(again.json == r.json);
  }
  SECTION("--store on a controller left unlocked stores and leaves it locked") {
    const SpindleFiles g = measure_spindle(w, "unlocked", 5, 1);
    REQUIRE(client.write_one(v::kUnlock, trueaxis::macros::kUnlockCode));
    REQUIRE(read_var(client, v::kUnlock) == 1.0);
    const sim::FlowResult again = spindle_flow(client, g.samples, g.machine, true);
    INFO(again.error);
    REQUIRE(again.ok);
    CHECK(read_var(client, v::kUnlock) == 0.0);
    check_stored(client, parse(again.json));
  }
  SECTION("a later session with --store replaces the model; one revolution gets its intervals from every residual") {
    const SpindleFiles g = measure_spindle(w, "later", 9, 1);
    const sim::FlowResult later = spindle_flow(client, g.samples, g.machine, true);
    INFO(later.error);
    REQUIRE(later.ok);
    const Json out2 = parse(later.json);
    check_shape(out2, data_rows(g.samples));
    CHECK_FALSE(out2["fit"]["noise_from_repeats"].boolean);
    CHECK(out2["parameters"]["o_x_mm"]["value"].number != out["parameters"]["o_x_mm"]["value"].number);
    check_stored(client, out2);
  }
}

TEST_CASE("calibrate spindle: the command with --store and --report, the page drawn from simulator data",
          "[calibrate][spindle]") {
  InProcessSim sim;
  Workspace w("trueaxis-calibrate-spindle");
  const SpindleFiles f = measure_spindle(w, "cmd", 4, 2);
  const double tool = parse(slurp(f.truth))["tool_length_mm"].number;
  const auto command = [&](const std::string& in, const std::vector<std::string>& more) {
    std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY,
                                     "spindle",
                                     "--in",
                                     in,
                                     "--json",
                                     w.file("out.json"),
                                     "--port",
                                     std::to_string(sim.port()),
                                     "--store",
                                     "--report",
                                     w.file("report")};
    argv.insert(argv.end(), more.begin(), more.end());
    return run(argv, w.file("err.txt"));
  };

  // Refused: exit 1, one line, no OUT.json, no report, nothing stored.
  Run r = command(f.samples, {});
  CHECK(r.exit_code == 1);
  CHECK(r.err ==
        "trueaxis-calibrate: spindle needs --machine MACHINE.csv (name,value: bearing_spacing_mm, "
        "gauge_from_upper_bearing_mm, ball_1_mm, ball_2_mm, tool_length_mm)\n");
  CHECK(r.out.empty());
  std::vector<std::string> lines = lines_of(slurp(f.samples));
  lines.erase(std::remove_if(lines.begin() + 3, lines.end(),
                             [](const std::string& l) { return std::stod(fields_of(l)[0]) >= 290.0; }),
              lines.end());
  r = command(w.write("short.csv", text_of(lines)), {"--machine", f.machine});
  CHECK(r.exit_code == 1);
  CHECK(r.err == "trueaxis-calibrate: " + module_error(Status::kRevolutionIncomplete) + " (macro 9842)\n");
  CHECK(r.out.empty());
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK_FALSE(exists(w.file("report")));
  for (const auto& c : corrections(sim.client(), tool)) CHECK(c == kNoTable);

  r = command(f.samples, {"--machine", f.machine});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const Json out = parse(slurp(w.file("out.json")));
  check_shape(out, data_rows(f.samples));
  check_stored(sim.client(), out);
  CHECK(read_var(sim.client(), v::kUnlock) == 0.0);
  // One stdout line: the largest theta_e with its sigma and angle, what was written and stored.
  const Json* worst = &out["per_angle"].items[0];
  for (const Json& a : out["per_angle"].items) {
    if (a["theta_e_arcsec"].number > (*worst)["theta_e_arcsec"].number) worst = &a;
  }
  CHECK((*worst)["theta_e_arcsec"].number == out["theta_e_max_arcsec"].number);
  char summary[160];
  std::snprintf(summary, sizeof summary, "spindle: %g samples, worst theta_e %.4f\" +- %.2g\" (phi=%g), d_e up to %.2f um",
                out["fit"]["samples"].number, (*worst)["theta_e_arcsec"].number,
                (*worst)["theta_e_sigma_arcsec"].number, (*worst)["phi_deg"].number,
                1000.0 * out["d_e_max_mm"].number);
  CHECK(r.out == summary + ("; wrote " + w.file("out.json") + ", report " + w.file("report") +
                            "/index.html; stored (record 5 spindle_model), the first this controller stores; taken as "
                            "given (no data tests them): gauge_from_upper_bearing_mm 350, tool_length_mm 250, "
                            "bearing_spacing_mm 300\n"));

  const std::string page = slurp(w.file("report/index.html"));
  CHECK(page.find("<html") != std::string::npos);
  CHECK(page.find("spindle tool axis (M4)") != std::string::npos);
  CHECK(page.find("e_y_mm") != std::string::npos);           // the parameters' table
  CHECK(page.find("bearing spacing") != std::string::npos);  // said to be informative
  CHECK(page.find("synchronous RMS") != std::string::npos);
  const Json figures = parse(slurp(w.file("report/module_figures.json")));
  CHECK(figures["model_ball_mm"].numbers().size() == 2);
  const std::vector<std::string> pngs = pngs_in(w.file("report"));
  CHECK(pngs.size() == 5);
  for (const std::string& name : pngs) check_figure(page, w.file("report"), name);
}

TEST_CASE("calibrate spindle: a 1,000,000-row file (the samples over and over) is refused at its first repeat, in "
          "bounded memory, with progress for work over 2 s", "[calibrate][spindle]") {
  InProcessSim sim;
  Workspace w("trueaxis-calibrate-spindle");
  const SpindleFiles f = measure_spindle(w, "big", 5, 3);
  const double tool = parse(slurp(f.truth))["tool_length_mm"].number;
  const std::vector<std::string> lines = lines_of(slurp(f.samples));
  REQUIRE(lines.size() == 3 + 432);  // two comments, the header, 3 revolutions x 72 angles x 2 balls
  const std::string big = w.file("big.csv");
  {
    std::ofstream out(big, std::ios::binary);
    for (std::size_t n = 0; n < 3; ++n) out << lines[n] << '\n';
    for (std::size_t row = 0; row < 1000000; ++row) out << lines[3 + row % 432] << '\n';
  }
  const std::string err = w.file("big_err.txt");
  const std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "spindle", "--in", big, "--machine", f.machine,
                                         "--json", w.file("out.json"), "--port", std::to_string(sim.port()),
                                         "--store"};
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ) == 0);
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  struct rusage usage {};
  REQUIRE(::wait4(pid, &status, 0, &usage) == pid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string text = slurp(err);
  INFO(text);
  INFO("peak RSS " << usage.ru_maxrss << " KiB, " << seconds << " s");
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 1);
  CHECK(usage.ru_maxrss <= 50 * 1024);  // KiB: at most 50 MB whatever the file's length
  // The last line the error at the first repeated row (3 + 432 + 1), the lines before it progress.
  const std::vector<std::string> said = lines_of(text);
  REQUIRE_FALSE(said.empty());
  CHECK(said.back() ==
        "trueaxis-calibrate: " + big + ":436: " + module_error(Status::kDuplicateSample) + " (macro 9841)");
  for (std::size_t n = 0; n + 1 < said.size(); ++n) {
    CHECK(said[n].rfind("trueaxis-calibrate: " + big + ": ", 0) == 0);
    CHECK(said[n].find(" of ") != std::string::npos);
  }
  if (seconds > 3.0) CHECK(said.size() > 1);  // work over 2 s said so (3: the process's start and end besides)
  CHECK_FALSE(exists(w.file("out.json")));
  for (const auto& c : corrections(sim.client(), tool)) CHECK(c == kNoTable);
}

TEST_CASE("calibrate spindle: 4,096 samples a revolution x 5, and 3 time-sampled revolutions of a drifting speed, "
          "within 3 sigma of the truth", "[calibrate][spindle][sampling]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-spindle-sampling");
  const struct {
    const char* tag;
    int revolutions;
    std::vector<std::string> sampling;
    std::size_t rows;
  } cases[] = {{"encoder_4096", 5, {"--samples-per-rev", "4096"}, 2 * 4096 * 5},
               {"time_sampled", 3, {"--time-sampled", "--drift-percent", "1"}, 2 * 1024 * 3}};
  for (const auto& c : cases) {
    CAPTURE(c.tag);
    const SpindleFiles f = measure_spindle(w, c.tag, 4, c.revolutions, c.sampling);
    REQUIRE(data_rows(f.samples) == c.rows);
    const Json truth = parse(slurp(f.truth));
    const sim::FlowResult r = spindle_flow(client, f.samples, f.machine, true);
    INFO(r.error);
    REQUIRE(r.ok);
    const Json out = parse(r.json);
    check_shape(out, c.rows);
    CHECK(out["fit"]["noise_from_repeats"].boolean);
    CHECK(out["fit"]["noise_sigma_mm"].number == Approx(15e-6).epsilon(0.05));  // the probes', not the form error
    check_truth(out, truth, truth["tool_length_mm"].number);
    check_stored(client, out);
  }
}
