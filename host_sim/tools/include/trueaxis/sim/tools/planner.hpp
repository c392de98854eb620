// trueaxis-calibrate plan: the measurement judged before it is made (issue
// "The calibration lifecycle", item 4). Host only: it allocates.
//
// Contract
//  1. A plan is what an operator would measure: the poses (M3: A poses and
//     their C positions; M2: the gantry's groups; M4: the analyser's sampling
//     and ball depths; M1: the probe points) on a nominal machine, and the
//     instrument's noise. Its readings are the instrument's noise-free
//     readings of that machine (the simulator's virtual machine of the method,
//     whose errors are small enough that the sensitivities below are those of
//     any machine of its geometry), each with its noise covariance L L^T.
//  2. The prediction is the method's own computation linearised: the method's
//     firmware_core routine (the very code the module runs) is evaluated on
//     the readings and on each reading moved by one column of its L (one
//     sigma; forward differences), giving g_ij = f(moved) - f, and
//         Cov = sum_ij g_ij g_ij^T,
//     the covariance of the outputs to first order. Where the method is a
//     least-squares fit with the instrument's weights this is the inverse of
//     its Fisher information, mapped to the outputs; where it is a chain of
//     fits (M2, M3) it is that chain's own propagation, not an ideal
//     estimator's bound. A plan the method refuses is reported with the
//     module's error, as the module would refuse it.
//  3. Outputs: per method the figures OUT.json reports, each with its unit
//     and, where the check judges it (check.hpp), the check's default
//     tolerance. A check judges some figures by a vector's length (M3's
//     rotation vector, M2's origin and frame turn, M1's tilt): their
//     components share a `group`. The plan's valuation V is the largest of
//     q95 / tolerance over the judged figures, q95 the 95th percentile of the
//     figure's noise: 1.96 sigma for a scalar, the length's for a group (from
//     the group's covariance block; 2.80 sigma for three equal, independent
//     components). With V < 1 the plan's own noise stays within every
//     tolerance 95 % of the time. A check compares two such measurements and
//     adds a guard band of 2 sigma, so an unchanged machine passes a check
//     against a table from the same plan 95 % of the time only below about
//     V = 0.35 (scalar; 0.41 for a group of three).
//  4. Inseparable outputs: pairs whose correlation |rho| > kInseparable (the
//     plan moves them together; only their combination is measured), derived
//     outputs left out.
//  5. Suggestions: each method offers changes of about one pose's cost
//     (PlanModel::candidates: an A pose or the ball higher on its stem, a
//     probe point, a wider arc or one more pass, one more revolution); the
//     best change by the resulting valuation, then the best second change
//     after it (greedy).
//  6. The module's judgement first: a plan is refused as the module would
//     refuse its measurement, with the module's own sentence. The plan's
//     readings with one draw of the instrument's noise (a fixed seed: what a
//     measurement of the plan looks like; noise-free repeats would be refused
//     as duplicates) are streamed into a module built in this process, the
//     method's macros as trueaxis-calibrate runs them (clear, add every
//     reading, the MACHINE data, compute with R = 0), with the configuration
//     at its defaults but the instrument's stated noise, which the plan gives.
//     So every limit and gate the module applies to such data applies to the
//     plan (its capacities, argument ranges, the plausibility and fit gates);
//     the change gate needs a stored table and never trips. A refusal reads
//     "[WHAT: ]module error CODE NAME: MESSAGE (macro N[; item I (#9012): V
//     (#9013) against the limit L (#9014)])", WHAT the reading a sample
//     macro refused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/types.hpp"

