// `trueaxis-calibrate spindle`'s flow (calibrate_spindle, store_spindle) driven
// in this process against a simulator served in this process too (see
// test_calibrate_spindle.cpp): every bad input gets its own one-line error (the
// file and physical line, or the module's code) and stores nothing: 9843
// answers afterwards exactly as before (no_table, or the model stored
// earlier), and the module is locked.
#include <catch2/catch.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "calibrate_spindle_support.hpp"
#include "calibrate_support.hpp"
#include "in_process_sim.hpp"
#include "trueaxis/core/status.hpp"

namespace {

namespace v = trueaxis::macros::var;
namespace sim = trueaxis::sim;
using trueaxis::core::Status;
using namespace trueaxis::test;

}  // namespace

TEST_CASE("calibrate spindle: every bad input has its own error and stores nothing", "[calibrate][spindle]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-spindle");
  // One revolution at 5 deg: lines 1-2 comments, 3 the header, then phi = 5 i
  // ball 1 on line 4 + 2 i and ball 2 on line 5 + 2 i.
  const SpindleFiles f = measure_spindle(w, "good", 3, 1);
  const std::vector<std::string> good = lines_of(slurp(f.samples));
  REQUIRE(good.size() == 3 + 144);
  REQUIRE(good[2] == "phi_deg,ball,x_mm,y_mm,z_mm");
  const std::vector<std::string> machine_lines = lines_of(slurp(f.machine));
  REQUIRE(machine_lines.size() == 7);  // a comment, the header, five names
  REQUIRE(machine_lines[6].rfind("tool_length_mm,", 0) == 0);
  const std::string bad = w.file("bad.csv");
  const std::string bad_machine = w.file("bad_machine.csv");
  const double tool = parse(slurp(f.truth))["tool_length_mm"].number;

  struct Case {
    std::string name, samples, machine, error;  // machine: a text, or "" for none; error: the line, or its start
    bool whole;
  };
  std::vector<Case> cases;
  const std::string machine = slurp(f.machine);
  const auto replaced = [&](std::size_t line, const std::string& text) {
    std::vector<std::string> lines = good;
    lines[line - 1] = text;
    return text_of(lines);
  };
  const auto kept = [&](bool (*keep)(double phi, int ball)) {
    std::vector<std::string> lines(good.begin(), good.begin() + 3);
    for (std::size_t n = 3; n < good.size(); ++n) {
      const std::vector<std::string> x = fields_of(good[n]);
      if (keep(std::stod(x[0]), std::stoi(x[1]))) lines.push_back(good[n]);
    }
    return text_of(lines);
  };
  const auto at = [&](std::size_t line, const std::string& what) {
    return bad + ":" + std::to_string(line) + ": " + what;
  };
  const auto machine_with = [&](std::size_t line, const std::string& text) {
    std::vector<std::string> lines = machine_lines;
    if (text.empty()) {
      lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(line - 1));
    } else {
      lines[line - 1] = text;
    }
    return text_of(lines);
  };
  const std::string samples = text_of(good);

  cases.push_back({"a malformed row", replaced(20, "40,1,1.5,abc,3"), machine,
                   at(20, "'y_mm' is not a finite number: 'abc'"), true});
  cases.push_back({"a row with a field missing", replaced(21, "40,2,1.5,2"), machine,
                   at(21, "too few fields: no value for 'z_mm'"), true});
  cases.push_back({"a missing column", replaced(3, "phi_deg,ball,x_mm,y_mm"), machine,
                   at(3, "the header has no column 'z_mm'"), true});
  cases.push_back(
      {"ball 3", replaced(30, "65,3,0.001,0.002,250"), machine, at(30, "ball must be 1 or 2, not '3'"), true});
  cases.push_back(
      {"ball 1.5", replaced(31, "65,1.5,0.001,0.002,250"), machine, at(31, "ball must be 1 or 2, not '1.5'"), true});
  cases.push_back(
      {"nan", replaced(40, "90,1,nan,0,250"), machine, at(40, "'x_mm' is not a finite number: 'nan'"), true});
  cases.push_back(
      {"inf", replaced(41, "inf,2,0,0,250"), machine, at(41, "'phi_deg' is not a finite number: 'inf'"), true});
  cases.push_back({"an angle beyond 1e6 deg", replaced(50, "2e6,1,0,0,250"), machine,
                   at(50, "the module refused the sample: Modbus: Illegal data value: out_of_range: Outside the variable's range, or not a whole number or a sign."), true});  // the register's range
  cases.push_back({"one ball height only", kept([](double, int ball) { return ball == 1; }), machine,
                   module_error(Status::kMissingGroup) + " (macro 9842): " + bad + " has no row for ball 2", true});
  {
    // The file given twice: refused at the repeat's first row (line 3 + 144 + 1), before any
    // sigma is computed; a row given twice in a row, at the second.
    std::vector<std::string> twice = good;
    twice.insert(twice.end(), good.begin() + 3, good.end());
    cases.push_back({"the file given twice", text_of(twice), machine,
                     at(148, module_error(Status::kDuplicateSample) + " (macro 9841)"), true});
    std::vector<std::string> row_twice = good;
    row_twice.insert(row_twice.begin() + 60, good[59]);
    cases.push_back({"a row given twice", text_of(row_twice), machine,
                     at(61, module_error(Status::kDuplicateSample) + " (macro 9841)"), true});
  }
  {
    std::string semicolons = samples;
    for (char& c : semicolons) c = c == ',' ? ';' : c;
    cases.push_back({"';' as separator", semicolons, machine,
                     at(3, "the file uses ';' as separator; trueaxis reads ','"), true});
  }
  cases.push_back({"7 angles of ball 2",
                   kept([](double phi, int ball) { return ball == 1 || static_cast<int>(phi) % 55 == 0; }), machine,
                   module_error(Status::kRevolutionIncomplete) + " (macro 9842)", true});  // gaps of 55 deg
  cases.push_back({"less than a revolution", kept([](double phi, int) { return phi < 300.0; }), machine,
                   module_error(Status::kRevolutionIncomplete) + " (macro 9842)", true});
  {
    // The angles in radians: a revolution spans 6.3 "degrees"; the refusal says radians.
    std::vector<std::string> lines(good.begin(), good.begin() + 3);
    for (std::size_t n = 3; n < good.size(); ++n) {
      std::vector<std::string> x = fields_of(good[n]);
      char rad[40];
      std::snprintf(rad, sizeof rad, "%.17g", std::stod(x[0]) * 3.14159265358979323846 / 180.0);
      lines.push_back(std::string(rad) + "," + x[1] + "," + x[2] + "," + x[3] + "," + x[4]);
    }
    REQUIRE(module_error(Status::kRevolutionIncomplete).find("radians") != std::string::npos);
    cases.push_back({"the angles in radians", text_of(lines), machine,
                     module_error(Status::kRevolutionIncomplete) + " (macro 9842)", true});
  }
  cases.push_back({"an empty samples file", "", machine, at(1, "no header row"), true});
  cases.push_back({"no samples file", "", machine, "", false});  // the path is replaced below
  // MACHINE: line 1 a comment, 2 the header, 3..7 the five names in docs/INTERFACE.md's order.
  cases.push_back({"no MACHINE file", samples, "", "spindle needs --machine MACHINE.csv", false});
  cases.push_back(
      {"a missing MACHINE name", samples, machine_with(7, ""), bad_machine + ": no row for 'tool_length_mm'", true});
  cases.push_back({"bearing_spacing_mm missing", samples, machine_with(3, ""),
                   bad_machine + ": no row for 'bearing_spacing_mm'", true});
  cases.push_back({"an unknown MACHINE name", samples, machine + "ball_3_mm,250\n",
                   bad_machine + ":8: unknown name 'ball_3_mm' (MACHINE names: bearing_spacing_mm, "
                                 "gauge_from_upper_bearing_mm, ball_1_mm, ball_2_mm, tool_length_mm)",
                   true});
  cases.push_back({"a MACHINE name twice", samples, machine + "ball_1_mm,60\n",
                   bad_machine + ":8: 'ball_1_mm' is given twice (first at line 5)", true});
  cases.push_back({"a malformed MACHINE value", samples, machine_with(6, "ball_2_mm,15O"),
                   bad_machine + ":6: 'value' is not a finite number: '15O'", true});
  cases.push_back({"MACHINE without its value column", samples, machine_with(2, "name,val"),
                   bad_machine + ":2: the header has no column 'value'", true});
  cases.push_back({"ball_2 at ball_1", samples, machine_with(6, "ball_2_mm,50"),
                   bad_machine + ": " + module_error(Status::kArgumentOutOfRange) +
                       " (macro 9842) (gauge_from_upper_bearing_mm > 0, 0 <= ball_1_mm < ball_2_mm)",
                   true});
  cases.push_back({"ball_2 nearer the spindle than ball_1", samples, machine_with(6, "ball_2_mm,20"),
                   bad_machine + ": " + module_error(Status::kArgumentOutOfRange), false});
  cases.push_back({"a zero gauge length", samples, machine_with(4, "gauge_from_upper_bearing_mm,0"),
                   bad_machine + ": " + module_error(Status::kArgumentOutOfRange), false});
  cases.push_back({"a zero bearing spacing", samples, machine_with(3, "bearing_spacing_mm,0"),
                   bad_machine + ":3: bearing_spacing_mm must be more than 0", true});
  {
    // MACHINE in metres, the samples in mm: every value finite, so never not_finite; the cause named.
    std::vector<std::string> metres = machine_lines;
    for (std::size_t n = 2; n < metres.size(); ++n) {
      const std::vector<std::string> x = fields_of(metres[n]);
      metres[n] = x[0] + "," + std::to_string(std::stod(x[1]) / 1000.0);
    }
    // The spacing gate refuses it before the fit (ball_spacing_implausible), the command names the files' units.
    cases.push_back({"MACHINE in metres", samples, text_of(metres), "module error 1300 ball_spacing_implausible", false});
    // Both files in metres: the spacings agree, 1000 times short; the ball-distance gate names both files.
    std::vector<std::string> lines(good.begin(), good.begin() + 3);
    for (std::size_t n = 3; n < good.size(); ++n) {
      const std::vector<std::string> x = fields_of(good[n]);
      char row[160];
      std::snprintf(row, sizeof row, "%s,%s,%.17g,%.17g,%.17g", x[0].c_str(), x[1].c_str(), std::stod(x[2]) / 1000.0,
                    std::stod(x[3]) / 1000.0, std::stod(x[4]) / 1000.0);
      lines.push_back(row);
    }
    cases.push_back({"both files in metres", text_of(lines), text_of(metres), "module error 1301 balls_too_close", false});
  }
  cases.push_back({"a negative tool length", samples, machine_with(7, "tool_length_mm,-1"),
                   bad_machine + ":7: " + module_error(Status::kArgumentOutOfRange) + " (macro 9844)", true});

  const auto check_refusals = [&](const std::vector<std::vector<double>>& before) {
    for (const Case& c : cases) {
      CAPTURE(c.name);
      const bool no_file = c.name == "no samples file";
      w.write("bad.csv", c.samples);
      if (!c.machine.empty()) w.write("bad_machine.csv", c.machine);
      const std::string in = no_file ? w.file("absent.csv") : bad;
      const sim::FlowResult r = spindle_flow(client, in, c.machine.empty() ? "" : bad_machine, true);
      CAPTURE(r.error);
      CHECK_FALSE(r.ok);
      CHECK(r.json.empty());
      if (no_file) {
        CHECK(r.error == w.file("absent.csv") + ": cannot be read");
      } else if (c.whole) {
        CHECK(r.error == c.error);
      } else {
        CHECK(r.error.compare(0, c.error.size(), c.error) == 0);
      }
      CHECK(r.error.find('\n') == std::string::npos);  // one line
      CHECK(r.error.find("not_finite") == std::string::npos);  // the CSV says 'not a finite number' for nan, inf
      if (c.name == "MACHINE in metres") CHECK(r.error.find("in metres") != std::string::npos);
      if (c.name == "both files in metres") {
        CHECK(r.error.find(bad_machine + ":6 and :5: ball_2_mm 0.15 - ball_1_mm 0.05 = 0.1 mm") != std::string::npos);
        CHECK(r.error.find("both files in metres? trueaxis takes mm") != std::string::npos);
      }
      CHECK(read_var(client, v::kUnlock) == 0.0);      // locked
      CHECK(corrections(client, tool) == before);      // nothing stored
    }
  };

  SECTION("with no model stored: still none") {
    const std::vector<std::vector<double>> none = corrections(client, tool);
    for (const auto& c : none) REQUIRE(c == std::vector<double>{static_cast<double>(Status::kNoTable)});
    check_refusals(none);
  }
  SECTION("with a model stored: 9843 answers exactly as before") {
    const sim::FlowResult r = spindle_flow(client, f.samples, f.machine, true);
    INFO(r.error);
    REQUIRE(r.ok);
    const std::vector<std::vector<double>> stored = corrections(client, tool);
    for (const auto& c : stored) REQUIRE(c.size() == 5);
    check_refusals(stored);
  }
}

