// The measuring log end to end (docs/INTERFACE.md "Check mode and the log"):
// a scripted sequence of weekly checks of a cradle machine whose rigidity at
// A = 60 grows by 1.5" a week (the simulator's sim_drift_arcsec), each check
// handed its date with --time; then `trueaxis-calibrate log` prints one entry
// per calibration and check, newest last, and the trend of the rotation
// change with the date it reaches its 12" tolerance, which the truth (week 8)
// must lie within 3 sigma of; --csv writes one row per figure. Bad usage is
// refused with one line.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <regex>
#include <string>
#include <vector>

#include "calibrate_support.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/calibrate_gantry.hpp"
#include "trueaxis/sim/tools/calibrate_rigidity.hpp"
#include "trueaxis/sim/tools/calibrate_spindle.hpp"
#include "trueaxis/sim/tools/log_reader.hpp"

namespace {

using trueaxis::sim::test::SimFixture;
using trueaxis::test::run;
using trueaxis::test::Run;
using trueaxis::test::slurp;
using trueaxis::test::Workspace;
namespace v = trueaxis::macros::var;

constexpr double kT0 = 1'800'000'000.0;  // 2027-01-15T08:00:00Z
constexpr double kWeek = 7.0 * 86400.0;
constexpr double kDriftPerWeek = 1.5;  // arcsec at A = 60
constexpr std::uint16_t kSimDriftArcsec = 12056;

Run calibrate(const std::vector<std::string>& args, int port, const Workspace& w) {
  std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--port", std::to_string(port)});
  return run(argv, w.file("calibrate.err"));
}

// "2027-03-12" as Unix seconds (UTC midnight).
double day_of(const std::string& text) {
  std::tm t{};
  REQUIRE(::strptime(text.c_str(), "%Y-%m-%d", &t) != nullptr);
  return static_cast<double>(::timegm(&t));
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

TEST_CASE("trueaxis-calibrate log: weekly checks of a drifting machine, the trend and the date it reaches its "
          "tolerance",
          "[calibrate][log]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-log");
  const std::string port = std::to_string(sim.port());
  {
    const Run empty = calibrate({"log"}, sim.port(), w);
    INFO(empty.err);
    REQUIRE(empty.exit_code == 0);
    CHECK(empty.out.find("(the log is empty)") != std::string::npos);
  }
  const auto measure = [&](double drift_arcsec) {
    REQUIRE(sim.client().write_one(kSimDriftArcsec, drift_arcsec));
    REQUIRE(sim.client().give_back_interface());
    const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", port, "--out", w.file("samples.csv")}, w.file("measure.err"));
    REQUIRE(m.exit_code == 0);
  };
  measure(0.0);
  const Run stored = calibrate({"rigidity", "--in", w.file("samples.csv"), "--json", w.file("out.json"), "--store",
                                "--time", "2027-01-15T08:00:00Z"},
                               sim.port(), w);
  INFO(stored.err);
  REQUIRE(stored.exit_code == 0);
  for (int week = 1; week <= 5; ++week) {
    measure(kDriftPerWeek * week);
    const Run check = calibrate({"rigidity", "--in", w.file("samples.csv"), "--json", w.file("out.json"), "--check",
                                 "--time", std::to_string(static_cast<long>(kT0 + week * kWeek))},
                                sim.port(), w);
    INFO(check.err);
    REQUIRE(check.exit_code == 0);  // 7.5" at week 5: within the 12" tolerance
  }

  const Run log = calibrate({"log", "--csv", w.file("log.csv")}, sim.port(), w);
  INFO(log.err);
  REQUIRE(log.exit_code == 0);
  INFO(log.out);
  const std::vector<std::string> lines = lines_of(log.out);
  REQUIRE(lines.size() >= 7);
  CHECK(lines[0].find("serial") == 0);
  // One entry per run: the store replaced its calibration, each check its own.
  CHECK(lines[1].find("     1  2027-01-15 08:00:00  rigidity   9832  stored") == 0);
  for (int week = 1; week <= 5; ++week) {
    INFO("week " << week);
    const std::string& line = lines[static_cast<std::size_t>(week) + 1];
    CHECK(line.find("     " + std::to_string(week + 1) + "  2027-") == 0);  // the serial column
    CHECK(line.find("rigidity   9836  check        pass") != std::string::npos);
    CHECK(line.find("rotation_change_") != std::string::npos);
  }
  CHECK(lines[2].find("2027-01-22 08:00:00") != std::string::npos);
  CHECK(lines[7].empty());

  // The trend: 1.5" a week is 6.43" per 30 days; the line reaches 12" at week 8
  // (2027-03-12 08:00), which the projected date must hold within 3 sigma.
  const std::size_t at = log.out.find("rigidity rotation_change: +");
  REQUIRE(at != std::string::npos);
  const std::string trend = log.out.substr(at, log.out.find('\n', at) - at);
  INFO(trend);
  const double per_30_days = std::stod(trend.substr(trend.find('+') + 1));
  CHECK(per_30_days == Approx(kDriftPerWeek * 30.0 / 7.0).margin(2.0));
  const std::size_t about = trend.find("reaches its tolerance about ");
  REQUIRE(about != std::string::npos);
  const double projected = day_of(trend.substr(about + 28, 10));
  const double sigma_days = std::stod(trend.substr(trend.find("(+- ", about) + 4));
  const double truth = kT0 + 8.0 * kWeek;
  CHECK(sigma_days > 0.0);
  CHECK(sigma_days < 30.0);
  CHECK(std::abs(projected - truth) / 86400.0 <= 3.0 * sigma_days + 1.0);
  // The date is where the printed line reaches 12": now + slope x (date - last check).
  const std::size_t now_at = trend.find("; now ");
  REQUIRE(now_at != std::string::npos);
  const double now = std::stod(trend.substr(now_at + 6));
  const double last = kT0 + 5.0 * kWeek;
  CHECK(now + per_30_days / 30.0 * (projected - last) / 86400.0 == Approx(12.0).margin(0.2 + per_30_days / 30.0));
  CHECK(log.out.find("rigidity a_positioning_error_change: ") != std::string::npos);

  // CSV: a header, then one row per figure (two per entry).
  const std::vector<std::string> csv = lines_of(slurp(w.file("log.csv")));
  REQUIRE(csv.size() == 1 + 6 * 2);
  CHECK(csv[0] == "serial,time_utc,time_s,method,macro,entry,verdict,stored,table_sequence,figure,item,value,sigma,"
                  "tolerance,unit");
  CHECK(csv[1].find("1,2027-01-15 08:00:00,1800000000,rigidity,9832,stored,,1,") == 0);
  CHECK(csv[3].find("2,2027-01-22 08:00:00,1800604800,rigidity,9836,check,pass,0,") == 0);
  CHECK(csv[3].find(",rotation_change,") != std::string::npos);
}

TEST_CASE("trueaxis-calibrate log and --time: bad usage is one line and exit 1", "[calibrate][log]") {
  SimFixture sim;
  Workspace w("trueaxis-calibrate-log-usage");
  const Run unknown = calibrate({"log", "--store"}, sim.port(), w);
  CHECK(unknown.exit_code == 1);
  CHECK(unknown.err.find("unknown or incomplete option '--store' for log") != std::string::npos);
  const Run csv = calibrate({"log", "--csv", w.file("no/such/dir/log.csv")}, sim.port(), w);
  CHECK(csv.exit_code == 1);
  CHECK(csv.err.find("cannot be written") != std::string::npos);
  for (const char* bad : {"yesterday", "2027-13-01", "0", "-5", "2027-01-15T08:00:00+01:00"}) {
    INFO(bad);
    const Run time = calibrate({"rigidity", "--in", "x.csv", "--json", "y.json", "--time", bad}, sim.port(), w);
    CHECK(time.exit_code == 1);
    CHECK(time.err.find("--time takes Unix seconds or a UTC date and time") != std::string::npos);
  }
}

namespace {

// A check entry of method `method` at day `day` with one figure.
trueaxis::sim::LogRow check_row(double day, const std::string& figure, double value, double sigma, double tolerance) {
  trueaxis::sim::LogRow r;
  r.time_s = static_cast<std::uint32_t>(kT0 + day * 86400.0);
  r.method = "rigidity";
  r.check = true;
  r.verdict = 0;
  trueaxis::sim::LogFigureRow f;
  f.name = figure;
  f.unit = "arcsec";
  f.value = value;
  f.sigma = sigma;
  f.tolerance = tolerance;
  r.figures.push_back(f);
  return r;
}

}  // namespace

TEST_CASE("fit_drift against the closed forms: an exact line, a signed figure, scatter beyond the sigmas, too few",
          "[log][drift]") {
  using trueaxis::sim::fit_drift;
  // Exactly 1 + 0.5 / day at days 0, 7, 14, 21: slope 0.5, 12 reached at day 22.
  std::vector<trueaxis::sim::LogRow> rows;
  for (double day : {0.0, 7.0, 14.0, 21.0}) rows.push_back(check_row(day, "rotation_change", 1.0 + 0.5 * day, 0.1, 12.0));
  std::vector<trueaxis::sim::Drift> d = fit_drift(rows);
  REQUIRE(d.size() == 1);
  CHECK(d[0].enough);
  CHECK(d[0].significant);
  CHECK(d[0].slope_per_day == Approx(0.5).epsilon(1e-12));
  CHECK(d[0].value_now == Approx(11.5).epsilon(1e-12));
  CHECK(d[0].cross_s == Approx(kT0 + 22.0 * 86400.0).margin(1e-3));
  // Equal sigmas 0.1, chi-square 0: the slope's sigma is 0.1 / sqrt(sum (t - mean)^2), t in days.
  CHECK(d[0].slope_sigma == Approx(0.1 / std::sqrt(245.0)).epsilon(1e-9));
  CHECK(d[0].cross_sigma_days > 0.0);

  // A signed figure is judged by |deviation|: -1 - 0.25 / day reaches 8 at day
  // 28, and so does a series whose sign changes (+1.25, -3.5, +6).
  rows.clear();
  for (double day : {0.0, 10.0, 20.0}) rows.push_back(check_row(day, "a_x", -1.0 - 0.25 * day, 0.05, 8.0));
  d = fit_drift(rows);
  REQUIRE(d.size() == 1);
  CHECK(d[0].cross_s == Approx(kT0 + 28.0 * 86400.0).margin(1e-3));
  rows.clear();
  const double signs[] = {1.0, -1.0, 1.0};
  for (int i = 0; i < 3; ++i) {
    const double day = 10.0 * i;
    rows.push_back(check_row(day, "a_x", signs[i] * (1.0 + 0.25 * day), 0.05, 8.0));
  }
  CHECK(fit_drift(rows)[0].cross_s == Approx(kT0 + 28.0 * 86400.0).margin(1e-3));

  // A store starts the series again: checks against an older table are left
  // out, and a NaN figure (a failed one) is no point of the line.
  rows.clear();
  for (double day : {0.0, 7.0, 14.0}) {
    rows.push_back(check_row(day, "rotation_change", 1.0 + 0.5 * day, 0.1, 12.0));
    rows.back().table_sequence = 1;
  }
  for (double day : {21.0, 28.0, 35.0, 42.0}) {
    rows.push_back(check_row(day, "rotation_change", day == 35.0 ? std::nan("") : 0.3, 0.1, 12.0));
    rows.back().table_sequence = 2;
  }
  d = fit_drift(rows);
  REQUIRE(d.size() == 1);
  CHECK(d[0].checks == 3);  // days 21, 28, 42
  CHECK(d[0].slope_per_day == Approx(0.0).margin(1e-12));
  CHECK_FALSE(d[0].significant);

  // Scatter beyond the stated sigmas widens the slope's sigma by sqrt(chi^2 / dof):
  // residuals +1, -1, +1, -1 about the line through them (sigma 0.1).
  rows.clear();
  const double days[] = {0.0, 1.0, 2.0, 3.0};
  const double bumps[] = {1.0, -1.0, -1.0, 1.0};  // orthogonal to 1 and t: the fit is the line 2 + 0 t
  for (int i = 0; i < 4; ++i) rows.push_back(check_row(days[i] * 2.0, "rotation_change", 2.0 + bumps[i], 0.1, 12.0));
  d = fit_drift(rows);
  REQUIRE(d.size() == 1);
  CHECK(d[0].slope_per_day == Approx(0.0).margin(1e-12));
  CHECK_FALSE(d[0].significant);
  // chi^2 = 4 / 0.01 = 400 over 2 dof: sigma_b = sqrt(200) x 0.1 / sqrt(sum (t - 3)^2 = 20).
  CHECK(d[0].slope_sigma == Approx(std::sqrt(200.0) * 0.1 / std::sqrt(20.0)).epsilon(1e-9));
  CHECK(d[0].cross_s == 0.0);

  // Two checks, or three within a day: no trend.
  rows.resize(2);
  CHECK_FALSE(fit_drift(rows)[0].enough);
  rows.clear();
  for (double day : {0.0, 0.3, 0.6}) rows.push_back(check_row(day, "rotation_change", 1.0 + day, 0.1, 12.0));
  CHECK_FALSE(fit_drift(rows)[0].enough);
  CHECK(trueaxis::sim::drift_line(fit_drift(rows)[0]).find("no trend") != std::string::npos);
}

TEST_CASE("trueaxis-calibrate log: 100 scratch runs and failed stores after a store and a check still show both",
          "[calibrate][log]") {
  SimFixture sim({"--errors", "realistic"});
  Workspace w("trueaxis-calibrate-scratch");
  REQUIRE(sim.client().give_back_interface());
  const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("samples.csv")},
                    w.file("measure.err"));
  REQUIRE(m.exit_code == 0);
  const std::vector<std::string> in = {"rigidity", "--in", w.file("samples.csv"), "--json", w.file("out.json")};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = in;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  Run r = calibrate(with({"--store", "--time", "2027-01-15T08:00:00Z"}), sim.port(), w);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  r = calibrate(with({"--check", "--time", "2027-01-16T08:00:00Z"}), sim.port(), w);
  REQUIRE(r.exit_code == 0);
  for (int i = 0; i < 100; ++i) {
    // Scratch: measured, nothing stored or checked; every tenth a store refused (a wrong unlock code).
    const bool refused = i % 10 == 9;
    r = calibrate(refused ? with({"--store", "--unlock-code", "1234", "--time", "2027-01-17T08:00:00Z"})
                          : with({"--time", "2027-01-17T08:00:00Z"}),
                  sim.port(), w);
    INFO("run " << i << ": " << r.err);
    REQUIRE(r.exit_code == (refused ? 1 : 0));
  }
  r = calibrate({"log"}, sim.port(), w);
  REQUIRE(r.exit_code == 0);
  INFO(r.out);
  const std::vector<std::string> lines = lines_of(r.out);
  REQUIRE(lines.size() > 33);
  CHECK(lines[1].find("2027-01-15 08:00:00  rigidity   9832  stored") != std::string::npos);
  CHECK(lines[2].find("2027-01-16 08:00:00  rigidity   9836  check") != std::string::npos);
  CHECK(lines[3].find("2027-01-17") != std::string::npos);  // then the newest 30 scratch runs
  CHECK(lines[32].find("2027-01-17") != std::string::npos);
  CHECK(lines[33].empty());
  // The present table's entries name their poses by A (name_poses); a scratch
  // run's poses are its own, which the log does not keep: numbers.
  const std::regex by_a("_a-?[0-9]+(\\.[0-9]+)? ");
  CHECK(std::regex_search(lines[1], by_a));
  CHECK(std::regex_search(lines[2], std::regex("rotation_change_a-?[0-9]+(\\.[0-9]+)? ")));
  CHECK_FALSE(std::regex_search(lines[3], by_a));
  CHECK(std::regex_search(lines[3], std::regex("_[0-9]+ ")));
}

