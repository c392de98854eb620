// `trueaxis-calibrate rigidity` as an integrator runs it (docs/INTERFACE.md "The
// integrator's command", "M3 rigidity"): the tools run as child processes (argv,
// no shell) against a trueaxis-sim; OUT.json is parsed and held against what the
// module answers over Modbus (9832, 9834, 9833); every bad input gets exit 1, one
// stderr line naming its physical line or the module's code, no OUT.json, no
// report, nothing stored and the module locked again; a stored table whose CRC
// fails falls back to the older copy, then to no table.
#include <catch2/catch.hpp>
#include <dirent.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;
using trueaxis::sim::SimProcess;
using trueaxis::sim::VariableClient;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

// ---- the tools ------------------------------------------------------------------------

std::string measure(int port, const Workspace& w, const std::string& name, std::vector<std::string> extra = {}) {
  std::vector<std::string> argv = {TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(port), "--out", w.file(name)};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const Run r = run(argv, w.file("measure.err"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return slurp(w.file(name));
}

Run calibrate(int port, const Workspace& w, const std::string& in, const std::string& json, bool store,
              const std::string& report = "", bool accept_change = false) {
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", in, "--json", json,
                                   "--port", std::to_string(port)};
  if (store) argv.emplace_back("--store");
  if (!report.empty()) argv.insert(argv.end(), {"--report", report});
  if (accept_change) argv.emplace_back("--accept-change");
  return run(argv, w.file("calibrate.err"));
}

// The pose's 20 figures in 9834's order (#100..#116, #118..#120), -1e300 for a missing or ill-typed key.
std::vector<double> pose_figures(const Json& pose) {
  std::vector<double> f;
  const auto num = [&](const char* key) { f.push_back(pose[key].kind == Json::kNumber ? pose[key].number : -1e300); };
  const auto vec = [&](const char* key) {
    const Json& a = pose[key];
    for (std::size_t i = 0; i < 3; ++i) {
      f.push_back(a.items.size() == 3 && a.items[i].kind == Json::kNumber ? a.items[i].number : -1e300);
    }
  };
  num("a_deg");
  vec("rotation_vector_arcsec");
  vec("rotation_vector_sigma_arcsec");
  num("rigidity_arcsec");
  num("rigidity_sigma_arcsec");
  num("a_positioning_error_arcsec");
  vec("c_centre_mm");
  vec("c_direction");
  num("c_circle_rms_mm");
  num("a_positioning_error_sigma_arcsec");
  num("c_circle_rms_sigma_mm");
  num("c_circle_rms_noise_floor_mm");
  return f;
}

// 9834's #100..#120 less #117 (the pose count): what pose_figures reads from OUT.json.
std::vector<double> figures_of(const std::vector<double>& p) {
  std::vector<double> f(p.begin(), p.begin() + 17);
  f.insert(f.end(), p.begin() + 18, p.end());
  return f;
}

// ---- the module over Modbus --------------------------------------------------------------

// 9834 pose q of the table built last (stored = 0) or the stored one: #100..#120,
// or {error} when the macro fails.
std::vector<double> pose(VariableClient& client, int q, int stored) {
  const double args[2] = {static_cast<double>(q), static_cast<double>(stored)};
  REQUIRE(client.write(v::kArgQ, 2, args));
  const auto outcome = client.run_macro(9834);
  REQUIRE(outcome.status >= 2);
  REQUIRE(client.give_back_interface());  // for the commands the test runs next
  if (outcome.status == 3) return {static_cast<double>(outcome.error)};
  std::vector<double> p(21);
  REQUIRE(client.read(v::kPoseA, 21, p.data()));
  return p;
}

// 9833 at commanded A, blend Q, clamp R: #100..#103, or {error}.
std::vector<double> query(VariableClient& client, double a_deg, int blend, int clamp) {
  const double qr[2] = {static_cast<double>(blend), static_cast<double>(clamp)};
  REQUIRE(client.write_one(v::kArgA, a_deg));
  REQUIRE(client.write(v::kArgQ, 2, qr));
  const auto outcome = client.run_macro(9833);
  REQUIRE(outcome.status >= 2);
  REQUIRE(client.give_back_interface());  // for the commands the test runs next
  if (outcome.status == 3) return {static_cast<double>(outcome.error)};
  std::vector<double> r(4);
  REQUIRE(client.read(v::kRigidityRotvecX, 4, r.data()));
  return r;
}

// What a client can see of the stored table: every pose (9834 R = 1) and 9833
// at three A with every blend; 404s when there is none.
std::vector<std::vector<double>> stored_table(VariableClient& client) {
  std::vector<std::vector<double>> t;
  const std::vector<double> first = pose(client, 1, 1);
  t.push_back(first);
  for (int q = 2; first.size() == 21 && q <= static_cast<int>(first[17]); ++q) t.push_back(pose(client, q, 1));
  for (double a : {-75.0, 10.0, 45.0}) {
    for (int blend = 0; blend <= 2; ++blend) t.push_back(query(client, a, blend, 0));
  }
  return t;
}

double read_var(VariableClient& client, std::uint16_t number) {
  double x = 0.0;
  REQUIRE(client.read_one(number, x));
  return x;
}

const std::vector<double> kNoTable = {404.0};
const std::vector<double> kTableDamaged = {405.0};

// ---- samples files ------------------------------------------------------------------------

struct Row {
  double a_deg, c_deg;
  std::string text;
};

std::vector<Row> rows_of(const std::string& csv) {
  std::vector<Row> rows;
  std::istringstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'a') continue;
    char* end = nullptr;
    const double a = std::strtod(line.c_str(), &end);
    rows.push_back({a, std::strtod(end + 1, nullptr), line});
  }
  return rows;
}

