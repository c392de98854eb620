// The module's measuring log on the host (macros/measuring_log.hpp): read
// entry by entry over the registers, named by the module's method list,
// printed, written as CSV, and the drift of every checked figure over time.
// Host only; trueaxis-calibrate log and the check's report use it.
//
// Contract
//  1. read_log() takes the macro interface's window (#9028 -> #9020..#9059)
//     for each entry held, by its place from the oldest (1) to #9016, and
//     returns the entries oldest first; when the log changes meanwhile (an
//     entry appended by another client), an entry seen already is skipped.
//  2. fit_drift(): per method and figure kind of the checks against the stored
//     table the method's newest check judged (a store starts a new series), a
//     straight line |deviation| = a + b t (the verdict judges |deviation|, so a
//     signed figure's worst may change sign between checks), NaNs left out,
//     weighted by 1 / sigma^2;
//     the parameters' covariance scaled by the reduced chi-square when that
//     is above 1 (a scatter beyond the stated sigmas widens the trend's
//     uncertainty, never narrows it). At least 3 checks with known times over
//     more than one day; fewer gives no trend. The trend is significant when
//     |b| > 2 sigma_b; then, when it rises, the projected crossing is where the
//     line reaches the tolerance, with its 1-sigma from the parameters'
//     covariance.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/core/status.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::sim {

struct LogFigureRow {
  int kind = 0;
  int item = 0;
  double value = 0.0;
  double sigma = 0.0;
  double tolerance = 0.0;
  std::string name;  // the kind's name from the method's map entry ("figure_K" when unknown); a
                     // refusal's own figure (kind 0): the status's name, its code in `sigma`
  std::string unit;
  std::string item_text;  // a refusal's item as the reader says it: "item 3", "270 deg" (M4's change: its step)
  std::string item_name;  // the item by what it is, where known: M3's pose by its A ("a-90"; name_poses)
};

struct LogRow {
  std::uint32_t serial = 0;
  std::uint32_t time_s = 0;  // 0 unknown
  int macro = 0;
  std::string method;        // "" when no built method has the macro
  bool check = false;
  bool refusal = false;      // a refused calibration or store (measuring_log.hpp convention 1)
  int verdict = -1;          // -1 none (a calibration), else 0 pass, 1 warn, 2 fail
  bool stored = false;
  std::uint32_t table_sequence = 0;
  std::vector<LogFigureRow> figures;
};

// Contract 1; false with `error` set on a transport failure.
bool read_log(VariableClient& client, std::vector<LogRow>& rows, std::string& error);

// M3's figures named by their pose's A (item_name "a-90", as the check's
// page names them): the log keeps a pose's number in the table its entry
// carries the sequence of (a stored calibration's own, a check's stored
// table's: measuring_log.hpp convention 1); the present table's poses are
// asked for (9834, R = 1), so the entries of the present table are named,
// older tables' keep their numbers. False with `error` on a transport failure.
bool name_poses(VariableClient& client, std::vector<LogRow>& rows, std::string& error);

struct Drift {
  std::string method;
  std::string figure;
  std::string unit;
  double tolerance = 0.0;
  std::size_t checks = 0;        // points in the fit
  double first_s = 0.0;          // their time span
  double last_s = 0.0;
  double slope_per_day = 0.0;    // b
  double slope_sigma = 0.0;
  double value_now = 0.0;        // the line at the last check
  double value_now_sigma = 0.0;
  bool enough = false;           // contract 2: a fit was possible
  bool significant = false;
  bool crossed = false;          // the line is at or beyond the tolerance at the last check
  double cross_s = 0.0;          // the projected crossing (Unix s), when significant and ahead
  double cross_sigma_days = 0.0;
};

// Contract 2, one Drift per method and check figure kind that has entries.
std::vector<Drift> fit_drift(const std::vector<LogRow>& rows);

// "2027-01-15 08:00:00" (UTC); "unknown" for 0.
// A refusal's item as the reader says it (measuring_log.hpp convention 1):
// "at item N", M4's change gate's logged angle step as "at A deg", "" for 0.
std::string refusal_item_text(const std::string& method, core::Status status, int item);

std::string utc_text(double unix_s);

// The log as a table, newest last, then the drift lines.
std::string log_table(const std::vector<LogRow>& rows, const std::vector<Drift>& drift);
std::string drift_line(const Drift& d);

// One CSV row per figure (an entry without figures has one row with its
// figure columns empty): serial,time_utc,time_s,method,macro,entry,verdict,
// stored,table_sequence,figure,item,value,sigma,tolerance,unit.
std::string log_csv(const std::vector<LogRow>& rows);

// The drift as a JSON array, for the report.
std::string drift_json(const std::vector<Drift>& drift);

}  // namespace trueaxis::sim
