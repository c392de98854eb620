// trueaxis-calibrate's outputs tried before the work (issue 32, item 3): an
// OUT.json, a report folder or a LinuxCNC file that cannot be written is found
// before anything is sent to the module, with its cause named (no such
// directory, a file where a folder is wanted, a folder where a file is wanted,
// no permission), exit 1, nothing run on the controller, nothing stored, no
// OUT.json; and the samples read as spreadsheets and R write them (quoted
// headers and fields), giving the very OUT.json of the unquoted file.
#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/sha256.hpp"

namespace {

namespace v = trueaxis::macros::var;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

Run calibrate(int port, const Workspace& w, std::vector<std::string> args) {
  args.insert(args.begin(), {TRUEAXIS_CALIBRATE_BINARY, "rigidity"});
  args.insert(args.end(), {"--port", std::to_string(port)});
  return run(args, w.file("calibrate.err"));
}

std::string measure(int port, const Workspace& w, const std::string& name) {
  const Run r = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(port), "--out", w.file(name)}, w.file("m.err"));
  REQUIRE(r.exit_code == 0);
  return w.file(name);
}

// Every field of a CSV text's header and rows in double quotes (a spreadsheet's "quote all").
std::string quoted(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out += line + "\n";
      continue;
    }
    std::string q = "\"";
    for (const char c : line) q += c == ',' ? std::string("\",\"") : std::string(1, c);
    out += q + "\"\n";
  }
  return out;
}

}  // namespace

TEST_CASE("calibrate: an output that cannot be written is named with its cause before anything is sent",
          "[calibrate][outputs]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-outputs");
  const std::string samples = measure(sim.port(), w, "ball.csv");
  const std::string a_file = w.write("a_file", "x\n");
  const std::string json = w.file("out.json");
  struct Case {
    std::vector<std::string> args;
    std::string says;  // the whole line after "trueaxis-calibrate: "
  };
  const std::string nothing = "; nothing was sent to the controller, nothing stored\n";
  const std::vector<Case> cases = {
      {{"--json", w.file("no/such/out.json")},
       w.file("no/such/out.json") + ": cannot be written (no such directory '" + w.file("no") + "')" + nothing},
      {{"--json", w.dir}, w.dir + ": cannot be written (it is a folder, where a file is wanted)" + nothing},
      {{"--json", a_file + "/out.json"},
       a_file + "/out.json: cannot be written ('" + a_file + "' is a file, where a folder is wanted)" + nothing},
      {{"--json", "/sys/out.json"},
       "/sys/out.json: cannot be written ('/sys' is read-only: no permission to write in it)" + nothing},
      {{"--json", json, "--report", w.file("no/report")},
       w.file("no/report") + ": the report cannot be made there (no such directory '" + w.file("no") + "')" + nothing},
      {{"--json", json, "--report", a_file},
       a_file + ": the report cannot be made there ('" + a_file + "' is a file, where a folder is wanted)" + nothing},
      {{"--json", json, "--report", a_file + "/report"},
       a_file + "/report: the report cannot be made there ('" + a_file + "' is a file, where a folder is wanted)" +
           nothing},
      {{"--json", json, "--report", "/sys/report"},
       "/sys/report: the report cannot be made there ('/sys' is read-only: no permission to write in it)" + nothing},
      {{"--json", json, "--store", "--linuxcnc-comp", w.file("no/a.comp")},
       w.file("no/a.comp") + ": cannot be written (no such directory '" + w.file("no") + "')" + nothing},
      {{"--json", json, "--store", "--linuxcnc-kins", a_file + "/table.kins"},
       a_file + "/table.kins: cannot be written ('" + a_file + "' is a file, where a folder is wanted)" + nothing},
      {{"--json", json, "--store", "--linuxcnc-comp", json},
       "--json and --linuxcnc-comp name the same file '" + json + "' (trueaxis-calibrate --help)\n"},
      // A compensation file of a table not stored, or beside the kinematics' table: A corrected by
      // what the controller does not hold, or twice.
      {{"--json", json, "--linuxcnc-comp", w.file("a.comp")},
       "--linuxcnc-comp goes with --store: the joint's compensation is the stored table's A positioning error, "
       "not a table the controller does not hold (trueaxis-calibrate --help)\n"},
      {{"--json", json, "--store", "--linuxcnc-comp", w.file("a.comp"), "--linuxcnc-kins", w.file("m3.table")},
       "--linuxcnc-comp and --linuxcnc-kins both correct the A positioning error (the kinematics' table holds it): "
       "together they correct it twice; give one (trueaxis-calibrate --help)\n"},
  };
  const double done_before = sim.get(v::kDoneCount);
  const double log_before = sim.get(v::kLogNewest);
  for (const Case& c : cases) {
    std::vector<std::string> args = {"--in", samples};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const Run r = calibrate(sim.port(), w, args);
    INFO(c.args.back());
    CHECK(r.exit_code == 1);
    CHECK(r.err == "trueaxis-calibrate: " + c.says);
    CHECK(r.out.empty());
    CHECK_FALSE(exists(json));
    CHECK_FALSE(exists(w.file("out.json.tmp")));
    // Nothing was sent: no macro ran (not even the session's clear), nothing was logged.
    CHECK(sim.get(v::kDoneCount) == done_before);
    CHECK(sim.get(v::kLogNewest) == log_before);
  }
  // The same with every output writable: the work is done.
  const Run good = calibrate(sim.port(), w, {"--in", samples, "--json", json, "--report", w.file("report"),
                                             "--store", "--linuxcnc-comp", w.file("a.comp")});
  INFO(good.err);
  CHECK(good.exit_code == 0);
  CHECK(exists(json));
  CHECK(exists(w.file("report/index.html")));
}

