// The spindle flow (docs/INTERFACE.md "M4 spindle"): analyser samples -> session
// 9840/9841, MACHINE's lengths -> identification 9842 (stored with --store),
// the parameters 9845 and one revolution of 9844 (R = 0: the identification
// just made) -> OUT.json.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/spindle/spindle_macros.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_spindle.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

namespace var = macros::var;

namespace {

constexpr std::uint16_t kClear = macros::spindle::kMacroSessionClear;
constexpr std::uint16_t kAdd = macros::spindle::kMacroSessionAdd;
constexpr std::uint16_t kBuild = macros::spindle::kMacroBuild;
constexpr std::uint16_t kReport = macros::spindle::kMacroReport;
constexpr std::uint16_t kModel = macros::spindle::kMacroModel;

// MACHINE's names (docs/INTERFACE.md), in the order the flow keeps their values.
enum Name : std::size_t { kBearingSpacing, kGauge, kBall1, kBall2, kToolLength, kNames };
constexpr const char* kNameText[kNames] = {"bearing_spacing_mm", "gauge_from_upper_bearing_mm", "ball_1_mm",
                                           "ball_2_mm", "tool_length_mm"};

struct Machine {
  double value[kNames] = {};
  int line[kNames] = {};  // 0: not given
};

// An empty string when MACHINE's rows give each name once, else the one line saying what is wrong.
std::string read_machine(const std::string& path, Machine& m) {
  const CsvResult csv = read_csv(path, {{"name", false}, {"value"}});
  if (!csv.ok) return csv.error;
  for (const CsvRow& row : csv.rows) {
    const std::string where = path + ":" + std::to_string(row.line) + ": ";
    const auto* const known = std::find(std::begin(kNameText), std::end(kNameText), row.texts[0]);
    if (known == std::end(kNameText)) {
      std::string names;
      for (const char* n : kNameText) names += (names.empty() ? "" : ", ") + std::string(n);
      return where + "unknown name '" + row.texts[0] + "' (MACHINE names: " + names + ")";
    }
    const auto k = static_cast<std::size_t>(known - std::begin(kNameText));
    if (m.line[k] != 0) {
      return where + "'" + row.texts[0] + "' is given twice (first at line " + std::to_string(m.line[k]) + ")";
    }
    m.line[k] = row.line;
    m.value[k] = row.numbers[1];
  }
  for (std::size_t k = 0; k < kNames; ++k) {
    if (m.line[k] == 0) return path + ": no row for '" + kNameText[k] + "'";
  }
  // The one length the module never sees: checked here.
  if (!(m.value[kBearingSpacing] > 0.0)) {
    return path + ":" + std::to_string(m.line[kBearingSpacing]) + ": bearing_spacing_mm must be more than 0";
  }
  return "";
}

std::string json_bool(double flag) { return flag != 0.0 ? "true" : "false"; }

}  // namespace