TEST_CASE("fit_drift calls a trend significant beyond 2 sigma of its slope, not 1: the exact boundary", "[log][drift]") {
  using trueaxis::sim::fit_drift;
  // An exact line (chi-square 0) at days 0, 7, 14 with sigma 0.1: the
  // slope's sigma is 0.1 / sqrt(98) per day in closed form; a slope of
  // 2 sigma_b (1 +- 1e-9) on either side of the rule, and 1.5 sigma_b.
  const double sigma_b = 0.1 / std::sqrt(98.0);
  const auto drift_of = [](double slope) {
    std::vector<trueaxis::sim::LogRow> rows;
    for (double day : {0.0, 7.0, 14.0}) rows.push_back(check_row(day, "rotation_change", 1.0 + slope * day, 0.1, 12.0));
    const std::vector<trueaxis::sim::Drift> d = fit_drift(rows);
    REQUIRE(d.size() == 1);
    REQUIRE(d[0].enough);
    return d[0];
  };
  const trueaxis::sim::Drift above = drift_of(2.0 * sigma_b * (1.0 + 1e-9));
  CHECK(above.slope_sigma == Approx(sigma_b).epsilon(1e-12));
  CHECK(above.significant);
  CHECK(above.cross_s > 0.0);
  CHECK(trueaxis::sim::drift_line(above).find("reaches its tolerance about") != std::string::npos);
  const trueaxis::sim::Drift below = drift_of(2.0 * sigma_b * (1.0 - 1e-9));
  CHECK(below.slope_sigma == Approx(sigma_b).epsilon(1e-12));
  CHECK_FALSE(below.significant);
  CHECK(below.cross_s == 0.0);
  CHECK(trueaxis::sim::drift_line(below).find("no significant trend") != std::string::npos);
  CHECK_FALSE(drift_of(1.5 * sigma_b).significant);
  CHECK_FALSE(drift_of(-1.5 * sigma_b).significant);
  CHECK(drift_of(-2.0 * sigma_b * (1.0 + 1e-9)).significant);  // falling: |b| counts
  CHECK_FALSE(drift_of(-2.0 * sigma_b * (1.0 - 1e-9)).significant);
}

