// The check (docs/INTERFACE.md "Checks"): the same measurement as a
// calibration, compared with the stored table without storing anything. What
// machine-tool users run most: "has this machine moved since it was
// calibrated, by more than its tolerance?"
//
// Conventions
//  1. A figure is one thing the method stores, measured again: `stored` (the
//     stored table's), `measured` (the table just built, R = 0), `deviation`
//     (measured - stored; for a vector figure the length of the vectors'
//     difference, >= 0), `sigma` (the deviation's 1-sigma: the new figure's
//     and the stored figure's uncertainties together; for a vector figure the
//     1-sigma along one direction, the deviation's once it is well above it)
//     and `tolerance` (a configuration row of the method, > 0). Each has a
//     kind (the method's kCheckFigures, numbered from 1) and an item (the
//     pose, sub-machine or parameter it concerns, 1-based; 0 for the whole).
//  2. A figure's verdict, ISO 14253-1's guard band with k = 2:
//       fail  |deviation| > tolerance                  the machine has moved beyond it
//       warn  |deviation| + 2 sigma > tolerance         within it, not proven within (95 %)
//       pass  otherwise.
//     The check's verdict is its worst figure's: the worst verdict, among
//     those the largest ratio (|deviation| + 2 sigma) / tolerance (the first on
//     a tie). A NaN deviation or sigma fails, its ratio counted as infinite.
//  3. A method's check macro reads its last build (R = 0; kNoTable when none,
//     kResultReplaced when another method's computation has used the work
//     arena since) and its stored table (kNoTable, kTableDamaged,
//     kTableInvalid), stores nothing, and publishes, for Q = #17:
//       #100 the check's verdict (0 pass, 1 warn, 2 fail), #101 its figures,
//       #102 the worst figure's number, #103 its ratio;
//       #104 .. #111 figure Q (1..#101; Q = 0 the worst): verdict, kind, item,
//       stored, measured, deviation, sigma, tolerance.
//     kArgumentOutOfRange for any other Q. With Q = 0 the check is logged
//     (measuring_log.hpp, in a method that logs): its verdict and, per kind,
//     its worst figure. A check with no figure (a stored
//     table that shares no pose or sub-machine with the build) is
//     kNothingToCheck: nothing is judged.
//  No allocation, no exceptions.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/arguments.hpp"
#include "trueaxis/macros/list.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/measuring_log.hpp"
#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::macros {

enum class Verdict : std::uint8_t { kPass = 0, kWarn = 1, kFail = 2 };

inline const char* verdict_name(Verdict v) {
  return v == Verdict::kPass ? "pass" : (v == Verdict::kWarn ? "warn" : "fail");
}

// Convention 1: a kind of figure, for the map and the reports.
struct CheckFigureInfo {
  std::uint16_t kind;
  const char* name;  // "rotation_change": OUT.json's figure name is name + "_" + item when item > 0
  const char* unit;
  const char* what;
};

// A method's check, in its descriptor (method.hpp kCheck, optional): the
// macro and its figures' kinds (kind k is figures[k - 1]).
struct CheckInfo {
  std::uint16_t macro = 0;
  List<CheckFigureInfo> figures;
};

struct CheckFigure {
  std::uint16_t kind = 0;
  std::uint16_t item = 0;
  std::uint16_t log_item = 0;  // the item the measuring log keeps when not `item` (M3: the stored pose's); 0 `item`
  double stored = 0.0;
  double measured = 0.0;
  double deviation = 0.0;
  double sigma = 0.0;
  double tolerance = 0.0;
};

// Convention 2. A NaN deviation or sigma fails.
inline Verdict judge(const CheckFigure& f) {
  const double d = std::abs(f.deviation);
  if (!(d <= f.tolerance) || std::isnan(f.sigma)) return Verdict::kFail;
  if (!(d + 2.0 * f.sigma <= f.tolerance)) return Verdict::kWarn;
  return Verdict::kPass;
}

inline double check_ratio(const CheckFigure& f) {
  const double r = (std::abs(f.deviation) + 2.0 * f.sigma) / f.tolerance;
  return std::isnan(r) ? HUGE_VAL : r;
}

// Convention 2's order of figures: a worse verdict, then a larger ratio.
inline bool outranks(Verdict v, double ratio, Verdict than_v, double than_ratio) {
  return v > than_v || (v == than_v && ratio > than_ratio);
}

namespace var {
inline constexpr std::uint16_t kCheckVerdict = 100;
inline constexpr std::uint16_t kCheckFigures = 101;
inline constexpr std::uint16_t kCheckWorst = 102;
inline constexpr std::uint16_t kCheckWorstRatio = 103;
inline constexpr std::uint16_t kCheckFigureVerdict = 104;
inline constexpr std::uint16_t kCheckFigureKind = 105;
inline constexpr std::uint16_t kCheckFigureItem = 106;
inline constexpr std::uint16_t kCheckFigureStored = 107;
inline constexpr std::uint16_t kCheckFigureMeasured = 108;
inline constexpr std::uint16_t kCheckFigureDeviation = 109;
inline constexpr std::uint16_t kCheckFigureSigma = 110;
inline constexpr std::uint16_t kCheckFigureTolerance = 111;
}  // namespace var

