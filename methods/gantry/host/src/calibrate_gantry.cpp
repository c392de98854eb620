// The gantry flow (docs/INTERFACE.md "M2 gantry"): samples grouped by name -> session
// 9820/9821, MACHINE rows -> 9822, frames 9823 (stored with --store), global
// 9824 and per sub-machine 9826 -> OUT.json.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_gantry.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

namespace var = macros::var;
using macros::gantry::GroupKind;

namespace {

constexpr std::uint16_t kClear = macros::gantry::kMacroSessionClear;
constexpr std::uint16_t kAdd = macros::gantry::kMacroSessionAdd;
constexpr std::uint16_t kSubMachine = macros::gantry::kMacroSubMachine;
constexpr std::uint16_t kBuild = macros::gantry::kMacroBuild;
constexpr std::uint16_t kGlobal = macros::gantry::kMacroGlobal;
constexpr std::uint16_t kSub = macros::gantry::kMacroSubReport;

// A group's name as (T, Q, D) (gantry_map.hpp convention 3) and its order in
// the stream: the machine's groups first, then each sub-machine's.
struct Group {
  int t = 0;
  GroupKind q = GroupKind::kBed;
  int d = 0;
  int order() const { return (t * 16 + static_cast<int>(q)) * 16 + d; }
};

// A whole number in lo..hi written in decimal digits only, without a leading zero.
bool whole(const std::string& s, int lo, int hi, int& out) {
  if (s.empty() || s.size() > 3 || s[0] == '0' || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  out = std::atoi(s.c_str());
  return out >= lo && out <= hi;
}

// "bed", "side_1", "side_2", "gantry_K", "spN_x_K", "spN_y_K", "spN_z_K",
// "spN_c", "spN_a"; an empty string on success, else what is wrong.
std::string parse_group(const std::string& name, Group& g) {
  const int passes = macros::gantry::kMaxPasses;
  const std::string pass_range = "1.." + std::to_string(passes);
  if (name == "bed") return g = {0, GroupKind::kBed, 0}, "";
  if (name == "side_1") return g = {0, GroupKind::kSide1, 0}, "";
  if (name == "side_2") return g = {0, GroupKind::kSide2, 0}, "";
  if (name.rfind("gantry_", 0) == 0) {
    if (!whole(name.substr(7), 1, passes, g.d)) return "group '" + name + "': the pass K must be " + pass_range;
    g.t = 0;
    g.q = GroupKind::kGantryPass;
    return "";
  }
  const std::size_t us = name.find('_');
  if (name.rfind("sp", 0) != 0 || us == std::string::npos) return "unknown group '" + name + "'";
  if (!whole(name.substr(2, us - 2), 1, 8, g.t)) return "group '" + name + "': the sub-machine N must be 1..8";
  const std::string rest = name.substr(us + 1);
  if (rest == "c") return g.q = GroupKind::kCCircle, g.d = 0, "";
  if (rest == "a") return g.q = GroupKind::kACircle, g.d = 0, "";
  if (rest.size() >= 3 && rest[1] == '_' && (rest[0] == 'x' || rest[0] == 'y' || rest[0] == 'z')) {
    g.q = static_cast<GroupKind>(static_cast<int>(GroupKind::kXPass) + (rest[0] - 'x'));
    if (!whole(rest.substr(2), 1, passes, g.d)) return "group '" + name + "': the pass K must be " + pass_range;
    return "";
  }
  return "unknown group '" + name + "'";
}

// A group's name as SAMPLES writes it.
std::string group_name(const Group& g) {
  const std::string k = std::to_string(g.d);
  const std::string n = "sp" + std::to_string(g.t) + "_";
  switch (g.q) {
    case GroupKind::kBed: return "bed";
    case GroupKind::kSide1: return "side_1";
    case GroupKind::kSide2: return "side_2";
    case GroupKind::kGantryPass: return "gantry_" + k;
    case GroupKind::kXPass: return n + "x_" + k;
    case GroupKind::kYPass: return n + "y_" + k;
    case GroupKind::kZPass: return n + "z_" + k;
    case GroupKind::kCCircle: return n + "c";
    default: return n + "a";
  }
}

std::size_t capacity_of(GroupKind q) {
  if (q == GroupKind::kBed || q == GroupKind::kSide1 || q == GroupKind::kSide2) return macros::gantry::kMaxPlanePoints;
  if (q == GroupKind::kCCircle || q == GroupKind::kACircle) return macros::gantry::kMaxCirclePoints;
  return macros::gantry::kMaxPassPoints;
}

// The group the module found missing (it names none): the first absent in the
// order it fits them (core/gantry_frames.hpp): bed, side_1, side_2, the gantry's
// passes 1..the last given, then each sub-machine in id order: its x, y, z passes
// (1..the last given of each axis), its C circle, its A circle; before all, at
// least one sub-machine.
std::string first_missing_group(const std::vector<Group>& sent, const std::string& file) {
  const auto has = [&](int t, GroupKind q, int d) {
    return std::any_of(sent.begin(), sent.end(), [&](const Group& g) { return g.t == t && g.q == q && g.d == d; });
  };
  const auto last_pass = [&](int t, GroupKind q) {
    int last = 0;
    for (const Group& g : sent) {
      if (g.t == t && g.q == q) last = std::max(last, g.d);
    }
    return last;
  };
  if (std::none_of(sent.begin(), sent.end(), [](const Group& g) { return g.t > 0; })) {
    return file + " measures no sub-machine (no row of a group spN_...)";
  }
  std::vector<Group> needed = {{0, GroupKind::kBed, 0}, {0, GroupKind::kSide1, 0}, {0, GroupKind::kSide2, 0}};
  for (int k = 1; k <= std::max(1, last_pass(0, GroupKind::kGantryPass)); ++k) needed.push_back({0, GroupKind::kGantryPass, k});
  for (int t = 1; t <= 8; ++t) {
    if (std::none_of(sent.begin(), sent.end(), [t](const Group& g) { return g.t == t; })) continue;
    for (const GroupKind q : {GroupKind::kXPass, GroupKind::kYPass, GroupKind::kZPass}) {
      for (int k = 1; k <= std::max(1, last_pass(t, q)); ++k) needed.push_back({t, q, k});
    }
    needed.push_back({t, GroupKind::kCCircle, 0});
    needed.push_back({t, GroupKind::kACircle, 0});
  }
  for (const Group& g : needed) {
    if (!has(g.t, g.q, g.d)) return file + " has no row of group '" + group_name(g) + "'";
  }
  return "every group trueaxis-calibrate knows of was sent";
}

std::string json_axes(const double* x, const double* y, const double* z) {
  return "\"x\": " + json_vec3(x) + ", \"y\": " + json_vec3(y) + ", \"z\": " + json_vec3(z);
}

}  // namespace

namespace {

// The MACHINE row behind a refusal of the swing or nominal-origin gate: the
// file, the row, its values and the likely mistake; "" for another refusal.
std::string machine_row_cause(VariableClient& client, const FlowResult& r, const std::map<int, const CsvRow*>& rows,
                              const std::string& machine_path) {
  const bool swing = module_refused(r, static_cast<int>(macros::gantry::kSwingImplausible));
  const bool nominal = module_refused(r, static_cast<int>(macros::gantry::kOriginOffNominal));
  double gate[3] = {0.0, 0.0, 0.0};  // #9012 .. #9014: the sub-machine, the figure, the limit
  if ((!swing && !nominal) || !client.read(var::kGateItem, 3, gate)) return "";
  const auto found = rows.find(static_cast<int>(gate[0]));
  if (found == rows.end()) return "";
  const CsvRow& row = *found->second;
  char text[400];
  if (swing) {
    std::snprintf(text, sizeof text, " -- %s:%d: sub-machine %d's swing_mm %g is shorter than %g mm: MACHINE.csv in "
                  "metres? trueaxis takes mm", machine_path.c_str(), row.line, found->first, row.numbers[1], gate[2]);
  } else {
    std::snprintf(text, sizeof text, " -- %s:%d: sub-machine %d's measured origin lies %.4g mm from its nominal origin "
                  "(%g, %g, %g) (limit %g mm, #708): is swing_mm %g typed wrong (a digit twice? metres?), the tool "
                  "direction (%g, %g, %g) the wrong way round, or the nominal origin in another frame than the "
                  "global one?", machine_path.c_str(), row.line, found->first, gate[1], row.numbers[5], row.numbers[6],
                  row.numbers[7], gate[2], row.numbers[1], row.numbers[2], row.numbers[3], row.numbers[4]);
  }
  return text;
}

}  // namespace

FlowResult calibrate_gantry(VariableClient& client, const CalibrateOptions& options) {
  FlowResult r;
  if (options.machine_path.empty()) {
    r.error = "gantry needs --machine MACHINE.csv (sub_machine,swing_mm,tool_x,tool_y,tool_z)";
    return r;
  }
  // The rows are kept to sort them by group: at most the session's capacity.
  std::vector<CsvRow> rows;
  {
    CsvReader reader(options.in_path, {{"group", false}, {"x_mm"}, {"y_mm"}, {"z_mm"}});
    CsvRow row;
    while (reader.next(row)) {
      if (rows.size() == macros::gantry::kSessionCapacity) {
        const std::string capacity = std::to_string(macros::gantry::kSessionCapacity);
        r.error = options.in_path + ":" + std::to_string(row.line) + ": point " + capacity + " + 1: the module's " +
                  "gantry session holds " + capacity + " points (session_full); nothing was sent";
        return r;
      }
      rows.push_back(row);
    }
    if (!reader.error().empty()) {
      r.error = reader.error();
      return r;
    }
  }
  // origin_x_mm .. origin_z_mm: the nominal origin (global frame), optional: with
  // it the module holds the measured origin to it (#708), without it the swing
  // length and the tool direction are taken as given.
  const CsvResult machine = read_csv(options.machine_path,
                                     {{"sub_machine"}, {"swing_mm"}, {"tool_x"}, {"tool_y"}, {"tool_z"},
                                      {"origin_x_mm", true, true}, {"origin_y_mm", true, true},
                                      {"origin_z_mm", true, true}});
  if (!machine.ok) {
    r.error = machine.error;
    return r;
  }
  // Each row's group; then the rows grouped (stably: measuring order kept).
  struct Sample {
    Group group;
    const CsvRow* row;
  };
  std::vector<Sample> samples;
  bool mentioned[9] = {};
  for (const CsvRow& row : rows) {
    Group g;
    const std::string what = parse_group(row.texts[0], g);
    if (!what.empty()) {
      r.error = options.in_path + ":" + std::to_string(row.line) + ": " + what;
      return r;
    }
    mentioned[g.t] = true;
    samples.push_back({g, &row});
  }
  std::stable_sort(samples.begin(), samples.end(),
                   [](const Sample& a, const Sample& b) { return a.group.order() < b.group.order(); });
  std::map<int, const CsvRow*> parameters;
  for (const CsvRow& row : machine.rows) {
    const double n = row.numbers[0];
    const std::string where = options.machine_path + ":" + std::to_string(row.line);
    if (!(n >= 1 && n <= 8 && n == static_cast<int>(n))) {
      r.error = where + ": sub_machine must be a whole number 1..8";
      return r;
    }
    const int given = (std::isnan(row.numbers[5]) ? 0 : 1) + (std::isnan(row.numbers[6]) ? 0 : 1) +
                      (std::isnan(row.numbers[7]) ? 0 : 1);
    if (given != 0 && given != 3) {
      r.error = where + ": a nominal origin needs origin_x_mm, origin_y_mm and origin_z_mm, all three, or none";
      return r;
    }
    if (!parameters.emplace(static_cast<int>(n), &row).second) {
      r.error = where + ": sub-machine " + std::to_string(static_cast<int>(n)) + " is given twice";
      return r;
    }
  }
  // A MACHINE row with no points, or a point of a sub-machine --sub-machines leaves out.
  const std::vector<int>& listed = options.sub_machines;
  const auto in_list = [&listed](int n) { return listed.empty() || std::count(listed.begin(), listed.end(), n) > 0; };
  std::string measured;
  for (int n = 1; n <= 8; ++n) measured += mentioned[n] ? (measured.empty() ? "" : ",") + std::to_string(n) : "";
  const Sample* outside = nullptr;  // the first in the file
  for (const Sample& s : samples) {
    if (s.group.t != 0 && !in_list(s.group.t) && (outside == nullptr || s.row->line < outside->row->line)) outside = &s;
  }
  if (outside != nullptr) {
    r.error = options.in_path + ":" + std::to_string(outside->row->line) + ": group '" + outside->row->texts[0] +
              "': sub-machine " + std::to_string(outside->group.t) + " is not among --sub-machines";
    return r;
  }
  for (int n = 1; n <= 8; ++n) {
    if (mentioned[n] && parameters.count(n) == 0) {
      r.error = options.machine_path + ": no row for sub-machine " + std::to_string(n) + ", which " +
                options.in_path + " measures";
      return r;
    }
  }
  for (const auto& [n, row] : parameters) {
    if (!in_list(n) || mentioned[n]) continue;
    r.error = options.machine_path + ":" + std::to_string(row->line) + ": sub-machine " + std::to_string(n) +
              " has no points in " + options.in_path + " (no group sp" + std::to_string(n) + "_...)" +
              (listed.empty() ? ": not measured, or its groups misnamed? (to calibrate some sub-machines only, name "
                                "them: --sub-machines " + (measured.empty() ? std::string("N,...") : measured) + ")"
                              : ", though --sub-machines names it");
    return r;
  }
  for (const int n : listed) {
    if (!mentioned[n] && parameters.count(n) == 0) {
      r.error = "--sub-machines names sub-machine " + std::to_string(n) + ", which neither " + options.in_path +
                " measures nor " + options.machine_path + " gives";
      return r;
    }
  }

  r.stage = "opening the session (macro 9820): nothing sent yet";
  if (!run_or_fail(client, kClear, "", r)) return r;
  std::size_t streamed = 0;
  for (const Sample& s : samples) {
    const std::string where = options.in_path + ":" + std::to_string(s.row->line);
    r.stage = "streaming sample " + std::to_string(++streamed) + " of " + std::to_string(samples.size()) + " of " + where;
    const double tqd[3] = {static_cast<double>(s.group.t), static_cast<double>(s.group.q),
                           static_cast<double>(s.group.d)};
    const double xyz[3] = {s.row->numbers[1], s.row->numbers[2], s.row->numbers[3]};
    if (!client.write_one(var::kArgT, tqd[0]) || !client.write_one(var::kArgQ, tqd[1]) ||
        !client.write_one(var::kArgD, tqd[2]) || !client.write(var::kArgX, 3, xyz)) {
      r.error = refused_sample(client, where, r);
      return r;
    }
    if (!run_or_fail(client, kAdd, where, r)) {
      if (module_refused(r, static_cast<int>(core::Status::kTooManyPoints))) {
        r.error += ": group '" + s.row->texts[0] + "' holds at most " + std::to_string(capacity_of(s.group.q)) +
                   " points, and this is one more";
      } else if (module_refused(r, static_cast<int>(core::Status::kSessionFull))) {
        r.error += ": the session holds " + std::to_string(macros::gantry::kSessionCapacity) + " points";
      }
      return r;
    }
  }
  // Only the sub-machines the samples measure: a MACHINE file may describe the
  // whole machine while one sub-machine is measured again (the module computes
  // every sub-machine given a 9822, and one without points is missing_group).
  for (const auto& [n, row] : parameters) {
    if (!mentioned[n]) continue;
    const std::string where = options.machine_path + ":" + std::to_string(row->line);
    r.stage = "sending sub-machine " + std::to_string(n) + "'s row of " + where + " (macro 9822)";
    const double tool[3] = {row->numbers[2], row->numbers[3], row->numbers[4]};
    const bool nominal = !std::isnan(row->numbers[5]);
    const double origin[3] = {row->numbers[5], row->numbers[6], row->numbers[7]};
    if (!client.write_one(var::kArgT, n) || !client.write_one(var::kArgD, row->numbers[1]) ||
        !client.write(var::kArgI, 3, tool) || (nominal && !client.write_one(var::kArgQ, 1.0)) ||
        (nominal && !client.write(var::kArgX, 3, origin))) {
      r.error = where + ": the module refused the row: " + client.failure_text();
      return r;
    }
    if (!run_or_fail(client, kSubMachine, where, r)) return r;
    if (!nominal) {
      char text[200];
      std::snprintf(text, sizeof text, "sub-machine %d's swing_mm %g and tool direction (%g, %g, %g) (%s; no nominal "
                    "origin to hold them to)", n, row->numbers[1], tool[0], tool[1], tool[2], where.c_str());
      r.as_given.push_back(text);
    }
  }

  // The module's item for a sub-machine is its id: named so in a gate's refusal and the check.
  for (int n = 1; n <= 8; ++n) {
    if (mentioned[n]) r.check_items[n] = {"sp" + std::to_string(n), "sub_machine", static_cast<double>(n)};
  }
  std::string unheld;  // the sub-machines without a nominal origin
  for (const auto& [n, row] : parameters) {
    if (mentioned[n] && std::isnan(row->numbers[5])) unheld += (unheld.empty() ? "" : ", ") + std::to_string(n);
  }
  if (!unheld.empty()) {
    r.as_given_summary = "swing_mm and tool direction of sub-machine" +
                         std::string(unheld.find(',') != std::string::npos ? "s " : " ") + unheld + " (" +
                         options.machine_path + " gives no nominal origin: origin_x_mm .. origin_z_mm)";
  }
  // Computed without storing: the command stores only after the JSON and the
  // report are made (store_gantry), so a later failure stores nothing.
  r.stage = "running the build (macro 9823, R = 0), every sample sent";
  if (!hand_time(client, options.log_time, r)) return r;  // the calibration's entry in the measuring log
  if (!transport(client, client.write_one(var::kArgR, 0.0), r)) return r;
  if (!run_or_fail(client, kBuild, "", r)) {
    if (module_refused(r, static_cast<int>(core::Status::kMissingGroup))) {
      std::vector<Group> sent;
      for (const Sample& s : samples) sent.push_back(s.group);
      r.error += ": " + first_missing_group(sent, options.in_path);
    }
    r.error += machine_row_cause(client, r, parameters, options.machine_path);
    return r;
  }
  r.stage = "running the report query (macros 9824, 9826)";
  double build[4];
  double global[26];
  if (!transport(client, client.read(var::kGantryBuilt, 4, build), r) ||
      !transport(client, client.write_one(var::kArgR, 0.0), r) || !run_or_fail(client, kGlobal, "", r) ||
      !transport(client, client.read(var::kGlobalOriginX, 26, global), r)) {
    return r;
  }
  const int mask = static_cast<int>(global[19]);
  std::string subs;
  std::string extras;
  int count = 0;
  int worst_id = 0;
  double worst_sigma_mm = -1.0;
  for (int n = 1; n <= 8; ++n) {
    if ((mask & (1 << (n - 1))) == 0) continue;
    double s[32];
    if (!transport(client, client.write_one(var::kArgR, 0.0), r) ||  // R = 0: the frames just computed
        !transport(client, client.write_one(var::kArgT, n), r) || !run_or_fail(client, kSub, "", r) ||
        // Two reads: 32 variables are 128 registers, over Modbus's 125 per request.
        !transport(client, client.read(var::kSubOriginX, 27, s), r) ||
        !transport(client, client.read(var::kSubSquarenessSigmaXY, 5, s + 27), r)) {
      return r;
    }
    ++count;
    r.check_items[n] = {"sp" + std::to_string(n), "sub_machine", static_cast<double>(n)};  // the check's item: its id
    if (s[3] > worst_sigma_mm) {
      worst_sigma_mm = s[3];
      worst_id = n;
    }
    const double* o = s;
    const double* x = s + 4;
    const double* y = s + 7;
    const double* z = s + 10;
    std::string t = "[";
    for (int row = 0; row < 3; ++row) {
      t += json_number(x[row]) + ", " + json_number(y[row]) + ", " + json_number(z[row]) + ", " +
           json_number(o[row]) + ", ";
    }
    t += "0, 0, 0, 1]";
    const char* master[3] = {"x", "y", "z"};
    subs += subs.empty() ? "\n" : ",\n";
    subs += "    { \"id\": " + std::to_string(n) + ", \"origin_mm\": " + json_vec3(o) +
            ", \"origin_sigma_mm\": " + json_number(s[3]) + ",\n      " + json_axes(x, y, z) +
            ", \"master_axis\": \"" + master[static_cast<int>(s[13]) % 3] + "\",\n      \"squareness_arcsec\": { \"xy\": " +
            json_number(s[14]) + ", \"yz\": " + json_number(s[15]) + ", \"zx\": " + json_number(s[16]) +
            " },\n      \"a_c_offset_mm\": " + json_number(s[17]) + ", \"a_c_angle_deg\": " + json_number(s[18]) +
            ",\n      \"global_T_sub\": " + t + ",\n      \"squareness_sigma_arcsec\": { \"xy\": " +
            json_number(s[27]) + ", \"yz\": " + json_number(s[28]) + ", \"zx\": " + json_number(s[29]) +
            " },\n      \"a_c_offset_sigma_mm\": " + json_number(s[30]) + ", \"a_c_angle_sigma_deg\": " +
            json_number(s[31]) + ", \"angle_sigma_arcsec\": " + json_vec3(s + 19) + " }";
    extras += extras.empty() ? "\n" : ",\n";
    extras += "    { \"id\": " + std::to_string(n) + ", \"angle_sigma_arcsec\": " + json_vec3(s + 19) +
              ", \"straightness_mm\": " + json_vec3(s + 22) + ", \"c_circle_rms_mm\": " + json_number(s[25]) +
              ", \"a_circle_rms_mm\": " + json_number(s[26]) + " }";
  }
  r.json = "{\n  \"method\": \"gantry\",\n  \"global\": { \"origin_mm\": " + json_vec3(global) + ",\n    " +
           json_axes(global + 3, global + 6, global + 9) + ",\n    \"bed_flatness_mm\": " + json_number(global[12]) +
           ", \"gantry_straightness_mm\": " + json_number(global[13]) + ",\n    \"bed_flatness_noise_floor_mm\": " +
           json_number(global[20]) + ", \"gantry_straightness_noise_floor_mm\": " + json_number(global[21]) +
           ",\n    \"bed_form_error_mm\": " + json_number(global[22]) + ", \"bed_form_error_sigma_mm\": " +
           json_number(global[23]) + ",\n    \"gantry_form_error_mm\": " + json_number(global[24]) +
           ", \"gantry_form_error_sigma_mm\": " + json_number(global[25]) + " },\n  \"sub_machines\": [" + subs +
           "\n  ]\n}\n";
  // What the module computed beyond docs/INTERFACE.md's OUT.json, for the report only.
  // A key of its own ("sub_machine_figures"): the report merges this file into
  // OUT.json's keys, and must not lose OUT.json's "sub_machines".
  r.report_extras = "{ \"global_origin_sigma_mm\": " + json_number(global[14]) +
                    ", \"global_angle_sigma_arcsec\": " + json_vec3(global + 15) +
                    ",\n  \"sub_machine_figures\": [" +
                    extras + "\n  ] }\n";
  char line[200];
  std::snprintf(line, sizeof line, "gantry: %d sub-machines, worst origin 1-sigma %.1f um (sp%d)", count,
                1000.0 * worst_sigma_mm, worst_id);
  r.summary = line;
  r.ok = true;
  return r;
}

bool store_gantry(VariableClient& client, FlowResult& fail) { return store_built(client, kBuild, fail); }

// The method's entry in trueaxis-calibrate's table (host_methods.hpp, folded
// from the one list). The files' text follows docs/INTERFACE.md "Calibration
// flows", which is the definition; this is the short form `trueaxis-calibrate
// gantry --help` prints.
const CalibrateMethod& calibrate_method_gantry() {
  // clang-format off
  static const CalibrateMethod kMethod{"gantry", "M2 gantry zero frames: laser-tracker points of the bed, the gantry and each sub-machine",
   "SAMPLES.csv: group,x_mm,y_mm,z_mm\n"
   "  group              bed, side_1, side_2, gantry_K, spN_x_K, spN_y_K, spN_z_K, spN_c, spN_a\n"
   "                     (N the sub-machine 1..8, K the pass 1..4; no leading zeros)\n"
   "  x_mm, y_mm, z_mm   a tracker point (mm, tracker frame, levelled: +Z up)\n"
   "  Passes in measuring order along the axis' positive direction, circles in order of\n"
   "  increasing angle; a group's rows need not be adjacent.\n"
   "MACHINE.csv (--machine, required): sub_machine,swing_mm,tool_x,tool_y,tool_z\n"
   "  sub_machine        N, 1..8, each once; a row for every sub-machine SAMPLES measures, and\n"
   "                     points for every row (or --sub-machines N,N...: the ones measured)\n"
   "  swing_mm           the A axis' swing length, wrist centre to tool tip (mm)\n"
   "  tool_x, tool_y, tool_z  the nominal tool direction, tracker frame (only its sense is used)\n",
   calibrate_gantry, store_gantry, "gantry", nullptr, macros::gantry::kMacroGlobal, 0.0};
  // clang-format on
  return kMethod;
}

}  // namespace trueaxis::sim