namespace trueaxis::sim {

inline constexpr double kInseparable = 0.99;

// Contract 1: one reading, noise-free, and the factor of its noise covariance.
struct PlanReading {
  core::Vec3 value = core::Vec3::Zero();
  core::Mat3 noise_factor = core::Mat3::Zero();  // L: covariance L L^T (mm^2)
};

// Contract 3: one output of the method.
struct PlanOutput {
  std::string name;       // as OUT.json names it, with the item: "A=30 rotation_vector_x"
  std::string unit;       // "mm", "arcsec"
  double tolerance = 0.0;  // the check's default (same unit); 0: not judged
  bool derived = false;    // a function of other outputs (M1's A and C of its normal): never "not separated"
  int group = 0;           // > 0: a component of a vector the check judges by its length (contract 3)
};

class PlanModel;

// Contract 6: one macro of the plan's measurement as the module is given it.
struct PlanMacro {
  std::uint16_t macro = 0;
  std::vector<std::pair<std::uint16_t, double>> arguments;  // #N = value, written before it
  std::string what;  // the reading it carries ("reading 12 (A = 30, C = 40 deg)"), "" for none
};

// A change to a plan (contract 5) and the plan it makes.
struct PlanChange {
  std::string what;  // "add the A pose 45 deg (36 C positions)"
  std::shared_ptr<const PlanModel> plan;
};

// One method on one plan (contract 1).
class PlanModel {
 public:
  virtual ~PlanModel() = default;
  virtual const char* method() const = 0;
  // The plan in one line: "7 A poses -90..90 x 36 C, ball 1 um".
  virtual std::string description() const = 0;
  virtual const std::vector<PlanReading>& readings() const = 0;
  virtual const std::vector<PlanOutput>& outputs() const = 0;
  // The outputs from `values` (one per reading, in order) by the method's own
  // code; false with `error` the module's refusal ("module error 210 ...").
  virtual bool evaluate(const std::vector<core::Vec3>& values, std::vector<double>& out, std::string& error) const = 0;
  virtual std::vector<PlanChange> candidates() const = 0;
  // Contract 6: the configuration rows the plan states (#N = value: the
  // instrument's noise), and the macros of its measurement with `values`
  // (one per reading, in order) as their samples.
  virtual std::vector<std::pair<std::uint16_t, double>> module_configuration() const = 0;
  virtual std::vector<PlanMacro> module_macros(const std::vector<core::Vec3>& values) const = 0;
};

// Contract 6: "" when the module takes the plan's measurement, else its
// refusal in one line.
std::string module_refusal(const PlanModel& model);

// A pair of outputs the plan cannot separate (contract 4).
struct PlanInseparable {
  std::size_t first = 0;
  std::size_t second = 0;
  double rho = 0.0;
};

struct PlanPrediction {
  bool ok = false;
  std::string error;                   // when !ok: the method's refusal
  std::vector<PlanOutput> outputs;
  std::vector<double> value;           // at the noise-free readings
  std::vector<double> sigma;           // 1 sigma, contract 2
  std::vector<double> covariance;      // n x n, row-major
  double valuation = 0.0;              // contract 3
  std::size_t worst = 0;               // the output that gives it (a group's first component)
  std::vector<double> q95;             // per output: its figure's 95th percentile (contract 3; 0 unjudged)
  std::vector<PlanInseparable> inseparable;
  std::size_t readings = 0;
  std::size_t evaluations = 0;
};

// Contract 2; `progress` (may be empty) is told evaluations done of total.
// A plan with more than kMaxPlanReadings readings is refused (each of its 3 n
// evaluations runs the method over all n).
inline constexpr std::size_t kMaxPlanReadings = 12000;
PlanPrediction predict_plan(const PlanModel& model,
                            const std::function<void(std::size_t, std::size_t)>& progress = {});

struct PlanSuggestion {
  std::string what;
  double valuation = 0.0;  // of the plan with this change and those before it
  std::string worst;       // its worst output
  std::string description; // that plan
};

// Contract 5: up to `count` changes, each the best after those before it;
// stops early when no change lowers the valuation.
std::vector<PlanSuggestion> suggest_changes(const PlanModel& model, const PlanPrediction& base, int count,
                                            const std::function<void(std::size_t, std::size_t)>& progress = {});

// ---- the methods' plans: each method's host part (methods/<name>/host/include/
// trueaxis/sim/tools/<name>_plan.hpp: its plan, its model).

// printf into a string (the format checked by the compiler): the planner's texts.
[[gnu::format(printf, 1, 2)]] std::string plan_text(const char* format, ...);

// ---- the command's texts -------------------------------------------------------

// The prediction as a table: every output's value and sigma, the valuation,
// the inseparable pairs, the suggestions (`searched`: changes were looked for).
std::string plan_table(const PlanModel& model, const PlanPrediction& p, const std::vector<PlanSuggestion>& s,
                       bool searched);
// The same as JSON (PLAN.json).
std::string plan_json(const PlanModel& model, const PlanPrediction& p, const std::vector<PlanSuggestion>& s);

}  // namespace trueaxis::sim
