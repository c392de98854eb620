// `trueaxis-calibrate gantry` (docs/INTERFACE.md "The integrator's command", "M2
// gantry"): its flow (calibrate_gantry, store_gantry) driven in this process
// against a simulator served in this process too (a thread, 127.0.0.1 port 0, RAM
// storage), on files the virtual laser tracker measured off the virtual gantry
// (gantry_measure.hpp), with that gantry's truth beside them:
//  1. good data: OUT.json parses, every origin within 3 sigma of the truth,
//     global_T_sub a rigid transform; the stored frames convert (9825) as
//     OUT.json's global_T_sub says; any CSV order gives the same OUT.json; a
//     later session of one sub-machine replaces only that one;
//  2. the command itself (its binary, against the same simulator) with --store
//     and --report: the page and its figures from simulator data.
// Every bad input: test_calibrate_gantry_inputs.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "calibrate_gantry_support.hpp"
#include "calibrate_support.hpp"

namespace {

namespace v = trueaxis::macros::var;
namespace sim = trueaxis::sim;
using namespace trueaxis::test;

}  // namespace

TEST_CASE("calibrate gantry: the frames of the virtual gantry, within 3 sigma of its truth, stored and converting",
          "[calibrate][gantry]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-gantry");
  const Measured m = measure(sim::GantryPlan{}, 1);
  const std::string samples = w.write("samples.csv", m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const Json truth = parse(m.truth);
  for (const auto& c : conversions(client)) CHECK(c == std::vector<double>{404.0});  // no_table

  const sim::FlowResult r = flow(client, samples, machine, true);
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
  const Json out = parse(r.json);
  CHECK(out["method"].text == "gantry");
  for (const char* key : {"origin_mm", "x", "y", "z"}) CHECK(out["global"][key].numbers().size() == 3);
  CHECK(out["global"]["bed_flatness_mm"].kind == Json::kNumber);
  CHECK(out["global"]["gantry_straightness_mm"].kind == Json::kNumber);
  // issue 17 item 6 (docs/INTERFACE.md "Additions"): the noise floors near the
  // peak-to-valley figures, the virtual bed flat (form error 0 within 3 sigma).
  const Json& glob = out["global"];
  for (const char* key : {"bed_flatness_noise_floor_mm", "gantry_straightness_noise_floor_mm", "bed_form_error_mm",
                          "bed_form_error_sigma_mm", "gantry_form_error_mm", "gantry_form_error_sigma_mm"}) {
    CAPTURE(key);
    CHECK(glob[key].kind == Json::kNumber);
    CHECK(glob[key].number >= 0.0);
  }
  CHECK(glob["bed_flatness_noise_floor_mm"].number > 0.5 * glob["bed_flatness_mm"].number);
  CHECK(glob["bed_flatness_noise_floor_mm"].number < 2.0 * glob["bed_flatness_mm"].number);
  CHECK(glob["gantry_straightness_noise_floor_mm"].number > 0.5 * glob["gantry_straightness_mm"].number);
  CHECK(glob["bed_form_error_sigma_mm"].number > 0.0);
  CHECK(glob["gantry_form_error_sigma_mm"].number > 0.0);
  CHECK(glob["bed_form_error_mm"].number <= 3.0 * glob["bed_form_error_sigma_mm"].number);
  REQUIRE(out["sub_machines"].items.size() == 4);
  const std::vector<std::vector<double>> converted = conversions(client);
  // The added keys are the module's outputs, each in its place (9824, 9826 from
  // the frames just stored, which hold this computation whole).
  const auto outputs = [&](std::uint16_t macro, int sub, std::uint16_t first, std::uint16_t count) {
    REQUIRE(client.write_one(v::kArgR, 1.0));
    REQUIRE(client.write_one(v::kArgT, sub));
    REQUIRE(client.run_macro(macro).status == 2);
    std::vector<double> got(count);
    REQUIRE(client.read(first, count, got.data()));
    return got;
  };
  const std::vector<double> floors = outputs(9824, 1, v::kGlobalBedFlatnessFloor, 6);
  const char* global_keys[6] = {"bed_flatness_noise_floor_mm", "gantry_straightness_noise_floor_mm",
                                "bed_form_error_mm", "bed_form_error_sigma_mm", "gantry_form_error_mm",
                                "gantry_form_error_sigma_mm"};
  for (std::size_t k = 0; k < 6; ++k) CHECK(glob[global_keys[k]].number == Approx(floors[k]).epsilon(1e-14));
  for (int n = 1; n <= 4; ++n) {
    CAPTURE(n);
    const Json& s = sub_of(out, n);
    const std::vector<double> sigmas = outputs(9826, n, v::kSubSquarenessSigmaXY, 5);
    const std::vector<double> angles = outputs(9826, n, v::kSubAngleSigmaX, 3);
    CHECK(s["squareness_sigma_arcsec"]["xy"].number == Approx(sigmas[0]).epsilon(1e-14));
    CHECK(s["squareness_sigma_arcsec"]["yz"].number == Approx(sigmas[1]).epsilon(1e-14));
    CHECK(s["squareness_sigma_arcsec"]["zx"].number == Approx(sigmas[2]).epsilon(1e-14));
    CHECK(s["a_c_offset_sigma_mm"].number == Approx(sigmas[3]).epsilon(1e-14));
    CHECK(s["a_c_angle_sigma_deg"].number == Approx(sigmas[4]).epsilon(1e-14));
    for (std::size_t k = 0; k < 3; ++k) CHECK(s["angle_sigma_arcsec"].numbers()[k] == Approx(angles[k]).epsilon(1e-14));
  }
  REQUIRE(client.give_back_interface());
  for (int n = 1; n <= 4; ++n) {
    CAPTURE(n);
    const Json& s = sub_of(out, n);
    const Json& t = sub_of(truth, n);
    CHECK(s["master_axis"].text == t["master_axis"].text);
    for (const char* pair : {"xy", "yz", "zx"}) CHECK(s["squareness_arcsec"][pair].kind == Json::kNumber);
    CHECK(s["a_c_offset_mm"].kind == Json::kNumber);
    CHECK(s["a_c_angle_deg"].number == Approx(90.0).margin(0.1));
    // Their 1-sigma (docs/INTERFACE.md "Additions"), and the truth within 3 of them.
    for (const char* pair : {"xy", "yz", "zx"}) {
      CAPTURE(pair);
      const double sigma = s["squareness_sigma_arcsec"][pair].number;
      CHECK(sigma > 0.01);
      CHECK(sigma < 30.0);
      CHECK(std::abs(s["squareness_arcsec"][pair].number - t["squareness_arcsec"][pair].number) < 3.0 * sigma);
    }
    CHECK(s["a_c_offset_sigma_mm"].number > 0.0);
    CHECK(std::abs(s["a_c_offset_mm"].number - t["a_c_offset_mm"].number) < 3.0 * s["a_c_offset_sigma_mm"].number);
    CHECK(s["a_c_angle_sigma_deg"].number > 0.0);
    CHECK(std::abs(s["a_c_angle_deg"].number - t["a_c_angle_deg"].number) < 3.0 * s["a_c_angle_sigma_deg"].number);
    REQUIRE(s["angle_sigma_arcsec"].numbers().size() == 3);
    for (const double a : s["angle_sigma_arcsec"].numbers()) CHECK(a > 0.0);
    // The origin within 3 sigma of the truth (the sigma from the data's scatter).
    const double sigma = s["origin_sigma_mm"].number;
    CHECK(sigma > 0.001);
    CHECK(sigma < 0.1);
    const double error = distance(s["origin_mm"].numbers(), t["origin_mm"].numbers());
    CAPTURE(error, sigma);
    CHECK(error < 3.0 * sigma);
    // global_T_sub: [x' y' z' O] as columns, rows 1-3 orthonormal, last row 0 0 0 1.
    const std::vector<double> T = s["global_T_sub"].numbers();
    REQUIRE(T.size() == 16);
    CHECK(std::vector<double>(T.begin() + 12, T.end()) == std::vector<double>{0, 0, 0, 1});
    const std::vector<double> cols[3] = {s["x"].numbers(), s["y"].numbers(), s["z"].numbers()};
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(T[4 * i + 3] == s["origin_mm"].numbers()[i]);
      for (std::size_t j = 0; j < 3; ++j) {
        CHECK(T[4 * i + j] == cols[j][i]);
        double dot = 0.0;
        for (std::size_t k = 0; k < 3; ++k) dot += T[4 * k + i] * T[4 * k + j];
        CHECK(dot == Approx(i == j ? 1.0 : 0.0).margin(1e-12));
      }
    }
    const double det = T[0] * (T[5] * T[10] - T[6] * T[9]) - T[1] * (T[4] * T[10] - T[6] * T[8]) +
                       T[2] * (T[4] * T[9] - T[5] * T[8]);
    CHECK(det == Approx(1.0).margin(1e-12));
    // What the controller stored converts as OUT.json says.
    const std::vector<double> q = to_sub(T, kPoint);
    REQUIRE(converted[static_cast<std::size_t>(n - 1)].size() == 3);
    CHECK(distance(converted[static_cast<std::size_t>(n - 1)], q) < 1e-9);
  }
  // The report's extra figures are not OUT.json's.
  CHECK(r.json.find("\"straightness_mm\"") == std::string::npos);
  CHECK(r.report_extras.find("sub_machine_figures") != std::string::npos);
  // Nothing renamed: every key of docs/INTERFACE.md's OUT.json is still there (above), once.
  for (const char* key : {"\"bed_flatness_mm\"", "\"bed_form_error_mm\"", "\"a_c_offset_mm\""}) {
    CAPTURE(key);
    const std::size_t first = r.json.find(key);
    CHECK(first != std::string::npos);
    if (std::string(key) != "\"a_c_offset_mm\"") CHECK(r.json.find(key, first + 1) == std::string::npos);
  }

  SECTION("any CSV order: groups interleaved, each group's own order kept, gives the same OUT.json") {
    std::vector<Row> rows = rows_of(m.samples);
    std::vector<Row> mixed;
    // Round robin over the groups, last group first.
    std::vector<std::string> groups;
    for (const Row& row : rows) {
      if (std::find(groups.begin(), groups.end(), row.group) == groups.end()) groups.push_back(row.group);
    }
    std::reverse(groups.begin(), groups.end());
    std::vector<std::size_t> next(groups.size(), 0);
    for (bool any = true; any;) {
      any = false;
      for (std::size_t g = 0; g < groups.size(); ++g) {
        std::size_t seen = 0;
        for (const Row& row : rows) {
          if (row.group != groups[g]) continue;
          if (seen++ == next[g]) {
            mixed.push_back(row);
            ++next[g];
            any = true;
            break;
          }
        }
      }
    }
    REQUIRE(mixed.size() == rows.size());
    REQUIRE(mixed.front().group != rows.front().group);
    const sim::FlowResult again = flow(client, w.write("mixed.csv", "# mixed\n" + text_of(mixed)), machine, false);
    INFO(again.error);
    REQUIRE(again.ok);
    CHECK(again.json == r.json);
  }
  SECTION("a session of one sub-machine (--sub-machines 2), with the whole MACHINE file, replaces that one only") {
    std::vector<Row> rows = rows_of(measure(small_plan(), 7).samples);
    rows.erase(std::remove_if(rows.begin(), rows.end(),
                              [](const Row& row) { return row.group.rfind("sp", 0) == 0 && row.group.rfind("sp2_", 0) != 0; }),
               rows.end());
    // Without --sub-machines the other rows' missing points are refused (test_calibrate_gantry_inputs.cpp).
    const sim::FlowResult two = flow(client, w.write("sp2.csv", text_of(rows)), machine, true, {2});
    INFO(two.error);
    REQUIRE(two.ok);
    REQUIRE(parse(two.json)["sub_machines"].items.size() == 1);
    const std::vector<std::vector<double>> now = conversions(client);
    CHECK(now[0] == converted[0]);
    CHECK(now[1] != converted[1]);
    CHECK(now[2] == converted[2]);
    CHECK(now[3] == converted[3]);
    CHECK(distance(now[1], to_sub(sub_of(parse(two.json), 2)["global_T_sub"].numbers(), kPoint)) < 1e-9);
  }
}

