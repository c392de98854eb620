// trueaxis-map: writes the register map, generated from the code's tables, as
// JSON (default) or as the human page (--markdown). The committed
// macros/register_map.json and macros/REGISTER_MAP.md are this program's output;
// the test register_map_is_current fails when they differ.
#include <cstdio>
#include <cstring>
#include <string>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/modbus/register_codec.hpp"
#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/server/sim_map.hpp"

namespace {

namespace m = trueaxis::macros;
namespace core = trueaxis::core;

std::string escaped(const char* s) {
  std::string out;
  for (; *s != '\0'; ++s) {
    if (*s == '"' || *s == '\\') out += '\\';
    out += *s;
  }
  return out;
}

const char* access_name(m::Access a) {
  switch (a) {
    case m::Access::kReadWrite: return "read_write";
    case m::Access::kReadOnly: return "read_only";
    case m::Access::kPersistent: return "persistent";
    case m::Access::kConfig: return "config";
    case m::Access::kCommand: return "command";
    case m::Access::kUnlock: return "unlock";
    case m::Access::kInterface: return "interface";
  }
  return "?";
}

const char* kind_name(m::ValueKind k) {
  switch (k) {
    case m::ValueKind::kReal: return "real";
    case m::ValueKind::kInteger: return "integer";
    case m::ValueKind::kSign: return "sign";
  }
  return "?";
}

const char* var_name(std::uint16_t number) {
  const m::VarInfo* v = m::find_var(number);
  return v != nullptr ? v->name : "?";
}

using Built = m::BuiltMethods;

// A method's block as JSON ([first, last], or null for none) and as text.
std::string block_json(bool present, unsigned first, unsigned last) {
  return present ? "[" + std::to_string(first) + ", " + std::to_string(last) + "]" : "null";
}
std::string block_text(bool present, unsigned first, unsigned last) {
  return present ? "#" + std::to_string(first) + "..#" + std::to_string(last) : "none";
}

// One session's limits of `group` ("": the method's own) as JSON members.
void json_limits(const m::SessionInfo& session, const char* group) {
  bool first = true;
  for (const m::SessionLimit& l : session.limits) {
    if (std::strcmp(l.group, group) != 0) continue;
    std::printf("%s\"%s\": %zu", first ? "" : ", ", l.name, l.value);
    first = false;
  }
}

int as_int(m::AccessFault f) { return static_cast<int>(f); }
int as_int(m::ModbusException e) { return static_cast<int>(e); }

template <typename Table>
void json_variables(const Table& table, bool sim_only, bool& first) {
  for (const m::VarInfo& v : table) {
    std::printf("%s\n    {\"number\": %u, \"count\": %u, \"register\": %u, \"name\": \"%s\", \"access\": \"%s\", "
                "\"kind\": \"%s\", \"min\": %.17g, \"max\": %.17g, \"default\": %.17g, \"unit\": \"%s\", "
                "\"persistent\": %s, \"simulator_only\": %s,\n     \"description\": \"%s\"}",
                first ? "" : ",", v.number, v.count, static_cast<unsigned>(trueaxis::modbus::register_of(v.number)), v.name,
                access_name(v.access), kind_name(v.kind), v.min, v.max, v.default_value, v.unit,
                m::is_persistent(v) ? "true" : "false", sim_only ? "true" : "false", escaped(v.description).c_str());
    first = false;
  }
}

void print_json() {
  std::printf("{\n  \"interface_version\": %d,\n", static_cast<int>(m::kInterfaceVersionValue));
  std::printf(
      "  \"encoding\": {\"value\": \"IEEE-754 binary64\", \"registers_per_variable\": 4, "
      "\"register_of_variable\": \"4 * N\", \"word_order\": \"register 4N holds bits 63..48, 4N+3 bits 15..0\", "
      "\"function_codes\": [3, 16, 23], \"max_variables_per_read\": %u, \"max_variables_per_write\": %u},\n",
      trueaxis::modbus::kMaxVariablesPerRead, trueaxis::modbus::kMaxVariablesPerWrite);
  std::printf("  \"unlock_code\": %d,\n", static_cast<int>(m::kUnlockCode));
  std::printf("  \"macro_status\": {\"0\": \"idle\", \"1\": \"busy\", \"2\": \"done\", \"3\": \"error\"},\n");
  std::printf("  \"variables\": [");
  bool first = true;
  json_variables(m::kRegisterMap, false, first);
  json_variables(trueaxis::sim::kSimMap, true, first);
  std::printf("\n  ],\n  \"macros\": [");
  first = true;
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    for (const m::MacroInfo& mi : Built::kMacros[method]) {
      std::printf("%s\n    {\"number\": %u, \"name\": \"%s\", \"method\": \"%s\", \"description\": \"%s\",",
                  first ? "" : ",", mi.number, mi.name, Built::kNames[method], escaped(mi.description).c_str());
      std::printf("\n     \"inputs\": [");
      for (std::size_t k = 0; k < mi.input_count; ++k) {
        const m::InputRef& in = mi.inputs[k];
        std::printf("%s{\"number\": %u, \"count\": %u, \"name\": \"%s\", \"note\": \"%s\"}", k ? ", " : "",
                    in.first, in.count, var_name(in.first), escaped(in.note).c_str());
      }
      std::printf("],\n     \"outputs\": [");
      for (std::size_t k = 0; k < mi.output_count; ++k) {
        const m::OutputInfo& o = mi.outputs[k];
        std::printf("%s{\"number\": %u, \"name\": \"%s\", \"unit\": \"%s\", \"description\": \"%s\"}",
                    k ? ", " : "", o.number, o.name, o.unit, escaped(o.description).c_str());
      }
      std::printf("]}");
      first = false;
    }
  }
  std::printf("\n  ],\n  \"methods\": [");
  first = true;
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    const m::MethodBlock& b = Built::kBlocks[method];
    const m::StatusBlock& codes = Built::kStatusBlocks[method];
    std::printf("%s\n    {\"name\": \"%s\", \"config_block\": %s, \"data_block\": %s, \"built\": true, "
                "\"status_block\": [%u, %u]",
                first ? "" : ",", Built::kNames[method], block_json(b.has_config(), b.config_first, b.config_last).c_str(),
                block_json(b.has_data(), b.data_first, b.data_last).c_str(), codes.first, codes.last);
    const m::SessionInfo& sd = Built::kSessions[method];
    if (sd.capacity > 0) {
      std::printf(",\n     \"session\": {\"capacity\": %zu, \"capacity_counts\": \"%s\", \"sample\": \"%s\", "
                  "\"clear\": %u, \"add\": %u, \"compute\": %u",
                  sd.capacity, sd.capacity_unit, escaped(sd.sample).c_str(), sd.clear, sd.add, sd.compute);
      if (sd.compute_also != 0) std::printf(", \"compute_also\": %u", sd.compute_also);
      std::printf("}");
    }
    bool grouped = false;
    for (const m::SessionLimit& l : sd.limits) {
      if (l.group[0] == '\0') {
        std::printf(", \"%s\": %zu", l.name, l.value);
      } else if (!grouped) {
        grouped = true;  // one group per method today (gantry's group_capacity)
        std::printf(",\n     \"%s\": {", l.group);
        json_limits(sd, l.group);
        std::printf("}");
      }
    }
    if (Built::kHasTable[method]) std::printf(", \"stores_table\": true");
    if (!Built::kGates[method].empty()) {
      std::printf(",\n     \"gates\": [");
      bool first_gate = true;
      for (const m::GateInfo& g : Built::kGates[method]) {
        std::printf("%s\n       {\"name\": \"%s\", \"error\": %d, \"thresholds\": [", first_gate ? "" : ",", g.name,
                    static_cast<int>(g.status));
        bool first_threshold = true;
        for (std::uint16_t t : g.thresholds) {
          if (t == 0) continue;
          std::printf("%s%u", first_threshold ? "" : ", ", t);
          first_threshold = false;
        }
        std::printf("], \"what\": \"%s\"}", escaped(g.what).c_str());
        first_gate = false;
      }
      std::printf("]");
    }
    const m::CheckInfo& check = Built::kChecks[method];
    if (check.macro != 0) {
      std::printf(",\n     \"check\": {\"macro\": %u, \"figures\": [", check.macro);
      for (std::size_t k = 0; k < check.figures.size; ++k) {
        const m::CheckFigureInfo& f = check.figures[k];
        std::printf("%s\n       {\"kind\": %u, \"name\": \"%s\", \"unit\": \"%s\", \"what\": \"%s\"}", k ? "," : "",
                    f.kind, f.name, f.unit, escaped(f.what).c_str());
      }
      std::printf("]}");
    }
    if (Built::kLogs[method]) {
      std::printf(",\n     \"log\": {\"figures\": [");
      const m::List<m::CheckFigureInfo> figures = Built::kLogFigures[method];
      for (std::size_t k = 0; k < figures.size; ++k) {
        const m::CheckFigureInfo& f = figures[k];
        std::printf("%s\n       {\"kind\": %u, \"name\": \"%s\", \"unit\": \"%s\", \"what\": \"%s\"}", k ? "," : "",
                    f.kind, f.name, f.unit, escaped(f.what).c_str());
      }
      std::printf("]}");
    }
    std::printf("}");
    first = false;
  }
  std::printf("\n  ],\n  \"records\": [");
  first = true;
  for (const m::RecordSpec& r : m::kRecordSpecs) {
    std::printf("%s\n    {\"key\": %u, \"name\": \"%s\", \"layout_version\": %u, \"capacity_bytes\": %zu}",
                first ? "" : ",", r.key, r.name, r.layout_version, r.capacity_bytes);
    first = false;
  }
  std::printf("\n  ],\n  \"storage_bytes\": %zu,\n  \"step_bound_instructions\": %u,",
              m::kRequiredStorageBytes, static_cast<unsigned>(m::Module::kStepBoundInstructions));
  std::printf("\n  \"errors\": [");
  first = true;
  for (const core::StatusInfo& s : m::kStatusTable) {
    std::printf("%s\n    {\"code\": %d, \"name\": \"%s\", \"message\": \"%s\"}", first ? "" : ",",
                static_cast<int>(s.status), s.name, escaped(s.message).c_str());
    first = false;
  }
  std::printf("\n  ],\n  \"access_faults\": [");
  first = true;
  for (const m::AccessFaultInfo& f : m::kAccessFaultTable) {
    std::printf("%s\n    {\"code\": %d, \"name\": \"%s\", \"modbus_exception\": %d, \"message\": \"%s\"}",
                first ? "" : ",", as_int(f.fault), f.name, as_int(m::modbus_exception(f.fault)),
                escaped(f.message).c_str());
    first = false;
  }
  std::printf("\n  ]\n}\n");
}

