// trueaxis-level: the operator's three-point auto-level flow (docs/METHODS.md M1)
// against trueaxis-sim, over Modbus TCP only:
//   1. probe three points of the face into G57, G58, G59 with the table where it is;
//   2. run macro 9810 with A = #1, C = #3 = that table position;
//   3. turn the table to the chosen solution (#101 A, #100 C);
//   4. probe again and run 9810 with A, C = the leveled pose, where the table is;
//   5. print before / after: #117, the face's tilt in the machine frame at the
//      pose it was probed in (on the ideal and the calibrated axes alike; #107
//      is the tilt at table zero, which on calibrated axes is not the machine
//      frame), its 1 sigma #118, and the simulator's ground truth there.
// Before the table turned, that is the tilt where the operator left it.
// With --axes ideal|calibrated it first sets the module's level_axes (#508: the
// ideal axes, or the calibrated axes of the stored rigidity table), unlocking
// and locking again; without it the module's setting stays. With --home 1 it
// first turns the table to A = 0, C = 0.
// Exit 0 when the true residual tilt is within 3 x #118 (the module's 1-sigma
// uncertainty of the second measurement), 1 when it is not, 2 on bad usage,
// 3 on a communication failure or a macro error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/server/sim_map.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace {

using trueaxis::sim::VariableClient;
namespace simvar = trueaxis::sim::simvar;

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint16_t kG57 = 5281;
constexpr std::uint16_t kG58 = 5301;
constexpr std::uint16_t kG59 = 5321;
constexpr std::uint16_t kLevelMacro = trueaxis::macros::level::kMacroThreePoint;
constexpr std::uint16_t kResults = 100;
constexpr std::uint16_t kResultCount = 19;  // #100..#118
constexpr std::uint16_t kLevelAxes = 508;
constexpr std::uint16_t kUnlock = 9004;
constexpr double kUnlockCode = 2718.0;

struct Measurement {
  double c_deg = 0.0;             // #100
  double a_deg = 0.0;             // #101
  double table_zero_tilt_deg = 0.0;  // #107
  double tilt_deg = 0.0;          // #117: machine frame, at the probe pose
  double sigma_arcsec = 0.0;      // #118
  double true_tilt_deg = 0.0;     // #12013 at the probe pose
};

constexpr const char* kHelp =
    "usage: trueaxis-level --port PORT [--host ADDR] [--spread MM] [--axes ideal|calibrated] [--home 1]\n"
    "  probes three points of the face (an equilateral triangle of side MM, default 100,\n"
    "  centred on the table axis), levels the table with macro 9810 and measures again;\n"
    "  before and after: the face's tilt in the machine frame where it was probed (#117),\n"
    "  its 1 sigma (#118) and the simulator's truth there.\n"
    "  --axes ideal|calibrated  first sets level_axes (#508), unlocking and locking again\n"
    "  --home 1                 first turns the table to A = 0, C = 0\n"
    "  --help, --version        this text; the version line\n"
    "  Exit 0: true residual tilt within 3 sigma; 1: not; 2: usage; 3: communication or macro error.\n";

void usage() { std::fputs(kHelp, stderr); }

bool fail(VariableClient& client, const char* what) {
  std::fprintf(stderr, "trueaxis-level: %s: %s\n", what, client.error_text().c_str());
  return false;
}

// Probes the triangle into G57, G58, G59 and runs 9810 with the table at
// (arg_a, arg_c) as far as the module is told.
bool measure(VariableClient& client, double spread_mm, double arg_a, double arg_c, Measurement& m) {
  // The arguments first: they take the module's macro interface, so that no
  // other client's work offsets come between the touches and the macro
  // (docs/INTERFACE.md "One client at a time").
  const double args[3] = {arg_a, 0.0, arg_c};  // #1 A, #2 B, #3 C
  if (!client.write(1, 3, args)) return fail(client, "writing A, C");
  const double r = spread_mm / std::sqrt(3.0);  // circumradius of the triangle
  const std::uint16_t targets[3] = {kG57, kG58, kG59};
  for (int i = 0; i < 3; ++i) {
    const double angle = kPi / 2.0 + 2.0 * kPi * i / 3.0;
    const double probe[3] = {r * std::cos(angle), r * std::sin(angle), static_cast<double>(targets[i])};
    if (!client.write(simvar::kProbeX, 3, probe)) return fail(client, "probing");
  }
  const trueaxis::sim::MacroOutcome outcome = client.run_macro(kLevelMacro);
  if (outcome.status != 2) {
    if (outcome.status == 3) {
      std::fprintf(stderr, "trueaxis-level: macro 9810 failed with error %d\n", outcome.error);
      return false;
    }
    return fail(client, "running macro 9810");
  }
  double results[kResultCount];
  if (!client.read(kResults, kResultCount, results)) return fail(client, "reading results");
  m.c_deg = results[100 - kResults];
  m.a_deg = results[101 - kResults];
  m.table_zero_tilt_deg = results[107 - kResults];
  m.tilt_deg = results[117 - kResults];
  m.sigma_arcsec = results[118 - kResults];
  if (!client.read_one(simvar::kTrueTilt, m.true_tilt_deg)) return fail(client, "reading ground truth");
  return true;
}

