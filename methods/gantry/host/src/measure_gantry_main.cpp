// trueaxis-measure-gantry: measures the virtual gantry (gantry_machine.hpp,
// realistic_gantry()) with the virtual laser tracker (laser_tracker.hpp) and
// writes the files trueaxis-calibrate gantry reads (docs/INTERFACE.md "M2 gantry").
// Standalone: no simulator process is needed, because the gantry is measured by
// the tracker alone; the module only enters when the samples are calibrated.
//
// usage: trueaxis-measure-gantry --out SAMPLES.csv --machine MACHINE.csv [--seed N]
//          [--tracker-distance M] [--noise on|off] [--truth TRUTH.json]
//   --seed N              noise seed (default 1): the same seed, the same files
//   --tracker-distance M  metres from the machine's front to the tracker (default
//                         2.5; 1..20 accepted; 2..6 is the tracker's sweet spot)
//   --noise on|off        the tracker's noise (default on)
//   --truth TRUTH.json    also the TRUE values in the shape of OUT.json
// Prints the number of points, the ranges and the tracker's sigmas there. Exit
// 0, or 1 with one line on stderr; the files are written only after everything
// is computed, samples first, then MACHINE, then the truth.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"

using trueaxis::sim::write_text_file;

namespace {

constexpr const char* kHelp =
    "usage: trueaxis-measure-gantry --out SAMPLES.csv --machine MACHINE.csv [--seed N]\n"
    "         [--tracker-distance M] [--noise on|off] [--truth TRUTH.json]\n"
    "  Measures the virtual gantry (realistic errors, 4 sub-machines) with a virtual laser\n"
    "  tracker into the files trueaxis-calibrate gantry reads; no simulator process needed.\n"
    "  --seed N              noise seed (default 1): the same seed, the same files\n"
    "  --tracker-distance M  metres from the machine's front to the tracker (default 2.5; 1..20)\n"
    "  --noise on|off        the tracker's noise (default on)\n"
    "  --truth TRUTH.json    also the TRUE values in the shape of OUT.json\n"
    "  --help, --version     this text; the version line\n"
    "  Exit 0, or 1 with one line on stderr.\n";

int fail(const std::string& what) {
  std::fprintf(stderr, "trueaxis-measure-gantry: %s\n", what.c_str());
  return 1;
}

bool number(const char* text, double& out) { return trueaxis::sim::finite_number(text, out); }

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-measure-gantry", kHelp)) return 0;
  std::string out_path, machine_path, truth_path, noise = "on";
  double seed = 1, distance_m = 2.5;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    bool ok = true;
    if (arg == "--out") out_path = argv[i + 1];
    else if (arg == "--machine") machine_path = argv[i + 1];
    else if (arg == "--truth") truth_path = argv[i + 1];
    else if (arg == "--noise") noise = argv[i + 1];
    else if (arg == "--seed") ok = number(argv[i + 1], seed) && seed >= 0 && seed == std::floor(seed) && seed < 9e15;
    else if (arg == "--tracker-distance") ok = number(argv[i + 1], distance_m) && distance_m >= 1 && distance_m <= 20;
    else ok = false;
    if (!ok) return fail("bad option '" + arg + "'");
  }
  if (argc % 2 == 0 || out_path.empty() || machine_path.empty() || (noise != "on" && noise != "off")) {
    return fail("usage: trueaxis-measure-gantry --out SAMPLES.csv --machine MACHINE.csv [--seed N] "
                "[--tracker-distance M] [--noise on|off] [--truth TRUTH.json]");
  }

  using namespace trueaxis::sim;
  const GantryMachine machine(realistic_gantry());
  TrackerPlacement placement;
  placement.distance_m = distance_m;
  const LaserTracker tracker = place_tracker(machine, placement, TrackerSpec{}, noise == "on");
  const GantryPlan plan;
  SimRng rng(static_cast<std::uint64_t>(seed));
  const std::vector<TrackerSample> samples = measure_gantry(machine, tracker, plan, rng);

  double near_mm = 1e300, far_mm = 0.0;
  for (const TrackerSample& s : samples) {
    near_mm = std::min(near_mm, s.p_mm.norm());
    far_mm = std::max(far_mm, s.p_mm.norm());
  }
  char about[200];
  std::snprintf(about, sizeof about, "seed %.0f, tracker %.3f m from the machine, noise %s, ranges %.3f..%.3f m",
                seed, distance_m, noise.c_str(), near_mm / 1000.0, far_mm / 1000.0);
  const std::string samples_text = samples_csv_text(
      samples, {"trueaxis-measure-gantry: the virtual gantry (realistic errors), tracker frame, mm", about});
  if (!write_text_file(out_path, samples_text)) return fail(out_path + ": cannot be written");
  if (!write_text_file(machine_path, machine_csv_text(machine, tracker))) return fail(machine_path + ": cannot be written");
  if (!truth_path.empty() && !write_text_file(truth_path, truth_json_text(machine, tracker, plan))) {
    return fail(truth_path + ": cannot be written");
  }
  std::printf("measured %zu points of %zu sub-machines (%s) into %s\n", samples.size(), machine.sub_machine_count(),
              about, out_path.c_str());
  std::printf("tracker 1 sigma: radial %.1f um; transverse %.1f um at %.2f m .. %.1f um at %.2f m\n",
              1000.0 * tracker.radial_sigma_mm(near_mm), 1000.0 * tracker.transverse_sigma_mm(near_mm),
              near_mm / 1000.0, 1000.0 * tracker.transverse_sigma_mm(far_mm), far_mm / 1000.0);
  return 0;
}
