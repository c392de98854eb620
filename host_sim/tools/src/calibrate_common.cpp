#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/log_reader.hpp"
#include "trueaxis/sim/tools/sha256.hpp"

namespace trueaxis::sim {

std::string module_error_text(int code) {
  const auto status = static_cast<core::Status>(code);
  return "module error " + std::to_string(code) + " " + macros::status_name(status) + ": " +
         macros::status_message(status);
}

bool module_refused(const FlowResult& fail, int status) {
  const std::string text = module_error_text(status);
  return fail.error.find(text) != std::string::npos;
}

namespace {
std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
constexpr std::int64_t kProgressMs = 2000;
}  // namespace

Progress::Progress(std::string what, std::string unit)
    : what_(std::move(what)), unit_(std::move(unit)), start_ms_(now_ms()), last_ms_(start_ms_) {}

void Progress::update(std::uint64_t done, std::uint64_t total) {
  const std::int64_t now = now_ms();
  if (now - last_ms_ < kProgressMs) return;
  last_ms_ = now;
  std::fprintf(stderr, "trueaxis-calibrate: %s: %llu of %llu %s\n", what_.c_str(), static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total), unit_.c_str());
}

namespace {
// What a gate of `macro`'s method refused (#9012 .. #9014, gates.hpp), "" when
// no gate did: the gate by its name and what it judges (the JSON map's
// "gates"), the item by what it is (the flow's check_items: a pose's A, a
// sub-machine; else its number), the figure and the limit with the
// configuration variable that sets it.
std::string gate_text(VariableClient& client, std::uint16_t macro, int code, const FlowResult& fail) {
  double g[3] = {0.0, 0.0, 0.0};
  if (!client.read(macros::var::kGateItem, 3, g) || (g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0)) return "";
  const macros::GateInfo* gate = nullptr;
  const macros::MacroEntry entry = macros::find_macro_entry(macro);
  if (entry.info != nullptr) {
    for (const macros::GateInfo& info : macros::BuiltMethods::kGates[entry.method]) {
      if (static_cast<int>(info.status) == code) gate = &info;
    }
  }
  std::string text = "; ";
  if (gate != nullptr) text += std::string("gate ") + gate->name + " (" + gate->what + ")";
  const int item = static_cast<int>(g[0]);
  if (item > 0) {
    const auto named = fail.check_items.find(item);
    char what[80];
    if (named != fail.check_items.end() && named->second.key == "a_deg") {
      std::snprintf(what, sizeof what, " at pose %d (A = %g deg)", item, named->second.value);
    } else if (named != fail.check_items.end() && named->second.key == "sub_machine") {
      std::snprintf(what, sizeof what, " at sub-machine %d", item);
    } else {
      std::snprintf(what, sizeof what, " at item %d", item);
    }
    text += what;
  }
  char figures[240];
  if (code == static_cast<int>(core::Status::kFitBeyondNoise)) {
    std::snprintf(figures, sizeof figures, ": the residuals' chi-square statistic is %.4g times its quantile at #%u's "
                  "confidence (limit 1): more scatter than the stated noise", g[1],
                  static_cast<unsigned>(macros::var::kGateConfidence));
    return text + figures;
  }
  // The limit is one of the gate's configuration variables: the one that holds it now.
  const macros::VarInfo* limit = nullptr;
  for (int k = 0; gate != nullptr && k < 3 && limit == nullptr; ++k) {
    double now = 0.0;
    if (gate->thresholds[k] != 0 && client.read_one(gate->thresholds[k], now) && now == g[2]) {
      limit = macros::find_var(gate->thresholds[k]);
    }
  }
  const std::string unit = limit != nullptr && limit->unit[0] != '\0' ? std::string(" ") + limit->unit : "";
  std::snprintf(figures, sizeof figures, ": %.6g%s against the limit %.6g%s", g[1], unit.c_str(), g[2], unit.c_str());
  text += figures;
  if (limit != nullptr) text += " (#" + std::to_string(limit->number) + " " + limit->name + ")";
  return text;
}
}  // namespace

