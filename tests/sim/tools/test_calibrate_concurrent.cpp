// Two clients against one controller (issue "Nothing wrong reaches the
// machine", item 3; macros/module.hpp contract 8): trueaxis-calibrate runs of
// two methods started at once over TCP both end correctly, no message blames a
// valid line, and what the module stores is exactly what a run alone stores;
// a run that cannot get the macro interface waits with a message, or fails
// with that sentence and leaves nothing.
#include <catch2/catch.hpp>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace {

namespace v = trueaxis::macros::var;
using trueaxis::sim::VariableClient;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

const std::string kHeld = "controller busy: another client holds the macro interface";

// A process started and not yet waited for.
struct Started {
  pid_t pid = -1;
  std::string err_path;
};

Started start(const std::vector<std::string>& argv, const std::string& err_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string out_path = err_path + ".out";
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  Started s;
  s.err_path = err_path;
  REQUIRE(posix_spawn(&s.pid, args[0], &actions, nullptr, args.data(), environ) == 0);
  posix_spawn_file_actions_destroy(&actions);
  return s;
}

Run finish(const Started& s) {
  int status = 0;
  REQUIRE(::waitpid(s.pid, &status, 0) == s.pid);
  Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.err = slurp(s.err_path);
  r.out = slurp(s.err_path + ".out");
  return r;
}

std::vector<std::string> rigidity_argv(int port, const std::string& in, const std::string& json) {
  return {TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", in, "--json", json, "--port", std::to_string(port),
          "--store"};
}

std::vector<std::string> spindle_argv(int port, const SpindleFiles& f, const std::string& json) {
  return {TRUEAXIS_CALIBRATE_BINARY, "spindle", "--in", f.samples, "--machine", f.machine, "--json", json,
          "--port", std::to_string(port), "--store"};
}

// The rigidity samples of the virtual cradle (trueaxis-measure-ball).
std::string measure_ball(int port, const Workspace& w) {
  const std::string path = w.file("rigidity.csv");
  const Run r = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(port), "--out", path}, w.file("ball.err"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return path;
}

// What a client sees of both stored tables: 9833 at three A (blend 0, stored)
// and 9843 at kQueryAngles with a 100 mm tool; the interface given back after.
std::vector<std::vector<double>> stored(VariableClient& client) {
  std::vector<std::vector<double>> seen = corrections(client, 100.0);
  for (double a : {-30.0, 0.0, 30.0}) {
    const double qr[2] = {0.0, 1.0};
    REQUIRE(client.write_one(v::kArgA, a));
    REQUIRE(client.write(v::kArgQ, 2, qr));
    const auto outcome = client.run_macro(9833);
    REQUIRE(outcome.status == 2);
    std::vector<double> r(4);
    REQUIRE(client.read(v::kRigidityRotvecX, 4, r.data()));
    seen.push_back(r);
  }
  REQUIRE(client.give_back_interface());
  return seen;
}

// stderr without its progress lines ("FILE: N of M samples sent", over 2 s of work).
std::string without_progress(const std::string& err) {
  std::string out;
  std::size_t at = 0;
  while (at < err.size()) {
    const std::size_t end = err.find('\n', at);
    const std::string line = err.substr(at, end == std::string::npos ? std::string::npos : end + 1 - at);
    if (line.find(" samples sent\n") == std::string::npos && line.find(" bytes read\n") == std::string::npos) out += line;
    at = end == std::string::npos ? err.size() : end + 1;
  }
  return out;
}

