#include <chrono>
#include <cstdio>
#include <utility>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"

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

bool run_or_fail(VariableClient& client, std::uint16_t macro, const std::string& context, FlowResult& fail) {
  const MacroOutcome outcome = client.run_macro(macro, 20000);
  if (outcome.status == 2) return true;
  const std::string where = context.empty() ? "" : context + ": ";
  if (outcome.status == 3) {
    fail.error = where + module_error_text(outcome.error) + " (macro " + std::to_string(macro) + ")";
  } else if (client.exception() != 0) {  // the command was refused: not the sample's doing, no line named
    fail.error = "macro " + std::to_string(macro) + " not started: " + client.failure_text();
  } else {
    fail.error = where + "macro " + std::to_string(macro) + " did not finish: " + client.error_text();
  }
  return false;
}

bool transport(VariableClient& client, bool ok, FlowResult& fail) {
  if (!ok) fail.error = client.failure_text();
  return ok;
}

bool store_built(VariableClient& client, std::uint16_t build_macro, FlowResult& fail,
                 const std::vector<MacroArgument>& arguments) {
  namespace var = macros::var;
  if (!transport(client, client.write_one(var::kUnlock, fail.unlock_code), fail)) return false;
  // The same session computed again, now stored: the computation is
  // deterministic, so what is stored is what OUT.json describes.
  bool stored = true;
  for (const MacroArgument& a : arguments) {
    stored = stored && transport(client, client.write_one(a.number, a.value), fail);
  }
  stored = stored && transport(client, client.write_one(var::kArgR, 1.0), fail) &&
           run_or_fail(client, build_macro, "", fail);
  const bool locked = client.write_one(var::kUnlock, 0.0);  // lock again, whatever happened
  if (stored && !locked) fail.error = "the controller could not be locked again: " + client.failure_text();
  return stored && locked;
}

std::string json_number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_vec3(const double* v) {
  return "[" + json_number(v[0]) + ", " + json_number(v[1]) + ", " + json_number(v[2]) + "]";
}

std::string refused_sample(VariableClient& client, const std::string& where) {
  // Exceptions 02 and 03 are about the values written (their range, their
  // finiteness): the line is named. Anything else (the interface held, a macro
  // running, the transport) is not the line's doing.
  const int exception = client.exception();
  const std::string why = client.failure_text();
  return exception == 2 || exception == 3 ? where + ": the module refused the sample: " + why : why;
}

}  // namespace trueaxis::sim