const std::string kHeader = "a_deg,c_deg,x_mm,y_mm,z_mm\n";

template <class Keep>
std::string csv_where(const std::vector<Row>& rows, Keep keep) {
  std::string out = kHeader;
  for (const Row& r : rows) {
    if (keep(r)) out += r.text + "\n";
  }
  return out;
}

std::string module_error(Status s) {
  return "trueaxis-calibrate: module error " + std::to_string(static_cast<int>(s)) + " " +
         trueaxis::macros::status_name(s) + ": " + trueaxis::macros::status_message(s);
}

// The command's one stdout line for OUT.json's poses (the largest rigidity with
// its sigma and pose), then what it wrote and stored (`tail`).
std::string summary_line(const Json& json, const std::string& tail) {
  const Json* worst = nullptr;
  for (const Json& p : json["poses"].items) {
    if (worst == nullptr || p["rigidity_arcsec"].number > (*worst)["rigidity_arcsec"].number) worst = &p;
  }
  REQUIRE(worst != nullptr);
  char line[200];
  std::snprintf(line, sizeof line, "rigidity: %zu poses, worst rigidity %.2f\" +- %.2f\" (pose A=%g)",
                json["poses"].items.size(), (*worst)["rigidity_arcsec"].number,
                (*worst)["rigidity_sigma_arcsec"].number, (*worst)["a_deg"].number);
  return line + tail + "\n";
}

}  // namespace

