// trueaxis-measure-spindle: measures the virtual spindle (virtual_spindle.hpp,
// realistic_spindle()) with the virtual spindle analyser (spindle_analyser.hpp)
// and writes the files trueaxis-calibrate spindle reads (docs/INTERFACE.md "M4
// spindle"). Standalone: no simulator process is needed.
//
// usage: trueaxis-measure-spindle --out SAMPLES.csv --machine MACHINE.csv [--seed N]
//          [--revolutions R] [--step-deg S | --samples-per-rev N]
//          [--time-sampled [--drift-percent P]] [--noise on|off] [--form-nm F]
//          [--tool-length L] [--truth TRUTH.json]
//   --seed N          noise, form and start-angle seed (default 1): the same seed,
//                     the same files
//   --revolutions R   whole revolutions measured (default 3; 1..100)
//   Encoder-synchronous sampling (the default; analyser convention 1): the same
//   angles every revolution, one of
//   --step-deg S      angle step (default 5; 360 / S a whole number from 8 to 3600)
//   --samples-per-rev N  N angles a revolution, 360 / N apart (8..4096; not with
//                     --step-deg)
//   Time-sampled sampling (analyser convention 3):
//   --time-sampled    a fixed sampling clock, N = --samples-per-rev (default 1024)
//                     samples a revolution at the nominal speed; the speed rises
//                     linearly from 1 - P/200 to 1 + P/200 of nominal over the
//                     measurement, so no angle comes back on a later revolution;
//                     R N instants, the start angle and the clock's phase drawn
//                     from the seed (not with --step-deg)
//   --drift-percent P the speed's drift over the measurement, % (default 1; 0..10;
//                     only with --time-sampled)
//   --noise on|off    the probes' noise (15 nm per axis) and the balls' form error
//                     (default on); off: the true ball centres
//   --form-nm F       the balls' form error, RMS in nm (default 50; 0..1000)
//   --tool-length L   MACHINE's tool_length_mm and the truth's tool tip (default
//                     250: beyond the balls, a length the fit does not use)
//   --truth TRUTH.json  the TRUE values in the shape of OUT.json
// Files (conventions of virtual_spindle.hpp and spindle_analyser.hpp):
//   SAMPLES  `phi_deg,ball,x_mm,y_mm,z_mm`, the analyser's order; phi_deg keeps
//            growing past 360 on later revolutions; mm with 9 decimals. phi_deg
//            has 10 significant digits with --step-deg (and by default), 17 (it
//            reads back exactly) with --samples-per-rev or --time-sampled. The
//            second comment line says how it was sampled (the "about" line the
//            command prints too).
//   MACHINE  `name,value`: bearing_spacing_mm, gauge_from_upper_bearing_mm,
//            ball_1_mm, ball_2_mm, tool_length_mm, all nominal.
//   TRUTH    OUT.json's keys, with "parameters" identifiable_truth() (sigma 0;
//            o_x_mm, o_y_mm, o_z_mm, a_x, a_y, e_x_mm, e_y_mm, w_x, w_y; a and w
//            unitless direction components), "per_angle" every 5 deg from the
//            spindle's own geometry (convention 5), "evaluations" 0, and three
//            keys more: "truth": true, "tool_length_mm", and "axial_error_mm"
//            (delta of convention 4: o = O1 + delta a; the analyser cannot see
//            it, and the true tip's z error holds about -delta of it).
// Prints the sample count and the truth's extremes. Exit 0, or 1 with one line
// on stderr (a bad value says what the option takes); the files are written
// only after everything is computed, samples first, then MACHINE, then the truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/spindle_measure.hpp"

using trueaxis::sim::write_text_file;