FlowResult calibrate_spindle(VariableClient& client, const CalibrateOptions& options) {
  FlowResult r;
  if (options.machine_path.empty()) {
    r.error =
        "spindle needs --machine MACHINE.csv (name,value: bearing_spacing_mm, gauge_from_upper_bearing_mm, "
        "ball_1_mm, ball_2_mm, tool_length_mm)";
    return r;
  }
  Machine m;
  r.error = read_machine(options.machine_path, m);
  if (!r.error.empty()) return r;
  const std::vector<CsvColumn> columns = {{"phi_deg"}, {"ball"}, {"x_mm"}, {"y_mm"}, {"z_mm"}};
  // First pass: every row checked; each ball's mean centre, to tell lengths
  // in other units from a fit that failed for another reason.
  std::uint64_t rows = 0;
  double sum[2][3] = {};
  std::uint64_t count[2] = {};
  {
    CsvReader reader(options.in_path, columns);
    CsvRow row;
    Progress progress(options.in_path, "bytes read");
    while (reader.next(row)) {
      if (row.numbers[1] != 1.0 && row.numbers[1] != 2.0) {
        r.error = options.in_path + ":" + std::to_string(row.line) + ": ball must be 1 or 2, not '" + row.texts[1] + "'";
        return r;
      }
      const int k = row.numbers[1] == 1.0 ? 0 : 1;
      for (std::size_t i = 0; i < 3; ++i) sum[k][i] += row.numbers[2 + i];
      ++count[k];
      ++rows;
      progress.update(reader.bytes_read(), reader.size_bytes());
    }
    if (!reader.error().empty()) {
      r.error = reader.error();
      return r;
    }
  }

  r.stage = "opening the session (macro 9840): nothing sent yet";
  if (!run_or_fail(client, kClear, "", r)) return r;
  {
    CsvReader reader(options.in_path, columns);
    CsvRow row;
    Progress progress(options.in_path, "samples sent");
    std::uint64_t sent = 0;
    while (reader.next(row)) {
      const std::string where = options.in_path + ":" + std::to_string(row.line);
      r.stage = "streaming sample " + std::to_string(sent + 1) + " of " + std::to_string(rows) + " of " + where;
      const double st[2] = {row.numbers[0], row.numbers[1]};  // S = #19, T = #20
      const double xyz[3] = {row.numbers[2], row.numbers[3], row.numbers[4]};
      if (!client.write(var::kArgS, 2, st) || !client.write(var::kArgX, 3, xyz)) {
        r.error = refused_sample(client, where, r);
        return r;
      }
      if (!run_or_fail(client, kAdd, where, r)) {
        if (module_refused(r, static_cast<int>(core::Status::kSessionFull))) {
          r.error += ": ball " + row.texts[1] + "'s angle bin holds " + std::to_string(core::kMaxBinCount) +
                     " samples already, the most it holds";
        }
        return r;
      }
      progress.update(++sent, rows);
    }
  }

  // Identified without storing: the command stores only after the JSON and the
  // report are made (store_spindle), so a later failure stores nothing.
  r.stage = "running the build (macro 9842, R = 0), every sample sent";
  r.build_arguments = {{var::kArgD, m.value[kGauge]}, {var::kArgU, m.value[kBall1]}, {var::kArgV, m.value[kBall2]}};
  bool written = true;
  for (const MacroArgument& a : r.build_arguments) written = written && client.write_one(a.number, a.value);
  if (!hand_time(client, options.log_time, r)) return r;  // the calibration's entry in the measuring log
  if (!transport(client, written && client.write_one(var::kArgR, 0.0), r)) return r;
  if (!run_or_fail(client, kBuild, "", r)) {
    if (module_refused(r, static_cast<int>(core::Status::kMissingGroup))) {
      r.error += ": " + options.in_path + " has no row for ball " + (count[0] == 0 ? "1" : "2");
      return r;
    }
    // The balls' mean centres lie ball_2_mm - ball_1_mm apart along the axis:
    // a distance far from it says which file's lengths are in other units.
    double d2 = 0.0;
    for (int i = 0; i < 3 && count[0] > 0 && count[1] > 0; ++i) {
      const double d = sum[1][i] / static_cast<double>(count[1]) - sum[0][i] / static_cast<double>(count[0]);
      d2 += d * d;
    }
    const double apart_mm = std::sqrt(d2);
    const double machine_mm = m.value[kBall2] - m.value[kBall1];
    const bool units = machine_mm > 0.0 && apart_mm > 0.0 && (apart_mm / machine_mm > 10.0 || machine_mm / apart_mm > 10.0);
    if (units || module_refused(r, static_cast<int>(macros::spindle::kBallSpacingImplausible))) {
      char why[300];
      std::snprintf(why, sizeof why, " (the balls' centres in %s lie %.6g mm apart, %s's ball_2_mm - ball_1_mm is %.6g: %s)",
                    options.in_path.c_str(), apart_mm, options.machine_path.c_str(), machine_mm,
                    units ? "are the lengths of one file in metres, or in other units than mm?"
                          : "is a ball distance typed wrong?");
      r.error += why;
      return r;
    }
    if (module_refused(r, static_cast<int>(macros::spindle::kBallsTooClose))) {
      char why[400];
      std::snprintf(why, sizeof why, " -- %s:%d and :%d: ball_2_mm %g - ball_1_mm %g = %g mm, and the balls' centres "
                    "in %s lie %.6g apart: both files in metres? trueaxis takes mm",
                    options.machine_path.c_str(), m.line[kBall2], m.line[kBall1], m.value[kBall2], m.value[kBall1],
                    machine_mm, options.in_path.c_str(), apart_mm);
      r.error += why;
      return r;
    }
    // D, U and V are MACHINE's lengths: name the file when the module refuses one.
    if (module_refused(r, static_cast<int>(core::Status::kArgumentOutOfRange))) {
      r.error =
          options.machine_path + ": " + r.error + " (gauge_from_upper_bearing_mm > 0, 0 <= ball_1_mm < ball_2_mm)";
    }
    return r;
  }
  // What no data of this run tests (docs/METHODS.md M4): the analyser sees the
  // balls, not the bearings, the gauge line or the tool.
  const auto given = [&](int k, const char* use) {
    char text[200];
    std::snprintf(text, sizeof text, "%s %g (%s:%d; %s)", kNameText[k], m.value[k], options.machine_path.c_str(),
                  m.line[k], use);
    r.as_given.push_back(text);
  };
  given(kGauge, "places O1, the ideal axis' point, on the measured axis");
  given(kToolLength, "where the tool-tip error is given");
  given(kBearingSpacing, "shown in the report only");
  char clause[200];
  std::snprintf(clause, sizeof clause, "gauge_from_upper_bearing_mm %g, tool_length_mm %g, bearing_spacing_mm %g",
                m.value[kGauge], m.value[kToolLength], m.value[kBearingSpacing]);
  r.as_given_summary = clause;
  r.stage = "running the report query (macros 9845, 9844)";
  double build[5];  // evaluations, noise sigma, synchronous RMS, noise from repeats, samples
  if (!transport(client, client.read(var::kSpindleEvaluations, 5, build), r)) return r;

  std::string parameters;
  double model[12] = {};  // 9845's outputs, the last parameter's; the fit's figures are every parameter's
  for (int q = 1; q <= core::kSpindleParams; ++q) {
    const double qr[2] = {static_cast<double>(q), 0.0};  // Q = parameter, R = 0: the identification just made
    if (!transport(client, client.write(var::kArgQ, 2, qr), r) || !run_or_fail(client, kModel, "", r) ||
        !transport(client, client.read(var::kSpindleParamValue, 12, model), r)) {
      return r;
    }
    parameters += q > 1 ? ",\n" : "\n";
    parameters += "    \"" + std::string(macros::spindle::kParameterNames[q - 1]) +
                  "\": { \"value\": " + json_number(model[0]) + ", \"sigma\": " + json_number(model[1]) + " }";
  }

  const double tool_mm = m.value[kToolLength];
  const std::string tool_where = options.machine_path + ":" + std::to_string(m.line[kToolLength]);
  const int steps = static_cast<int>(360.0 / kSpindleStepDeg);
  std::string per_angle;
  double theta_max = 0.0;
  double theta_max_sigma = 0.0;
  double theta_max_phi = 0.0;
  double d_e_max = 0.0;
  double c[16] = {};  // 9844's outputs: the mean tip error is the same at every angle
  for (int i = 0; i < steps; ++i) {
    const double phi = kSpindleStepDeg * i;
    const double rs[2] = {0.0, phi};  // R = 0: the identification just made, S
    if (!transport(client, client.write(var::kArgR, 2, rs), r) ||
        !transport(client, client.write_one(var::kArgZ, tool_mm), r) || !run_or_fail(client, kReport, tool_where, r) ||
        !transport(client, client.read(var::kSpindleThetaE, 16, c), r)) {
      return r;
    }
    if (i == 0 || c[0] > theta_max) {
      theta_max = c[0];
      theta_max_sigma = c[5];
      theta_max_phi = phi;
    }
    d_e_max = std::max(d_e_max, c[1]);
    per_angle += i > 0 ? ",\n" : "\n";
    per_angle += "    { \"phi_deg\": " + json_number(phi) + ", \"theta_e_arcsec\": " + json_number(c[0]) +
                 ", \"d_e_mm\": " + json_number(c[1]) + ", \"tool_tip_error_mm\": " + json_vec3(c + 2) +
                 ",\n      \"theta_e_sigma_arcsec\": " + json_number(c[5]) +
                 ", \"d_e_sigma_mm\": " + json_number(c[6]) + ", \"tool_tip_error_sigma_mm\": " + json_vec3(c + 7) +
                 " }";
  }

  r.json = "{\n  \"method\": \"spindle\",\n  \"parameters\": {" + parameters + "\n  },\n  \"per_angle\": [" +
           per_angle + "\n  ],\n  \"theta_e_max_arcsec\": " + json_number(theta_max) +
           ", \"d_e_max_mm\": " + json_number(d_e_max) + ", \"evaluations\": " + json_number(build[0]) +
           ",\n  \"tool_length_mm\": " + json_number(tool_mm) + ", \"mean_tool_tip_error_mm\": " + json_vec3(c + 10) +
           ", \"mean_tool_tip_error_sigma_mm\": " + json_vec3(c + 13) +
           ",\n  \"fit\": { \"samples\": " + json_number(build[4]) + ", \"noise_sigma_mm\": " + json_number(build[1]) +
           ", \"noise_from_repeats\": " + json_bool(build[3]) + ", \"synchronous_rms_mm\": " + json_number(build[2]) +
           ", \"rms_mm\": " + json_number(model[2]) + " }\n}\n";
  // What the module holds beyond OUT.json, and MACHINE's informative length, for the report only.
  r.report_extras = "{ \"model_gauge_mm\": " + json_number(model[8]) + ", \"model_ball_mm\": [" +
                    json_number(model[9]) + ", " + json_number(model[10]) +
                    "], \"eigenvalue_ratio\": " + json_number(model[11]) +
                    ", \"bearing_spacing_mm\": " + json_number(m.value[kBearingSpacing]) + " }\n";
  char line[200];
  std::snprintf(line, sizeof line,
                "spindle: %.0f samples, worst theta_e %.4f\" +- %.2g\" (phi=%g), d_e up to %.2f um", build[4],
                theta_max, theta_max_sigma, theta_max_phi, 1000.0 * d_e_max);
  r.summary = line;
  r.ok = true;
  return r;
}