TEST_CASE("calibrate rigidity: OUT.json holds exactly what the module computed, --store stores it, --report draws it",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-cli");
  const std::string samples = measure(sim.port(), w, "samples.csv");
  REQUIRE(rows_of(samples).size() == 252);
  REQUIRE(read_var(client, v::kUnlock) == 0.0);  // locked
  CHECK(query(client, 0.0, 0, 0) == kNoTable);

  // Without --store: the module's figures, nothing stored.
  Run r = calibrate(sim.port(), w, w.file("samples.csv"), w.file("built.json"), false);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const std::string built = slurp(w.file("built.json"));
  Json json;
  REQUIRE(JsonReader(built).parse(json));
  CHECK(r.out == summary_line(json, "; wrote " + w.file("built.json") + "; not stored"));
  CHECK(json["method"].text == "rigidity");
  CHECK(json["reference_a_deg"].kind == Json::kNumber);
  CHECK(json["reference_a_deg"].number == 0.0);
  const Json& poses = json["poses"];
  REQUIRE(poses.items.size() == 7);
  for (int q = 1; q <= 7; ++q) {
    CAPTURE(q);
    const std::vector<double> p = pose(client, q, 0);
    REQUIRE(p.size() == 21);
    CHECK(p[17] == 7.0);
    CHECK(pose_figures(poses.items[static_cast<std::size_t>(q - 1)]) == figures_of(p));
    CHECK(p[19] > 0.0);  // the C-circle RMS's sigma and noise floor under the default #601
    CHECK(p[20] > 0.0);
    CHECK((q == 4) == (p[18] == 0.0));  // the A error's sigma: 0 only at the reference
    CHECK(p[0] == -120.0 + 30.0 * q);
  }
  const std::vector<double> reference = pose_figures(poses.items[3]);
  CHECK(std::vector<double>(reference.begin(), reference.begin() + 4) == std::vector<double>{0.0, 0.0, 0.0, 0.0});
  // The A axis as the build reports it (9832 R = 0 again on the session kept).
  REQUIRE(client.write_one(v::kArgR, 0.0));
  REQUIRE(client.run_macro(9832).status == 2);
  double build[12];
  REQUIRE(client.read(v::kRigidityPoses, 12, build));
  CHECK(build[0] == 7.0);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(json["a_axis"]["point_mm"].items.at(i).number == build[3 + i]);
    CHECK(json["a_axis"]["direction"].items.at(i).number == build[6 + i]);
  }
  CHECK(pose(client, 1, 1) == kNoTable);
  CHECK(query(client, 45.0, 0, 0) == kNoTable);

  // The same samples with the columns in another order, an extra column, spaces,
  // CRLF, comments and blank lines: the same OUT.json byte for byte.
  std::string variant = "# shuffled\r\n\r\nz_mm,note,c_deg , a_deg,y_mm,x_mm\r\n";
  for (const Row& row : rows_of(samples)) {
    std::vector<std::string> f;
    std::istringstream fields(row.text);
    for (std::string s; std::getline(fields, s, ',');) f.push_back(s);
    variant += f[4] + ",probe 7, " + f[1] + " ," + f[0] + "," + f[3] + "," + f[2] + "\r\n# again\r\n";
  }
  r = calibrate(sim.port(), w, w.write("variant.csv", variant), w.file("variant.json"), false);
  CHECK(r.exit_code == 0);
  CHECK(slurp(w.file("variant.json")) == built);

  // With --store (the controller locked) and --report.
  r = calibrate(sim.port(), w, w.file("samples.csv"), w.file("stored.json"), true, w.file("report"));
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK(r.out == summary_line(json, "; wrote " + w.file("stored.json") + ", report " + w.file("report") +
                                        "/index.html; stored (record 3 rigidity_table), the first this controller stores"));
  CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
  CHECK(slurp(w.file("stored.json")) == built);
  for (int q = 1; q <= 7; ++q) {
    CAPTURE(q);
    const std::vector<double> p = pose(client, q, 1);
    REQUIRE(p.size() == 21);
    CHECK(pose_figures(poses.items[static_cast<std::size_t>(q - 1)]) == figures_of(p));
    for (int blend = 0; blend <= 2; ++blend) {
      const std::vector<double> at_pose = query(client, p[0], blend, 0);
      REQUIRE(at_pose.size() == 4);
      for (std::size_t i = 0; i < 3; ++i) CHECK(at_pose[i] == Approx(p[1 + i]).margin(1e-9));
    }
  }

  {  // A query outside the measured A range is refused, or clamped to the end pose.
    const std::vector<double> first = pose(client, 1, 1), last = pose(client, 7, 1);
    for (int blend = 0; blend <= 2; ++blend) {
      CAPTURE(blend);
      CHECK(query(client, 95.0, blend, 0) == std::vector<double>{106.0});
      CHECK(query(client, -90.5, blend, 0) == std::vector<double>{106.0});
      const std::vector<double> high = query(client, 95.0, blend, 1), low = query(client, -200.0, blend, 1);
      REQUIRE(high.size() == 4);
      REQUIRE(low.size() == 4);
      for (std::size_t i = 0; i < 3; ++i) {
        CHECK(high[i] == Approx(last[1 + i]).margin(1e-9));
        CHECK(low[i] == Approx(first[1 + i]).margin(1e-9));
      }
      CHECK(high[3] == Approx(last[7]).margin(1e-9));
    }
  }
  {  // The report is a page and four PNG figures.
    const std::string page = slurp(w.file("report/index.html"));
    CHECK(page.find("<html") != std::string::npos);
    const std::vector<std::string> pngs = pngs_in(w.file("report"));
    CHECK(pngs.size() == 4);
    for (const std::string& name : pngs) check_figure(page, w.file("report"), name);
  }
}

