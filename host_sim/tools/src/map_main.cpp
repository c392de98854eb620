// trueaxis-map: writes the register map, generated from the code's tables, as
// JSON (default) or as the human page (--markdown). The committed
// macros/register_map.json and macros/REGISTER_MAP.md are this program's output;
// the test register_map_is_current fails when they differ.
#include <cstdio>
#include <cstring>
#include <string>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/methods.hpp"
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

// The streaming sessions, for the map's readers: capacity from the code.
struct SessionDoc {
  const char* method;
  std::size_t capacity;
  const char* sample;
  unsigned clear, add, compute;
};
const SessionDoc kSessions[] = {
    {"level", m::level::kSessionCapacity, "X, Y, Z (#24..#26, mm, machine frame)", 9812, 9813, 9814},
    {"rigidity", m::rigidity::kSessionCapacity, "A, C (#1, #3, deg), ball centre X, Y, Z (#24..#26, mm)", 9830, 9831,
     9832},
    {"gantry", m::gantry::kSessionCapacity, "group T, Q, D (#20, #17, #7), point X, Y, Z (#24..#26, mm, tracker frame)",
     9820, 9821, 9823},
};

// The gantry's group capacities (docs/INTERFACE.md: "limited by capacities that the map states").
struct GroupCapacity {
  const char* group;
  std::size_t points;
};
const GroupCapacity kGantryGroups[] = {
    {"bed", m::gantry::kMaxPlanePoints},      {"side_1", m::gantry::kMaxPlanePoints},
    {"side_2", m::gantry::kMaxPlanePoints},   {"gantry_K", m::gantry::kMaxPassPoints},
    {"spN_x_K", m::gantry::kMaxPassPoints},   {"spN_y_K", m::gantry::kMaxPassPoints},
    {"spN_z_K", m::gantry::kMaxPassPoints},   {"spN_c", m::gantry::kMaxCirclePoints},
    {"spN_a", m::gantry::kMaxCirclePoints},
};

const char* var_name(std::uint16_t number) {
  const m::VarInfo* v = m::find_var(number);
  return v != nullptr ? v->name : "?";
}

bool method_built(const char* method) {
  for (const m::MacroSource& src : m::kMacroSources) {
    if (std::strcmp(src.method, method) == 0) return true;
  }
  return false;
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
  for (const m::MacroSource& src : m::kMacroSources) {
    for (std::size_t i = 0; i < src.count; ++i) {
      const m::MacroInfo& mi = src.macros[i];
      std::printf("%s\n    {\"number\": %u, \"name\": \"%s\", \"method\": \"%s\", \"description\": \"%s\",",
                  first ? "" : ",", mi.number, mi.name, src.method, escaped(mi.description).c_str());
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
  for (const m::MethodBlock& b : m::kMethodBlocks) {
    std::printf("%s\n    {\"name\": \"%s\", \"config_block\": [%u, %u], \"data_block\": [%u, %u], \"built\": %s",
                first ? "" : ",", b.method, b.config_first, b.config_last, b.data_first, b.data_last,
                method_built(b.method) ? "true" : "false");
    for (const SessionDoc& sd : kSessions) {
      if (std::strcmp(sd.method, b.method) == 0) {
        std::printf(",\n     \"session\": {\"capacity\": %zu, \"sample\": \"%s\", \"clear\": %u, \"add\": %u, "
                    "\"compute\": %u}",
                    sd.capacity, sd.sample, sd.clear, sd.add, sd.compute);
      }
    }
    if (std::strcmp(b.method, "gantry") == 0) {
      std::printf(",\n     \"group_capacity\": {");
      for (std::size_t i = 0; i < sizeof kGantryGroups / sizeof kGantryGroups[0]; ++i) {
        std::printf("%s\"%s\": %zu", i == 0 ? "" : ", ", kGantryGroups[i].group, kGantryGroups[i].points);
      }
      std::printf("}, \"passes\": %zu, \"sub_machines\": %zu", static_cast<std::size_t>(m::gantry::kMaxPasses),
                  trueaxis::core::kMaxSubMachines);
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
  for (const core::StatusInfo& s : core::kStatusTable) {
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
  std::printf("\n## Methods and their blocks\n\nEach method defines variables only inside its blocks; blocks of "
              "methods not built yet are reserved.\n\n| method | configuration | data | built | session |\n"
              "|---|---|---|---|---|\n");
  for (const m::MethodBlock& b : m::kMethodBlocks) {
    std::string session = "";
    for (const SessionDoc& sd : kSessions) {
      if (std::strcmp(sd.method, b.method) == 0) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "%zu samples of %s; clear %u, add %u, compute %u", sd.capacity, sd.sample,
                      sd.clear, sd.add, sd.compute);
        session = buf;
      }
    }
    if (std::strcmp(b.method, "gantry") == 0) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "; at most %zu points per plane, %zu per pass, %zu per circle, %zu passes per axis",
                    static_cast<std::size_t>(m::gantry::kMaxPlanePoints),
                    static_cast<std::size_t>(m::gantry::kMaxPassPoints),
                    static_cast<std::size_t>(m::gantry::kMaxCirclePoints),
                    static_cast<std::size_t>(m::gantry::kMaxPasses));
      session += buf;
    }
    std::printf("| %s | #%u..#%u | #%u..#%u | %s | %s |\n", b.method, b.config_first, b.config_last, b.data_first,
                b.data_last, method_built(b.method) ? "yes" : "reserved", session.c_str());
  }
  std::printf("\n## Macros\n\nEvery macro runs in steps of at most %u Cortex-M7 instructions "
              "(#9008 tells how many steps the last one took).\n",
              static_cast<unsigned>(m::Module::kStepBoundInstructions));
  for (const m::MacroSource& src : m::kMacroSources) {
    for (std::size_t i = 0; i < src.count; ++i) {
      const m::MacroInfo& mi = src.macros[i];
      std::printf("\n### %u %s (%s)\n\n%s\n\n| | variables |\n|---|---|\n", mi.number, mi.name, src.method,
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
  for (const core::StatusInfo& s : core::kStatusTable) {
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