TEST_CASE("trueaxis-calibrate --operator refuses control characters and broken UTF-8, at the printable boundaries",
          "[calibrate][log]") {
  SimFixture sim;
  Workspace w("trueaxis-calibrate-operator");
  const std::string sentence = "--operator takes a name in UTF-8 without control characters";
  const auto refused = [&](const std::string& name) {
    const Run r = calibrate({"rigidity", "--in", w.file("none.csv"), "--json", w.file("y.json"), "--operator", name},
                            sim.port(), w);
    CHECK(r.exit_code == 1);  // refused for the name, or (accepted) for the missing file
    return r.err.find(sentence) != std::string::npos;
  };
  // C0 (0x01, 0x1F: tab, newline and escape among them), DEL, C1 (U+0080,
  // U+009F), a lead byte alone, a continuation byte alone, 0xFF.
  for (const std::string bad : {"A\x01", "A\x1f", "A\tB", "A\nB", "A\x1b[31m", "A\x7f", "A\xc2\x80", "A\xc2\x9f",
                                "A\xc3", "A\x80", "A\xff"}) {
    INFO("refused: " << bad);
    CHECK(refused(bad));
  }
  // Their neighbours: space (0x20), '~' (0x7E), U+00A0 and U+00FF, and names in other scripts.
  for (const std::string good : {"A B", "A~", "A\xc2\xa0" "B", "Zo\xc3\xab \xc3\x98rsted", "\xe6\x9d\x8e \xe5\xa8\x9c",
                                 "\xf0\x9f\x94\xa7"}) {
    INFO("taken: " << good);
    CHECK_FALSE(refused(good));
  }
}