// Waits (at most 20 s) until the file at `path` holds `text`; true when it does.
bool wait_for(const std::string& path, const std::string& text) {
  for (int i = 0; i < 400; ++i) {
    if (slurp(path).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// No line of a failed run's stderr names a sample file's line.
bool blames_a_line(const std::string& err) {
  return err.find(".csv:") != std::string::npos;
}

}  // namespace

TEST_CASE("two calibrate runs of different methods at once both end correctly and store exactly what each stores alone",
          "[calibrate][concurrent]") {
  Workspace w("trueaxis-concurrent");
  const SpindleFiles spindle = measure_spindle(w, "sp", 3, 2);

  // Alone, one after the other: the reference OUT.json texts and stored tables.
  std::string rigidity_alone, spindle_alone;
  std::vector<std::vector<double>> tables_alone;
  std::string rigidity_in;
  {
    SimFixture sim({"--errors", "realistic"});
    rigidity_in = measure_ball(sim.port(), w);
    Run r = run(rigidity_argv(sim.port(), rigidity_in, w.file("r_alone.json")), w.file("r_alone.err"));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    r = run(spindle_argv(sim.port(), spindle, w.file("s_alone.json")), w.file("s_alone.err"));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    rigidity_alone = slurp(w.file("r_alone.json"));
    spindle_alone = slurp(w.file("s_alone.json"));
    tables_alone = stored(sim.client());
  }

  // At once, three times on one controller: each pair started together while
  // the test's own client holds the interface, then let go at once, so that
  // both contend for it (the first round without the hold).
  SimFixture sim({"--errors", "realistic"});
  for (int round = 0; round < 3; ++round) {
    CAPTURE(round);
    const std::string rj = w.file("r" + std::to_string(round) + ".json");
    const std::string sj = w.file("s" + std::to_string(round) + ".json");
    if (round > 0) REQUIRE(sim.client().write_one(v::kInterface, 1.0));
    const Started a = start(rigidity_argv(sim.port(), rigidity_in, rj), w.file("r.err"));
    const Started b = start(spindle_argv(sim.port(), spindle, sj), w.file("s.err"));
    if (round > 0) {  // both waiting (they say so), then let go
      CHECK(wait_for(a.err_path, ", waiting (up to 120 s)"));
      CHECK(wait_for(b.err_path, ", waiting (up to 120 s)"));
      REQUIRE(sim.client().give_back_interface());
    }
    const Run ra = finish(a);
    const Run rb = finish(b);
    INFO("rigidity: " << ra.err << "spindle: " << rb.err);
    CHECK(ra.exit_code == 0);
    CHECK(rb.exit_code == 0);
    CHECK_FALSE(blames_a_line(ra.err));
    CHECK_FALSE(blames_a_line(rb.err));
    // The one that waited said so, and nothing else; with the hold, one did at least.
    int waited = 0;
    for (const Run* r : {&ra, &rb}) {
      const std::string err = without_progress(r->err);
      const bool said = err == "trueaxis-calibrate: " + kHeld + ", waiting (up to 120 s)\n";
      CHECK((err.empty() || said));
      waited += said ? 1 : 0;
    }
    if (round > 0) CHECK(waited == 2);
    CHECK(slurp(rj) == rigidity_alone);
    CHECK(slurp(sj) == spindle_alone);
    CHECK(stored(sim.client()) == tables_alone);
  }
}

TEST_CASE("calibrate waits while another client holds the macro interface, or fails with that sentence and writes nothing",
          "[calibrate][concurrent]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-held");
  const SpindleFiles spindle = measure_spindle(w, "sp", 4, 1);
  REQUIRE(sim.client().write_one(v::kInterface, 1.0));  // the test's client holds it

  std::vector<std::string> argv = spindle_argv(sim.port(), spindle, w.file("out.json"));
  argv.insert(argv.end(), {"--wait", "1"});
  const auto t0 = std::chrono::steady_clock::now();
  Run r = run(argv, w.file("held.err"));
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(r.exit_code == 1);
  CHECK(without_progress(r.err) == "trueaxis-calibrate: " + kHeld + ", waiting (up to 1 s)\ntrueaxis-calibrate: " +
                                      kHeld + " (waited 1 s; --wait SECONDS)\n");
  CHECK(r.out.empty());
  CHECK(waited_s >= 1.0);
  CHECK(waited_s < 5.0);
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK(correction(sim.client(), 0.0, 100.0) == std::vector<double>{404.0});  // no_table: nothing stored

  // Given back once the command waits: it goes on and stores.
  argv.back() = "30";
  const Started s = start(argv, w.file("wait.err"));
  CHECK(wait_for(s.err_path, ", waiting (up to 30 s)"));
  REQUIRE(sim.client().give_back_interface());
  r = finish(s);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(without_progress(r.err) == "trueaxis-calibrate: " + kHeld + ", waiting (up to 30 s)\n");
  CHECK(exists(w.file("out.json")));
  CHECK(correction(sim.client(), 0.0, 100.0).size() == 5);
}

TEST_CASE("calibrate waits at most 2 s behind a client that ran one query macro on a connection it keeps open",
          "[calibrate][concurrent]") {
  SimFixture sim;
  Workspace w("trueaxis-query-beside");
  const SpindleFiles spindle = measure_spindle(w, "sp", 4, 1);
  // An HMI's query (9833 at A = 30: no table yet, error 404), its connection kept.
  REQUIRE(sim.client().write_one(v::kArgA, 30.0));
  const auto outcome = sim.client().run_macro(9833);
  REQUIRE(outcome.status == 3);
  std::vector<std::string> argv = spindle_argv(sim.port(), spindle, w.file("out.json"));
  argv.insert(argv.end(), {"--wait", "4"});  // held for the module's whole idle limit (30 s), this would fail
  const auto t0 = std::chrono::steady_clock::now();
  const Run r = run(argv, w.file("beside.err"));
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(without_progress(r.err) == "trueaxis-calibrate: " + kHeld + ", waiting (up to 4 s)\n");  // the 2 s grace
  CHECK(exists(w.file("out.json")));
  std::printf("calibrate beside a client that ran 9833: waited the grace, done in %.1f s\n", took_s);
  double interface = -1.0;
  REQUIRE(sim.client().read_one(v::kInterface, interface));
  CHECK(interface == 0.0);  // calibrate gave it back; the HMI's connection still open
}
