// trueaxis-calibrate when the connection fails (calibrate.hpp contract 5;
// issue 32, item 3): a proxy between the command and a trueaxis-sim the test
// starts cuts the connection (reset, or silence until the response time-out)
// at a chosen request, and the one line names what was under way (which
// sample of which file, the build, the report query, the store) and what
// became of the store: nothing stored, not known, or stored; exit 1, no
// OUT.json, no report, the controller locked, and the module's table as the
// line says.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "calibrate_support.hpp"
#include "cutting_proxy.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace {

namespace v = trueaxis::macros::var;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The macro `number` started (#9000 written).
std::function<bool(const ProxyRequest&)> macro(int number) {
  return [number](const ProxyRequest& r) { return r.writes(9000, number); };
}

// 9834 pose 1 of the stored table: 2 when there is one, else the macro's status.
int stored_table(SimFixture& sim) {
  // The proxy's connection to the sim may close a moment after the command's end.
  const bool taken = sim.client().take_interface(5000, {});
  INFO(sim.client().failure_text());
  REQUIRE(taken);
  const double args[2] = {1.0, 1.0};
  REQUIRE(sim.client().write(v::kArgQ, 2, args));
  const int status = sim.client().run_macro(9834).status;
  REQUIRE(sim.client().give_back_interface());
  return status;
}

}  // namespace

TEST_CASE("calibrate: a connection cut says what was under way and what became of the store", "[calibrate][transport]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-transport");
  const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("ball.csv")},
                    w.file("m.err"));
  REQUIRE(m.exit_code == 0);
  const std::string samples = w.file("ball.csv");
  // The samples' lines: sample k is on line header + k (no comment between rows).
  const std::string text = slurp(samples);
  int header_line = 1;
  for (std::size_t at = 0; text.compare(at, 5, "a_deg") != 0; at = text.find('\n', at) + 1) ++header_line;

  struct Case {
    const char* name;
    CuttingProxy::Cut how;
    std::function<bool(const ProxyRequest&)> at;
    bool store;
    std::string says;   // a part of the line
    std::string store_says;  // its end: what became of the store
    int table_after;    // stored_table(): 2 stored, 3 none
  };
  const std::string nothing = "; nothing was stored";
  const std::vector<Case> cases = {
      {"a reset while streaming", CuttingProxy::Cut::kReset, nth(20, macro(9831)), false,
       "Modbus: Connection reset by peer while streaming sample 20 of 252 of " + samples + ":" +
           std::to_string(header_line + 20) + " (macro 9831 sent, its end not seen)",
       nothing, 3},
      {"a time-out while streaming", CuttingProxy::Cut::kSilence, nth(5, macro(9831)), true,
       "Modbus: Connection timed out while streaming sample 5 of 252 of " + samples + ":" +
           std::to_string(header_line + 5),
       nothing, 3},
      {"a reset at the build", CuttingProxy::Cut::kReset, nth(1, macro(9832)), true,
       "Modbus: Connection reset by peer while running the build (macro 9832, R = 0), every sample sent", nothing, 3},
      {"a reset at the report query", CuttingProxy::Cut::kReset, nth(3, macro(9834)), true,
       "Modbus: Connection reset by peer while running the report query (macro 9834, pose 3 of 7)", nothing, 3},
      {"a reset at the store's unlock", CuttingProxy::Cut::kReset,
       [](const ProxyRequest& r) { return r.writes(9004, 2718.0); }, true,
       "Modbus: Connection reset by peer while storing (macro 9832, R = 1)", nothing, 3},
      {"a reset as the store's macro is sent", CuttingProxy::Cut::kReset, nth(2, macro(9832)), true,
       "Modbus: Connection reset by peer while storing (macro 9832, R = 1) (macro 9832 sent, its end not seen)",
       "; whether the table was stored is not known (the connection failed after the store's macro was sent): "
       "`trueaxis-calibrate log` shows it",
       3},
      {"a reset as the controller is locked again", CuttingProxy::Cut::kReset,
       [](const ProxyRequest& r) { return r.writes(9004, 0.0); }, true,
       "the controller could not be locked again: Modbus: Connection reset by peer",
       "; the table WAS stored (record 3 rigidity_table): `trueaxis-calibrate log` shows the store; OUT.json and the "
       "report were not written",
       2},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    CuttingProxy proxy(sim.port(), c.how, c.at);
    std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", samples, "--json",
                                     w.file("out.json"), "--report", w.file("report"), "--port",
                                     std::to_string(proxy.port())};
    if (c.store) argv.emplace_back("--store");
    const Run r = run(argv, w.file("calibrate.err"));
    INFO(r.err);
    CHECK(proxy.cut());
    CHECK(r.exit_code == 1);
    CHECK(r.err.rfind("trueaxis-calibrate: ", 0) == 0);
    CHECK(r.err.find('\n') == r.err.size() - 1);  // one line
    CHECK(has(r.err, c.says));
    CHECK(r.err.size() > c.store_says.size());
    CHECK(r.err.compare(r.err.size() - 1 - c.store_says.size(), c.store_says.size(), c.store_says) == 0);
    CHECK_FALSE(exists(w.file("out.json")));
    CHECK_FALSE(exists(w.file("report")));
    CHECK(stored_table(sim) == c.table_after);  // after the proxy's connection to the sim closed
    CHECK(sim.get(v::kUnlock) == 0.0);          // an unlock closes with its connection
  }
}
