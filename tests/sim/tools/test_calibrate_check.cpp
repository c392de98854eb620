// trueaxis-calibrate METHOD --check (docs/INTERFACE.md "Check mode and the
// log"): the same inputs as a calibration, compared with the stored one and
// nothing stored. OUT.json's "check" object against the module's check macro;
// exit 0 on pass, 3 on fail (OUT.json and the report written), 1 with one line
// without a stored calibration or with --store; the stored table untouched
// every time; the report opens with the verdict and the record.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "calibrate_gantry_support.hpp"
#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "in_process_sim.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/sim/tools/sha256.hpp"

namespace {

using trueaxis::sim::VariableClient;
using trueaxis::test::exists;
using trueaxis::test::Json;
using trueaxis::test::parse;
using trueaxis::test::run;
using trueaxis::test::Run;
using trueaxis::sim::test::SimFixture;
using trueaxis::test::slurp;
using trueaxis::test::Workspace;
namespace v = trueaxis::macros::var;

// 9833 at A = 60 (R = 1 clamps): the stored table's rotation vector and its norm.
std::vector<double> stored_rotvec(VariableClient& client) {
  REQUIRE(client.write_one(v::kArgA, 60.0));
  REQUIRE(client.write_one(v::kArgR, 1.0));
  REQUIRE(client.run_macro(9833).status == 2);
  std::vector<double> r(4);
  REQUIRE(client.read(v::kRigidityRotvecX, 4, r.data()));
  REQUIRE(client.give_back_interface());
  return r;
}

Run calibrate(const std::vector<std::string>& args, int port, const Workspace& w) {
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--port", std::to_string(port)});
  return run(argv, w.file("calibrate.err"));
}

// OUT.json's check: the verdict and the keys of every figure, each judged as check.hpp says.
void check_object(const Json& check, const std::string& verdict) {
  CHECK(check["verdict"].text == verdict);
  REQUIRE(check["figures"].kind == Json::kArray);
  REQUIRE_FALSE(check["figures"].items.empty());
  std::string worst = "pass";
  for (const Json& f : check["figures"].items) {
    INFO(f["name"].text);
    CHECK_FALSE(f["name"].text.empty());
    for (const char* key : {"stored", "measured", "deviation", "sigma", "tolerance"}) CHECK(f[key].kind == Json::kNumber);
    trueaxis::macros::CheckFigure figure;
    figure.deviation = f["deviation"].number;
    figure.sigma = f["sigma"].number;
    figure.tolerance = f["tolerance"].number;
    CHECK(f["verdict"].text == trueaxis::macros::verdict_name(trueaxis::macros::judge(figure)));
    if (f["verdict"].text == "fail" || (f["verdict"].text == "warn" && worst == "pass")) worst = f["verdict"].text;
  }
  CHECK(worst == verdict);
}

}  // namespace

