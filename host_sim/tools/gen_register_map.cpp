// trueaxis-map: writes the register map, generated from the code's tables, as
// JSON (default) or as the human page (--markdown). The committed
// macros/register_map.json and macros/REGISTER_MAP.md are this program's output;
// the test register_map_is_current fails when they differ.
#include <cstdio>
#include <cstring>
#include <string>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/macro_table.hpp"
#include "trueaxis/macros/register_codec.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/sim_map.hpp"

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

int as_int(m::AccessFault f) { return static_cast<int>(f); }
int as_int(m::ModbusException e) { return static_cast<int>(e); }

template <std::size_t N>
void json_variables(const m::VarInfo (&table)[N], bool sim_only, bool& first) {
  for (const m::VarInfo& v : table) {
    std::printf("%s\n    {\"number\": %u, \"count\": %u, \"register\": %u, \"name\": \"%s\", \"access\": \"%s\", "
                "\"kind\": \"%s\", \"min\": %.17g, \"max\": %.17g, \"default\": %.17g, \"unit\": \"%s\", "
                "\"persistent\": %s, \"simulator_only\": %s,\n     \"description\": \"%s\"}",
                first ? "" : ",", v.number, v.count, static_cast<unsigned>(m::register_of(v.number)), v.name,
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
      m::kMaxVariablesPerRead, m::kMaxVariablesPerWrite);
  std::printf("  \"unlock_code\": %d,\n", static_cast<int>(m::kUnlockCode));
  std::printf("  \"macro_status\": {\"0\": \"idle\", \"1\": \"busy\", \"2\": \"done\", \"3\": \"error\"},\n");
  std::printf("  \"variables\": [");
  bool first = true;
  json_variables(m::kRegisterMap, false, first);
  json_variables(trueaxis::sim::kSimMap, true, first);
  std::printf("\n  ],\n  \"macros\": [");
  first = true;
  for (const m::MacroInfo& mi : m::kMacroTable) {
    std::printf("%s\n    {\"number\": %u, \"name\": \"%s\", \"description\": \"%s\"}", first ? "" : ",", mi.number,
                mi.name, escaped(mi.description).c_str());
    first = false;
  }
  std::printf("\n  ],\n  \"errors\": [");
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

template <std::size_t N>
void markdown_rows(const m::VarInfo (&table)[N]) {
  for (const m::VarInfo& v : table) {
    char number[32];
    if (v.count == 1) {
      std::snprintf(number, sizeof number, "#%u", v.number);
    } else {
      std::snprintf(number, sizeof number, "#%u..#%u", v.number, v.number + v.count - 1);
    }
    std::printf("| %s | %u | %s | %s | %s | %s | %.10g | %s |\n", number,
                static_cast<unsigned>(m::register_of(v.number)), v.name, access_name(v.access), v.unit,
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
      static_cast<int>(m::kInterfaceVersionValue), m::kMaxVariablesPerRead, m::kMaxVariablesPerWrite,
      static_cast<int>(m::kUnlockCode));
  const char* header =
      "| variable | register | name | access | unit | range | default | meaning |\n"
      "|---|---|---|---|---|---|---|---|\n";
  std::printf("## Module variables\n\n%s", header);
  markdown_rows(m::kRegisterMap);
  std::printf("\n## Simulator-only variables\n\nServed by `trueaxis-sim` only; never by the module in a "
              "controller.\n\n%s", header);
  markdown_rows(trueaxis::sim::kSimMap);
  std::printf("\n## Macros\n\n| number | name | what it does |\n|---|---|---|\n");
  for (const m::MacroInfo& mi : m::kMacroTable) std::printf("| %u | %s | %s |\n", mi.number, mi.name, mi.description);
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

int main(int argc, char** argv) {
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