TEST_CASE("calibrate rigidity: a bad sample is named by its line or the module's code; nothing written or stored",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-cli");
  const std::vector<Row> good = rows_of(measure(sim.port(), w, "samples.csv"));
  const std::vector<Row> fine = rows_of(measure(sim.port(), w, "fine.csv", {"--a-from", "30", "--a-to", "30",
                                                                           "--c-step", "5"}));
  const std::vector<Row> many = rows_of(measure(sim.port(), w, "many.csv", {"--a-from", "-80", "--a-to", "80",
                                                                           "--a-step", "10", "--c-step", "30"}));
  REQUIRE(good.size() == 252);
  REQUIRE(fine.size() == 72);
  REQUIRE(many.size() == 17 * 12);

  struct Case {
    std::string name, csv, line;  // line: the whole stderr line (CSV) or its start (module)
    bool module_called;
  };
  std::vector<Case> cases;
  const std::string bad = w.file("bad.csv"), at = "trueaxis-calibrate: " + bad + ":";
  // Lines 1 comment, 2 blank, 3 header, 4 a sample, 5 comment, 6 blank, 7 the bad row.
  const std::string lead = "# rig 3\n\n" + kHeader + "0,0,1,2,3\n   # an indented comment\n\n";
  const auto csv_case = [&](const std::string& name, const std::string& row, const std::string& what) {
    cases.push_back({name, lead + row + "\n0,10,1,2,3\n", at + "7: " + what + "\n", false});
  };
  csv_case("a word", "0,abc,1,2,3", "'c_deg' is not a finite number: 'abc'");
  csv_case("a number with a tail", "0,0,1.5x,2,3", "'x_mm' is not a finite number: '1.5x'");
  csv_case("nan", "0,0,1,nan,3", "'y_mm' is not a finite number: 'nan'");
  csv_case("-inf", "0,0,1,2,-inf", "'z_mm' is not a finite number: '-inf'");
  csv_case("an overflow", "1e999,0,1,2,3", "'a_deg' is not a finite number: '1e999'");
  csv_case("an empty field", "0,,1,2,3", "'c_deg' is not a finite number: ''");
  csv_case("a missing field", "0,0,1,2", "too few fields: no value for 'z_mm'");
  cases.push_back({"a missing column", "# rig 3\na_deg,c_deg,x_mm,z_mm\n0,0,1,3\n",
                   at + "2: the header has no column 'y_mm'\n", false});
  cases.push_back({"an empty file", "", at + "1: no header row\n", false});
  cases.push_back({"';' as separator", "a_deg;c_deg;x_mm;y_mm;z_mm\n0;0;1;2;3\n",
                   at + "1: the file uses ';' as separator; trueaxis reads ','\n", false});
  cases.push_back({"tabs as separator", "# rig 3\na_deg\tc_deg\tx_mm\ty_mm\tz_mm\n0\t0\t1\t2\t3\n",
                   at + "2: the file uses tabs as separator; trueaxis reads ','\n", false});
  cases.push_back({"CRLF lines", "a_deg,c_deg,x_mm,y_mm,z_mm\r\n0,0,1,2,3\r\n0,0,x,2,3\r\n",
                   at + "3: 'x_mm' is not a finite number: 'x'\n", false});
  {
    // A measured file, a nan in its 200th physical line.
    std::string text = "# measured\n" + kHeader;
    for (std::size_t k = 0; k < good.size(); ++k) text += k == 197 ? "30,0,1,2,nan\n" : good[k].text + "\n";
    cases.push_back({"nan late in a measured file", text, at + "200: 'z_mm' is not a finite number: 'nan'\n", false});
  }
  const auto module_case = [&](const std::string& name, const std::string& csv, Status s) {
    cases.push_back({name, csv, module_error(s), true});
  };
  module_case("a header and no rows", kHeader, Status::kTooFewPoses);
  module_case("two A poses", csv_where(good, [](const Row& r) { return r.a_deg == 0 || r.a_deg == 30; }),
              Status::kTooFewPoses);
  module_case("no pose at A = 0", csv_where(good, [](const Row& r) { return r.a_deg != 0; }),
              Status::kNoReferencePose);
  module_case("a pose of 3 C positions",
              csv_where(good, [](const Row& r) { return r.a_deg != 30 || r.c_deg < 25; }), Status::kTooFewCPositions);
  module_case("a stray sample at A = 45 (a pose of its own)", csv_where(good, [](const Row&) { return true; }) +
              "45,0,1,2,3\n", Status::kTooFewCPositions);
  {
    std::string short_arc = csv_where(good, [](const Row& r) { return r.a_deg != 30; });
    std::string too_many = csv_where(good, [](const Row&) { return true; });
    for (const Row& r : fine) {
      if (r.c_deg <= 15) short_arc += r.text + "\n";  // C 0, 5, 10, 15: a 15 deg arc
      if (r.c_deg == 5) too_many += r.text + "\n";     // the 37th sample of pose 30
    }
    module_case("a pose spanning 15 deg of C", short_arc, Status::kArcTooShort);
    // The module names no pose: the command names it, and the line of its 37th sample (header 1, 252 rows).
    cases.push_back({"37 samples in one pose", too_many,
                     at + "254: " + module_error(Status::kTooManyPoints).substr(20) +
                         " (macro 9832): the pose at A = 30 deg has 37 samples, at most 36 (its sample 37)\n",
                     true});
  }
  {
    // A row given twice, and the file given twice: refused at the repeat's line, before any sigma.
    const std::string once = csv_where(good, [](const Row&) { return true; });
    cases.push_back({"a row given twice", once + good[100].text + "\n",
                     at + "254: " + module_error(Status::kDuplicateSample).substr(20) + " (macro 9831)\n", true});
    std::string twice = once;
    for (const Row& r : good) twice += r.text + "\n";
    cases.push_back({"the file given twice", twice,
                     at + "254: " + module_error(Status::kDuplicateSample).substr(20) + " (macro 9831)\n", true});
  }
  {
    // Pose 30's samples at C 0 and C 180 with their C swapped: their phases are 180 deg off.
    std::string swapped = kHeader;
    for (const Row& r : good) {
      std::string text = r.text;
      if (r.a_deg == 30 && (r.c_deg == 0 || r.c_deg == 180)) {
        const std::size_t c0 = text.find(',') + 1, c1 = text.find(',', c0);
        text.replace(c0, c1 - c0, r.c_deg == 0 ? "180" : "0");
      }
      swapped += text + "\n";
    }
    module_case("two samples with their C swapped", swapped, Status::kCPhaseInconsistent);
  }
  module_case("17 A poses", csv_where(many, [](const Row&) { return true; }), Status::kTooManyPoses);
  {
    // 513 distinct samples: the session is full at the 513th, physical line 2 + 513.
    std::string full = "# three times over\n" + kHeader;
    for (int k = 0; k < 513; ++k) full += "0," + std::to_string(k) + ",1,2,3\n";
    cases.push_back({"more samples than the session holds", full,
                     at + "515: " + module_error(Status::kSessionFull).substr(20) +
                         " (macro 9831): the session holds 512 samples\n",
                     true});
  }

  const auto check_refusals = [&](const std::vector<std::vector<double>>& table_before) {
    for (const Case& c : cases) {
      CAPTURE(c.name);
      w.write("bad.csv", c.csv);
      REQUIRE(read_var(client, v::kUnlock) == 0.0);
      const double done_before = read_var(client, v::kDoneCount);
      const Run r = calibrate(sim.port(), w, bad, w.file("out.json"), true, w.file("report"));
      CAPTURE(r.err);
      CHECK(r.exit_code == 1);
      CHECK(r.err.compare(0, c.line.size(), c.line) == 0);
      CHECK(r.err.find('\n') == r.err.size() - 1);  // one line
      CHECK(r.out.empty());
      CHECK_FALSE(exists(w.file("out.json")));
      CHECK_FALSE(exists(w.file("out.json.tmp")));
      CHECK_FALSE(exists(w.file("report")));
      CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
      CHECK((read_var(client, v::kDoneCount) > done_before) == c.module_called);
      CHECK(stored_table(client) == table_before);
    }
  };

  SECTION("with no table stored, there is still none") {
    const std::vector<std::vector<double>> none = stored_table(client);
    REQUIRE(none.size() == 10);
    for (const auto& answer : none) REQUIRE(answer == kNoTable);
    check_refusals(none);
  }
  SECTION("with a table stored, it answers exactly as before") {
    REQUIRE(calibrate(sim.port(), w, w.file("samples.csv"), w.file("good.json"), true).exit_code == 0);
    const std::vector<std::vector<double>> table = stored_table(client);
    REQUIRE(table.size() == 16);
    REQUIRE(table[0].size() == 21);
    check_refusals(table);
    // An OUT.json already there stays as it was.
    w.write("out.json", "before");
    w.write("bad.csv", cases.front().csv);
    CHECK(calibrate(sim.port(), w, bad, w.file("out.json"), true).exit_code == 1);
    CHECK(slurp(w.file("out.json")) == "before");
  }
}

