#include "trueaxis/sim/tools/log_reader.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <utility>

#include "trueaxis/macros/measuring_log.hpp"
#include "trueaxis/macros/method_list.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"

namespace trueaxis::sim {

namespace {

namespace var = macros::var;
using Built = macros::BuiltMethods;
constexpr double kDayS = 86400.0;

// The method whose build or check macro `macro` is, and its figure names.
void name_entry(LogRow& row) {
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    const bool check = Built::kChecks[i].macro == row.macro;
    if (!check && Built::kSessions[i].compute != row.macro) continue;
    row.method = Built::kNames[i];
    const macros::List<macros::CheckFigureInfo> kinds = check ? Built::kChecks[i].figures : Built::kLogFigures[i];
    for (LogFigureRow& f : row.figures) {
      if (row.refusal && f.kind == macros::kRefusalFigure) {
        const auto status = static_cast<core::Status>(static_cast<int>(f.sigma));
        f.name = macros::status_name(status);
        f.item_text = refusal_item_text(row.method, status, f.item);
        continue;
      }
      const bool known = f.kind >= 1 && static_cast<std::size_t>(f.kind) <= kinds.size;
      f.name = known ? kinds[static_cast<std::size_t>(f.kind) - 1].name : "figure_" + std::to_string(f.kind);
      f.unit = known ? kinds[static_cast<std::size_t>(f.kind) - 1].unit : "";
    }
    return;
  }
  for (LogFigureRow& f : row.figures) f.name = "figure_" + std::to_string(f.kind);
}

}  // namespace

bool name_poses(VariableClient& client, std::vector<LogRow>& rows, std::string& error) {
  std::uint32_t present = 0;  // the present M3 table's sequence: its newest store's
  for (const LogRow& r : rows) {
    if (r.method == "rigidity" && r.stored && !r.check && !r.refusal) present = r.table_sequence;
  }
  if (present == 0) return true;
  std::map<int, std::string> names;
  for (LogRow& r : rows) {
    if (r.method != "rigidity" || r.table_sequence != present || r.refusal || !(r.stored || r.check)) continue;
    for (LogFigureRow& f : r.figures) {
      if (f.item <= 0) continue;
      if (names.count(f.item) == 0) {
        const double args[2] = {static_cast<double>(f.item), 1.0};  // Q = the pose, R = 1: the stored table
        const MacroOutcome m = client.write(var::kArgQ, 2, args) ? client.run_macro(9834) : MacroOutcome{};
        double a = 0.0;
        if (m.status == -1 || (m.status == 2 && !client.read(100, 1, &a))) {
          error = client.failure_text() + " (naming the log's poses, 9834)";
          return false;
        }
        char name[32] = "";
        if (m.status == 2) std::snprintf(name, sizeof name, "a%g", a);
        names[f.item] = name;  // "" when the table answers no such pose: its number stays
      }
      f.item_name = names[f.item];
    }
  }
  return true;
}

std::string refusal_item_text(const std::string& method, core::Status status, int item) {
  if (item <= 0) return "";
  // M4's change gate logs the angle's step (spindle_macros.cpp): 1 .. 36, angle 10 (step - 1) deg.
  if (method == "spindle" && status == core::Status::kChangeBeyondLimit) {
    return "at " + std::to_string(static_cast<int>(macros::spindle::change_angle_of_step(item))) + " deg";
  }
  return "at item " + std::to_string(item);
}

namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string general(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

bool read_log(VariableClient& client, std::vector<LogRow>& rows, std::string& error) {
  rows.clear();
  double counts[2] = {0.0, 0.0};  // #9016, #9017
  if (!client.read(var::kLogCount, 2, counts)) {
    error = client.failure_text();
    return false;
  }
  // By place, oldest first (#9028): serials need not be contiguous (measuring_log.hpp convention 5).
  double previous = 0.0;
  for (double place = 1.0; place <= counts[0]; place += 1.0) {
    double v[40] = {};  // #9020..#9059; #9028, #9029 are not the entry's
    if (!client.write_one(var::kLogIndex, place) || !client.read(var::kLogSerial, 8, v) ||
        !client.read(var::kLogFigureFirst, 30, v + 10)) {
      error = client.failure_text();
      return false;
    }
    if (v[0] <= previous) continue;  // the log changed meanwhile (contract 1): an entry seen already
    previous = v[0];
    LogRow row;
    row.serial = static_cast<std::uint32_t>(v[0]);
    row.time_s = static_cast<std::uint32_t>(v[1]);
    row.macro = static_cast<int>(v[2]);
    row.check = v[3] == 1.0;
    row.refusal = v[3] == 2.0;
    row.verdict = static_cast<int>(v[4]);
    row.stored = v[5] == 1.0;
    row.table_sequence = static_cast<std::uint32_t>(v[6]);
    const auto figures = static_cast<std::size_t>(v[7]);
    for (std::size_t k = 0; k < figures && k < macros::kLogFigures; ++k) {
      const double* f = v + 10 + 5 * k;
      LogFigureRow figure;
      figure.kind = static_cast<int>(f[0]);
      figure.item = static_cast<int>(f[1]);
      figure.value = f[2];
      figure.sigma = f[3];
      figure.tolerance = f[4];
      row.figures.push_back(figure);
    }
    name_entry(row);
    rows.push_back(row);
  }
  return true;
}

std::vector<Drift> fit_drift(const std::vector<LogRow>& rows) {
  struct Point {
    double t, value, sigma, tolerance;
  };
  // Per (method, figure) in the order they first appear.
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<Point>> series;
  std::map<std::pair<std::string, std::string>, std::string> units;
  // Per method, the stored table its newest check judged against: a store
  // starts the drift again (deviations from another table are another series).
  std::map<std::string, std::uint32_t> table_of;
  for (const LogRow& row : rows) {
    if (row.check && !row.method.empty()) table_of[row.method] = row.table_sequence;
  }
  for (const LogRow& row : rows) {
    if (!row.check || row.method.empty() || row.table_sequence != table_of[row.method]) continue;
    for (const LogFigureRow& f : row.figures) {
      const auto key = std::make_pair(row.method, f.name);
      if (series.find(key) == series.end()) order.push_back(key);
      units[key] = f.unit;
      // The verdict judges |deviation| (check.hpp): so does the trend. A NaN is
      // a failed figure, not a point of a line.
      if (row.time_s != 0 && std::isfinite(f.value) && std::isfinite(f.sigma)) {
        series[key].push_back({static_cast<double>(row.time_s), std::abs(f.value), f.sigma, f.tolerance});
      }
    }
  }
  std::vector<Drift> out;
  for (const auto& key : order) {
    const std::vector<Point>& p = series[key];
    Drift d;
    d.method = key.first;
    d.figure = key.second;
    d.unit = units[key];
    d.checks = p.size();
    if (!p.empty()) {
      d.first_s = p.front().t;
      d.last_s = p.back().t;
      d.tolerance = p.back().tolerance;
      for (const Point& q : p) {
        d.first_s = std::fmin(d.first_s, q.t);
        d.last_s = std::fmax(d.last_s, q.t);
      }
    }
    d.enough = p.size() >= 3 && d.last_s - d.first_s > kDayS;
    if (!d.enough) {
      out.push_back(d);
      continue;
    }
    // Weighted least squares in days about the weighted mean time (the
    // intercept and the slope are then uncorrelated). A zero sigma (an exact
    // figure) weighs as the smallest positive sigma of the series, or 1 when
    // there is none, so the fit stays defined.
    double smallest = 0.0;
    for (const Point& q : p) {
      if (q.sigma > 0.0 && (smallest == 0.0 || q.sigma < smallest)) smallest = q.sigma;
    }
    const bool weighted = smallest > 0.0;
    double sw = 0.0, swt = 0.0;
    std::vector<double> w(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double s = weighted ? std::fmax(p[i].sigma, smallest) : 1.0;
      w[i] = 1.0 / (s * s);
      sw += w[i];
      swt += w[i] * p[i].t / kDayS;
    }
    const double tc = swt / sw;  // days
    double stt = 0.0, sty = 0.0, swy = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double dt = p[i].t / kDayS - tc;
      stt += w[i] * dt * dt;
      sty += w[i] * dt * p[i].value;
      swy += w[i] * p[i].value;
    }
    const double a = swy / sw;  // the line at tc
    const double b = sty / stt;
    double chi2 = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double r = p[i].value - (a + b * (p[i].t / kDayS - tc));
      chi2 += w[i] * r * r;
    }
    const double dof = static_cast<double>(p.size()) - 2.0;
    const double scale = weighted ? std::fmax(1.0, chi2 / dof) : chi2 / dof;
    const double var_a = scale / sw;
    const double var_b = scale / stt;
    const double last = d.last_s / kDayS - tc;
    d.slope_per_day = b;
    d.slope_sigma = std::sqrt(var_b);
    d.value_now = a + b * last;
    d.value_now_sigma = std::sqrt(var_a + last * last * var_b);
    d.significant = std::abs(b) > 2.0 * d.slope_sigma;
    // |deviation| reaches the tolerance where a rising line meets it.
    const double target = d.tolerance;
    d.crossed = d.tolerance > 0.0 && d.value_now >= d.tolerance;
    if (d.significant && d.tolerance > 0.0 && !d.crossed && b > 0.0) {
      const double t_cross = (target - a) / b;  // days from tc
      d.cross_s = (tc + t_cross) * kDayS;
      d.cross_sigma_days = std::sqrt(var_a + t_cross * t_cross * var_b) / std::abs(b);
    }
    out.push_back(d);
  }
  return out;
}

std::string utc_text(double unix_s) {
  if (!(unix_s > 0.0)) return "unknown";
  const std::time_t t = static_cast<std::time_t>(unix_s);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &utc);
  return buf;
}

