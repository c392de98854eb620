// The rigidity flow (docs/INTERFACE.md "M3 rigidity"): samples -> session 9830/9831
// -> build 9832 (stored with --store) -> per pose 9834 -> OUT.json.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/status.hpp"

#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/services.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_rigidity.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

namespace var = macros::var;

namespace {

constexpr std::uint16_t kClear = macros::rigidity::kMacroSessionClear;
constexpr std::uint16_t kAdd = macros::rigidity::kMacroSessionAdd;
constexpr std::uint16_t kBuild = macros::rigidity::kMacroBuild;
constexpr std::uint16_t kPose = macros::rigidity::kMacroPose;
constexpr std::uint16_t kReals = macros::rigidity::kMacroTableReals;

}  // namespace

FlowResult calibrate_rigidity(VariableClient& client, const CalibrateOptions& options) {
  FlowResult r;
  const std::vector<CsvColumn> columns = {{"a_deg"}, {"c_deg"}, {"x_mm"}, {"y_mm"}, {"z_mm"}};
  // First pass: every row checked, and the poses as the module forms them
  // (A within kPoseAToleranceDeg), to name a pose the module refuses.
  struct Pose {
    double a_deg;
    int samples;
    int line_beyond;  // the line of its sample kMaxPoseSamples + 1, 0 while none
  };
  std::vector<Pose> pose_rows;
  std::uint64_t rows = 0;
  {
    CsvReader reader(options.in_path, columns);
    CsvRow row;
    Progress progress(options.in_path, "bytes read");
    while (reader.next(row)) {
      ++rows;
      progress.update(reader.bytes_read(), reader.size_bytes());
      auto pose = std::find_if(pose_rows.begin(), pose_rows.end(), [&](const Pose& p) {
        return std::fabs(p.a_deg - row.numbers[0]) <= core::kPoseAToleranceDeg;
      });
      if (pose == pose_rows.end()) {
        if (pose_rows.size() > core::kMaxAPoses) continue;  // the module refuses too_many_poses
        pose_rows.push_back({row.numbers[0], 0, 0});
        pose = pose_rows.end() - 1;
      }
      if (++pose->samples == macros::rigidity::kMaxPoseSamples + 1) pose->line_beyond = row.line;
    }
    if (!reader.error().empty()) {
      r.error = reader.error();
      return r;
    }
  }

  r.stage = "opening the session (macro 9830): nothing sent yet";
  // The module numbers the poses in A order (its builder's): a gate's refusal names a pose by its A.
  {
    std::vector<double> as;
    for (const Pose& p : pose_rows) as.push_back(p.a_deg);
    std::sort(as.begin(), as.end());
    for (std::size_t q = 0; q < as.size(); ++q) {
      char a_name[32];
      std::snprintf(a_name, sizeof a_name, "a%g", as[q]);
      r.check_items[static_cast<int>(q + 1)] = {a_name, "a_deg", as[q]};
    }
  }
  if (!run_or_fail(client, kClear, "", r)) return r;
  CsvReader reader(options.in_path, columns);
  CsvRow row;
  Progress progress(options.in_path, "samples sent");
  std::uint64_t sent = 0;
  while (reader.next(row)) {
    const std::string where = options.in_path + ":" + std::to_string(row.line);
    r.stage = "streaming sample " + std::to_string(sent + 1) + " of " + std::to_string(rows) + " of " + where;
    const double ac[3] = {row.numbers[0], 0.0, row.numbers[1]};
    const double xyz[3] = {row.numbers[2], row.numbers[3], row.numbers[4]};
    if (!client.write(var::kArgA, 3, ac) || !client.write(var::kArgX, 3, xyz)) {
      r.error = refused_sample(client, where, r);
      return r;
    }
    if (!run_or_fail(client, kAdd, where, r)) {
      if (module_refused(r, static_cast<int>(core::Status::kSessionFull))) {
        r.error += ": the session holds " + std::to_string(macros::rigidity::kSessionCapacity) + " samples";
      }
      return r;
    }
    progress.update(++sent, rows);
  }

  // Built without storing: the command stores only after the JSON and the
  // report are made (store_rigidity), so a later failure stores nothing.
  r.stage = "running the build (macro 9832, R = 0), every sample sent";
  if (!hand_time(client, options.log_time, r)) return r;  // the calibration's entry in the measuring log
  if (!transport(client, client.write_one(var::kArgR, 0.0), r)) return r;
  if (!run_or_fail(client, kBuild, "", r)) {
    // The module names no pose: the first in A order beyond its capacity (the builder's order).
    std::sort(pose_rows.begin(), pose_rows.end(), [](const Pose& a, const Pose& b) { return a.a_deg < b.a_deg; });
    const auto full = std::find_if(pose_rows.begin(), pose_rows.end(), [](const Pose& p) { return p.line_beyond != 0; });
    if (module_refused(r, static_cast<int>(core::Status::kTooManyPoints)) && full != pose_rows.end()) {
      char what[160];
      std::snprintf(what, sizeof what, ": the pose at A = %g deg has %d samples, at most %d (its sample %d)",
                    full->a_deg, full->samples, static_cast<int>(macros::rigidity::kMaxPoseSamples),
                    static_cast<int>(macros::rigidity::kMaxPoseSamples) + 1);
      r.error = options.in_path + ":" + std::to_string(full->line_beyond) + ": " + r.error + what;
    }
    return r;
  }

  double summary[12];
  if (!transport(client, client.read(var::kRigidityPoses, 12, summary), r)) return r;
  const int poses = static_cast<int>(summary[0]);
  double reference_a_deg = 0.0;
  double worst[3] = {-1.0, 0.0, 0.0};  // rigidity, its sigma, A (arcsec, arcsec, deg)
  std::string pose_json;
  std::string comp;
  for (int q = 1; q <= poses; ++q) {
    r.stage = "running the report query (macro 9834, pose " + std::to_string(q) + " of " + std::to_string(poses) + ")";
    const double args[2] = {static_cast<double>(q), 0.0};  // Q = pose, R = 0: the table just built
    if (!transport(client, client.write(var::kArgQ, 2, args), r)) return r;
    if (!run_or_fail(client, kPose, "", r)) return r;
    double p[21];  // #100..#120 (rigidity_map.hpp kPoseOutputs)
    if (!transport(client, client.read(var::kPoseA, 21, p), r)) return r;
    if (std::fabs(p[0]) <= core::kPoseAToleranceDeg) reference_a_deg = p[0];
    char a_name[32];  // the check names pose q by its A (calibrate.hpp, check_items)
    std::snprintf(a_name, sizeof a_name, "a%g", p[0]);
    r.check_items[q] = {a_name, "a_deg", p[0]};
    if (p[7] > worst[0]) {
      worst[0] = p[7];
      worst[1] = p[8];
      worst[2] = p[0];
    }
    // LinuxCNC's joint compensation, COMP_FILE_TYPE 1: "nominal forward-trim
    // reverse-trim" a line, ascending (the poses come in A order), the motor
    // commanded at A + trim. The cradle turns e (arcsec) more than commanded,
    // so the trim is -e, the same both ways (M3 sees no reversal error).
    char line[96];
    std::snprintf(line, sizeof line, "%.6f %.9f %.9f\n", p[0], -p[9] / 3600.0, -p[9] / 3600.0);
    comp += line;
    pose_json += q > 1 ? ",\n" : "\n";
    pose_json += "    { \"a_deg\": " + json_number(p[0]) + ", \"rotation_vector_arcsec\": " + json_vec3(p + 1) +
                 ",\n      \"rotation_vector_sigma_arcsec\": " + json_vec3(p + 4) +
                 ", \"rigidity_arcsec\": " + json_number(p[7]) + ", \"rigidity_sigma_arcsec\": " + json_number(p[8]) +
                 ",\n      \"a_positioning_error_arcsec\": " + json_number(p[9]) +
                 ", \"a_positioning_error_sigma_arcsec\": " + json_number(p[18]) + ", \"c_centre_mm\": " +
                 json_vec3(p + 10) + ",\n      \"c_direction\": " + json_vec3(p + 13) +
                 ", \"c_circle_rms_mm\": " + json_number(p[16]) + ", \"c_circle_rms_sigma_mm\": " +
                 json_number(p[19]) + ", \"c_circle_rms_noise_floor_mm\": " + json_number(p[20]) + " }";
  }
  // docs/INTERFACE.md writes the reference A as 0.0; keep that form when it is exactly 0.
  const std::string reference = reference_a_deg == 0.0 ? "0.0" : json_number(reference_a_deg);
  r.linuxcnc_comp = comp;
  r.json = "{\n  \"method\": \"rigidity\",\n  \"reference_a_deg\": " + reference + ",\n" +
           "  \"a_axis\": { \"point_mm\": " + json_vec3(summary + 3) + ", \"direction\": " + json_vec3(summary + 6) +
           " },\n  \"poses\": [" + pose_json + "\n  ]\n}\n";
  // What the module computed beyond docs/INTERFACE.md's OUT.json, for the report only.
  double ball_noise_mm = 0.0;
  if (!transport(client, client.read(var::kRigidityBallNoise, 1, &ball_noise_mm), r)) return r;
  r.report_extras = "{ \"c_to_a_offset_mm\": " + json_number(summary[9]) +
                    ", \"c_to_a_squareness_arcsec\": " + json_number(summary[10]) +
                    ", \"ball_noise_mm\": " + json_number(ball_noise_mm) + " }\n";
  char line[160];
  std::snprintf(line, sizeof line, "rigidity: %d poses, worst rigidity %.2f\" +- %.2f\" (pose A=%g)", poses,
                worst[0], worst[1], worst[2]);
  r.summary = line;
  r.ok = true;
  return r;
}

