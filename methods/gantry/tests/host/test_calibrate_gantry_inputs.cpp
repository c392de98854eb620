// `trueaxis-calibrate gantry`'s flow (calibrate_gantry, store_gantry) driven in
// this process against a simulator served in this process too (see
// test_calibrate_gantry.cpp): every bad input gets its own one-line error (the
// file and physical line, or the module's code) and stores nothing: 9825 answers
// afterwards exactly as before (no_table, or the frames stored earlier), and the
// module is locked.
#include <catch2/catch.hpp>

#include <cstddef>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "calibrate_gantry_support.hpp"
#include "calibrate_support.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"

namespace {

namespace v = trueaxis::macros::var;
namespace sim = trueaxis::sim;
using trueaxis::core::Status;
using namespace trueaxis::test;

}  // namespace

TEST_CASE("calibrate gantry: every bad input has its own error and stores nothing", "[calibrate][gantry]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-gantry");
  const Measured m = measure(small_plan(), 3);
  const std::vector<Row> good = rows_of(m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const std::string bad = w.file("bad.csv");

  struct Case {
    std::string name, samples, machine, error;  // error: the whole line, or its start
    bool whole;
    std::vector<int> sub_machines = {};  // --sub-machines
  };
  std::vector<Case> cases;
  std::vector<std::string> nominal_texts;  // the MACHINE files of the nominal-origin cases
  // Lines 1 comment, 2 header, then good[k] on line 3 + k.
  const auto with = [&](const std::vector<Row>& rows) { return "# bad\n" + text_of(rows); };
  const auto line_of = [](std::size_t k) { return std::to_string(3 + k); };
  const auto replaced = [&](std::size_t k, const std::string& text) {
    std::vector<Row> rows = good;
    rows[k].text = text;
    return with(rows);
  };
  const auto without = [&](const std::string& group) {
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != group) rows.push_back(r);
    }
    return with(rows);
  };
  const auto at = [&](std::size_t k, const std::string& what) { return bad + ":" + line_of(k) + ": " + what; };

  std::size_t first_sp1_x = 0;
  while (good[first_sp1_x].group != "sp1_x_1") ++first_sp1_x;
  cases.push_back({"a malformed row", replaced(40, "side_1,1.5,abc,3"), machine,
                   at(40, "'y_mm' is not a finite number: 'abc'"), true});
  cases.push_back({"a missing field", replaced(41, "side_1,1.5,2"), machine,
                   at(41, "too few fields: no value for 'z_mm'"), true});
  cases.push_back({"nan", replaced(first_sp1_x + 2, "sp1_x_1,1,2,nan"), machine,
                   at(first_sp1_x + 2, "'z_mm' is not a finite number: 'nan'"), true});
  cases.push_back({"inf", replaced(5, "bed,inf,2,3"), machine, at(5, "'x_mm' is not a finite number: 'inf'"), true});
  cases.push_back({"an unknown group", replaced(first_sp1_x, "sp1_w_1,1,2,3"), machine,
                   at(first_sp1_x, "unknown group 'sp1_w_1'"), true});
  cases.push_back({"a misspelt group", replaced(3, "beds,1,2,3"), machine, at(3, "unknown group 'beds'"), true});
  cases.push_back({"sub-machine 9", replaced(first_sp1_x, "sp9_x_1,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp9_x_1': the sub-machine N must be 1..8"), true});
  cases.push_back({"sub-machine 0", replaced(first_sp1_x, "sp0_c,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp0_c': the sub-machine N must be 1..8"), true});
  cases.push_back({"a leading zero", replaced(first_sp1_x, "sp01_c,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp01_c': the sub-machine N must be 1..8"), true});
  cases.push_back({"pass 5", replaced(first_sp1_x, "sp1_x_5,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp1_x_5': the pass K must be 1..4"), true});
  cases.push_back({"gantry pass 0", replaced(2, "gantry_0,1,2,3"), machine,
                   at(2, "group 'gantry_0': the pass K must be 1..4"), true});
  // The module names no group: the command names the one it did not send.
  cases.push_back({"a missing group", without("sp2_a"), machine,
                   module_error(Status::kMissingGroup) + " (macro 9823): " + bad + " has no row of group 'sp2_a'", true});
  cases.push_back({"no bed", without("bed"), machine,
                   module_error(Status::kMissingGroup) + " (macro 9823): " + bad + " has no row of group 'bed'", true});
  cases.push_back({"a missing middle pass", without("gantry_1"), machine,
                   module_error(Status::kMissingGroup) + " (macro 9823): " + bad + " has no row of group 'gantry_1'",
                   true});
  {
    // A row given twice (at the end of the file), and the file given twice: refused at the repeat's line.
    std::vector<Row> rows = good;
    rows.push_back(good[10]);
    cases.push_back({"a row given twice", with(rows), machine,
                     at(good.size(), module_error(Status::kDuplicateSample) + " (macro 9821)"), true});
    rows = good;
    rows.insert(rows.end(), good.begin(), good.end());
    std::size_t first_bed = 0;
    while (good[first_bed].group != "bed") ++first_bed;
    cases.push_back({"the file given twice", with(rows), machine,
                     at(good.size() + first_bed, module_error(Status::kDuplicateSample) + " (macro 9821)"), true});
    // More rows than the session holds: refused while reading, at the first beyond it.
    rows = good;
    for (std::size_t k = good.size(); k <= trueaxis::macros::gantry::kSessionCapacity; ++k) {
      rows.push_back({"bed", "bed," + std::to_string(k) + ",2,0"});
    }
    cases.push_back({"more points than the session holds", with(rows), machine,
                     at(trueaxis::macros::gantry::kSessionCapacity,
                        "point 2048 + 1: the module's gantry session holds 2048 points (session_full); nothing was sent"),
                     true});
  }
  {
    // sp3's C circle 31 points (its capacity 30): the 31st in file order is refused.
    std::vector<Row> rows = good;
    std::vector<Row> c;
    for (const Row& r : good) {
      if (r.group == "sp3_c") c.push_back(r);
    }
    REQUIRE(c.size() == 12);
    const std::size_t extra = trueaxis::macros::gantry::kMaxCirclePoints + 1 - c.size();
    for (std::size_t k = 0; k < extra; ++k) rows.push_back({"sp3_c", "sp3_c," + std::to_string(1000 + k) + ",2,3"});
    cases.push_back({"a circle over its capacity", with(rows), machine,
                     bad + ":" + line_of(rows.size() - 1) + ": " + module_error(Status::kTooManyPoints) +
                         " (macro 9821): group 'sp3_c' holds at most 30 points, and this is one more",
                     true});
    // A pass of 65 points (capacity 64).
    rows = good;
    std::size_t in_pass = 0;
    for (const Row& r : good) in_pass += r.group == "gantry_2" ? 1u : 0u;
    for (std::size_t k = in_pass; k <= trueaxis::macros::gantry::kMaxPassPoints; ++k) {
      rows.push_back({"gantry_2", "gantry_2," + std::to_string(k) + ",2,3"});
    }
    cases.push_back({"a pass over its capacity", with(rows), machine,
                     bad + ":" + line_of(rows.size() - 1) + ": " + module_error(Status::kTooManyPoints) +
                         " (macro 9821): group 'gantry_2' holds at most 64 points, and this is one more",
                     true});
  }
  {
    // sp2's A circle of 4 points (a circle needs 5): too_few_points.
    std::vector<Row> rows;
    std::size_t kept = 0;
    for (const Row& r : good) {
      if (r.group != "sp2_a" || kept++ < 4) rows.push_back(r);
    }
    cases.push_back({"a circle of 4 points", with(rows), machine, module_error(Status::kTooFewPoints), false});
  }
  {
    // sp1's C circle measured over 20 deg only (the minimum arc is 30 deg).
    sim::GantryPlan short_arc = small_plan();
    short_arc.c_to_deg = 20.0;
    short_arc.circle_points = 5;
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != "sp1_c") rows.push_back(r);
    }
    for (const Row& r : rows_of(measure(short_arc, 4).samples)) {
      if (r.group == "sp1_c") rows.push_back(r);
    }
    cases.push_back({"a C circle over 20 deg", with(rows), machine, module_error(Status::kArcTooShort), false});
  }
  {
    // sp2's A circle replaced by its C circle: A parallel to C.
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != "sp2_a") rows.push_back(r);
    }
    for (const Row& r : good) {
      if (r.group == "sp2_c") rows.push_back({"sp2_a", "sp2_a" + r.text.substr(r.text.find(','))});
    }
    cases.push_back({"A parallel to C", with(rows), machine, module_error(Status::kAxesParallel), false});
  }
  {
    // sp4's x passes measured backwards: all of them, or one of two.
    const auto reversed = [&](const std::vector<std::string>& groups) {
      std::vector<Row> rows = good;
      for (const std::string& g : groups) {
        std::vector<std::size_t> at_rows;
        for (std::size_t k = 0; k < rows.size(); ++k) {
          if (rows[k].group == g) at_rows.push_back(k);
        }
        REQUIRE(at_rows.size() == 8);
        for (std::size_t k = 0; k < at_rows.size() / 2; ++k) {
          std::swap(rows[at_rows[k]], rows[at_rows[at_rows.size() - 1 - k]]);
        }
      }
      return with(rows);
    };
    cases.push_back({"every x pass backwards", reversed({"sp4_x_1", "sp4_x_2"}), machine,
                     module_error(Status::kAxisOppositeGantry), false});
    cases.push_back({"one x pass backwards", reversed({"sp4_x_2"}), machine, module_error(Status::kPassesDisagree),
                     false});
  }
  {
    // MACHINE without sub-machine 3's row (line 5: a comment, the header, then 1, 2, 3, 4).
    std::istringstream in(m.machine);
    std::string text, line;
    int number = 0;
    while (std::getline(in, line)) {
      if (++number != 5) text += line + "\n";
    }
    REQUIRE(m.machine.find("\n3,") != std::string::npos);
    REQUIRE(text.find("\n3,") == std::string::npos);
    const std::string no3 = w.write("no3.csv", text);
    cases.push_back({"a sub-machine without a MACHINE row", with(good), no3,
                     no3 + ": no row for sub-machine 3, which " + bad + " measures", true});
    const std::string twice = w.write("twice.csv", m.machine + "2,250,0,0,1\n");
    cases.push_back({"a sub-machine twice in MACHINE", with(good), twice,
                     twice + ":7: sub-machine 2 is given twice", true});
    const std::string nine = w.write("nine.csv", m.machine + "9,250,0,0,1\n");
    cases.push_back({"sub-machine 9 in MACHINE", with(good), nine, nine + ":7: sub_machine must be a whole number 1..8",
                     true});
    // Not taken as sub-machine 1.
    const std::string half = w.write("half.csv", m.machine.substr(0, m.machine.find("\n1,") + 1) + "1.5" +
                                                     m.machine.substr(m.machine.find("\n1,") + 2));
    REQUIRE(half.size() > 0);
    cases.push_back({"a fractional sub-machine in MACHINE", with(good), half,
                     half + ":3: sub_machine must be a whole number 1..8", true});
    const std::string word = w.write("word.csv", m.machine + "4,abc,0,0,1\n");
    cases.push_back({"a malformed MACHINE row", with(good), word,
                     word + ":7: 'swing_mm' is not a finite number: 'abc'", true});
    const std::string zero = w.write("zero.csv", m.machine.substr(0, m.machine.find("\n1,") + 1) + "1,300,0,0,0\n" +
                                                     m.machine.substr(m.machine.find("\n2,") + 1));
    cases.push_back({"a zero tool direction", with(good), zero,
                     zero + ":3: " + module_error(Status::kArgumentOutOfRange), false});
    cases.push_back({"no MACHINE file", with(good), "", "gantry needs --machine MACHINE.csv", false});
    // A MACHINE row (sub-machine 3, line 5) whose sub-machine has no points: forgotten, or its groups misnamed.
    std::vector<Row> no_sp3;
    for (const Row& r : good) {
      if (r.group.rfind("sp3_", 0) != 0) no_sp3.push_back(r);
    }
    cases.push_back({"a MACHINE row without points", with(no_sp3), machine,
                     machine + ":5: sub-machine 3 has no points in " + bad + " (no group sp3_...): not measured, or "
                     "its groups misnamed? (to calibrate some sub-machines only, name them: --sub-machines 1,2,4)",
                     true});
    // The same with --sub-machines naming it, and a point of one it leaves out (sp2's first, in file order).
    cases.push_back({"--sub-machines names one without points", with(no_sp3), machine,
                     machine + ":5: sub-machine 3 has no points in " + bad + " (no group sp3_...), though "
                     "--sub-machines names it",
                     true, {1, 2, 3, 4}});
    std::size_t first_sp2 = 0;
    while (good[first_sp2].group.rfind("sp2_", 0) != 0) ++first_sp2;
    cases.push_back({"a point of a sub-machine --sub-machines leaves out", with(good), machine,
                     at(first_sp2, "group '" + good[first_sp2].group + "': sub-machine 2 is not among --sub-machines"),
                     true, {1, 3, 4}});
    cases.push_back({"--sub-machines names one neither file has", with(no_sp3), no3,
                     "--sub-machines names sub-machine 3, which neither " + bad + " measures nor " + no3 + " gives",
                     true, {1, 2, 3, 4}});
  }
  {
    // Nominals typed wrong (issue "Nothing wrong reaches the machine", item 1):
    // each MACHINE line as machine_csv_text writes it, line 3 sub-machine 1.
    const auto lines_of = [](const std::string& text) {
      std::vector<std::string> out;
      std::istringstream in(text);
      for (std::string line; std::getline(in, line);) out.push_back(line);
      return out;
    };
    const auto joined = [](const std::vector<std::string>& lines) {
      std::string text;
      for (const std::string& l : lines) text += l + "\n";
      return text;
    };
    const auto field = [](const std::string& line, std::size_t k) {
      std::istringstream in(line);
      std::string f;
      for (std::size_t i = 0; i <= k; ++i) std::getline(in, f, ',');
      return f;
    };
    const auto with_field = [&](const std::string& line, std::size_t k, const std::string& value) {
      std::istringstream in(line);
      std::string f, out;
      for (std::size_t i = 0; std::getline(in, f, ','); ++i) out += (i > 0 ? "," : "") + (i == k ? value : f);
      return out;
    };
    // MACHINE in metres: every swing length 1000 times short (the directions are unit vectors either way).
    std::vector<std::string> metres = lines_of(m.machine);
    for (std::size_t n = 2; n < metres.size(); ++n) {
      metres[n] = with_field(metres[n], 1, std::to_string(std::stod(field(metres[n], 1)) / 1000.0));
    }
    const std::string in_metres = w.write("metres.csv", joined(metres));
    cases.push_back({"MACHINE in metres", with(good), in_metres,
                     module_error(trueaxis::macros::gantry::kSwingImplausible) + " (macro 9823; gate swing (each sub-machine's swing "
                     "length (MACHINE in metres?)) at sub-machine 1: 0.3 mm against the limit 10 mm (#709 "
                     "gantry_min_swing)) -- " + in_metres + ":3: sub-machine 1's swing_mm 0.3 is shorter than 10 "
                     "mm: MACHINE.csv in metres? trueaxis takes mm", true});
    // With nominal origins: a swing length typed 2500 for 250 (sub-machine 2, line 4) and a tool direction
    // the wrong way round (sub-machine 1, line 3) are held to them.
    std::vector<std::string> typed = lines_of(m.machine_nominal);
    REQUIRE(field(typed[3], 1) == "250.000000000");
    typed[3] = with_field(typed[3], 1, "2500");
    const std::string typed_file = w.write("typed.csv", joined(typed));
    cases.push_back({"a swing length typed 2500 for 250", with(good), typed_file,
                     module_error(trueaxis::macros::gantry::kOriginOffNominal), false});
    std::vector<std::string> flipped = lines_of(m.machine_nominal);
    for (std::size_t k = 2; k <= 4; ++k) {
      const std::string f = field(flipped[2], k);
      flipped[2] = with_field(flipped[2], k, f[0] == '-' ? f.substr(1) : "-" + f);
    }
    const std::string flipped_file = w.write("flipped.csv", joined(flipped));
    cases.push_back({"a tool direction with its sign flipped", with(good), flipped_file,
                     module_error(trueaxis::macros::gantry::kOriginOffNominal), false});
    std::vector<std::string> partial = lines_of(m.machine_nominal);
    partial[2] = with_field(partial[2], 7, "");
    const std::string partial_file = w.write("partial.csv", joined(partial));
    cases.push_back({"a nominal origin without its z", with(good), partial_file,
                     partial_file + ":3: a nominal origin needs origin_x_mm, origin_y_mm and origin_z_mm, all three, "
                     "or none", true});
    nominal_texts = {typed_file, flipped_file};
  }

  const auto check_refusals = [&](const std::vector<std::vector<double>>& before) {
    for (const Case& c : cases) {
      CAPTURE(c.name);
      w.write("bad.csv", c.samples);
      const sim::FlowResult r = flow(client, bad, c.machine, true, c.sub_machines);
      CAPTURE(r.error);
      CHECK_FALSE(r.ok);
      CHECK(r.json.empty());
      if (c.whole) {
        CHECK(r.error == c.error);
      } else {
        CHECK(r.error.compare(0, c.error.size(), c.error) == 0);
      }
      CHECK(r.error.find('\n') == std::string::npos);  // one line
      if (c.name == "a swing length typed 2500 for 250") {
        CHECK(r.error.find(" -- " + nominal_texts[0] + ":4: sub-machine 2's measured origin lies 22") != std::string::npos);
        CHECK(r.error.find("is swing_mm 2500 typed wrong (a digit twice? metres?)") != std::string::npos);
      }
      if (c.name == "a tool direction with its sign flipped") {
        CHECK(r.error.find(" -- " + nominal_texts[1] + ":3: sub-machine 1's measured origin lies 6") != std::string::npos);
        CHECK(r.error.find("the wrong way round") != std::string::npos);
      }
      CHECK(read_var(client, v::kUnlock) == 0.0);     // locked
      CHECK(conversions(client) == before);           // nothing stored
    }
  };

  SECTION("with no frames stored: still none") {
    const std::vector<std::vector<double>> none = conversions(client);
    for (const auto& c : none) REQUIRE(c == std::vector<double>{404.0});
    check_refusals(none);
  }
  SECTION("with frames stored: they convert exactly as before") {
    const sim::FlowResult r = flow(client, w.write("good.csv", m.samples), machine, true);
    INFO(r.error);
    REQUIRE(r.ok);
    const std::vector<std::vector<double>> stored = conversions(client);
    for (const auto& c : stored) REQUIRE(c.size() == 3);
    check_refusals(stored);
  }
}

