// trueaxis-var over Modbus TCP (tools/src/var_main.cpp, var_session.hpp) as an
// operator runs it: a child process (argv, no shell) against a trueaxis-sim the
// test starts on 127.0.0.1 port 0. What it prints is held against what a
// libmodbus client reads; every failure is exit 1 with one stderr line naming
// the cause and nothing on stdout; bad usage is exit 2. The same program over
// RTU against the firmware image: tests/protocol/test_var_rtu_qemu.py.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/var_info.hpp"
#include "trueaxis/sim/server/sim_map.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::sim::test::SimFixture;
using namespace trueaxis::test;

Run var(const SimFixture& sim, const Workspace& w, const std::vector<std::string>& args,
        const std::vector<std::string>& options = {}) {
  std::vector<std::string> argv = {TRUEAXIS_VAR_BINARY, "--port", std::to_string(sim.port())};
  argv.insert(argv.end(), options.begin(), options.end());
  argv.insert(argv.end(), args.begin(), args.end());
  return run(argv, w.file("var.err"));
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// "#N = V..." -> N and V; the test stops when the line is not that.
struct Printed {
  std::uint16_t number = 0;
  double value = 0.0;
  std::string rest;  // what follows the value
};

Printed printed(const std::string& line) {
  INFO(line);
  REQUIRE(line.compare(0, 1, "#") == 0);
  const std::size_t eq = line.find(" = ");
  REQUIRE(eq != std::string::npos);
  Printed p;
  p.number = static_cast<std::uint16_t>(std::stoul(line.substr(1, eq - 1)));
  const char* value = line.c_str() + eq + 3;
  char* end = nullptr;
  p.value = std::strtod(value, &end);
  REQUIRE(end != value);
  p.rest = end;
  return p;
}

// Exactly one line on stderr, nothing on stdout, exit 1.
void check_failure(const Run& r, const std::string& line) {
  CHECK(r.exit_code == 1);
  CHECK(r.err == "trueaxis-var: " + line + "\n");
  CHECK(r.out.empty());
}

std::string fault_text(m::AccessFault fault) {
  for (const m::AccessFaultInfo& f : m::kAccessFaultTable) {
    if (f.fault == fault) return std::string(f.name) + ": " + f.message;
  }
  return "";
}

// "#N: NAME (Modbus EX TEXT: MESSAGE)".
std::string refusal(const std::string& what, m::AccessFault fault, const std::string& exception) {
  const std::string text = fault_text(fault);
  const std::size_t colon = text.find(": ");
  return what + ": " + text.substr(0, colon) + " (Modbus " + exception + ": " + text.substr(colon + 2) + ")";
}

// A TCP port on 127.0.0.1 that is bound but not listening (a connect is refused),
// or listening but never read (a request gets no reply); closed when it goes.
struct Socket {
  int fd = -1;
  int port = 0;
  explicit Socket(bool listening) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t size = sizeof a;
    REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size) == 0);
    port = ntohs(a.sin_port);
    if (listening) REQUIRE(::listen(fd, 4) == 0);
  }
  ~Socket() { ::close(fd); }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
};

}  // namespace