bool store_rigidity(VariableClient& client, FlowResult& fail) { return store_built(client, kBuild, fail); }

bool rigidity_kins_file(VariableClient& client, bool stored, std::string& file, FlowResult& fail) {
  const std::size_t n = core::kRigidityPoseReals;
  double out[2 + core::kRigidityPoseReals + 1];  // the count, the reference, the reals, the home (#129)
  std::vector<double> header(core::kRigidityHeaderReals);
  std::vector<double> poses;
  std::size_t count = 0;
  std::size_t reference = 0;
  double home = 0.0;
  for (std::size_t q = 0; q == 0 || q <= count; ++q) {
    const double args[2] = {static_cast<double>(q), stored ? 1.0 : 0.0};  // Q, R
    if (!transport(client, client.write(var::kArgQ, 2, args), fail)) return false;
    if (!run_or_fail(client, kReals, "", fail)) return false;
    static_assert(var::kRealsHomeIdentity == var::kRealsPoseCount + 2 + core::kRigidityPoseReals, "#129 follows");
    if (!transport(client, client.read(var::kRealsPoseCount, static_cast<std::uint16_t>(3 + n), out), fail)) {
      return false;
    }
    // The pose count and the reference, whole numbers in range, the same in every part.
    const bool whole = out[0] == std::floor(out[0]) && out[0] >= static_cast<double>(core::kMinAPoses) &&
                       out[0] <= static_cast<double>(core::kMaxAPoses) && out[1] == std::floor(out[1]) &&
                       out[1] >= 1.0 && out[1] <= out[0];
    const double h = out[2 + n];
    const bool home_whole = h == std::floor(h) && h >= 0.0 && h <= var::kMaxHomeIdentity;
    if (!whole || !home_whole ||
        (q > 0 && (out[0] != static_cast<double>(count) || out[1] != static_cast<double>(reference) || h != home))) {
      fail.error = "the module's table (9837) gave an impossible pose count or reference";
      return false;
    }
    if (q == 0) {
      count = static_cast<std::size_t>(out[0]);
      reference = static_cast<std::size_t>(out[1]);
      home = h;
      std::copy(out + 2, out + 2 + core::kRigidityHeaderReals, header.begin());
    } else {
      poses.insert(poses.end(), out + 2, out + 2 + n);
    }
  }
  std::uint8_t record[core::kRigidityTableMaxBytes];
  const std::size_t length =
      reference >= 1 ? core::encode_rigidity_reals(count, reference - 1, static_cast<std::uint16_t>(home), header.data(),
                                                   poses.data(), record, sizeof record)
                     : 0;
  core::RigidityTable check;
  if (length == 0 || core::decode_rigidity_table(record, length, check) != core::Status::kOk) {
    fail.error = "the module's table (9837) does not form a valid rigidity record";
    return false;
  }
  std::vector<std::uint8_t> bytes(length + macros::kRecordFileOverhead);
  const std::size_t size = macros::encode_record_file(macros::RigidityTableRecord::kRecord.key, record, length,
                                                      bytes.data(), bytes.size());
  file.assign(reinterpret_cast<const char*>(bytes.data()), size);
  return true;
}

