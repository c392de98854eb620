// The canary's flow: SAMPLES.csv's values -> session 9851/9852 -> sum 9853
// (stored with --store) -> OUT.json {"method": "canary", "sum": ...}.
#include <string>
#include <vector>

#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

namespace {

namespace var = macros::var;

constexpr std::uint16_t kClear = 9851;
constexpr std::uint16_t kAdd = 9852;
constexpr std::uint16_t kSum = 9853;
constexpr std::uint16_t kStored = 9854;

FlowResult calibrate_canary(VariableClient& client, const CalibrateOptions& options) {
  FlowResult r;
  {
    CsvReader reader(options.in_path, {{"value"}});  // first pass: every row checked
    CsvRow row;
    while (reader.next(row)) {
    }
    if (!reader.error().empty()) {
      r.error = reader.error();
      return r;
    }
  }
  if (!run_or_fail(client, kClear, "", r)) return r;
  CsvReader reader(options.in_path, {{"value"}});
  CsvRow row;
  while (reader.next(row)) {
    const std::string where = options.in_path + ":" + std::to_string(row.line);
    if (!client.write(var::kArgA, 1, &row.numbers[0])) {
      r.error = refused_sample(client, where, r);
      return r;
    }
    if (!run_or_fail(client, kAdd, where, r)) return r;
  }
  if (!hand_time(client, options.log_time, r)) return r;
  if (!transport(client, client.write_one(var::kArgR, 0.0), r)) return r;
  if (!run_or_fail(client, kSum, "", r)) return r;
  double sum = 0.0;
  if (!transport(client, client.read(100, 1, &sum), r)) return r;
  r.json = "{\n  \"method\": \"canary\",\n  \"sum\": " + json_number(sum) + "\n}\n";
  r.summary = "canary: the gain times the sum " + json_number(sum);
  r.ok = true;
  return r;
}

bool store_canary(VariableClient& client, FlowResult& fail) { return store_built(client, kSum, fail); }

}  // namespace

const CalibrateMethod& calibrate_method_canary() {
  static const CalibrateMethod kMethod{"canary", "the canary: a sum of values",
                                       "SAMPLES.csv: value\n  value   a number (1..4 rows)\nMACHINE.csv: not read.\n",
                                       calibrate_canary, store_canary, "canary", nullptr, kStored, 0.0};
  return kMethod;
}

}  // namespace trueaxis::sim
