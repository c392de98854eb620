// trueaxis-calibrate's one table of methods: a fold over the methods built
// into the module that have a calibrate flow (host_methods.hpp, generated from
// the one list; each entry is its method's calibrate_method_<name>(), in
// methods/<name>/host).
#include "trueaxis/sim/tools/calibrate.hpp"

#include <string>
#include <vector>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"

namespace trueaxis::sim {

bool has_stored_table(VariableClient& client, const CalibrateMethod& method, bool& has, FlowResult& fail) {
  const double qr[2] = {method.stored_query_q, 1.0};  // Q, R = 1: the stored table
  if (!client.write(macros::var::kArgQ, 2, qr)) {
    fail.error = client.failure_text();
    return false;
  }
  const MacroOutcome outcome = client.run_macro(method.stored_query, 20000);
  if (outcome.status != 2 && outcome.status != 3) {
    fail.error = client.failure_text() + " while asking for the stored table (macro " +
                 std::to_string(method.stored_query) + ")";
    return false;
  }
  // Any answer but no_table means a table was stored (a damaged one too).
  has = !(outcome.status == 3 && outcome.error == static_cast<int>(core::Status::kNoTable));
  return true;
}

CalibrateMethods calibrate_methods() {
  static const std::vector<CalibrateMethod> kMethods = [] {
    std::vector<CalibrateMethod> all;
    for (const auto& of : kCalibrateMethodsOf) all.push_back(of());
    return all;
  }();
  return {kMethods.data(), kMethods.size()};
}

const macros::RecordSpec* stored_record(const char* name) {
  using Built = macros::BuiltMethods;
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    if (std::string(Built::kNames[i]) == name && Built::kHasTable[i]) return &Built::kTableRecordOf[i];
  }
  return nullptr;
}

macros::CheckInfo check_of(const char* name) {
  using Built = macros::BuiltMethods;
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    if (std::string(Built::kNames[i]) == name) return Built::kChecks[i];
  }
  return {};
}

const CalibrateMethod* find_calibrate_method(const std::string& name) {
  for (const CalibrateMethod& m : calibrate_methods()) {
    if (name == m.name) return &m;
  }
  return nullptr;
}

std::string spoken_list(const std::vector<const char*>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ");
    text += names[i];
  }
  return text;
}

std::string calibrate_method_names() {
  std::vector<const char*> names;
  for (const CalibrateMethod& m : calibrate_methods()) names.push_back(m.name);
  return spoken_list(names);
}

}  // namespace trueaxis::sim