TEST_CASE("calibrate spindle: the lengths no data tests are taken as given, named with their values and lines",
          "[calibrate][spindle]") {
  InProcessSim sim;
  Workspace w("trueaxis-calibrate-spindle-given");
  const SpindleFiles f = measure_spindle(w, "good", 3, 1);
  // gauge_from_upper_bearing_mm 3500 for 350 (a digit typed twice): no data of the analyser's can test it.
  std::string machine = slurp(f.machine);
  const std::size_t at = machine.find("gauge_from_upper_bearing_mm,");
  REQUIRE(at != std::string::npos);
  const std::size_t end = machine.find('\n', at);
  machine.replace(at, end - at, "gauge_from_upper_bearing_mm,3500");
  const std::string typed = w.write("typed_machine.csv", machine);
  const sim::FlowResult r = spindle_flow(sim.client(), f.samples, typed, false);
  INFO(r.error);
  REQUIRE(r.ok);
  REQUIRE(r.as_given.size() == 3);
  CHECK(r.as_given[0] == "gauge_from_upper_bearing_mm 3500 (" + typed + ":4; places O1, the ideal axis' point, on the "
                         "measured axis)");
  CHECK(r.as_given[1].rfind("tool_length_mm ", 0) == 0);
  CHECK(r.as_given[2].rfind("bearing_spacing_mm ", 0) == 0);
  CHECK(r.as_given_summary.rfind("gauge_from_upper_bearing_mm 3500, tool_length_mm ", 0) == 0);
}