// The method's entry in trueaxis-calibrate's table (host_methods.hpp, folded
// from the one list). The files' text follows docs/INTERFACE.md "Calibration
// flows", which is the definition; this is the short form `trueaxis-calibrate
// rigidity --help` prints.
const CalibrateMethod& calibrate_method_rigidity() {
  // clang-format off
  static const CalibrateMethod kMethod{"rigidity", "M3 AC-axis rigidity: a ball on the table measured at several A while C turns",
   "SAMPLES.csv: a_deg,c_deg,x_mm,y_mm,z_mm\n"
   "  a_deg, c_deg       the commanded A and C (deg)\n"
   "  x_mm, y_mm, z_mm   the calibration ball's centre at that pose (mm, machine coordinates)\n"
   "  Rows whose a_deg agree within 1e-6 deg form one A pose, in any order; one pose at A = 0\n"
   "  (the reference); 3..16 poses, each with at least 4 distinct C over an arc of at least\n"
   "  #600 (45 deg by default) and at most 36 samples; at most 512 samples in all.\n"
   "MACHINE.csv: not read.\n",
   calibrate_rigidity, store_rigidity, "rigidity", rigidity_kins_file, macros::rigidity::kMacroPose, 1.0};
  // clang-format on
  return kMethod;
}

}  // namespace trueaxis::sim