TEST_CASE("calibrate rigidity: a stored table whose CRC fails is not used after a restart, and says so",
          "[calibrate]") {
  Workspace w("trueaxis-calibrate-cli");
  const std::string nv = w.file("sim.nv");
  SimProcess sim;
  VariableClient client;
  const auto start = [&] {
    REQUIRE(sim.start(TRUEAXIS_SIM_BINARY, {"--host", "127.0.0.1", "--port", "0", "--nv", nv, "--errors", "realistic"}));
    REQUIRE(client.connect("127.0.0.1", sim.port()));
  };
  const auto stop = [&] {
    client.close();
    REQUIRE(sim.stop() == 0);
  };
  start();
  const std::vector<Row> rows = rows_of(measure(sim.port(), w, "samples.csv"));
  // Two different tables: six poses (no A = 90) into slot 0, then all seven into slot 1.
  const std::string six = w.write("six.csv", csv_where(rows, [](const Row& r) { return r.a_deg != 90; }));
  REQUIRE(calibrate(sim.port(), w, six, w.file("six.json"), true).exit_code == 0);
  const std::vector<std::vector<double>> older = stored_table(client);
  // The seven poses' table differs from the six's at A = 90 beyond #604 (the six clamp there): confirmed.
  REQUIRE(calibrate(sim.port(), w, w.file("samples.csv"), w.file("all.json"), true, "", true).exit_code == 0);
  const std::vector<std::vector<double>> newest = stored_table(client);
  REQUIRE(older[0].size() == 21);
  REQUIRE(older[0][17] == 6.0);
  REQUIRE(newest[0][17] == 7.0);
  stop();

  std::size_t index = 0;
  while (m::kRecordSpecs[index].key != m::RigidityTableRecord::kRecord.key) ++index;
  const std::size_t slot[2] = {m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 0),
                               m::KeyedStore::slot_offset(m::kRecordSpecs.data(), index, 1)};
  std::string bytes = slurp(nv);
  REQUIRE(bytes.size() == m::kRequiredStorageBytes);
  for (std::size_t s : slot) {
    REQUIRE(bytes.compare(s, 4, "TAK1") == 0);
    REQUIRE(static_cast<unsigned char>(bytes[s + 4]) == m::RigidityTableRecord::kRecord.key);
  }
  const auto flip = [&](std::size_t offset) {
    bytes[offset] = static_cast<char>(bytes[offset] ^ 0x10);
    std::ofstream(nv, std::ios::binary | std::ios::trunc) << bytes;
  };

  start();
  CHECK(stored_table(client) == newest);  // a restart keeps the newest
  stop();

  flip(slot[1] + m::KeyedStore::kHeaderBytes + 300);  // a payload byte of the newest
  start();
  CHECK(stored_table(client) == older);
  stop();

  flip(slot[0] + 12);  // the older one's sequence: the CRC covers the header too
  start();
  const std::vector<std::vector<double>> none = stored_table(client);
  REQUIRE(none.size() == 10);
  for (const auto& answer : none) CHECK(answer == kTableDamaged);  // not kNoTable: a table was stored
  // A new store is whole again.
  REQUIRE(calibrate(sim.port(), w, w.file("samples.csv"), w.file("again.json"), true).exit_code == 0);
  CHECK(stored_table(client) == newest);
  stop();
}