namespace {
// Contract 5: what was under way when the connection failed.
std::string under_way(const FlowResult& fail) { return fail.stage.empty() ? "" : " while " + fail.stage; }
}  // namespace

bool run_or_fail(VariableClient& client, std::uint16_t macro, const std::string& context, FlowResult& fail) {
  const MacroOutcome outcome = client.run_macro(macro, 20000);
  if (outcome.status == 2) return true;
  const std::string where = context.empty() ? "" : context + ": ";
  if (outcome.status == 3) {
    fail.error = where + module_error_text(outcome.error) + " (macro " + std::to_string(macro) +
                 gate_text(client, macro, outcome.error, fail) + ")";
  } else if (client.exception() != 0) {  // the command was refused: not the sample's doing, no line named
    fail.error = "macro " + std::to_string(macro) + " not started: " + client.failure_text();
  } else {
    fail.transport_failed = true;
    fail.macro_started = outcome.started;
    const std::string state = " (macro " + std::to_string(macro) + (outcome.started ? " sent, its end not seen)" : " not sent)");
    fail.error = fail.stage.empty() ? where + "macro " + std::to_string(macro) + " did not finish: Modbus: " + client.error_text()
                                    : "Modbus: " + client.error_text() + under_way(fail) + state;
  }
  return false;
}

bool transport(VariableClient& client, bool ok, FlowResult& fail) {
  if (!ok) {
    fail.error = client.failure_text();
    if (client.exception() == 0) {
      fail.transport_failed = true;
      fail.error += under_way(fail);
    }
  }
  return ok;
}

bool hand_time(VariableClient& client, double unix_s, FlowResult& fail) {
  if (!(unix_s > 0.0) || client.write_one(macros::var::kLogTime, unix_s)) return true;
  // Never the controller's clock instead of the time asked for: the entry
  // would carry another date (and a drift another slope).
  fail.error = "the controller refused the measuring log's time #9015 = " + json_number(unix_s) +
               " (--time: Unix seconds 1 .. 4294967295): " + client.failure_text() + "; nothing was stored";
  return false;
}

bool store_built(VariableClient& client, std::uint16_t build_macro, FlowResult& fail,
                 const std::vector<MacroArgument>& arguments) {
  namespace var = macros::var;
  fail.stage = "storing (macro " + std::to_string(build_macro) + ", R = 1)";
  if (!transport(client, client.write_one(var::kUnlock, fail.unlock_code), fail)) return false;
  // The same session computed again, now stored: the computation is
  // deterministic, so what is stored is what OUT.json describes.
  bool stored = true;
  for (const MacroArgument& a : arguments) {
    stored = stored && transport(client, client.write_one(a.number, a.value), fail);
  }
  stored = stored && hand_time(client, fail.log_time, fail);
  stored = stored && transport(client, client.write_one(var::kArgR, 1.0), fail) &&
           (!fail.accept_change || transport(client, client.write_one(var::kArgM, 1.0), fail)) &&
           run_or_fail(client, build_macro, "", fail);
  if (!stored && module_refused(fail, static_cast<int>(core::Status::kChangeBeyondLimit))) {
    fail.error += " (trueaxis-calibrate --accept-change stores it: check the machine first)";
  }
  fail.stored = stored;
  fail.stage = "locking the controller again after the store";
  const bool locked = client.write_one(var::kUnlock, 0.0);  // lock again, whatever happened
  if (stored && !locked) {
    fail.transport_failed = client.exception() == 0;
    fail.error = "the controller could not be locked again: " + client.failure_text() +
                 " (an unlock closes with its connection, or 300 s after its last write)";
  }
  return stored && locked;
}

std::string json_number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string with_member(const std::string& object, const std::string& member) {
  const std::size_t close = object.rfind('}');
  if (close == std::string::npos) return "{\n  " + member + "\n}\n";
  std::size_t end = close;
  while (end > 0 && (object[end - 1] == '\n' || object[end - 1] == ' ')) --end;
  const bool empty = end > 0 && object[end - 1] == '{';
  return object.substr(0, end) + (empty ? "\n  " : ",\n  ") + member + "\n}\n";
}