double height_um(double tilt_deg) { return 100.0 * std::tan(tilt_deg * kPi / 180.0) * 1000.0; }

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-level", kHelp)) return 0;
  std::string host = "127.0.0.1";
  int port = -1;
  double spread_mm = 100.0;
  double axes = -1.0;  // #508 to set: 0 ideal, 1 calibrated; -1 leave it
  bool home = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--port") {
      port = std::atoi(argv[i + 1]);
    } else if (arg == "--host") {
      host = argv[i + 1];
    } else if (arg == "--spread") {
      spread_mm = std::atof(argv[i + 1]);
    } else if (arg == "--home" && std::string(argv[i + 1]) == "1") {
      home = true;
    } else if (arg == "--axes" && (std::string(argv[i + 1]) == "ideal" || std::string(argv[i + 1]) == "calibrated")) {
      axes = std::string(argv[i + 1]) == "ideal" ? 0.0 : 1.0;
    } else {
      port = -1;
      break;
    }
  }
  if (argc % 2 == 0 || port <= 0 || port > 65535 || !(spread_mm > 0.0)) {
    usage();
    return 2;
  }

  VariableClient client;
  if (!client.connect(host, port)) {
    std::fprintf(stderr, "trueaxis-level: cannot connect to %s:%d: %s\n", host.c_str(), port,
                 client.error_text().c_str());
    return 3;
  }
  if (axes >= 0.0) {
    const bool set = client.write_one(kUnlock, kUnlockCode) && client.write_one(kLevelAxes, axes);
    client.write_one(kUnlock, 0.0);
    if (!set) {
      fail(client, "setting level_axes (#508)");
      return 3;
    }
    std::printf("leveling on the %s axes (#508 = %.0f)\n", axes == 0.0 ? "ideal" : "calibrated", axes);
  }
  const double zero[2] = {0.0, 0.0};
  if (home && !client.write(simvar::kAxisA, 2, zero)) {
    fail(client, "turning the table to zero");
    return 3;
  }
  double table[2];  // A, C where the operator left the table
  if (!client.read(simvar::kAxisA, 2, table)) {
    fail(client, "reading the table position");
    return 3;
  }

  Measurement before;
  if (!measure(client, spread_mm, table[0], table[1], before)) return 3;
  std::printf("table at A %.4f C %.4f deg: level at A %.6f C %.6f deg\n", table[0], table[1], before.a_deg,
              before.c_deg);
  const double leveled[2] = {before.a_deg, before.c_deg};
  if (!client.write(simvar::kAxisA, 2, leveled)) {
    fail(client, "turning the table");
    return 3;
  }

  Measurement after;
  if (!measure(client, spread_mm, leveled[0], leveled[1], after)) return 3;

  std::printf("%-36s %16s %16s\n", "", "before", "after");
  std::printf("%-36s %16.6f %16.6f\n", "tilt #117 (deg)", before.tilt_deg, after.tilt_deg);
  std::printf("%-36s %16.2f %16.2f\n", "tilt #117 (arcsec)", before.tilt_deg * 3600.0, after.tilt_deg * 3600.0);
  std::printf("%-36s %16.2f %16.3f\n", "height difference over 100 mm (um)", height_um(before.tilt_deg),
              height_um(after.tilt_deg));
  std::printf("%-36s %16.3f %16.3f\n", "uncertainty #118, 1 sigma (arcsec)", before.sigma_arcsec,
              after.sigma_arcsec);
  std::printf("%-36s %16.3f %16.3f\n", "true tilt #12013 (arcsec)", before.true_tilt_deg * 3600.0,
              after.true_tilt_deg * 3600.0);
  std::printf("%-36s %16.6f %16.6f\n", "tilt at table zero #107 (deg)", before.table_zero_tilt_deg,
              after.table_zero_tilt_deg);
  const double miss_arcsec = std::fabs(after.tilt_deg - after.true_tilt_deg) * 3600.0;
  if (after.sigma_arcsec > 0.0) {
    std::printf("after-probe %.3f arcsec against the truth %.3f arcsec: %.2f sigma\n", after.tilt_deg * 3600.0,
                after.true_tilt_deg * 3600.0, miss_arcsec / after.sigma_arcsec);
  }
  const double limit_arcsec = 3.0 * after.sigma_arcsec;  // #118
  const bool ok = after.true_tilt_deg * 3600.0 <= limit_arcsec;
  std::printf("true residual tilt %.3f arcsec %s 3 sigma = %.3f arcsec: %s\n", after.true_tilt_deg * 3600.0,
              ok ? "<=" : ">", limit_arcsec, ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}