TEST_CASE("calibrate rigidity: a report that cannot be made leaves no OUT.json and nothing stored",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-cli");
  measure(sim.port(), w, "samples.csv");
  w.write("a_file", "not a directory");
  const Run r = calibrate(sim.port(), w, w.file("samples.csv"), w.file("out.json"), true, w.file("a_file/report"));
  CHECK(r.exit_code == 1);
  CHECK(r.err.find('\n') == r.err.size() - 1);  // one line
  CHECK(r.out.empty());
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK(query(sim.client(), 45.0, 0, 0) == kNoTable);
  CHECK(read_var(sim.client(), v::kUnlock) == 0.0);
}

TEST_CASE("calibrate --store unlocks with the machine's own code (--unlock-code), and the published one fails then",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-code");
  measure(sim.port(), w, "samples.csv");
  VariableClient& client = sim.client();
  REQUIRE(client.write_one(v::kUnlock, m::kUnlockCode));
  REQUIRE(client.write_one(v::kUnlockCodeSetting, 4321.0));
  REQUIRE(client.write_one(v::kUnlock, 0.0));
  REQUIRE(client.give_back_interface());
  // The published code, now wrong: said as such, with the back-off it started; a
  // store that fails leaves no OUT.json and no report, nor their temporaries.
  Run r = calibrate(sim.port(), w, w.file("samples.csv"), w.file("out.json"), true, w.file("report"));
  CHECK(r.exit_code == 1);
  CHECK(r.err == "trueaxis-calibrate: wrong unlock code: the controller refused it (--unlock-code must be the "
                 "machine's code, #900), and takes no code for the next 1 s\n");
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK_FALSE(exists(w.file("out.json.tmp")));
  CHECK_FALSE(exists(w.file("report")));
  DIR* d = ::opendir(w.dir.c_str());
  REQUIRE(d != nullptr);
  while (const dirent* e = ::readdir(d)) CHECK(std::string(e->d_name).rfind("report", 0) != 0);  // no report.tmp-*
  ::closedir(d);
  CHECK(query(sim.client(), 45.0, 0, 0) == kNoTable);
  CHECK(read_var(client, v::kFailedUnlocks) == 1.0);
  // A retry at once: the back-off, with its seconds (not "server is busy"); or,
  // when streaming the samples took longer than the back-off, the second wrong
  // code and the 2 s it starts.
  r = calibrate(sim.port(), w, w.file("samples.csv"), w.file("out.json"), true);
  CHECK(r.exit_code == 1);
  const bool in_backoff = read_var(client, v::kFailedUnlocks) == 1.0;  // a code in the back-off is not compared
  CHECK(r.err == (in_backoff ? "trueaxis-calibrate: the controller takes no unlock code for 1 s more: a wrong code "
                               "was written moments ago (the back-off doubles with each wrong code, up to 64 s)\n"
                             : "trueaxis-calibrate: wrong unlock code: the controller refused it (--unlock-code must "
                               "be the machine's code, #900), and takes no code for the next 2 s\n"));
  CHECK_FALSE(exists(w.file("out.json")));
  std::this_thread::sleep_for(std::chrono::milliseconds(in_backoff ? 1100 : 2100));  // the wrong code's back-off
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", w.file("samples.csv"), "--json",
                                   w.file("out.json"), "--port", std::to_string(sim.port()), "--store",
                                   "--unlock-code", "4321"};
  r = run(argv, w.file("calibrate.err"));
  CHECK(r.exit_code == 0);
  CHECK(query(sim.client(), 45.0, 0, 0) != kNoTable);
  CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
  argv.back() = "0";
  CHECK(run(argv, w.file("calibrate.err")).exit_code == 1);  // 1..9999 only
}