namespace {

using trueaxis::core::Vec3;
using trueaxis::sim::VirtualSpindle;

constexpr const char* kHelp =
    "usage: trueaxis-measure-spindle --out SAMPLES.csv --machine MACHINE.csv [--seed N]\n"
    "         [--revolutions R] [--step-deg S | --samples-per-rev N]\n"
    "         [--time-sampled [--drift-percent P]] [--noise on|off] [--form-nm F]\n"
    "         [--tool-length L] [--truth TRUTH.json]\n"
    "  Measures the virtual spindle (realistic errors) with a virtual spindle analyser into\n"
    "  the files trueaxis-calibrate spindle reads; no simulator process needed.\n"
    "  --seed N          noise, form and start-angle seed (default 1): the same seed, the same files\n"
    "  --revolutions R   whole revolutions measured (default 3; 1..100)\n"
    "  Encoder-synchronous sampling (the default): the same angles every revolution\n"
    "  --step-deg S      angle step (default 5; 360 / S a whole number from 8 to 3600)\n"
    "  --samples-per-rev N  N angles a revolution, 360 / N apart (8..4096; not with --step-deg)\n"
    "  Time-sampled sampling: a fixed clock, the spindle's speed drifting, no angle repeated\n"
    "  --time-sampled    N = --samples-per-rev samples a nominal revolution (default 1024),\n"
    "                    R N in all; the start angle drawn from the seed (not with --step-deg)\n"
    "  --drift-percent P the speed rises linearly by P % over the measurement, from\n"
    "                    1 - P/200 to 1 + P/200 of nominal (default 1; 0..10; with --time-sampled)\n"
    "  --noise on|off    the probes' noise (15 nm) and the balls' form error (default on)\n"
    "  --form-nm F       the balls' form error, RMS in nm (default 50; 0..1000)\n"
    "  --tool-length L   MACHINE's tool_length_mm and the truth's tool tip (default 250)\n"
    "  --truth TRUTH.json  the TRUE values in the shape of OUT.json\n"
    "  --help, --version this text; the version line\n"
    "  Exit 0, or 1 with one line on stderr.\n";

constexpr const char* kUsage =
    "usage: trueaxis-measure-spindle --out SAMPLES.csv --machine MACHINE.csv [--seed N] "
    "[--revolutions R] [--step-deg S | --samples-per-rev N] [--time-sampled [--drift-percent P]] "
    "[--noise on|off] [--form-nm F] [--tool-length L] [--truth TRUTH.json]";

int fail(const std::string& what) {
  std::fprintf(stderr, "trueaxis-measure-spindle: %s\n", what.c_str());
  return 1;
}

bool number(const char* text, double& out) { return trueaxis::sim::finite_number(text, out); }

bool whole(double v) { return v == std::floor(v); }

// 360 / step a whole number from 8 (kMinSpindleSamples) to 3600 (finer angles:
// --samples-per-rev, whose phi_deg the file keeps to 17 digits).
bool splits_revolution(double step_deg) {
  const double n = 360.0 / step_deg;
  return n >= 8 && n <= 3600 && std::abs(n - std::round(n)) < 1e-9 * n;
}

std::string num(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.15g", v == 0.0 ? 0.0 : v);  // no "-0"
  return text;
}

// phi_deg with 10 significant digits (--step-deg, as before the other modes) or
// 17 (exact_phi: it reads back as the double it was).
std::string samples_text(const std::vector<trueaxis::core::SpindleSample>& samples, const std::string& about,
                         bool exact_phi) {
  std::string text = "# trueaxis-measure-spindle: the virtual spindle (realistic errors), analyser frame, mm\n# " +
                     about + "\nphi_deg,ball,x_mm,y_mm,z_mm\n";
  text.reserve(text.size() + 64 * samples.size());
  for (const auto& s : samples) {
    char line[160];
    if (exact_phi) {
      std::snprintf(line, sizeof line, "%.17g,%d,%.9f,%.9f,%.9f\n", s.phi_deg, s.ball, s.p_mm.x(), s.p_mm.y(),
                    s.p_mm.z());
    } else {
      std::snprintf(line, sizeof line, "%.10g,%d,%.9f,%.9f,%.9f\n", s.phi_deg, s.ball, s.p_mm.x(), s.p_mm.y(),
                    s.p_mm.z());
    }
    text += line;
  }
  return text;
}

std::string machine_text(const VirtualSpindle& spindle, double tool_length_mm) {
  const auto& c = spindle.config();
  const std::pair<const char*, double> rows[] = {{"bearing_spacing_mm", c.bearing_spacing_mm},
                                                 {"gauge_from_upper_bearing_mm", spindle.gauge_mm()},
                                                 {"ball_1_mm", c.ball_mm[0]},
                                                 {"ball_2_mm", c.ball_mm[1]},
                                                 {"tool_length_mm", tool_length_mm}};
  std::string text = "# nominal lengths of the virtual spindle, mm\nname,value\n";
  for (const auto& row : rows) {
    char line[120];
    std::snprintf(line, sizeof line, "%s,%.9f\n", row.first, row.second);
    text += line;
  }
  return text;
}

std::string truth_text(const VirtualSpindle& spindle, double tool_length_mm, double& theta_max_arcsec,
                       double& d_e_max_mm, double& tip_max_mm) {
  const char* names[9] = {"o_x_mm", "o_y_mm", "o_z_mm", "a_x", "a_y", "e_x_mm", "e_y_mm", "w_x", "w_y"};
  const trueaxis::core::SpindleParams q = spindle.identifiable_truth();
  std::string json = "{\n  \"method\": \"spindle\",\n  \"truth\": true,\n  \"parameters\": {";
  for (int k = 0; k < 9; ++k) {
    json += std::string(k > 0 ? "," : "") + "\n    \"" + names[k] + "\": { \"value\": " + num(q(k)) + ", \"sigma\": 0 }";
  }
  json += "\n  },\n  \"per_angle\": [";
  theta_max_arcsec = d_e_max_mm = tip_max_mm = 0.0;
  for (int i = 0; i < 72; ++i) {
    const double phi = 5.0 * i;
    const trueaxis::sim::ScrewError s = spindle.screw_error(phi);
    const Vec3 tip = spindle.tool_tip_error_mm(tool_length_mm, phi);
    const double theta = s.theta_e_rad * trueaxis::sim::kArcsecPerRad;
    theta_max_arcsec = std::max(theta_max_arcsec, theta);
    d_e_max_mm = std::max(d_e_max_mm, s.d_e_mm);
    tip_max_mm = std::max(tip_max_mm, std::hypot(tip.x(), tip.y()));
    json += std::string(i > 0 ? "," : "") + "\n    { \"phi_deg\": " + num(phi) + ", \"theta_e_arcsec\": " +
            num(theta) + ", \"d_e_mm\": " + num(s.d_e_mm) + ", \"tool_tip_error_mm\": [" + num(tip.x()) + ", " +
            num(tip.y()) + ", " + num(tip.z()) + "] }";
  }
  json += "\n  ],\n  \"theta_e_max_arcsec\": " + num(theta_max_arcsec) + ", \"d_e_max_mm\": " + num(d_e_max_mm) +
          ", \"evaluations\": 0,\n  \"tool_length_mm\": " + num(tool_length_mm) +
          ", \"axial_error_mm\": " + num(spindle.axial_error_mm()) + "\n}\n";
  return json;
}

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-measure-spindle", kHelp)) return 0;
  std::string out_path, machine_path, truth_path, noise = "on";
  double seed = 1, revolutions = 3, step_deg = 5, form_nm = 50, tool_length_mm = 250, samples_per_rev = 0,
         drift_percent = 1;
  bool step_given = false, drift_given = false, time_sampled = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--time-sampled") {  // the one option without a value
      time_sampled = true;
      continue;
    }
    static const char* const kValued[] = {"--out",      "--machine",       "--truth",         "--noise",
                                          "--seed",     "--revolutions",   "--step-deg",      "--samples-per-rev",
                                          "--form-nm",  "--tool-length",   "--drift-percent"};
    if (std::find_if(std::begin(kValued), std::end(kValued), [&](const char* o) { return arg == o; }) ==
        std::end(kValued)) {
      return fail("bad option '" + arg + "'");
    }
    if (i + 1 >= argc) return fail(arg + " needs a value; " + kUsage);
    const char* value = argv[++i];
    const std::string given = "bad option '" + arg + " " + value + "': ";
    if (arg == "--out") out_path = value;
    else if (arg == "--machine") machine_path = value;
    else if (arg == "--truth") truth_path = value;
    else if (arg == "--noise") {
      noise = value;
      if (noise != "on" && noise != "off") return fail(given + "on or off");
    } else if (arg == "--seed") {
      if (!(number(value, seed) && seed >= 0 && whole(seed) && seed < 9e15)) {
        return fail(given + "a whole number from 0, below 9e15");
      }
    } else if (arg == "--revolutions") {
      if (!(number(value, revolutions) && whole(revolutions) && revolutions >= 1 && revolutions <= 100)) {
        return fail(given + "a whole number of revolutions from 1 to 100");
      }
    } else if (arg == "--step-deg") {
      step_given = true;
      if (!(number(value, step_deg) && step_deg > 0 && splits_revolution(step_deg))) {
        return fail(given + "a step S with 360 / S a whole number from 8 to 3600 (finer: --samples-per-rev)");
      }
    } else if (arg == "--samples-per-rev") {
      if (!(number(value, samples_per_rev) && whole(samples_per_rev) &&
            samples_per_rev >= trueaxis::sim::kMinSamplesPerRevolution &&
            samples_per_rev <= trueaxis::sim::kMaxSamplesPerRevolution)) {
        return fail(given + "a whole number of samples per revolution from 8 to 4096");
      }
    } else if (arg == "--drift-percent") {
      drift_given = true;
      if (!(number(value, drift_percent) && drift_percent >= 0 && drift_percent <= 10)) {
        return fail(given + "a speed drift in percent from 0 to 10");
      }
    } else if (arg == "--form-nm") {
      if (!(number(value, form_nm) && form_nm >= 0 && form_nm <= 1000)) {
        return fail(given + "an RMS in nm from 0 to 1000");
      }
    } else if (arg == "--tool-length") {
      if (!(number(value, tool_length_mm) && tool_length_mm > 0 && tool_length_mm <= 1000)) {
        return fail(given + "a length in mm above 0, at most 1000");
      }
    }
  }
  if (out_path.empty() || machine_path.empty()) return fail(kUsage);
  if (step_given && samples_per_rev > 0) {
    return fail("--step-deg and --samples-per-rev are exclusive: the one sets the other (N = 360 / S)");
  }
  if (step_given && time_sampled) {
    return fail("--step-deg does not go with --time-sampled: its angles are not stepped (--samples-per-rev N sets "
                "the nominal rate)");
  }
  if (drift_given && !time_sampled) return fail("--drift-percent goes with --time-sampled only");

  using namespace trueaxis::sim;
  const VirtualSpindle spindle(realistic_spindle());
  AnalyserConfig ac;
  ac.revolutions = static_cast<int>(revolutions);
  ac.step_deg = step_deg;
  ac.samples_per_revolution = static_cast<int>(samples_per_rev);
  if (time_sampled) {
    if (ac.samples_per_revolution == 0) ac.samples_per_revolution = kTimeSampledDefaultSamples;
    ac.time_sampled = true;
    ac.speed_drift = drift_percent / 100.0;
  }
  ac.form_seed = static_cast<std::uint64_t>(seed);
  ac.noise_sigma_mm = noise == "on" ? 15e-6 : 0.0;
  ac.form_rms_mm = noise == "on" ? form_nm * 1e-6 : 0.0;
  const VirtualAnalyser analyser(ac);
  SimRng rng(static_cast<std::uint64_t>(seed));
  const std::vector<trueaxis::core::SpindleSample> samples = measure_spindle(analyser, spindle, rng);

  // How it was sampled; with --step-deg (or by default) the words of before.
  char sampling[240];
  if (time_sampled) {
    std::snprintf(sampling, sizeof sampling,
                  "%d revolutions time-sampled at %d samples per nominal revolution (%zu instants), speed rising "
                  "linearly by %g%% (%g to %g of nominal), the first at %.6f deg",
                  ac.revolutions, ac.samples_per_revolution, samples.size() / 2, drift_percent,
                  1.0 - ac.speed_drift / 2.0, 1.0 + ac.speed_drift / 2.0, samples.empty() ? 0.0 : samples[0].phi_deg);
  } else if (ac.samples_per_revolution > 0) {
    std::snprintf(sampling, sizeof sampling,
                  "%d revolutions at %d encoder-synchronous samples per revolution (every %.10g deg)", ac.revolutions,
                  ac.samples_per_revolution, 360.0 / ac.samples_per_revolution);
  } else {
    std::snprintf(sampling, sizeof sampling, "%d revolutions at %g deg", ac.revolutions, step_deg);
  }
  char about[400];
  std::snprintf(about, sizeof about, "seed %.0f, %s, noise %s (15 nm), form %g nm RMS", seed, sampling, noise.c_str(),
                1e6 * ac.form_rms_mm);
  const bool exact_phi = time_sampled || ac.samples_per_revolution > 0;
  double theta_max = 0, d_e_max = 0, tip_max = 0;
  const std::string truth = truth_text(spindle, tool_length_mm, theta_max, d_e_max, tip_max);
  if (!write_text_file(out_path, samples_text(samples, about, exact_phi))) return fail(out_path + ": cannot be written");
  if (!write_text_file(machine_path, machine_text(spindle, tool_length_mm))) return fail(machine_path + ": cannot be written");
  if (!truth_path.empty() && !write_text_file(truth_path, truth)) return fail(truth_path + ": cannot be written");
  std::printf("measured %zu ball centres (%s) into %s\n", samples.size(), about, out_path.c_str());
  std::printf("truth: theta_e up to %.3f arcsec, d_e up to %.3f um, tool tip at %g mm up to %.3f um across the axis\n",
              theta_max, 1000.0 * d_e_max, tool_length_mm, 1000.0 * tip_max);
  return 0;
}
