// trueaxis-measure-ball: measures the simulator's calibration ball over a grid
// of commanded A and C, as an operator with a ball and an instrument would for
// M3, and writes the samples CSV trueaxis-calibrate reads (docs/INTERFACE.md "M3
// rigidity": a_deg,c_deg,x_mm,y_mm,z_mm).
//
// usage: trueaxis-measure-ball --port PORT [--host ADDR] --out SAMPLES.csv
//          [--a-from DEG --a-to DEG --a-step DEG] [--c-step DEG]
//   defaults: A from -90 to 90 every 30 (0 included), C every 10 over a turn.
// It moves the virtual axes (#12000, #12001), writes sim_ball_measure (#12025)
// and reads the measurement (#12026..#12028). Exit 0, or 1 with one line on
// stderr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/server/sim_map.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace {

namespace simvar = trueaxis::sim::simvar;

constexpr const char* kHelp =
    "usage: trueaxis-measure-ball --port PORT [--host ADDR] --out SAMPLES.csv\n"
    "         [--a-from DEG --a-to DEG --a-step DEG] [--c-step DEG]\n"
    "  Measures the simulator's calibration ball over a grid of commanded A and C into the\n"
    "  samples trueaxis-calibrate rigidity reads (a_deg,c_deg,x_mm,y_mm,z_mm).\n"
    "  defaults: A from -90 to 90 every 30 (0 included), C every 10 over a turn.\n"
    "  --help, --version  this text; the version line\n"
    "  Exit 0, or 1 with one line on stderr.\n";

int fail(const std::string& what) {
  std::fprintf(stderr, "trueaxis-measure-ball: %s\n", what.c_str());
  return 1;
}

bool number(const char* text, double& out) { return trueaxis::sim::finite_number(text, out); }

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-measure-ball", kHelp)) return 0;
  std::string host = "127.0.0.1";
  std::string out_path;
  double port = 0, a_from = -90, a_to = 90, a_step = 30, c_step = 10;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    bool ok = true;
    if (arg == "--host") host = argv[i + 1];
    else if (arg == "--out") out_path = argv[i + 1];
    else if (arg == "--port") ok = number(argv[i + 1], port);
    else if (arg == "--a-from") ok = number(argv[i + 1], a_from);
    else if (arg == "--a-to") ok = number(argv[i + 1], a_to);
    else if (arg == "--a-step") ok = number(argv[i + 1], a_step);
    else if (arg == "--c-step") ok = number(argv[i + 1], c_step);
    else ok = false;
    if (!ok) return fail("bad option '" + arg + "'");
  }
  if (argc % 2 == 0 || out_path.empty() || !(port >= 1 && port <= 65535) || !(a_step > 0) || !(c_step > 0) ||
      !(a_to >= a_from)) {
    return fail("usage: trueaxis-measure-ball --port PORT [--host ADDR] --out SAMPLES.csv "
                "[--a-from DEG --a-to DEG --a-step DEG] [--c-step DEG]");
  }
  trueaxis::sim::VariableClient client;
  if (!client.connect(host, static_cast<int>(port))) return fail("cannot connect: " + client.error_text());
  std::ofstream out(out_path, std::ios::trunc);
  if (!out) return fail(out_path + ": cannot be written");
  out << "# trueaxis-measure-ball: the simulator's calibration ball, machine frame\n";
  out << "a_deg,c_deg,x_mm,y_mm,z_mm\n";
  int samples = 0;
  const int a_count = static_cast<int>(std::floor((a_to - a_from) / a_step + 1e-9)) + 1;
  const int c_count = static_cast<int>(std::floor(360.0 / c_step - 1e-9)) + 1;
  for (int i = 0; i < a_count; ++i) {
    const double a = a_from + a_step * i;
    for (int k = 0; k < c_count; ++k) {
      const double c = c_step * k;
      const double axes[2] = {a, c};
      double p[3];
      if (!client.write(simvar::kAxisA, 2, axes) || !client.write_one(simvar::kBallMeasure, 1.0) ||
          !client.read(simvar::kLastBallX, 3, p)) {
        return fail("measuring at A " + std::to_string(a) + " C " + std::to_string(c) + ": " + client.error_text());
      }
      char line[160];
      std::snprintf(line, sizeof line, "%.10g,%.10g,%.9f,%.9f,%.9f\n", a, c, p[0], p[1], p[2]);
      out << line;
      ++samples;
    }
  }
  const double home[2] = {0.0, 0.0};
  if (!client.write(simvar::kAxisA, 2, home)) return fail("returning the table to zero: " + client.error_text());
  if (!out.flush()) return fail(out_path + ": cannot be written");
  std::printf("measured the ball at %d poses x %d C positions: %d samples in %s\n", a_count, c_count, samples,
              out_path.c_str());
  return 0;
}
