// bench_modbus_cycle: the round trip of one whole leveling cycle over Modbus TCP,
// as a PLC or HMI would run it:
//   write the 9 coordinates of G57, G58, G59 (three FC16 writes of X, Y, Z),
//   write the arguments #1..#3, write #9000 = 9810, poll #9001..#9003 until
//   done_count grows, read #100..#115.
// Not a test: it prints the median and the 99th percentile in microseconds.
//
// usage: bench_modbus_cycle [--port PORT [--host ADDR]] [--cycles N]
//   without --port it starts build/host/bin/trueaxis-sim (beside this program)
//   on 127.0.0.1 port 0 with a temporary NV file, and stops it at the end.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <unistd.h>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/sim_process.hpp"

constexpr const char* kHelp =
    "usage: bench_modbus_cycle [--port PORT [--host ADDR]] [--cycles N]\n"
    "  The round trip of one whole leveling cycle over Modbus TCP (G57..G59, arguments,\n"
    "  #9000 = 9810, poll, results): median and 99th percentile in microseconds.\n"
    "  Without --port it starts trueaxis-sim beside this program on 127.0.0.1 port 0.\n"
    "  --cycles N         cycles measured (default 2000)\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_modbus_cycle", kHelp)) return 0;
  using trueaxis::sim::SimProcess;
  using trueaxis::sim::VariableClient;
  std::string host = "127.0.0.1";
  int port = 0;
  int cycles = 2000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--port") port = std::atoi(argv[i + 1]);
    if (arg == "--host") host = argv[i + 1];
    if (arg == "--cycles") cycles = std::atoi(argv[i + 1]);
  }
  if (cycles < 1) cycles = 1;

  SimProcess sim;
  char nv_path[] = "/tmp/trueaxis-bench-XXXXXX";
  bool own_sim = false;
  if (port == 0) {
    const int fd = mkstemp(nv_path);
    if (fd < 0) return 1;
    close(fd);
    if (!sim.start(trueaxis::sim::executable_dir() + "/trueaxis-sim",
                   {"--host", host, "--port", "0", "--nv", nv_path})) {
      std::fprintf(stderr, "bench: cannot start trueaxis-sim\n");
      unlink(nv_path);
      return 1;
    }
    port = sim.port();
    own_sim = true;
  }

  VariableClient client;
  if (!client.connect(host, port)) {
    std::fprintf(stderr, "bench: cannot connect: %s\n", client.error_text().c_str());
    return 1;
  }
  // A face tilted by about 10 deg, points 100 mm apart.
  const double points[3][3] = {{0.0, 57.735, 50.0}, {-50.0, -28.868, 40.0}, {50.0, -28.868, 42.0}};
  const std::uint16_t offsets[3] = {5281, 5301, 5321};
  const double args[3] = {0.0, 0.0, 0.0};
  std::vector<double> micros;
  micros.reserve(static_cast<std::size_t>(cycles));
  int failures = 0;
  for (int k = 0; k < cycles + 50; ++k) {  // the first 50 warm up
    const auto t0 = std::chrono::steady_clock::now();
    bool ok = true;
    for (int i = 0; i < 3; ++i) ok = ok && client.write(offsets[i], 3, points[i]);
    ok = ok && client.write(1, 3, args);
    ok = ok && client.run_macro(9810).status == 2;
    double results[16];
    ok = ok && client.read(100, 16, results);
    const auto t1 = std::chrono::steady_clock::now();
    if (!ok) ++failures;
    if (k >= 50) micros.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  std::sort(micros.begin(), micros.end());
  const auto pct = [&](double p) {
    const auto at = static_cast<std::size_t>(p * static_cast<double>(micros.size() - 1) + 0.5);
    return micros[at];
  };
  std::printf("level cycle over Modbus TCP (%s:%d), %d cycles, %d failed\n", host.c_str(), port, cycles, failures);
  std::printf("  median %.1f us   p99 %.1f us   min %.1f us   max %.1f us\n", pct(0.5), pct(0.99), micros.front(),
              micros.back());
  client.close();
  if (own_sim) {
    sim.stop();
    unlink(nv_path);
  }
  return failures == 0 ? 0 : 1;
}