std::string json_vec3(const double* v) {
  return "[" + json_number(v[0]) + ", " + json_number(v[1]) + ", " + json_number(v[2]) + "]";
}

std::string refused_sample(VariableClient& client, const std::string& where, FlowResult& fail) {
  // Exceptions 02 and 03 are about the values written (their range, their
  // finiteness): the line is named. Anything else (the interface held, a macro
  // running, the transport) is not the line's doing.
  const int exception = client.exception();
  const std::string why = client.failure_text();
  if (exception == 2 || exception == 3) return where + ": the module refused the sample: " + why;
  if (exception == 0) {
    fail.transport_failed = true;
    return why + under_way(fail);
  }
  return why;
}

namespace {
// A number, or null when it is not finite (JSON has no NaN; the figure then fails, check.hpp).
std::string json_value(double v) { return std::isfinite(v) ? json_number(v) : "null"; }

// The stored calibration a check has just judged: its table sequence (the
// check's entry in the measuring log, #9026), when it was stored (the log's
// entry of the store that made that sequence), and the SHA-256 of its record
// as the module exports it (the method's kins_file: M3 9837, M4 9847; M2 has
// no exact export). The "stored_calibration" member of OUT.json's check;
// r.log_rows keeps the log read. A part that cannot be had is null, and
// "note" says why.
std::string stored_calibration(VariableClient& client, const CalibrateMethod& method, FlowResult& r) {
  std::string note;
  std::string error;
  r.log_read = read_log(client, r.log_rows, error);
  const LogRow* check = nullptr;
  const LogRow* store = nullptr;
  if (!r.log_read) {
    note = "the module's measuring log could not be read (" + error + "): no table sequence, no date";
  } else {
    for (const LogRow& row : r.log_rows) {
      if (row.method == method.name && row.check) check = &row;
    }
    for (const LogRow& row : r.log_rows) {
      if (check != nullptr && row.method == method.name && row.stored && row.table_sequence == check->table_sequence) {
        store = &row;
      }
    }
    if (check == nullptr) {
      note = "the module's measuring log holds no entry of this check";
    } else if (store == nullptr) {
      note = "the store of table sequence " + std::to_string(check->table_sequence) +
             " is no longer in the module's measuring log (its newest 32 entries): no date";
    } else if (store->time_s == 0) {
      note = "the store was logged without a time";
    }
  }
  const macros::RecordSpec* spec = stored_record(method.name);
  std::string sha = "null";
  std::size_t bytes = 0;
  if (method.kins_file == nullptr) {
    note += std::string(note.empty() ? "" : "; ") + method.name +
            " has no exact export of its stored record (no macro gives its bytes): it is named by its table sequence "
            "and the time of its store";
  } else {
    std::string file;
    FlowResult exported;
    const std::uint8_t* payload = nullptr;
    if (spec != nullptr && method.kins_file(client, true, file, exported) &&
        macros::decode_record_file(static_cast<std::uint8_t>(spec->key), reinterpret_cast<const std::uint8_t*>(file.data()),
                                   file.size(), payload, bytes) == macros::RecordFileError::kNone) {
      sha = "\"" + sha256_hex(payload, bytes) + "\"";
    } else {
      bytes = 0;
      note += std::string(note.empty() ? "" : "; ") + "the stored record could not be exported (" +
              (exported.error.empty() ? "not a valid record" : exported.error) + "): no hash";
    }
  }
  const bool timed = store != nullptr && store->time_s != 0;
  return "\"stored_calibration\": { \"table_sequence\": " +
         (check != nullptr ? std::to_string(check->table_sequence) : std::string("null")) +
         ", \"stored_time_s\": " + (timed ? std::to_string(store->time_s) : std::string("null")) +
         ", \"stored_time_utc\": " + (timed ? json_string(utc_text(store->time_s)) : std::string("null")) +
         ",\n    \"record\": " +
         (spec != nullptr ? json_string("record " + std::to_string(spec->key) + " " + spec->name) : std::string("null")) +
         ", \"record_bytes\": " + (sha == "null" ? std::string("null") : std::to_string(bytes)) +
         ", \"record_sha256\": " + sha + (note.empty() ? "" : ",\n    \"note\": " + json_string(note)) + " }";
}
}  // namespace

