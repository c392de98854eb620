// bench_offset_write: how fast a PLC can write a work offset (G57 X, Y, Z: one
// FC16 write of 12 registers) into trueaxis-sim, against a bare libmodbus
// server that only receives and replies (modbus_receive + modbus_reply over a
// plain register image) on the same machine, in the same run.
// Not a test: it prints both rates and their ratio.
//
// The simulator's storage file is on tmpfs (/dev/shm), so what is measured is
// the module's own work (validation, building and CRC-ing the work-offset
// record, one pwrite + fsync of it) and not the disk. Rounds alternate between
// the two servers so that drift of the machine hits both alike; the figure is
// the median of the per-round ratios.
//
// usage: bench_offset_write [--writes N] [--rounds R]
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <modbus/modbus.h>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/sim_process.hpp"

namespace {

// Serves one client with modbus_receive + modbus_reply until it disconnects.
[[noreturn]] void bare_server(int listen_fd) {
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", 0);
  modbus_mapping_t* image = modbus_mapping_new(0, 0, 4 * 6000, 0);
  if (ctx == nullptr || image == nullptr) _exit(2);
  for (;;) {
    int fd = listen_fd;
    if (modbus_tcp_accept(ctx, &fd) < 0) _exit(3);
    std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {
      const int n = modbus_receive(ctx, query);
      if (n < 0) break;
      if (n > 0) modbus_reply(ctx, query, n, image);
    }
    close(fd);
  }
}

// Listens on 127.0.0.1, a free port; returns the socket and the port.
int listen_loopback(int& port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || listen(fd, 4) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    close(fd);
    return -1;
  }
  port = ntohs(addr.sin_port);
  return fd;
}

// Writes per second of G57 X, Y, Z over `client`; -1 on a failed write.
double write_rate(trueaxis::sim::VariableClient& client, int writes) {
  double xyz[3] = {10.0, 20.0, 30.0};
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < writes; ++i) {
    xyz[0] = 10.0 + 1e-3 * i;
    if (!client.write(5281, 3, xyz)) return -1.0;
  }
  const auto t1 = std::chrono::steady_clock::now();
  return writes / std::chrono::duration<double>(t1 - t0).count();
}

}  // namespace

constexpr const char* kHelp =
    "usage: bench_offset_write [--writes N] [--rounds R]\n"
    "  A work-offset write over Modbus TCP (FC16, 12 registers) into trueaxis-sim against a\n"
    "  bare libmodbus reply loop, alternating rounds: both rates and their ratio.\n"
    "  --writes N         writes per round (default 2000)\n"
    "  --rounds R         rounds (default 7)\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_offset_write", kHelp)) return 0;
  int writes = 2000;
  int rounds = 7;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--writes") writes = std::max(1, std::atoi(argv[i + 1]));
    if (arg == "--rounds") rounds = std::max(1, std::atoi(argv[i + 1]));
  }

  int bare_port = 0;
  const int listen_fd = listen_loopback(bare_port);
  if (listen_fd < 0) return 1;
  const pid_t bare = fork();
  if (bare == 0) bare_server(listen_fd);
  close(listen_fd);

  char nv_path[] = "/dev/shm/trueaxis-bench-XXXXXX";
  const int nv_fd = mkstemp(nv_path);
  if (nv_fd < 0) return 1;
  close(nv_fd);
  trueaxis::sim::SimProcess sim;
  if (!sim.start(trueaxis::sim::executable_dir() + "/trueaxis-sim",
                 {"--host", "127.0.0.1", "--port", "0", "--nv", nv_path})) {
    std::fprintf(stderr, "bench: cannot start trueaxis-sim\n");
    return 1;
  }

  trueaxis::sim::VariableClient to_bare;
  trueaxis::sim::VariableClient to_sim;
  int status = 0;
  if (!to_bare.connect("127.0.0.1", bare_port) || !to_sim.connect("127.0.0.1", sim.port())) {
    std::fprintf(stderr, "bench: cannot connect\n");
    status = 1;
  } else {
    write_rate(to_bare, 200);  // warm up both
    write_rate(to_sim, 200);
    std::vector<double> bare_rates, sim_rates, ratios;
    for (int r = 0; r < rounds && status == 0; ++r) {
      const double b = write_rate(to_bare, writes);
      const double s = write_rate(to_sim, writes);
      if (b <= 0 || s <= 0) status = 1;
      bare_rates.push_back(b);
      sim_rates.push_back(s);
      ratios.push_back(s / b);
    }
    if (status == 0) {
      const auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      std::printf("work-offset write (FC16, 12 registers), %d writes x %d rounds, NV file on tmpfs\n", writes, rounds);
      std::printf("  bare libmodbus reply loop: %.0f writes/s (median)\n", median(bare_rates));
      std::printf("  trueaxis-sim:              %.0f writes/s (median)\n", median(sim_rates));
      std::printf("  ratio trueaxis / bare:     %.2f (median of per-round ratios; min %.2f, max %.2f)\n",
                  median(ratios), *std::min_element(ratios.begin(), ratios.end()),
                  *std::max_element(ratios.begin(), ratios.end()));
    }
  }
  to_bare.close();
  to_sim.close();
  sim.stop();
  kill(bare, SIGTERM);
  waitpid(bare, nullptr, 0);
  unlink(nv_path);
  return status;
}
