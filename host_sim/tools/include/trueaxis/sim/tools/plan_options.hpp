// One method's `trueaxis-calibrate plan METHOD` (planner.hpp): its options, its
// help and its model. The command (calibrate_main.cpp) knows no method's
// options: it hands each option to the method's PlanOptions and asks it for
// the model. A method with a plan defines plan_options_<name>() in its host
// folder (methods/<name>/host) and says PLAN in its trueaxis_method entry; the
// command's list of them is a fold over the one list (host_methods.hpp).
//
// Contract
//  1. take() is called once per option after METHOD, with the next argument
//     as `value` (has = false when there is none): kNotMine when `arg` is not
//     the method's, kTaken when it took the option and its value, kBad when it
//     is the method's but the value is missing or out of range (then `form`
//     says what it takes, for the one-line usage error).
//  2. finish() is called once, after every option: the plan's model, or
//     nullptr with `error` (a usage error when `usage`, else a failure such as
//     an unreadable file).
//  3. hint() is a line (with its newline) the command prints after a refused
//     prediction's table, or "".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "trueaxis/sim/tools/planner.hpp"

namespace trueaxis::sim {

class PlanOptions {
 public:
  enum class Take { kNotMine, kTaken, kBad };

  virtual ~PlanOptions() = default;
  // "  NAME  --option ... (default)\n" lines for `plan --help`.
  virtual const char* help() const = 0;
  virtual Take take(const std::string& arg, const std::string& value, bool has, std::string& form) = 0;
  virtual std::shared_ptr<const PlanModel> finish(std::string& error, bool& usage) = 0;
  virtual std::string hint(const PlanPrediction& prediction) const {
    (void)prediction;
    return "";
  }
};

// A method with a plan, as the fold lists it.
struct PlanMethod {
  const char* name;
  std::unique_ptr<PlanOptions> (*make)();
};

// The values plan options take (each false on anything else): `count`
// comma-separated numbers; a whole number in low..high; a number > 0.
bool plan_numbers(const std::string& text, std::size_t count, std::vector<double>& out);
bool plan_whole(const std::string& text, int low, int high, int& out);
bool plan_positive(const std::string& text, double& out);

}  // namespace trueaxis::sim