TEST_CASE("trueaxis-var get prints each variable in decimal that reads back to the same double", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  const double values[] = {0.1, -1e-300, 1.0 / 3.0, 12345.678901234567, -0.0};
  sim.set(v::kArgA, {values[0], values[1], values[2]});
  sim.set(v::kArgX, {values[3], values[4]});
  const Run r = var(sim, w, {"get", "1..3", "24", "25", "9006"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const std::vector<std::string> lines = lines_of(r.out);
  REQUIRE(lines.size() == 6);
  const std::uint16_t numbers[] = {1, 2, 3, 24, 25, 9006};
  for (std::size_t k = 0; k < 6; ++k) {
    CAPTURE(lines[k]);
    const Printed p = printed(lines[k]);
    CHECK(p.number == numbers[k]);
    CHECK(p.rest.empty());
    const double expected = k < 5 ? values[k] : m::kInterfaceVersionValue;
    CHECK(std::memcmp(&p.value, &expected, sizeof expected) == 0);  // bit for bit, the sign of 0 too
  }
}

TEST_CASE("trueaxis-var set writes decimals, adjacent variables in one request, whole or refused", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  Run r = var(sim, w, {"set", "5281=0.1", "5282=-2.5e-3", "5283=40", "5301=100"});
  CHECK(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK(r.out.empty());
  CHECK(sim.get(5281) == 0.1);
  CHECK(sim.get(5282) == -2.5e-3);
  CHECK(sim.get(5283) == 40.0);
  CHECK(sim.get(5301) == 100.0);
  // One request for #5281..#5283: the refused Z leaves X and Y as they were.
  r = var(sim, w, {"set", "5281=7", "5282=8", "5283=nan"});
  check_failure(r, refusal("#5281..#5283", m::AccessFault::kNotFinite, "03 illegal data value"));
  CHECK(sim.get(5281) == 0.1);
  CHECK(sim.get(5282) == -2.5e-3);
  // Not adjacent: two requests, the first done before the second is refused.
  r = var(sim, w, {"set", "5281=7", "100=1"});
  check_failure(r, refusal("#100", m::AccessFault::kReadOnly, "02 illegal data address"));
  CHECK(sim.get(5281) == 7.0);
}

TEST_CASE("trueaxis-var run writes the G65 letters, waits for #9003 and prints the results by name", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  Run r = var(sim, w, {"set", "5281=0", "5282=0", "5283=40", "5301=100", "5302=0", "5303=40", "5321=0", "5322=100",
                       "5323=50"});
  REQUIRE(r.exit_code == 0);
  const double done_before = sim.get(v::kDoneCount);
  r = var(sim, w, {"run", "9810", "A=0", "C=0"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK(sim.get(v::kDoneCount) == done_before + 1.0);
  const std::vector<std::string> lines = lines_of(r.out);
  REQUIRE(lines.size() == 1 + sizeof m::level::kLevelOutputs / sizeof m::level::kLevelOutputs[0]);
  const std::string done = "9810 level_3pt: done, error 0 ok, 1 step, ";
  CHECK(lines[0].compare(0, done.size(), done) == 0);
  CHECK(lines[0].compare(lines[0].size() - 3, 3, " us") == 0);
  std::size_t k = 1;
  for (const m::OutputInfo& o : m::level::kLevelOutputs) {
    CAPTURE(lines[k]);
    const Printed p = printed(lines[k++]);
    CHECK(p.number == o.number);
    CHECK(p.value == sim.get(o.number));
    CHECK(p.rest == " (" + std::string(o.name) + (o.unit[0] != '\0' ? std::string(", ") + o.unit : "") + ")");
  }
  CHECK(std::fabs(printed(lines[2]).value + 5.7105931374996466) < 1e-9);  // #101: A levels the face

  // Every letter lands in its G65 variable: held busy, the module has not yet
  // cleared them when the wait ends.
  sim.set(trueaxis::sim::simvar::kHold, 1.0);
  r = var(sim, w,
          {"run", "9810", "A=1", "B=2", "C=3", "I=4", "J=5", "K=6", "D=7", "E=8", "F=9", "H=11", "M=13", "Q=17", "R=18",
           "S=19", "T=20", "U=21", "V=22", "W=23", "X=24", "Y=25", "z=26"},
          {"--wait", "100"});
  check_failure(r, "macro 9810 still busy after 100 ms (#9001 = 1)");
  for (std::uint16_t n = 1; n <= 26; ++n) {
    if (!m::is_defined(n)) continue;  // G, L, N, O, P
    CAPTURE(n);
    CHECK(sim.get(n) == static_cast<double>(n));
  }
  // Busy: the next write is refused, and #9007 says why.
  r = var(sim, w, {"set", "1=5"});
  check_failure(r, refusal("#1", m::AccessFault::kBusy, "06 server device busy"));
  sim.set(trueaxis::sim::simvar::kHold, 0.0);
}

TEST_CASE("trueaxis-var: a macro error is one line with the module's code, name and message", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  const double collinear[3][3] = {{0, 0, 40}, {50, 0, 40}, {100, 0, 40}};
  sim.set_points(collinear);
  sim.set(v::kInterface, 0.0);  // the fixture's connection gives the macro interface back to the command's
  const auto s = trueaxis::core::Status::kPointsCollinear;
  check_failure(var(sim, w, {"run", "9810"}), "macro 9810 level_3pt: module error 201 points_collinear: " +
                                                  std::string(trueaxis::macros::status_message(s)));
  check_failure(var(sim, w, {"run", "9999"}), "macro 9999: module error 400 unknown_macro: " +
                                                  std::string(trueaxis::macros::status_message(
                                                      trueaxis::core::Status::kUnknownMacro)));
}

TEST_CASE("trueaxis-var: refusals, time-outs and connections, each one line naming its cause", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  check_failure(var(sim, w, {"set", "500=1"}), refusal("#500", m::AccessFault::kLocked, "02 illegal data address"));
  check_failure(var(sim, w, {"get", "10"}), refusal("#10", m::AccessFault::kUndefined, "02 illegal data address"));
  check_failure(var(sim, w, {"get", "9058..9060"}),
                refusal("#9058..#9060", m::AccessFault::kUndefined, "02 illegal data address"));
  check_failure(var(sim, w, {"set", "9004=1234"}),
                refusal("#9004", m::AccessFault::kBadUnlockCode, "03 illegal data value"));

  const Socket silent(true);
  check_failure(run({TRUEAXIS_VAR_BINARY, "--port", std::to_string(silent.port), "--timeout", "200", "get", "1"},
                    w.file("var.err")),
                "#1: no reply from 127.0.0.1:" + std::to_string(silent.port) + " within 200 ms");
  const Socket closed(false);
  check_failure(run({TRUEAXIS_VAR_BINARY, "--port", std::to_string(closed.port), "get", "1"}, w.file("var.err")),
                "cannot connect to 127.0.0.1:" + std::to_string(closed.port) + ": Connection refused");
  check_failure(run({TRUEAXIS_VAR_BINARY, "--rtu", w.file("no-such-tty"), "get", "1"}, w.file("var.err")),
                "cannot open " + w.file("no-such-tty") + ": No such file or directory");
}

TEST_CASE("trueaxis-var: an unlock lasts one command, so configuration is written in the same one", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  const double before = sim.get(500);  // a_min, the A axis travel limit
  // #9004 and #500 are not adjacent: two requests on one connection, in order.
  Run r = var(sim, w, {"set", "9004=2718", "500=-80", "9004=0"});
  CHECK(r.exit_code == 0);
  CHECK(sim.get(500) == -80.0);
  CHECK(sim.get(v::kUnlock) == 0.0);
  // The connection that opened it has closed: the next command finds it locked.
  r = var(sim, w, {"set", "9004=2718"});
  CHECK(r.exit_code == 0);
  check_failure(var(sim, w, {"set", "500=-70"}), refusal("#500", m::AccessFault::kLocked, "02 illegal data address"));
  CHECK(sim.get(500) == -80.0);
  CHECK(before != -80.0);
}

TEST_CASE("trueaxis-var: run holds the macro interface for its macro only, set of a work offset takes nothing", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  // set of a work offset takes nothing: the interface is free after it.
  Run r = var(sim, w, {"set", "5281=1.5"});
  CHECK(r.exit_code == 0);
  CHECK(sim.get(v::kInterface) == 0.0);
  // run: its connection closes with the command, and the interface with it.
  r = var(sim, w, {"run", "9812"});
  CHECK(r.exit_code == 0);
  CHECK(sim.get(v::kInterface) == 0.0);
  sim.set(v::kArgX, 2.0);  // another client writes at once, no 2 s wait: taken by the fixture's connection
  CHECK(sim.get(v::kInterface) == 1.0);
  sim.set(v::kInterface, 1.0);  // held for the session's length: the commands below take longer than 2 s on a busy machine
  // While another client holds it, set and run are refused in one line naming the hold, nothing written.
  check_failure(var(sim, w, {"set", "5281=2.5"}),
                refusal("#5281", m::AccessFault::kInterfaceHeld, "06 server device busy"));
  CHECK(sim.get(5281) == 1.5);
  r = var(sim, w, {"run", "9812"});
  CHECK(r.exit_code == 1);
  CHECK(r.out.empty());
  CHECK(r.err.find("interface_held") != std::string::npos);
  // set with an unlock code holds the interface first: refused at #9009 while another holds it.
  check_failure(var(sim, w, {"set", "9004=2718", "500=-80", "9004=0"}),
                refusal("#9009", m::AccessFault::kInterfaceHeld, "06 server device busy"));
  REQUIRE(sim.client().give_back_interface());
  r = var(sim, w, {"set", "9004=2718", "500=-80", "9004=0"});
  CHECK(r.exit_code == 0);
  CHECK(sim.get(500) == -80.0);
  CHECK(sim.get(v::kInterface) == 0.0);  // its connection closed: given back
}

TEST_CASE("trueaxis-var: bad usage is exit 2 with one line, and nothing is sent", "[var]") {
  SimFixture sim;
  Workspace w("trueaxis-var");
  const double done_before = sim.get(v::kDoneCount);
  const std::vector<std::vector<std::string>> bad = {
      {},
      {"fetch", "1"},
      {"get"},
      {"get", "1.5"},
      {"get", "5..3"},
      {"get", "16384"},
      {"set", "1"},
      {"set", "1=1.5x"},
      {"set", "1="},
      {"run"},
      {"run", "0"},
      {"run", "10000"},
      {"run", "9810", "G=1"},
      {"run", "9810", "A=1", "a=2"},
      {"run", "9810", "AB=1"},
      {"--frob", "1", "get", "1"},
      {"--timeout", "0", "get", "1"}};
  for (const auto& args : bad) {
    std::string shown;
    for (const std::string& a : args) shown += a + " ";
    CAPTURE(shown);
    const Run r = var(sim, w, args);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.compare(0, 14, "trueaxis-var: ") == 0);
    CHECK(r.err.find("(trueaxis-var --help)\n") == r.err.size() - 22);  // one line
  }
  const Run r = run({TRUEAXIS_VAR_BINARY, "--port", "1", "--rtu", "/dev/null", "get", "1"}, w.file("var.err"));
  CHECK(r.exit_code == 2);
  CHECK(r.err == "trueaxis-var: --port and --rtu exclude each other (trueaxis-var --help)\n");
  CHECK(sim.get(v::kDoneCount) == done_before);
  CHECK(sim.get(v::kArgA) == 0.0);
}