// clang-format off
inline constexpr InputRef kCheckInputs[] = {
  {var::kArgQ, 1, "The figure to publish in #104..#111: 1..#101, 0 the worst."},
};
inline constexpr OutputInfo kCheckOutputs[] = {
  {var::kCheckVerdict, "check_verdict", "", "The check's verdict, its worst figure's: 0 pass, 1 warn (within tolerance, not proven within: |deviation| + 2 sigma above it), 2 fail (|deviation| above the tolerance)."},
  {var::kCheckFigures, "check_figures", "", "The number of figures judged."},
  {var::kCheckWorst, "check_worst", "", "The worst figure's number (the largest (|deviation| + 2 sigma) / tolerance)."},
  {var::kCheckWorstRatio, "check_worst_ratio", "", "That ratio: at most 1 passes."},
  {var::kCheckFigureVerdict, "check_figure_verdict", "", "Figure Q's verdict (0 pass, 1 warn, 2 fail)."},
  {var::kCheckFigureKind, "check_figure_kind", "", "Figure Q's kind (the method's check figures in the map, from 1)."},
  {var::kCheckFigureItem, "check_figure_item", "", "The pose, sub-machine or parameter figure Q concerns (1-based; 0 the whole)."},
  {var::kCheckFigureStored, "check_figure_stored", "", "Figure Q in the stored table (its kind's unit)."},
  {var::kCheckFigureMeasured, "check_figure_measured", "", "Figure Q as measured now."},
  {var::kCheckFigureDeviation, "check_figure_deviation", "", "Measured minus stored (a vector figure: the length of the difference)."},
  {var::kCheckFigureSigma, "check_figure_sigma", "", "The deviation's 1-sigma (the new and the stored figure's uncertainties together)."},
  {var::kCheckFigureTolerance, "check_figure_tolerance", "", "The tolerance it is judged against (configuration)."},
};
// clang-format on

// Convention 3's outputs for `count` figures, figure_at(k) giving figure k
// (0-based); Ctx is a method's MethodContext.
template <typename Ctx, typename FigureAt>
MacroStep publish_check(Ctx& ctx, std::size_t count, FigureAt figure_at) {
  if (count == 0) return done(core::Status::kNothingToCheck);
  const double q = ctx.template in<var::kArgQ>();
  if (!whole_in(q, 0.0, static_cast<double>(count))) return done(core::Status::kArgumentOutOfRange);
  Verdict verdict = Verdict::kPass;
  std::size_t worst = 0;
  double worst_ratio = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const CheckFigure f = figure_at(k);
    const Verdict v = judge(f);
    const double ratio = check_ratio(f);
    if (k == 0 || outranks(v, ratio, verdict, worst_ratio)) {
      worst = k;
      worst_ratio = ratio;
      verdict = v;
    }
  }
  if (q == 0.0) {
    // Per kind (1..kLogFigures) its worst figure, as the check's worst is chosen.
    std::size_t of_kind[kLogFigures] = {};
    double kind_ratio[kLogFigures] = {};
    Verdict kind_verdict[kLogFigures] = {};
    bool seen[kLogFigures] = {};
    for (std::size_t k = 0; k < count; ++k) {
      const CheckFigure f = figure_at(k);
      if (f.kind < 1 || f.kind > kLogFigures) continue;
      const std::size_t i = f.kind - 1U;
      const Verdict v = judge(f);
      const double ratio = check_ratio(f);
      if (!seen[i] || outranks(v, ratio, kind_verdict[i], kind_ratio[i])) {
        seen[i] = true;
        of_kind[i] = k;
        kind_ratio[i] = ratio;
        kind_verdict[i] = v;
      }
    }
    LogEntry entry;
    entry.type = LogType::kCheck;
    entry.verdict = static_cast<std::uint8_t>(verdict);
    for (std::size_t i = 0; i < kLogFigures; ++i) {
      if (!seen[i]) continue;
      const CheckFigure f = figure_at(of_kind[i]);
      entry.add(f.kind, f.log_item != 0 ? f.log_item : f.item, f.deviation, f.sigma, f.tolerance);
    }
    ctx.log(entry);
  }
  const CheckFigure f = figure_at(q == 0.0 ? worst : static_cast<std::size_t>(q) - 1);
  ctx.template out<var::kCheckVerdict>(static_cast<double>(verdict));
  ctx.template out<var::kCheckFigures>(static_cast<double>(count));
  ctx.template out<var::kCheckWorst>(static_cast<double>(worst + 1));
  ctx.template out<var::kCheckWorstRatio>(worst_ratio);
  ctx.template out<var::kCheckFigureVerdict>(static_cast<double>(judge(f)));
  ctx.template out<var::kCheckFigureKind>(static_cast<double>(f.kind));
  ctx.template out<var::kCheckFigureItem>(static_cast<double>(f.item));
  ctx.template out<var::kCheckFigureStored>(f.stored);
  ctx.template out<var::kCheckFigureMeasured>(f.measured);
  ctx.template out<var::kCheckFigureDeviation>(f.deviation);
  ctx.template out<var::kCheckFigureSigma>(f.sigma);
  ctx.template out<var::kCheckFigureTolerance>(f.tolerance);
  return done(core::Status::kOk);
}

}  // namespace trueaxis::macros