bool spindle_kins_file(VariableClient& client, bool stored, std::string& file, FlowResult& fail) {
  std::vector<std::uint8_t> record;
  for (const double q : {0.0, 1.0}) {
    const double args[2] = {q, stored ? 1.0 : 0.0};  // Q, R
    if (!transport(client, client.write(var::kArgQ, 2, args), fail)) return false;
    if (!run_or_fail(client, 9847, "", fail)) return false;
    // Modbus reads at most 125 registers (31 variables) a request.
    double out[2 + macros::spindle::kWordsPerPart];
    for (std::uint16_t at = 0; at < 2 + macros::spindle::kWordsPerPart; at += 25) {
      const auto n = static_cast<std::uint16_t>(std::min<std::size_t>(25, 2 + macros::spindle::kWordsPerPart - at));
      if (!transport(client, client.read(static_cast<std::uint16_t>(var::kSpindleWordsBytes + at), n, out + at), fail)) {
        return false;
      }
    }
    const double expected_words = q == 0.0 ? 98.0 : 30.0;
    if (out[0] != static_cast<double>(core::kSpindleModelBytes) || out[1] != expected_words) {
      fail.error = "the module's model (9847) gave an unexpected length";
      return false;
    }
    for (std::size_t k = 0; k < static_cast<std::size_t>(expected_words); ++k) {
      const double w = out[2 + k];
      if (!(w >= 0.0 && w <= 4294967295.0 && w == std::floor(w))) {
        fail.error = "the module's model (9847) gave a word that is not one";
        return false;
      }
      std::uint8_t b[4];
      core::put_u32(b, static_cast<std::uint32_t>(w));
      record.insert(record.end(), b, b + 4);
    }
  }
  core::SpindleModel check;
  if (record.size() != core::kSpindleModelBytes ||
      core::decode_spindle_model(record.data(), record.size(), check) != core::Status::kOk) {
    fail.error = "the module's model (9847) does not form a valid spindle record";
    return false;
  }
  std::vector<std::uint8_t> bytes(record.size() + macros::kRecordFileOverhead);
  const std::size_t size = macros::encode_record_file(macros::spindle::ModelRecord::kRecord.key, record.data(),
                                                      record.size(), bytes.data(), bytes.size());
  file.assign(reinterpret_cast<const char*>(bytes.data()), size);
  return true;
}