std::string range_text(const m::VarInfo& v) {
  char buf[160];
  if (v.kind == m::ValueKind::kSign) return "-1 or +1";
  if (v.access == m::Access::kReadOnly) return "";
  std::snprintf(buf, sizeof buf, "%.10g .. %.10g", v.min, v.max);
  return buf;
}

template <typename Table>
void markdown_rows(const Table& table) {
  for (const m::VarInfo& v : table) {
    char number[32];
    if (v.count == 1) {
      std::snprintf(number, sizeof number, "#%u", v.number);
    } else {
      std::snprintf(number, sizeof number, "#%u..#%u", v.number, v.number + v.count - 1);
    }
    std::printf("| %s | %u | %s | %s | %s | %s | %.10g | %s |\n", number,
                static_cast<unsigned>(trueaxis::modbus::register_of(v.number)), v.name, access_name(v.access), v.unit,
                range_text(v).c_str(), v.default_value, v.description);
  }
}

void print_markdown() {
  std::printf(
      "# trueaxis register map (interface version %d)\n\n"
      "Generated by `build/host/bin/trueaxis-map --markdown` from the code's tables; "
      "do not edit. The machine-readable twin is `register_map.json`.\n\n"
      "Variable #N is the four holding registers 4N..4N+3 (register 4N holds bits 63..48 of the IEEE-754 "
      "double). Function codes 3, 16 and 23; at most %u variables per read and %u per write. Configuration (`config`) is "
      "writable only after writing the unlock code %d to #9004. `persistent` and `config` variables survive a "
      "restart.\n\n",
      static_cast<int>(m::kInterfaceVersionValue), trueaxis::modbus::kMaxVariablesPerRead, trueaxis::modbus::kMaxVariablesPerWrite,
      static_cast<int>(m::kUnlockCode));
  const char* header =
      "| variable | register | name | access | unit | range | default | meaning |\n"
      "|---|---|---|---|---|---|---|---|\n";
  std::printf("## Module variables\n\n%s", header);
  markdown_rows(m::kRegisterMap);
  std::printf("\n## Simulator-only variables\n\nServed by `trueaxis-sim` only; never by the module in a "
              "controller.\n\n%s", header);
  markdown_rows(trueaxis::sim::kSimMap);
  std::printf("\n## Methods and their blocks\n\nEach method defines variables only inside its blocks and new "
              "status codes only inside its block of codes; the others are not defined in this module.\n\n"
              "| method | configuration | data | status codes | session |\n|---|---|---|---|---|\n");
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    const m::MethodBlock& b = Built::kBlocks[method];
    const m::SessionInfo& sd = Built::kSessions[method];
    std::string session = "";
    if (sd.capacity > 0) {
      char buf[300];
      std::snprintf(buf, sizeof buf, "%zu %s of %s; clear %u, add %u, compute %u", sd.capacity, sd.capacity_unit,
                    sd.sample, sd.clear, sd.add, sd.compute);
      session = buf;
      if (sd.compute_also != 0) session += " (also " + std::to_string(sd.compute_also) + ")";
    }
    for (const m::SessionLimit& l : sd.limits) {
      char buf[120];
      std::snprintf(buf, sizeof buf, "; %s%s%s %zu", l.group, l.group[0] ? " " : "", l.name, l.value);
      session += buf;
    }
    std::printf("| %s | %s | %s | %u..%u | %s |\n", Built::kNames[method],
                block_text(b.has_config(), b.config_first, b.config_last).c_str(),
                block_text(b.has_data(), b.data_first, b.data_last).c_str(), Built::kStatusBlocks[method].first,
                Built::kStatusBlocks[method].last, session.c_str());
  }
  std::printf("\n## Gates\n\nWhat a compute macro checks before it publishes or stores a result; a refusal "
              "leaves every result and table as it was and tells the item, the figure and its limit in #9012 .. "
              "#9014.\n\n| method | gate | error | thresholds | what |\n|---|---|---|---|---|\n");
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    for (const m::GateInfo& g : Built::kGates[method]) {
      std::string thresholds;
      for (std::uint16_t t : g.thresholds) {
        if (t == 0) continue;
        thresholds += (thresholds.empty() ? "#" : ", #") + std::to_string(t) + " " + var_name(t);
      }
      std::printf("| %s | %s | %d | %s | %s |\n", Built::kNames[method], g.name, static_cast<int>(g.status),
                  thresholds.c_str(), g.what);
    }
  }
  std::printf("\n## Checks\n\nA method's check macro compares the result it built last (R = 0) with its stored "
              "table and stores nothing (check.hpp): per figure its deviation with its 1-sigma and a verdict against "
              "the configured tolerance, fail when |deviation| > tolerance, warn when |deviation| + 2 sigma > "
              "tolerance, else pass. Q = 0 publishes the worst figure in #104 .. #111, Q = k figure k; #105 is the "
              "kind below.\n\n| method | macro | kind | figure | unit | what |\n|---|---|---|---|---|---|\n");
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    const m::CheckInfo& check = Built::kChecks[method];
    for (const m::CheckFigureInfo& f : check.figures) {
      std::string what = f.what;  // a '|' would end the Markdown cell
      for (std::size_t at = what.find('|'); at != std::string::npos; at = what.find('|', at + 2)) what.insert(at, "\\");
      std::printf("| %s | %u | %u | %s | %s | %s |\n", Built::kNames[method], check.macro, f.kind, f.name, f.unit,
                  what.c_str());
    }
  }
  std::printf("\n## The measuring log\n\nEvery calibration (a build with R = 0), store (R = 1) and check (Q = 0) of a "
              "method below appends an entry to the module's log, a ring of the newest %zu in one power-safe record "
              "(measuring_log.hpp; #9015 .. #9059): a check logs its verdict and, per kind of the table above, its "
              "worst figure; a calibration the figures below, each with its 1-sigma. A store or check right after "
              "its own method's calibration replaces that calibration's entry.\n\n"
              "| method | macro | kind | figure | unit | what |\n|---|---|---|---|---|---|\n",
              m::kLogEntries);
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    if (!Built::kLogs[method]) continue;
    for (const m::CheckFigureInfo& f : Built::kLogFigures[method]) {
      std::string what = f.what;
      for (std::size_t at = what.find('|'); at != std::string::npos; at = what.find('|', at + 2)) what.insert(at, "\\");
      std::printf("| %s | %u | %u | %s | %s | %s |\n", Built::kNames[method], Built::kSessions[method].compute, f.kind,
                  f.name, f.unit, what.c_str());
    }
  }
  std::printf("\n## Macros\n\nEvery macro runs in steps of at most %u Cortex-M7 instructions "
              "(#9008 tells how many steps the last one took).\n",
              static_cast<unsigned>(m::Module::kStepBoundInstructions));
  for (std::size_t method = 0; method < Built::kCount; ++method) {
    for (const m::MacroInfo& mi : Built::kMacros[method]) {
      std::printf("\n### %u %s (%s)\n\n%s\n\n| | variables |\n|---|---|\n", mi.number, mi.name, Built::kNames[method],
                  mi.description);
      for (std::size_t k = 0; k < mi.input_count; ++k) {
        const m::InputRef& in = mi.inputs[k];
        if (in.count == 1) {
          std::printf("| in | #%u %s: %s |\n", in.first, var_name(in.first), in.note);
        } else {
          std::printf("| in | #%u..#%u %s: %s |\n", in.first, in.first + in.count - 1, var_name(in.first),
                      in.note);
        }
      }
      for (std::size_t k = 0; k < mi.output_count; ++k) {
        const m::OutputInfo& o = mi.outputs[k];
        std::printf("| out | #%u %s (%s): %s |\n", o.number, o.name, o.unit[0] ? o.unit : "-", o.description);
      }
    }
  }
  std::printf("\n## Persistent records\n\nEach record is kept as two copies (A/B) with a layout version, a "
              "sequence number and a CRC-32 over the whole record; a write to one record never rewrites another. "
              "The storage needs %zu bytes.\n\n| key | record | layout | payload capacity (bytes) |\n|---|---|---|---|\n",
              m::kRequiredStorageBytes);
  for (const m::RecordSpec& r : m::kRecordSpecs) {
    std::printf("| %u | %s | %u | %zu |\n", r.key, r.name, r.layout_version, r.capacity_bytes);
  }
  std::printf("\n## Error codes (#9002)\n\n| code | name | message |\n|---|---|---|\n");
  for (const core::StatusInfo& s : m::kStatusTable) {
    std::printf("| %d | %s | %s |\n", static_cast<int>(s.status), s.name, s.message);
  }
  std::printf("\n## Refused register accesses (#9007 and the Modbus exception)\n\n"
              "| code | name | Modbus exception | meaning |\n|---|---|---|---|\n");
  for (const m::AccessFaultInfo& f : m::kAccessFaultTable) {
    std::printf("| %d | %s | %02d | %s |\n", as_int(f.fault), f.name, as_int(m::modbus_exception(f.fault)), f.message);
  }
}

}  // namespace

constexpr const char* kHelp =
    "usage: trueaxis-map [--json | --markdown]\n"
    "  Prints the register map the code defines: macros/register_map.json (--json, the default)\n"
    "  or macros/REGISTER_MAP.md (--markdown); toolchain/regenerate-map.sh writes both.\n"
    "  --help, --version  this text; the version line\n"
    "  Exit 0, or 2 on bad usage.\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-map", kHelp)) return 0;
  if (argc > 2 || (argc == 2 && std::strcmp(argv[1], "--markdown") != 0 && std::strcmp(argv[1], "--json") != 0)) {
    std::fprintf(stderr, "usage: trueaxis-map [--json | --markdown]\n");
    return 2;
  }
  if (argc == 2 && std::strcmp(argv[1], "--markdown") == 0) {
    print_markdown();
  } else {
    print_json();
  }
  return 0;
}
