// trueaxis-sim: the module on a virtual cradle machine, served over Modbus TCP.
// Usage and exit codes: usage() below; docs/INTERFACE.md "The simulator's command line".
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "trueaxis/hal/posix/file_nv_storage.hpp"
#include "trueaxis/hal/posix/steady_clock.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/server/modbus_server.hpp"
#include "trueaxis/sim/server/simulator.hpp"
#include "trueaxis/sim/server/variable_router.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int) { g_stop = 1; }

constexpr const char* kHelp =
    "usage: trueaxis-sim --port PORT [--host ADDR] [--nv PATH] [--seed N]\n"
    "                    [--face-tilt DEG] [--face-azimuth DEG] [--face-height MM]\n"
    "                    [--errors ideal|realistic|location] [--pivot X,Y,Z] [--a-offset DY,DZ]\n"
    "                    [--max-clients N]\n"
    "                    [--frame-timeout MS] [--idle-timeout MS]\n"
    "  --port PORT        TCP port; 0 picks a free one (printed)\n"
    "  --host ADDR        IPv4 address to listen on (default 127.0.0.1)\n"
    "  --nv PATH          non-volatile storage file (default ./trueaxis-sim.nv)\n"
    "  --seed N           probe and ball noise seed (default 1)\n"
    "  --face-tilt DEG    workpiece face tilt from horizontal, table at zero (default 12.5)\n"
    "  --face-azimuth DEG direction the face falls towards, from +X to +Y (default 30)\n"
    "  --face-height MM   Z of the face above the table centre (default 40)\n"
    "  --errors KIND      the machine's geometric errors at start (sim_errors #12020):\n"
    "                     ideal (none, the default), realistic or location (the axes out of\n"
    "                     place only; cradle_errors.hpp)\n"
    "  --pivot X,Y,Z      the cradle's nominal pivot: the C axis' point with the table at\n"
    "                     A = 0, the table's origin (mm; default 0,0,0), as xyzac-trt-kins'\n"
    "                     x/y/z-rot-point\n"
    "  --a-offset DY,DZ   the A axis' offset from it (mm; default 0,0), as xyzac-trt-kins'\n"
    "                     y/z-offset\n"
    "  --max-clients N    connections served at once; the next is closed at once (default 32)\n"
    "  --frame-timeout MS a connection holding a partial frame or an unsent reply that\n"
    "                     long is closed (default 5000)\n"
    "  --idle-timeout MS  a connection that sends no whole frame that long is closed\n"
    "                     (default 0: never)\n"
    "  --help, --version  this text; the version line\n"
    "Serves until SIGINT or SIGTERM; exit 0 then, 1 on a start-up failure, 2 on bad usage.\n";

void usage() { std::fputs(kHelp, stderr); }

bool parse_double(const char* text, double& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text, &end);
  return errno == 0 && end != text && *end == '\0';
}

// N numbers separated by commas, each finite.
bool parse_list(const char* text, double* out, int n) {
  std::string rest = text;
  for (int k = 0; k < n; ++k) {
    const std::size_t comma = rest.find(',');
    if ((comma == std::string::npos) != (k == n - 1)) return false;
    if (!parse_double(rest.substr(0, comma).c_str(), out[k]) || !std::isfinite(out[k])) return false;
    rest = comma == std::string::npos ? std::string() : rest.substr(comma + 1);
  }
  return true;
}

bool parse_u64(const char* text, unsigned long long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtoull(text, &end, 10);
  return errno == 0 && end != text && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  using namespace trueaxis;
  if (sim::answered_help_or_version(argc, argv, "trueaxis-sim", kHelp)) return 0;
  std::string host = "127.0.0.1";
  std::string nv_path = "./trueaxis-sim.nv";
  unsigned long long port = 65536;
  unsigned long long seed = 1;
  sim::FaceConfig face;
  bool errors_on = false;
  sim::CradleErrors errors = sim::realistic_errors();
  sim::CradlePivot pivot;
  sim::ServerLimits limits;
  unsigned long long number = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) {
      usage();
      return 2;
    }
    const char* value = argv[++i];
    bool ok = true;
    if (arg == "--port") {
      ok = parse_u64(value, port) && port <= 65535;
    } else if (arg == "--host") {
      host = value;
    } else if (arg == "--nv") {
      nv_path = value;
    } else if (arg == "--seed") {
      ok = parse_u64(value, seed);
    } else if (arg == "--face-tilt") {
      ok = parse_double(value, face.tilt_deg) && face.tilt_deg >= 0.0 && face.tilt_deg < 90.0;
    } else if (arg == "--face-azimuth") {
      ok = parse_double(value, face.azimuth_deg);
    } else if (arg == "--face-height") {
      ok = parse_double(value, face.height_mm);
    } else if (arg == "--errors") {
      const std::string kind = value;
      ok = kind == "ideal" || kind == "realistic" || kind == "location";
      errors_on = kind != "ideal";
      errors = kind == "location" ? sim::location_errors() : sim::realistic_errors();
    } else if (arg == "--pivot") {
      double xyz[3];
      ok = parse_list(value, xyz, 3);
      if (ok) pivot.c_point_mm = core::Vec3(xyz[0], xyz[1], xyz[2]);
    } else if (arg == "--a-offset") {
      double yz[2];
      ok = parse_list(value, yz, 2);
      if (ok) pivot.a_offset_y_mm = yz[0], pivot.a_offset_z_mm = yz[1];
    } else if (arg == "--max-clients") {
      ok = parse_u64(value, number) && number >= 1 && number <= 1024;
      limits.max_clients = static_cast<std::size_t>(number);
    } else if (arg == "--frame-timeout") {
      ok = parse_u64(value, number) && number >= 1 && number <= 3600000;
      limits.frame_timeout_ms = static_cast<int>(number);
    } else if (arg == "--idle-timeout") {
      ok = parse_u64(value, number) && number <= 3600000;
      limits.idle_timeout_ms = static_cast<int>(number);
    } else {
      ok = false;
    }
    if (!ok) {
      std::fprintf(stderr, "trueaxis-sim: bad option or value: %s %s\n", arg.c_str(), value);
      usage();
      return 2;
    }
  }
  if (port > 65535) {
    usage();
    return 2;
  }

  hal::FileNvStorage nv;
  if (nv.open(nv_path.c_str(), macros::kRequiredStorageBytes) != hal::IoStatus::kOk) {
    std::fprintf(stderr, "trueaxis-sim: cannot open %s: %s\n", nv_path.c_str(), std::strerror(errno));
    return 1;
  }
  hal::SteadyClock clock;
  macros::Module module(nv, clock);
  if (module.start() != core::Status::kOk) {
    std::fprintf(stderr, "trueaxis-sim: %s unreadable; using the map's defaults\n", nv_path.c_str());
  }
  sim::Simulator simulator(module, face, seed, errors_on, errors, pivot);
  sim::VariableRouter router(module, simulator);
  modbus::ModbusCore core(router);
  sim::ModbusTcpServer server(core, simulator, limits);

  // Block the stop signals; ppoll unblocks them only while waiting.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigset_t wait_mask;
  sigprocmask(SIG_BLOCK, &stop_signals, &wait_mask);
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  if (!server.listen(host.c_str(), static_cast<int>(port))) {
    std::fprintf(stderr, "trueaxis-sim: cannot listen on %s:%llu: %s\n", host.c_str(), port,
                 std::strerror(errno));
    return 1;
  }
  std::printf("listening on %s:%d\n", host.c_str(), server.port());
  std::fflush(stdout);
  server.serve(g_stop, wait_mask);
  return 0;
}