TEST_CASE("calibrate rigidity --check: refused without a stored table, passes unchanged, exits 3 on a moved machine; "
          "nothing stored",
          "[calibrate][check]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-check");
  const auto measure = [&](const std::string& name) {
    const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file(name)},
                      w.file("measure.err"));
    REQUIRE(m.exit_code == 0);
  };
  measure("first.csv");
  const std::vector<std::string> check_args = {"rigidity", "--in", w.file("first.csv"), "--json", w.file("out.json"),
                                               "--check", "--report", w.file("report"), "--operator", "Ann \"A\" O'Neil"};
  {
    const Run none = calibrate(check_args, sim.port(), w);
    INFO(none.err);
    CHECK(none.exit_code == 1);
    CHECK(none.err.find("no_table") != std::string::npos);
    CHECK(none.err.find("no stored calibration to check against") != std::string::npos);
    CHECK_FALSE(exists(w.file("out.json")));
  }
  {
    const Run both = calibrate({"rigidity", "--in", w.file("first.csv"), "--json", w.file("out.json"), "--check",
                                "--store"},
                               sim.port(), w);
    CHECK(both.exit_code == 1);
    CHECK(both.err.find("not with --store") != std::string::npos);
  }
  const Run stored = calibrate({"rigidity", "--in", w.file("first.csv"), "--json", w.file("first.json"), "--store",
                                "--time", "2027-01-15T08:00:00Z"},
                               sim.port(), w);
  REQUIRE(stored.exit_code == 0);
  // The stored record as the module exports it (9837), for its hash.
  const Run exported = calibrate({"linuxcnc-kins", "rigidity", "--out", w.file("table.kins")}, sim.port(), w);
  REQUIRE(exported.exit_code == 0);
  const std::string kins = slurp(w.file("table.kins"));
  REQUIRE(kins.size() > trueaxis::macros::kRecordFileOverhead);
  const std::string record_sha = trueaxis::sim::sha256_hex(kins.substr(16, kins.size() - 20));
  const std::vector<double> before = stored_rotvec(sim.client());

  measure("again.csv");
  std::vector<std::string> again = check_args;
  again[2] = w.file("again.csv");
  const Run pass = calibrate(again, sim.port(), w);
  INFO(pass.err);
  REQUIRE(pass.exit_code == 0);
  CHECK(pass.out.find("check: pass") != std::string::npos);
  CHECK(pass.out.find("not stored") != std::string::npos);
  const Json doc = parse(slurp(w.file("out.json")));
  check_object(doc["check"], "pass");
  CHECK(doc["check"]["figures"].items.size() == 12);  // 6 poses but the reference, 2 figures each
  CHECK(doc["poses"].items.size() == 7);               // and OUT.json is a calibration's besides
  const std::string page = slurp(w.file("report/index.html"));
  CHECK(page.find("Verdict: pass") != std::string::npos);
  CHECK(page.find("Ann &quot;A&quot; O&#x27;Neil") != std::string::npos);
  CHECK(page.find("rotation_change_a90") != std::string::npos);
  // Every figure named by its pose's A (issue 32): item q is OUT.json's pose q, in A order.
  for (const Json& f : doc["check"]["figures"].items) {
    INFO(f["name"].text);
    const auto q = static_cast<std::size_t>(f["item"].number);
    REQUIRE(q >= 1);
    REQUIRE(q <= doc["poses"].items.size());
    const double a = doc["poses"].items[q - 1]["a_deg"].number;
    CHECK(f["a_deg"].number == a);
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_a%g", a);
    CHECK(f["name"].text == f["kind"].text + suffix);
  }
  CHECK(doc["check"]["figures"].items[0]["name"].text == "rotation_change_a-90");
  CHECK(doc["check"]["figures"].items[1]["name"].text == "a_positioning_error_change_a-90");
  CHECK(page.find("SHA-256") != std::string::npos);
  CHECK(stored_rotvec(sim.client()) == before);
  // The stored calibration the check judged (issue 32): its table sequence, the
  // date of its store, the SHA-256 of its record as 9837 exports it, on the page too.
  const Json& judged = doc["check"]["stored_calibration"];
  CHECK(judged["table_sequence"].number == 1.0);
  CHECK(judged["stored_time_s"].number == 1800000000.0);
  CHECK(judged["stored_time_utc"].text == "2027-01-15 08:00:00");
  CHECK(judged["record"].text == "record 3 rigidity_table");
  CHECK(judged["record_bytes"].number == static_cast<double>(kins.size() - 20));
  CHECK(judged["record_sha256"].text == record_sha);
  CHECK(judged["note"].kind == Json::kNull);
  CHECK(page.find("Stored calibration judged") != std::string::npos);
  CHECK(page.find("table sequence 1; stored 2027-01-15 08:00:00 UTC; record 3 rigidity_table (" +
                  std::to_string(kins.size() - 20) + " bytes as the module exports it) SHA-256 " + record_sha) !=
        std::string::npos);

  // Tolerances set to the largest |deviation| + sigma of that check: no figure
  // beyond them, the worst's guard band over them: warn, and warn exits 0.
  double tolerance = 0.0;
  for (const Json& f : doc["check"]["figures"].items) {
    tolerance = std::max(tolerance, std::abs(f["deviation"].number) + f["sigma"].number);
  }
  REQUIRE(sim.client().write_one(v::kUnlock, trueaxis::macros::kUnlockCode));
  REQUIRE(sim.client().write_one(v::kRigidityCheckRotation, tolerance));
  REQUIRE(sim.client().write_one(v::kRigidityCheckAError, tolerance));
  REQUIRE(sim.client().write_one(v::kUnlock, 0.0));
  REQUIRE(sim.client().give_back_interface());
  const Run warn = calibrate(again, sim.port(), w);
  INFO(warn.err);
  CHECK(warn.exit_code == 0);
  CHECK(warn.out.find("check: warn") != std::string::npos);
  check_object(parse(slurp(w.file("out.json")))["check"], "warn");
  CHECK(slurp(w.file("report/index.html")).find("Verdict: warn") != std::string::npos);

  REQUIRE(sim.client().write_one(12020, 0.0));  // the ideal machine: some 50" less rigidity at A = +-60, 90
  REQUIRE(sim.client().give_back_interface());
  measure("moved.csv");
  std::vector<std::string> moved = check_args;
  moved[2] = w.file("moved.csv");
  const Run failed = calibrate(moved, sim.port(), w);
  INFO(failed.err);
  CHECK(failed.exit_code == 3);
  CHECK(failed.out.find("check: fail") != std::string::npos);
  const Json fail_doc = parse(slurp(w.file("out.json")));
  check_object(fail_doc["check"], "fail");
  CHECK(slurp(w.file("report/index.html")).find("Verdict: fail") != std::string::npos);
  CHECK(stored_rotvec(sim.client()) == before);  // a check stores nothing
}