namespace {

// 9833 at A = 0: true when a rigidity table is stored (404 no_table otherwise).
bool rigidity_stored(trueaxis::sim::VariableClient& client) {
  REQUIRE(client.write_one(v::kArgA, 0.0));
  const trueaxis::sim::MacroOutcome outcome = client.run_macro(9833);
  REQUIRE(client.give_back_interface());
  REQUIRE((outcome.status == 2 || (outcome.status == 3 && outcome.error == 404)));
  return outcome.status == 2;
}

}  // namespace

TEST_CASE("--time takes 2^32 - 1 s and refuses one more; a #9015 the module refuses fails the run, nothing stored "
          "or logged, never the controller's clock instead",
          "[calibrate][log]") {
  namespace ts = trueaxis::sim;
  Workspace w("trueaxis-calibrate-time");
  {
    SimFixture sim;
    REQUIRE(sim.client().give_back_interface());
    const Run m = run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("samples.csv")},
                      w.file("measure.err"));
    REQUIRE(m.exit_code == 0);
    const std::string sentence = "--time takes Unix seconds or a UTC date and time";
    for (const char* beyond : {"4294967296", "4294967295.5", "2106-02-07T06:28:16Z"}) {
      INFO(beyond);
      const Run r = calibrate({"rigidity", "--in", w.file("samples.csv"), "--json", w.file("y.json"), "--store",
                               "--time", beyond},
                              sim.port(), w);
      CHECK(r.exit_code == 1);
      CHECK(r.err.find(sentence) != std::string::npos);
    }
    CHECK(sim.get(v::kLogCount) == 0.0);
    for (const char* last : {"4294967295", "2106-02-07T06:28:15Z"}) {
      INFO(last);
      const Run r = calibrate({"rigidity", "--in", w.file("samples.csv"), "--json", w.file("y.json"), "--store",
                               "--time", last},
                              sim.port(), w);
      INFO(r.err);
      REQUIRE(r.exit_code == 0);
      sim.set(v::kLogSelect, sim.get(v::kLogNewest));
      CHECK(sim.get(v::kLogStored) == 1.0);
      CHECK(sim.get(v::kLogEntryTime) == 4294967295.0);  // the log's u32, to its last second
      REQUIRE(sim.client().give_back_interface());
    }
  }

  // Through the flows, a time the module's #9015 refuses (beyond its u32), on
  // a controller with nothing stored.
  SimFixture sim;
  ts::VariableClient& client = sim.client();
  const auto newest_entry = [&sim](std::uint16_t field) {
    sim.set(v::kLogSelect, sim.get(v::kLogNewest));
    const double value = sim.get(field);
    REQUIRE(sim.client().give_back_interface());
    return value;
  };
  ts::CalibrateOptions o;
  o.method = "rigidity";
  o.in_path = w.file("samples.csv");
  o.log_time = 4294967296.0;
  ts::FlowResult r = ts::calibrate_rigidity(client, o);
  CHECK_FALSE(r.ok);
  CHECK(r.error.find("the controller refused the measuring log's time #9015 = 4294967296") == 0);
  CHECK(r.error.find("nothing was stored") != std::string::npos);
  REQUIRE(client.give_back_interface());
  CHECK(sim.get(v::kLogCount) == 0.0);  // nothing logged under the controller's clock
  // A good calibration, then its store handed a refused time: nothing stored,
  // locked again, the log as it was.
  o.log_time = kT0;
  r = ts::calibrate_rigidity(client, o);
  INFO(r.error);
  REQUIRE(r.ok);
  REQUIRE(client.give_back_interface());
  const double newest = sim.get(v::kLogNewest);
  r.log_time = 4294967296.0;
  CHECK_FALSE(ts::store_rigidity(client, r));
  CHECK(r.error.find("#9015 = 4294967296") != std::string::npos);
  CHECK(r.error.find("nothing was stored") != std::string::npos);
  REQUIRE(client.give_back_interface());
  CHECK(sim.get(v::kUnlock) == 0.0);
  CHECK_FALSE(rigidity_stored(client));
  CHECK(sim.get(v::kLogNewest) == newest);
  if (newest > 0.0) {
    CHECK(newest_entry(v::kLogStored) == 0.0);
    CHECK(newest_entry(v::kLogEntryTime) == kT0);
  }
  // Stored with a good time, then a check handed a refused one: no check logged.
  r.log_time = kT0 + 60.0;
  REQUIRE(ts::store_rigidity(client, r));
  REQUIRE(client.give_back_interface());
  REQUIRE(rigidity_stored(client));
  r = ts::calibrate_rigidity(client, o);
  REQUIRE(r.ok);
  REQUIRE(client.give_back_interface());
  const double before = sim.get(v::kLogNewest);
  REQUIRE(before > 0.0);
  r.log_time = 4294967296.0;
  trueaxis::macros::Verdict verdict = trueaxis::macros::Verdict::kPass;
  CHECK_FALSE(ts::check_built(client, *ts::find_calibrate_method("rigidity"), r, verdict));
  CHECK(r.error.find("#9015 = 4294967296") != std::string::npos);
  REQUIRE(client.give_back_interface());
  CHECK(sim.get(v::kLogNewest) == before);
  CHECK(newest_entry(v::kLogType) == 0.0);  // no check replaced or followed the calibration
}

TEST_CASE("log: a refusal's item as the log keeps it: M4's change gate's angle step read back as its angle",
          "[log]") {
  using trueaxis::core::Status;
  CHECK(trueaxis::sim::refusal_item_text("spindle", Status::kChangeBeyondLimit, 1) == "at 0 deg");
  CHECK(trueaxis::sim::refusal_item_text("spindle", Status::kChangeBeyondLimit, 28) == "at 270 deg");
  CHECK(trueaxis::sim::refusal_item_text("spindle", Status::kChangeBeyondLimit, 36) == "at 350 deg");
  CHECK(trueaxis::sim::refusal_item_text("spindle", Status::kFitBeyondNoise, 2) == "at item 2");  // a ball
  CHECK(trueaxis::sim::refusal_item_text("rigidity", Status::kChangeBeyondLimit, 3) == "at item 3");  // a pose
  CHECK(trueaxis::sim::refusal_item_text("spindle", Status::kChangeBeyondLimit, 0).empty());
}