TEST_CASE("calibrate gantry: nominal origins hold the swing lengths and tool directions, without them they are taken "
          "as given; a first store says so",
          "[calibrate][gantry]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w("trueaxis-calibrate-gantry-nominal");
  const Measured m = measure(small_plan(), 5);
  const std::string samples = w.write("samples.csv", m.samples);
  // With nominal origins (a drawing's, to 0.1 mm): computed and stored, nothing taken as given.
  sim::FlowResult r = flow(client, samples, w.write("nominal.csv", m.machine_nominal), true);
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(r.as_given.empty());
  CHECK(r.as_given_summary.empty());
  // Without them: the same frames, and every measured sub-machine's swing length and tool direction named.
  const std::string plain = w.write("plain.csv", m.machine);
  r = flow(client, samples, plain, false);
  REQUIRE(r.ok);
  REQUIRE(r.as_given.size() == 4);
  CHECK(r.as_given[0].rfind("sub-machine 1's swing_mm 300 and tool direction (", 0) == 0);
  CHECK(r.as_given[0].find("(" + plain + ":3; no nominal origin to hold them to)") != std::string::npos);
  CHECK(r.as_given_summary == "swing_mm and tool direction of sub-machines 1, 2, 3, 4 (" + plain +
                                  " gives no nominal origin: origin_x_mm .. origin_z_mm)");
}