TEST_CASE("calibrate gantry: the command with --store and --report, the page drawn from simulator data",
          "[calibrate][gantry]") {
  InProcessSim sim;
  Workspace w("trueaxis-calibrate-gantry");
  const Measured m = measure(small_plan(), 5);
  const std::string samples = w.write("samples.csv", m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const auto command = [&](const std::string& in, const std::string& json, const std::vector<std::string>& more) {
    std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "gantry", "--in", in, "--json", json,
                                     "--port", std::to_string(sim.port())};
    argv.insert(argv.end(), more.begin(), more.end());
    return run(argv, w.file("err.txt"));
  };

  // Refused: exit 1, one line, no OUT.json, no report, nothing stored.
  Run r = command(samples, w.file("out.json"), {"--store", "--report", w.file("report")});
  CHECK(r.exit_code == 1);
  CHECK(r.err == "trueaxis-calibrate: gantry needs --machine MACHINE.csv (sub_machine,swing_mm,tool_x,tool_y,tool_z)\n");
  CHECK(r.out.empty());
  w.write("bad.csv", "group,x_mm,y_mm,z_mm\nbed,1,2,3\nsp1_q,1,2,3\n");
  r = command(w.file("bad.csv"), w.file("out.json"), {"--machine", machine, "--store", "--report", w.file("report")});
  CHECK(r.exit_code == 1);
  CHECK(r.err == "trueaxis-calibrate: " + w.file("bad.csv") + ":3: unknown group 'sp1_q'\n");
  CHECK(r.out.empty());
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK_FALSE(exists(w.file("report")));
  for (const auto& c : conversions(sim.client())) CHECK(c == std::vector<double>{404.0});

  r = command(samples, w.file("out.json"), {"--machine", machine, "--store", "--report", w.file("report")});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const Json out = parse(slurp(w.file("out.json")));
  REQUIRE(out["sub_machines"].items.size() == 4);
  // One stdout line: the largest origin sigma and its sub-machine, what was written and stored.
  const Json* worst = &out["sub_machines"].items[0];
  for (const Json& sub : out["sub_machines"].items) {
    if (sub["origin_sigma_mm"].number > (*worst)["origin_sigma_mm"].number) worst = &sub;
  }
  char summary[120];
  std::snprintf(summary, sizeof summary, "gantry: 4 sub-machines, worst origin 1-sigma %.1f um (sp%g)",
                1000.0 * (*worst)["origin_sigma_mm"].number, (*worst)["id"].number);
  CHECK(r.out == summary + ("; wrote " + w.file("out.json") + ", report " + w.file("report") +
                            "/index.html; stored (record 4 gantry_frames), the first this controller stores; taken as "
                            "given (no data tests them): swing_mm and tool direction of sub-machines 1, 2, 3, 4 (" +
                            w.file("machine.csv") + " gives no nominal origin: origin_x_mm .. origin_z_mm)\n"));
  const std::vector<std::vector<double>> converted = conversions(sim.client());
  for (std::size_t n = 0; n < 4; ++n) {
    REQUIRE(converted[n].size() == 3);
    CHECK(distance(converted[n], to_sub(out["sub_machines"].items[n]["global_T_sub"].numbers(), kPoint)) < 1e-9);
  }
  CHECK(read_var(sim.client(), v::kUnlock) == 0.0);

  const std::string page = slurp(w.file("report/index.html"));
  CHECK(page.find("<html") != std::string::npos);
  CHECK(page.find("gantry frames (M2)") != std::string::npos);
  CHECK(page.find("sp4 (global frame)") != std::string::npos);  // the table of the frames
  const Json figures = parse(slurp(w.file("report/module_figures.json")));
  CHECK(figures["sub_machine_figures"].items.size() == 4);
  const std::vector<std::string> pngs = pngs_in(w.file("report"));
  CHECK(pngs.size() == 6);
  for (const std::string& name : pngs) check_figure(page, w.file("report"), name);
}