TEST_CASE("calibrate: --help lists the methods, METHOD --help gives its files' columns and units, bad usage is one line",
          "[calibrate]") {
  Workspace w("trueaxis-calibrate-help");
  const auto command = [&](const std::vector<std::string>& args) {
    std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    return run(argv, w.file("help.err"));
  };
  Run r = command({"--help"});
  CHECK(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK(r.out.compare(0, 26, "usage: trueaxis-calibrate ") == 0);
  for (const char* method : {"rigidity", "gantry", "spindle"}) {
    CAPTURE(method);
    CHECK(r.out.find(std::string("\n  ") + method + " ") != std::string::npos);
  }
  // Each method's own columns, with units, and whether it reads MACHINE.
  const std::vector<std::vector<std::string>> expected = {
      {"rigidity", "SAMPLES.csv: a_deg,c_deg,x_mm,y_mm,z_mm", "the commanded A and C (deg)", "MACHINE.csv: not read"},
      {"gantry", "SAMPLES.csv: group,x_mm,y_mm,z_mm", "(mm, tracker frame",
       "MACHINE.csv (--machine, required): sub_machine,swing_mm,tool_x,tool_y,tool_z"},
      {"spindle", "SAMPLES.csv: phi_deg,ball,x_mm,y_mm,z_mm", "(deg; may pass 360)", "tool_length_mm"}};
  for (const auto& e : expected) {
    CAPTURE(e[0]);
    for (const std::vector<std::string>& args : {std::vector<std::string>{e[0], "--help"},
                                                 std::vector<std::string>{e[0], "--in", "x.csv", "-h"}}) {
      r = command(args);
      CHECK(r.exit_code == 0);
      CHECK(r.err.empty());
      const std::string title = "trueaxis-calibrate " + e[0] + ": ";
      CHECK(r.out.compare(0, title.size(), title) == 0);
      for (std::size_t k = 1; k < e.size(); ++k) CHECK(r.out.find(e[k]) != std::string::npos);
    }
  }
  CHECK(command({"gantry", "--help"}).out.find("a_deg") == std::string::npos);  // not another method's

  // Bad usage: exit 1, one line on stderr, nothing on stdout.
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{}, "no METHOD"},
      {{"nope", "--help"}, "unknown METHOD 'nope': rigidity, gantry or spindle"},
      {{"rigidity", "--in", "x.csv"}, "--in and --json are required"},
      {{"rigidity", "--in", "x.csv", "--json", "o.json", "--port", "0"}, "--port takes 1..65535"},
      {{"rigidity", "--frobnicate"}, "unknown or incomplete option '--frobnicate'"}};
  for (const auto& [args, why] : bad) {
    CAPTURE(why);
    r = command(args);
    CHECK(r.exit_code == 1);
    CHECK(r.err == "trueaxis-calibrate: " + why + " (trueaxis-calibrate --help)\n");
    CHECK(r.out.empty());
  }
}