bool store_spindle(VariableClient& client, FlowResult& result) {
  return store_built(client, kBuild, result, result.build_arguments);
}

// The method's entry in trueaxis-calibrate's table (host_methods.hpp, folded
// from the one list). The files' text follows docs/INTERFACE.md "Calibration
// flows", which is the definition; this is the short form `trueaxis-calibrate
// spindle --help` prints.
const CalibrateMethod& calibrate_method_spindle() {
  // clang-format off
  static const CalibrateMethod kMethod{"spindle", "M4 spindle tool axis: a spindle analyser's two balls over whole revolutions",
   "SAMPLES.csv: phi_deg,ball,x_mm,y_mm,z_mm\n"
   "  phi_deg            the spindle angle from M19's zero, growing in the M03 sense (deg; may pass 360)\n"
   "  ball               1 (nearer the spindle) or 2\n"
   "  x_mm, y_mm, z_mm   the ball's centre (mm, analyser frame)\n"
   "  Per ball at least 8 distinct angles, at most 360, no gap wider than #800 (45 deg by default).\n"
   "MACHINE.csv (--machine, required): name,value rows, each of these names once (mm):\n"
   "  bearing_spacing_mm           upper to lower bearing plane (checked, shown in the report)\n"
   "  gauge_from_upper_bearing_mm  O1, the upper bearing seat's centre, to the gauge line\n"
   "  ball_1_mm, ball_2_mm         the balls' centres below the gauge line, 0 <= ball 1 < ball 2\n"
   "  tool_length_mm               the tool tip below the gauge line (where the tip error is given)\n",
   calibrate_spindle, store_spindle, "spindle", spindle_kins_file, macros::spindle::kMacroModel, 1.0};
  // clang-format on
  return kMethod;
}

}  // namespace trueaxis::sim