TEST_CASE("calibrate: quoted headers and fields read as the unquoted file does", "[calibrate][csv]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-quoted");
  const std::string samples = measure(sim.port(), w, "ball.csv");
  const std::string text = slurp(samples);
  const std::string all = w.write("quoted.csv", quoted(text));
  REQUIRE(slurp(all).find("\"a_deg\",\"c_deg\"") != std::string::npos);
  const Run plain = calibrate(sim.port(), w, {"--in", samples, "--json", w.file("plain.json")});
  REQUIRE(plain.exit_code == 0);
  const Run q = calibrate(sim.port(), w, {"--in", all, "--json", w.file("quoted.json")});
  INFO(q.err);
  REQUIRE(q.exit_code == 0);
  CHECK(slurp(w.file("quoted.json")) == slurp(w.file("plain.json")));
  // R's write.csv: the header quoted, the numbers not.
  const std::string header_only = text.substr(0, text.find("a_deg")) + "\"a_deg\",\"c_deg\",\"x_mm\",\"y_mm\",\"z_mm\"" +
                                  text.substr(text.find('\n', text.find("a_deg")));
  const Run r = calibrate(sim.port(), w, {"--in", w.write("r.csv", header_only), "--json", w.file("r.json")});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(slurp(w.file("r.json")) == slurp(w.file("plain.json")));
}

TEST_CASE("sha256_hex gives FIPS 180-4's digests (what names a stored record on a check's page)", "[calibrate][sha256]") {
  using trueaxis::sim::sha256_hex;
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(sha256_hex(std::string(1000000, 'a')) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("calibrate: the machine's identity, #902 a number and --machine-name a name with letters, on the page",
          "[calibrate][record]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-machine");
  const std::string samples = measure(sim.port(), w, "ball.csv");
  // #902 holds a number only (every variable is one): a serial with letters goes with --machine-name.
  sim.set(v::kUnlock, trueaxis::sim::test::kUnlockCode);
  CHECK(sim.write_exception(v::kMachineId, {4711.5}) == 3);
  sim.set(v::kMachineId, 4711.0);
  sim.set(v::kUnlock, 0.0);
  REQUIRE(sim.client().give_back_interface());
  const Run r = calibrate(sim.port(), w, {"--in", samples, "--json", w.file("out.json"), "--report", w.file("report"),
                                          "--machine-name", "DMU 65 / A12"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string page = slurp(w.file("report/index.html"));
  CHECK(page.find("<th>Machine (#902)</th><td>4711; named DMU 65 / A12 (--machine-name)</td>") != std::string::npos);
  const Run bad = calibrate(sim.port(), w, {"--in", samples, "--json", w.file("bad.json"), "--machine-name", "A\tB"});
  CHECK(bad.exit_code == 1);
  CHECK(bad.err == "trueaxis-calibrate: --machine-name takes a name in UTF-8 without control characters "
                   "(trueaxis-calibrate --help)\n");
  CHECK_FALSE(exists(w.file("bad.json")));
}