TEST_CASE("calibrate spindle and gantry --check: a second measurement of the unchanged machine passes", "[calibrate][check]") {
  trueaxis::test::InProcessSim sim;
  Workspace w("trueaxis-calibrate-check");
  const trueaxis::test::SpindleFiles f = trueaxis::test::measure_spindle(w, "s", 2, 3);
  REQUIRE(calibrate({"spindle", "--in", f.samples, "--machine", f.machine, "--json", w.file("s.json"), "--store"},
                    sim.port(), w)
              .exit_code == 0);
  const trueaxis::test::SpindleFiles g = trueaxis::test::measure_spindle(w, "t", 3, 3);
  const Run spindle = calibrate({"spindle", "--in", g.samples, "--machine", g.machine, "--json", w.file("s.json"),
                                 "--check"},
                                sim.port(), w);
  INFO(spindle.err);
  REQUIRE(spindle.exit_code == 0);
  const Json s = parse(slurp(w.file("s.json")));
  check_object(s["check"], "pass");
  CHECK(s["check"]["figures"].items.size() == 6);
  CHECK(s["check"]["figures"].items[0]["name"].text == "a_x");
  // M4's stored model named by the hash of its record as 9847 exports it.
  REQUIRE(calibrate({"linuxcnc-kins", "spindle", "--out", w.file("model.kins")}, sim.port(), w).exit_code == 0);
  const std::string model = slurp(w.file("model.kins"));
  CHECK(s["check"]["stored_calibration"]["record_sha256"].text ==
        trueaxis::sim::sha256_hex(model.substr(16, model.size() - 20)));
  CHECK(s["check"]["stored_calibration"]["record"].text == "record 5 spindle_model");
  CHECK(s["check"]["stored_calibration"]["table_sequence"].number >= 1.0);

  const trueaxis::test::Measured m = trueaxis::test::measure(trueaxis::sim::GantryPlan{}, 5);
  w.write("g.csv", m.samples);
  w.write("g_machine.csv", m.machine);
  REQUIRE(calibrate({"gantry", "--in", w.file("g.csv"), "--machine", w.file("g_machine.csv"), "--json",
                     w.file("g.json"), "--store"},
                    sim.port(), w)
              .exit_code == 0);
  const trueaxis::test::Measured m2 = trueaxis::test::measure(trueaxis::sim::GantryPlan{}, 6);
  w.write("g2.csv", m2.samples);
  const Run gantry = calibrate({"gantry", "--in", w.file("g2.csv"), "--machine", w.file("g_machine.csv"), "--json",
                                w.file("g.json"), "--check"},
                               sim.port(), w);
  INFO(gantry.err);
  REQUIRE(gantry.exit_code == 0);
  const Json g2 = parse(slurp(w.file("g.json")));
  check_object(g2["check"], "pass");
  CHECK(g2["check"]["figures"].items.size() == 8);
  CHECK(g2["check"]["figures"].items[0]["name"].text == "origin_change_sp1");
  // M2 has no exact export of its stored frames: no hash, and the note says so.
  const Json& frames = g2["check"]["stored_calibration"];
  CHECK(frames["record_sha256"].kind == Json::kNull);
  CHECK(frames["table_sequence"].number >= 1.0);
  CHECK(frames["stored_time_s"].kind == Json::kNumber);
  CHECK(frames["note"].text.find("gantry has no exact export of its stored record") != std::string::npos);
  for (const Json& figure : g2["check"]["figures"].items) {
    CHECK(figure["sub_machine"].number == figure["item"].number);
    CHECK(figure["name"].text == figure["kind"].text + "_sp" + std::to_string(static_cast<int>(figure["item"].number)));
  }
}