bool check_built(VariableClient& client, const CalibrateMethod& method, FlowResult& r, macros::Verdict& verdict) {
  namespace var = macros::var;
  const macros::CheckInfo info = check_of(method.name);
  if (info.macro == 0) {
    r.error = std::string(method.name) + " has no check in this module";
    return false;
  }
  const auto run_q = [&](double q, double* out) {
    if (q == 0.0 && !hand_time(client, r.log_time, r)) return false;  // the check's entry in the measuring log
    if (!transport(client, client.write_one(var::kArgQ, q), r)) return false;
    if (!run_or_fail(client, info.macro, "", r)) {
      if (module_refused(r, static_cast<int>(core::Status::kNoTable))) {
        r.error += ": no stored calibration to check against (store one first: trueaxis-calibrate " +
                   std::string(method.name) + " --store)";
      }
      return false;
    }
    return transport(client, client.read(var::kCheckVerdict, 12, out), r);
  };
  double v[12];  // #100..#111 (check.hpp convention 3)
  r.stage = "running the check (macro " + std::to_string(info.macro) + ")";
  if (!run_q(0.0, v)) return false;
  verdict = static_cast<macros::Verdict>(static_cast<int>(v[0]));
  const int count = static_cast<int>(v[1]);
  const int worst = static_cast<int>(v[2]);
  std::string figures;
  std::string worst_line;
  for (int q = 1; q <= count; ++q) {
    double f[12];
    if (!run_q(q, f)) return false;
    const std::size_t kind = static_cast<std::size_t>(f[5]);
    const bool known = kind >= 1 && kind <= info.figures.size;
    const std::string kind_name = known ? info.figures[kind - 1].name : "figure_" + std::to_string(kind);
    const std::string unit = known ? info.figures[kind - 1].unit : "";
    // Named by what the item is (the pose's A, the sub-machine), not its number.
    const int item = static_cast<int>(f[6]);
    const auto named = r.check_items.find(item);
    const bool is_named = item > 0 && named != r.check_items.end();
    const std::string name =
        item <= 0 ? kind_name : kind_name + "_" + (is_named ? named->second.suffix : std::to_string(item));
    const std::string item_key =
        is_named ? ", \"" + named->second.key + "\": " + json_value(named->second.value) : std::string();
    const macros::Verdict fv = static_cast<macros::Verdict>(static_cast<int>(f[4]));
    figures += q > 1 ? ",\n" : "\n";
    figures += "      { \"name\": \"" + name + "\", \"kind\": \"" + kind_name + "\", \"item\": " +
               std::to_string(item) + item_key + ", \"unit\": \"" + unit + "\", \"verdict\": \"" + macros::verdict_name(fv) +
               "\",\n        \"stored\": " + json_value(f[7]) + ", \"measured\": " + json_value(f[8]) +
               ", \"deviation\": " + json_value(f[9]) + ", \"sigma\": " + json_value(f[10]) +
               ", \"tolerance\": " + json_value(f[11]) + " }";
    if (q == worst) {
      char line[200];
      std::snprintf(line, sizeof line, "worst %s: %.4g +- %.2g %s against %g", name.c_str(), f[9], f[10],
                    unit.c_str(), f[11]);
      worst_line = line;
    }
  }
  const std::string judged = stored_calibration(client, method, r);
  r.json = with_member(r.json, "\"check\": { \"verdict\": \"" + std::string(macros::verdict_name(verdict)) +
                                    "\", \"worst\": " + std::to_string(worst) + ",\n    " + judged +
                                    ",\n    \"figures\": [" + figures + "\n  ] }");
  r.summary += "; check: " + std::string(macros::verdict_name(verdict)) + " (" + worst_line + ")";
  return true;
}

}  // namespace trueaxis::sim
