// trueaxis-calibrate: the integrator's command (docs/INTERFACE.md, "The
// integrator's command"). Its methods as one table (calibrate_methods()), and the
// shared pieces of their flows: options, the connection to the module, failures
// as one line, and the JSON writer. Host only.
//
// Contract
//  1. Every flow reads its CSV files, streams the samples to the module over
//     Modbus, runs the method's macros there, and returns the JSON text of what
//     the module computed; it computes nothing of the method itself.
//  2. A failure is one line for stderr: "FILE:LINE: what" for a bad sample,
//     "module error CODE NAME: MESSAGE" for a macro the module refused (with the
//     sample's file and line when a sample caused it, and what the flow knows
//     beyond the module: the group, pose or ball concerned, the likely cause),
//     or a transport problem. The caller then writes no JSON and exits 1; with
//     --store the module has stored nothing and is locked again: the command
//     stores last, after the JSON is written and the report is made (each to
//     a temporary beside its target), and only then moves both into place.
//  3. On success a flow also gives a summary: "METHOD: what was computed, the
//     worst figure with its sigma", the start of the command's one stdout line.
//  4. A samples file is read twice, one row at a time (CsvReader): first
//     checked whole, then streamed to the module, so its length costs no
//     memory (the gantry keeps its rows to sort them, at most the session's
//     capacity: a longer file is refused at the first row beyond it). Work
//     that takes more than 2 s reports its progress on stderr (Progress).
//  5. A transport failure (the connection reset, a time-out) says what was
//     under way (FlowResult::stage: which sample of which file, the build,
//     the report query, the check, the store) and, through the command, what
//     became of the store: nothing stored, not known (the connection failed
//     after the store's macro was sent), or stored (a failure after it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/log_reader.hpp"

namespace trueaxis::sim {

struct CalibrateOptions {
  std::string method;
  std::string in_path;
  std::string json_path;
  std::string machine_path;  // "" when absent
  std::string report_dir;    // "" when absent
  std::string linuxcnc_comp_path;  // --linuxcnc-comp (rigidity): "" when absent
  std::string linuxcnc_kins_path;  // --linuxcnc-kins (rigidity, with --store): "" when absent
  // --sub-machines (gantry): the sub-machines this session measures, each
  // 1..8 once; empty: every sub-machine MACHINE gives (calibrate_gantry).
  std::vector<int> sub_machines;
  bool store = false;
  bool check = false;          // --check: compare with the stored calibration (check.hpp), store nothing
  std::string operator_name;   // --operator NAME: who measured, for the report
  std::string machine_name;    // --machine-name NAME: the machine's name with letters, for the report (#902 holds a number)
  bool accept_change = false;  // --accept-change: the store's M = 1 (gates.hpp, change)
  double unlock_code = macros::kUnlockCode;  // --unlock-code: the machine's own (#900)
  std::string host = "127.0.0.1";
  int port = 502;
  int wait_s = 120;  // --wait: for the macro interface another client holds
  double log_time = 0.0;  // --time (default now): the measuring log's time, Unix seconds (#9015)
};

// #number = value: one argument of a macro.
struct MacroArgument {
  std::uint16_t number = 0;
  double value = 0.0;
};

struct FlowResult {
  bool ok = false;
  std::string error;          // one line, when !ok
  std::string json;           // the OUT.json text, when ok
  std::string report_extras;  // JSON of the module's figures beyond OUT.json, for the report
  std::string summary;        // contract 3, when ok
  // M3 (rigidity): the A positioning error as a LinuxCNC joint compensation
  // file for the A joint, COMP_FILE_TYPE 1 (rigidity_comp_file); "" otherwise.
  std::string linuxcnc_comp;
  // The build macro's arguments besides R, written again by the store (the
  // module clears the arguments after every macro); empty when it takes none.
  std::vector<MacroArgument> build_arguments;
  // The code the store unlocks with (CalibrateOptions::unlock_code).
  double unlock_code = macros::kUnlockCode;
  // The store confirms a change beyond the method's change limit (M = 1).
  bool accept_change = false;
  // The measuring log's time for the store and the check (CalibrateOptions::log_time).
  double log_time = 0.0;
  // What was under way (contract 5), after "while": "streaming sample 12 of
  // 252 of ball.csv:14", "running the build (macro 9832, R = 0), every sample
  // sent", "storing (macro 9832, R = 1)"; a transport failure names it.
  std::string stage;
  bool transport_failed = false;  // the failure was the connection's (a reset, a time-out), not a refusal
  bool macro_started = false;     // ... after the macro number was sent: whether it ran is not known
  bool stored = false;            // the store's macro succeeded (a later failure leaves the table stored)
  // What the check's items are (check.hpp figure item, the module's number):
  // item -> the suffix of the figure's name ("a-90": the pose at A = -90 deg,
  // "sp2": sub-machine 2) and the key OUT.json's figure adds ("a_deg": -90,
  // "sub_machine": 2). An item not here is named by its number.
  struct CheckItem {
    std::string suffix;
    std::string key;
    double value = 0.0;
  };
  std::map<int, CheckItem> check_items;
  // --check: the module's measuring log as check_built read it (for the
  // stored calibration judged and the report's drift); log_read false when
  // the module could not give it.
  std::vector<LogRow> log_rows;
  bool log_read = false;
  // The MACHINE values no data of this run could test (issue "Nothing wrong
  // reaches the machine", item 1): each with its value, its file and line and
  // what it is used for, listed in the report as taken as given; the summary
  // line names them in one clause, as_given_summary.
  std::vector<std::string> as_given;
  std::string as_given_summary;
};

// Hands the module the measuring log's time (#9015, Unix seconds) for the
// next macro (nothing for 0: the module's own clock). A write the module
// refuses is a failure, fail.error naming #9015, the value and why: the entry
// never takes the controller's clock instead, and the flow stores nothing.
bool hand_time(VariableClient& client, double unix_s, FlowResult& fail);

// The text of a module error code, "module error 402 session_full: The session is full ...".
std::string module_error_text(int code);

// True when fail.error reports module error `status` (module_error_text).
bool module_refused(const FlowResult& fail, int status);

// Contract 4: "trueaxis-calibrate: WHAT: DONE of TOTAL UNIT" on stderr, at
// most every 2 s and only once the work has taken 2 s.
class Progress {
 public:
  Progress(std::string what, std::string unit);
  void update(std::uint64_t done, std::uint64_t total);