std::string drift_line(const Drift& d) {
  std::string line = d.method + " " + d.figure + ": ";
  if (!d.enough) {
    return line + "no trend (" + std::to_string(d.checks) +
           " checks with a time; a trend needs 3 over more than a day)";
  }
  const std::string per = " " + d.unit + " per 30 days";
  line += (d.slope_per_day >= 0.0 ? "+" : "") + general(30.0 * d.slope_per_day) + " +- " +
          general(30.0 * d.slope_sigma) + per + " over " + std::to_string(d.checks) + " checks (" +
          utc_text(d.first_s).substr(0, 10) + " .. " + utc_text(d.last_s).substr(0, 10) + "); now " +
          general(d.value_now) + " +- " + general(d.value_now_sigma) + " " + d.unit + " of " + general(d.tolerance);
  if (d.crossed) return line + ": at or beyond its tolerance";
  if (!d.significant) return line + ": no significant trend";
  if (d.cross_s > 0.0) {
    return line + ": reaches its tolerance about " + utc_text(d.cross_s).substr(0, 10) + " (+- " +
           fixed(d.cross_sigma_days, 0) + " days, 1 sigma)";
  }
  return line + ": moving away from its tolerance";
}

std::string log_table(const std::vector<LogRow>& rows, const std::vector<Drift>& drift) {
  std::string out = "serial  time (UTC)           method    macro  entry        verdict  table  figures\n";
  for (const LogRow& r : rows) {
    char head[160];
    const char* entry = r.check ? "check" : r.refusal ? "refused" : (r.stored ? "stored" : "calibration");
    const char* verdict = r.verdict < 0 ? "-" : macros::verdict_name(static_cast<macros::Verdict>(r.verdict));
    std::snprintf(head, sizeof head, "%6u  %-19s  %-8s  %5d  %-11s  %-7s  %5s  ", static_cast<unsigned>(r.serial),
                  utc_text(r.time_s).c_str(), r.method.empty() ? "?" : r.method.c_str(), r.macro, entry, verdict,
                  r.table_sequence > 0 ? std::to_string(r.table_sequence).c_str() : "-");
    out += head;
    for (std::size_t k = 0; k < r.figures.size(); ++k) {
      const LogFigureRow& f = r.figures[k];
      if (r.refusal && f.kind == macros::kRefusalFigure) {  // the refusal: what and against which limit
        out += (k > 0 ? "; " : "") + f.name + (f.item_text.empty() ? "" : " " + f.item_text) +
               (f.value != 0.0 || f.tolerance != 0.0 ? ": " + general(f.value) + " against " + general(f.tolerance) : "");
        continue;
      }
      const std::string item = f.item_name.empty() ? std::to_string(f.item) : f.item_name;
      out += (k > 0 ? "; " : "") + f.name + (f.item > 0 ? "_" + item : "") + " " +
             general(f.value) + " +- " + general(f.sigma) + " " + f.unit +
             (f.tolerance > 0.0 ? " / " + general(f.tolerance) : "");
    }
    out += "\n";
  }
  if (rows.empty()) out += "(the log is empty)\n";
  if (!drift.empty()) {
    out += "\ndrift of the checked figures (a line through each figure's worst deviation per check, "
           "weighted by 1/sigma^2):\n";
    for (const Drift& d : drift) out += "  " + drift_line(d) + "\n";
  }
  return out;
}

std::string log_csv(const std::vector<LogRow>& rows) {
  std::string out = "serial,time_utc,time_s,method,macro,entry,verdict,stored,table_sequence,figure,item,value,sigma,"
                    "tolerance,unit\n";
  for (const LogRow& r : rows) {
    const std::string head =
        std::to_string(r.serial) + "," + (r.time_s > 0 ? utc_text(r.time_s) : "") + "," + std::to_string(r.time_s) +
        "," + csv_field(r.method) + "," + std::to_string(r.macro) + "," +
        (r.check ? "check" : r.refusal ? "refusal" : (r.stored ? "stored" : "calibration")) + "," +
        (r.verdict < 0 ? "" : macros::verdict_name(static_cast<macros::Verdict>(r.verdict))) + "," +
        (r.stored ? "1" : "0") + "," + std::to_string(r.table_sequence) + ",";
    if (r.figures.empty()) out += head + ",,,,,\n";
    for (const LogFigureRow& f : r.figures) {
      out += head + csv_field(f.name) + "," + std::to_string(f.item) + "," + json_number(f.value) + "," +
             json_number(f.sigma) + "," + json_number(f.tolerance) + "," + csv_field(f.unit) + "\n";
    }
  }
  return out;
}

std::string drift_json(const std::vector<Drift>& drift) {
  std::string out = "[";
  for (std::size_t i = 0; i < drift.size(); ++i) {
    const Drift& d = drift[i];
    out += (i > 0 ? ",\n    " : "\n    ") + std::string("{ \"method\": ") + json_string(d.method) +
           ", \"figure\": " + json_string(d.figure) + ", \"unit\": " + json_string(d.unit) +
           ", \"checks\": " + std::to_string(d.checks) + ", \"text\": " + json_string(drift_line(d)) + " }";
  }
  return out + "]";
}

}  // namespace trueaxis::sim
