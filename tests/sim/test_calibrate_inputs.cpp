// trueaxis-calibrate rigidity end to end against a trueaxis-sim with realistic
// errors: a good run (JSON equal to what the module reports, the report page),
// and every bad input of issue 5 refused with its line or its module code, no
// OUT.json written, nothing stored, the module locked again.
#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sim_fixture.hpp"
#include "trueaxis/macros/module.hpp"

extern char** environ;

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::sim::test::SimFixture;

struct Run {
  int exit_code = -1;
  std::string err;
};

// Runs a program with argv (no shell), stderr captured through a file.
Run run(const std::vector<std::string>& argv, const std::string& dir) {
  const std::string err_path = dir + "/stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  Run r;
  if (posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ) == 0) {
    int status = 0;
    waitpid(pid, &status, 0);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  posix_spawn_file_actions_destroy(&actions);
  std::ifstream in(err_path);
  std::getline(in, r.err);
  return r;
}

bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Workspace {
  std::string dir;
  Workspace() {
    char path[] = "/tmp/trueaxis-calibrate-test-XXXXXX";
    REQUIRE(mkdtemp(path) != nullptr);
    dir = path;
  }
  ~Workspace() {
    const std::string cmd = "rm -rf '" + dir + "'";
    (void)std::system(cmd.c_str());
  }
  std::string file(const std::string& name) const { return dir + "/" + name; }
  void write(const std::string& name, const std::string& text) const { std::ofstream(file(name)) << text; }
};

// The measured samples of the fixture's simulator (7 A x 36 C).
std::string measure(SimFixture& sim, const Workspace& w) {
  const Run r = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("samples.csv")},
                    w.dir);
  REQUIRE(r.exit_code == 0);
  return slurp(w.file("samples.csv"));
}

Run calibrate(SimFixture& sim, const Workspace& w, const std::string& csv_name, bool store,
              const std::string& report = "") {
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", w.file(csv_name), "--json",
                                   w.file("out.json"), "--port", std::to_string(sim.port())};
  if (store) argv.push_back("--store");
  if (!report.empty()) {
    argv.push_back("--report");
    argv.push_back(w.file(report));
  }
  return run(argv, w.dir);
}

// The rows of the samples whose a_deg is in `keep` (the header and comments kept).
std::string only_poses(const std::string& csv, const std::vector<double>& keep, int max_per_pose = 1000) {
  std::istringstream in(csv);
  std::string line, out;
  std::vector<int> count(keep.size(), 0);
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'a') {
      out += line + "\n";
      continue;
    }
    const double a = std::stod(line.substr(0, line.find(',')));
    for (std::size_t k = 0; k < keep.size(); ++k) {
      if (a == keep[k] && count[k]++ < max_per_pose) out += line + "\n";
    }
  }
  return out;
}

// The stored table as 9834 R = 1 reports pose 7, or the error code.
std::vector<double> stored_pose(SimFixture& sim) {
  sim.set(v::kArgQ, {7.0, 1.0});
  const auto outcome = sim.run(9834);
  if (outcome.status != 2) return {static_cast<double>(outcome.error)};
  std::vector<double> p(18);
  REQUIRE(sim.client().read(v::kPoseA, 18, p.data()));
  return p;
}

// Restarts the sim after flipping the bytes at `offsets` of its NV file, and
// reads the stored table again.
std::vector<double> stored_pose_after_corruption(SimFixture& sim, const std::vector<std::size_t>& offsets) {
  sim.client().close();
  std::fstream nv(sim.nv_path(), std::ios::in | std::ios::out | std::ios::binary);
  for (std::size_t at : offsets) {
    nv.seekg(static_cast<std::streamoff>(at));
    char byte = 0;
    nv.read(&byte, 1);
    byte = static_cast<char>(byte ^ 0x5A);
    nv.seekp(static_cast<std::streamoff>(at));
    nv.write(&byte, 1);
  }
  nv.close();
  REQUIRE(sim.restart() == 0);
  return stored_pose(sim);
}

}  // namespace

TEST_CASE("calibrate rigidity: a good run writes the module's figures, stores them and draws the report",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w;
  measure(sim, w);
  CHECK(stored_pose(sim) == std::vector<double>{404.0});  // no table yet: no_table
  const Run r = calibrate(sim, w, "samples.csv", true, "report");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(sim.get(v::kUnlock) == 0.0);  // locked again

  const std::string json = slurp(w.file("out.json"));
  for (const char* key : {"\"method\": \"rigidity\"", "\"reference_a_deg\": 0.0", "\"a_axis\"", "\"point_mm\"",
                          "\"direction\"", "\"poses\"", "\"rotation_vector_arcsec\"",
                          "\"rotation_vector_sigma_arcsec\"", "\"rigidity_arcsec\"", "\"rigidity_sigma_arcsec\"",
                          "\"a_positioning_error_arcsec\"", "\"c_centre_mm\"", "\"c_direction\"",
                          "\"c_circle_rms_mm\""}) {
    CHECK(json.find(key) != std::string::npos);
  }
  CHECK(json.find("\"rotation_vector_arcsec\": [0, 0, 0]") != std::string::npos);  // the reference pose
  // The JSON holds exactly what the stored table reports (17 significant digits).
  const std::vector<double> p = stored_pose(sim);
  REQUIRE(p.size() == 18);
  char expected[120];
  std::snprintf(expected, sizeof expected, "\"rotation_vector_arcsec\": [%.17g, %.17g, %.17g]", p[1], p[2], p[3]);
  CHECK(json.find(expected) != std::string::npos);
  CHECK(p[17] == 7.0);

  CHECK(exists(w.file("report/index.html")));
  for (int k = 1; k <= 4; ++k) {
    const std::string png = slurp(w.file("report/figure_" + std::to_string(k) + ".png"));
    REQUIRE(png.size() > 8);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  }
}