 private:
  std::string what_;
  std::string unit_;
  std::int64_t start_ms_ = 0;
  std::int64_t last_ms_ = 0;
};

// Runs `macro` and turns anything but done into a FlowResult error; `context`
// (e.g. "samples.csv:12") is prefixed when not empty.
bool run_or_fail(VariableClient& client, std::uint16_t macro, const std::string& context, FlowResult& fail);

// The refusal of a sample's write: "FILE:LINE: the module refused the sample:
// WHY" when its values were refused (exception 02 or 03), else WHY alone,
// with what was under way (fail.stage) when it is the transport's (contract 5).
std::string refused_sample(VariableClient& client, const std::string& where, FlowResult& fail);

// `ok` as it is; when false, fail.error names the transport problem ("Modbus: ...").
bool transport(VariableClient& client, bool ok, FlowResult& fail);

// JSON pieces, numbers with 17 significant digits.
std::string json_number(double v);
std::string json_vec3(const double* v);
// The text of a JSON object with `member` ("key": value) added last.
std::string with_member(const std::string& object, const std::string& member);
// A JSON string literal of `text` (quotes, backslashes and control characters escaped).
std::string json_string(const std::string& text);

// Unlocks, runs `build_macro` with `arguments` and R = 1 on the session
// already in the module (the method stores what it computes), and locks again
// whatever happened; false with fail.error set when anything failed.
bool store_built(VariableClient& client, std::uint16_t build_macro, FlowResult& fail,
                 const std::vector<MacroArgument>& arguments = {});

// One method of trueaxis-calibrate: all the command knows of it. The command
// looks a method up by name in the one table (calibrate_methods()) and does
// what the entry says; nothing else in the command names a method. The record
// --store writes is the method descriptor's (stored_record()); a test holds the
// table to the module's method list (every method that stores a table has an
// entry, and every entry is such a method).
struct CalibrateMethod {
  const char* name;     // METHOD on the command line, OUT.json's "method"
  const char* title;    // what it calibrates, one line
  const char* files;    // the CSV files' columns with their units (METHOD --help)
  FlowResult (*calibrate)(VariableClient&, const CalibrateOptions&);  // streams, computes; stores nothing
  bool (*store)(VariableClient&, FlowResult&);  // stores the session's result: unlock, build, lock
  const char* report_module;  // host_sim/report/<report_module>.py draws --report
  // --linuxcnc-kins: the table built last (false) or stored (true) as the file
  // the LinuxCNC kinematics load (record_file.hpp); nullptr when they take none.
  bool (*kins_file)(VariableClient&, bool stored, std::string& file, FlowResult& fail);
  // A query of the stored table (R = 1, Q = stored_query_q): no_table when the
  // controller holds none, so that a store can say it is the first.
  std::uint16_t stored_query;
  double stored_query_q;
};

// Whether the controller holds a stored table of `method`: every answer of
// its stored_query but no_table says so (a damaged table too); false with
// `fail` set when the query got no answer.
bool has_stored_table(VariableClient& client, const CalibrateMethod& method, bool& has, FlowResult& fail);

// The check (check.hpp) of method `name` of the module's method list (its
// descriptor's kCheck): macro 0 when it has none or is not built.
macros::CheckInfo check_of(const char* name);

// --check (check.hpp): runs the method's check macro on the result the flow
// has just built (R = 0) against the stored calibration, adds OUT.json's
// "check" object (docs/INTERFACE.md "Check mode and the log") to r.json and
// the verdict to r.summary; verdict is set to the check's. The figures are
// named by r.check_items; "stored_calibration" names the calibration judged
// (its table sequence and store time from the measuring log, kept in
// r.log_rows, and the SHA-256 of the record the module exports). False with
// r.error set when the module refused (no stored calibration among others).
bool check_built(VariableClient& client, const CalibrateMethod& method, FlowResult& r, macros::Verdict& verdict);

// The record that method `name` of the module's method list stores its table
// in (the JSON map's "records"), or nullptr when it stores none or is not built.
const macros::RecordSpec* stored_record(const char* name);

// The table, in the order --help lists the methods.
struct CalibrateMethods {
  const CalibrateMethod* first;
  std::size_t count;
  const CalibrateMethod* begin() const { return first; }
  const CalibrateMethod* end() const { return first + count; }
};
CalibrateMethods calibrate_methods();

// The method called `name`; nullptr when there is none.
const CalibrateMethod* find_calibrate_method(const std::string& name);

// "rigidity, gantry or spindle": the methods' names, for messages.
std::string calibrate_method_names();

// "a, b or c": names as a sentence lists them.
std::string spoken_list(const std::vector<const char*>& names);

}  // namespace trueaxis::sim