TEST_CASE("calibrate rigidity: each bad input is refused by its line or its code, and nothing changes",
          "[calibrate]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w;
  const std::string good = measure(sim, w);
  w.write("good.csv", good);
  REQUIRE(calibrate(sim, w, "good.csv", true).exit_code == 0);
  const std::vector<double> stored = stored_pose(sim);
  REQUIRE(stored.size() == 18);
  std::remove(w.file("out.json").c_str());

  struct Case {
    const char* name;
    std::string csv;
    std::string error;  // the stderr line, or its start
  };
  const std::string header = "a_deg,c_deg,x_mm,y_mm,z_mm\n";
  const std::vector<Case> cases = {
      {"a word for a number", "# x\n" + header + "0,0,1,2,3\n\n0,abc,1,2,3\n",
       "trueaxis-calibrate: " + w.file("bad.csv") + ":5: 'c_deg' is not a finite number: 'abc'"},
      {"nan", header + "0,0,1,2,nan\n", "trueaxis-calibrate: " + w.file("bad.csv") + ":2: 'z_mm' is not a finite number: 'nan'"},
      {"inf", header + "0,0,inf,2,3\n", "trueaxis-calibrate: " + w.file("bad.csv") + ":2: 'x_mm' is not a finite number: 'inf'"},
      {"a missing field", header + "0,0,1,2\n", "trueaxis-calibrate: " + w.file("bad.csv") + ":2: too few fields: no value for 'z_mm'"},
      {"a missing column", "a_deg,c_deg,x_mm,y_mm\n0,0,1,2\n",
       "trueaxis-calibrate: " + w.file("bad.csv") + ":1: the header has no column 'z_mm'"},
      {"an empty file", "", "trueaxis-calibrate: " + w.file("bad.csv") + ":1: no header row"},
      {"two A poses", only_poses(good, {0.0, 30.0}), "trueaxis-calibrate: module error 208 too_few_poses"},
      {"no pose at A = 0", only_poses(good, {-30.0, 30.0, 60.0}), "trueaxis-calibrate: module error 209 no_reference_pose"},
      {"a pose with 37 samples", good + "30,5,1,2,3\n", "trueaxis-calibrate: module error 102 too_many_points"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    w.write("bad.csv", c.csv);
    const Run r = calibrate(sim, w, "bad.csv", true);
    CHECK(r.exit_code == 1);
    CHECK(r.err.compare(0, c.error.size(), c.error) == 0);
    INFO(r.err);
    CHECK_FALSE(exists(w.file("out.json")));
    CHECK(sim.get(v::kUnlock) == 0.0);
    CHECK(stored_pose(sim) == stored);
  }

  SECTION("a pose with fewer than 4 C positions, and one spanning too short an arc") {
    // Keep C 0, 10, 20 of pose A = 30 (3 positions), then C 0..30 (4 positions, 30 deg < the 45 deg minimum).
    std::string three = header, short_arc = header;
    std::istringstream in(good);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line[0] == 'a') continue;
      const double a = std::stod(line.substr(0, line.find(',')));
      const std::string rest = line.substr(line.find(',') + 1);
      const double c = std::stod(rest.substr(0, rest.find(',')));
      if (a != 30.0 || c < 25.0) three += line + "\n";
      if (a != 30.0 || c < 35.0) short_arc += line + "\n";
    }
    w.write("bad.csv", three);
    Run r = calibrate(sim, w, "bad.csv", true);
    CHECK(r.exit_code == 1);
    CHECK(r.err.rfind("trueaxis-calibrate: module error 210 too_few_c_positions", 0) == 0);
    w.write("bad.csv", short_arc);
    r = calibrate(sim, w, "bad.csv", true);
    CHECK(r.exit_code == 1);
    CHECK(r.err.rfind("trueaxis-calibrate: module error 205 arc_too_short", 0) == 0);
    CHECK_FALSE(exists(w.file("out.json")));
    CHECK(stored_pose(sim) == stored);
  }
  SECTION("a stored table whose CRC fails is no table after a restart") {
    // Store the same table a second time: slot 0 holds the first copy, slot 1
    // the newest. A flipped byte in the newest leaves the older answering; one
    // in both leaves no table.
    REQUIRE(calibrate(sim, w, "good.csv", true).exit_code == 0);
    std::size_t index = 0;
    while (m::kRecordSpecs[index].key != m::record_key(m::RecordKey::kRigidityTable)) ++index;
    const std::size_t payload = m::KeyedStore::kHeaderBytes + 100;
    const std::size_t first = m::KeyedStore::slot_offset(m::kRecordSpecs, index, 0) + payload;
    const std::size_t second = m::KeyedStore::slot_offset(m::kRecordSpecs, index, 1) + payload;
    CHECK(stored_pose_after_corruption(sim, {second}) == stored);
    CHECK(stored_pose_after_corruption(sim, {first}) == std::vector<double>{404.0});
    sim.set(v::kArgA, {45.0});
    CHECK(sim.run(9833).error == 404);
  }
}
