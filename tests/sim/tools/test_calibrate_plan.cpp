// trueaxis-calibrate plan (planner.hpp; docs/INTERFACE.md "Planning a
// measurement") as a user runs it: the table and PLAN.json, the exit codes
// (0, 3 when the method would refuse the plan, 1 on bad usage), and the
// mistakes people make: angles in radians, a pose list given twice over, an
// option out of its range, a directory for PLAN.json.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "calibrate_support.hpp"
#include "sim_fixture.hpp"

namespace {

namespace t = trueaxis::test;

t::Run plan(const t::Workspace& w, std::vector<std::string> args) {
  args.insert(args.begin(), {TRUEAXIS_CALIBRATE_BINARY, "plan"});
  return t::run(args, w.file("stderr"));
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// "module error CODE NAME: MESSAGE" out of a line that holds one.
std::string module_sentence(const std::string& line) {
  const std::size_t from = line.find("module error ");
  if (from == std::string::npos) return "";
  return line.substr(from, line.find(" (macro ", from) - from);
}

}  // namespace

TEST_CASE("plan: a prediction on stdout and in PLAN.json, exit 0", "[plan][cli]") {
  t::Workspace w("trueaxis-plan");
  const t::Run r = plan(w, {"level", "--points", "0,0;60,0;0,60;", "--json", w.file("plan.json")});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(has(r.out, "plan level: 3 probe points (0.0, 0.0), (60.0, 0.0), (0.0, 60.0)"));
  CHECK(has(r.out, "valuation "));
  CHECK(has(r.out, "suggestion 1: add the probe point"));
  const std::string json = t::slurp(w.file("plan.json"));
  for (const char* key : {"\"method\": \"level\"", "\"valuation\": ", "\"worst\": \"normal_turn_", "\"q95\": ",
                          "\"suggestions\": [", "\"inseparable\": ["}) {
    INFO(key);
    CHECK(has(json, key));
  }
  CHECK_FALSE(t::exists(w.file("plan.json.tmp")));
}

TEST_CASE("plan: a plan the method refuses exits 3 and says why; C in radians is named", "[plan][cli]") {
  t::Workspace w("trueaxis-plan");
  // Two A poses: the module takes three at least.
  std::string two = "a_deg,c_deg\n";
  for (const int a : {0, 30}) {
    for (const int c : {0, 90, 180, 270}) two += std::to_string(a) + "," + std::to_string(c) + "\n";
  }
  t::Run r = plan(w, {"rigidity", "--in", w.write("two.csv", two), "--json", w.file("p.json")});
  CHECK(r.exit_code == 3);
  CHECK(has(r.out, "the method refuses this plan: module error 208 too_few_poses"));
  CHECK(has(t::slurp(w.file("p.json")), "\"refused\": \"module error 208 too_few_poses"));
  // The same poses with C in radians.
  std::string radians = "a_deg,c_deg\n";
  for (const int a : {-30, 0, 30}) {
    for (const double c : {0.0, 1.5708, 3.1416, 4.7124}) radians += std::to_string(a) + "," + std::to_string(c) + "\n";
  }
  r = plan(w, {"rigidity", "--in", w.write("radians.csv", radians)});
  CHECK(r.exit_code == 3);
  CHECK(has(r.out, "arc_too_short"));
  CHECK(has(r.out, "are they in radians? the columns are degrees"));
}

TEST_CASE("plan: bad usage exits 1 with one line naming the option and its form", "[plan][cli]") {
  t::Workspace w("trueaxis-plan");
  const struct {
    std::vector<std::string> args;
    const char* says;
  } cases[] = {
      {{"foo", "--side", "3"}, "unknown METHOD 'foo'"},
      {{"gantry", "--circle-points", "37"}, "--circle-points '37': takes 5..36"},
      {{"rigidity", "--c-step", "5"}, "--c-step '5': takes degrees, 10..90"},
      {{"rigidity", "--a", "-400,400,30"}, "--a '-400,400,30': takes FROM,TO,STEP"},
      {{"rigidity", "--in", "x.csv", "--a", "-30,30,30"}, "--in gives the poses: not with --a or --c-step"},
      {{"level", "--points", "0,0;1,0"}, "takes X,Y;X,Y;X,Y"},
      {{"level", "--json", ""}, "--json '': takes a value"},
      {{"spindle", "--side", "100"}, "unknown option '--side' for plan spindle"},
      {{"level", "--json", "/tmp"}, "/tmp: cannot be written"},
  };
  for (const auto& c : cases) {
    const t::Run r = plan(w, c.args);
    INFO(c.args[0] << " " << c.args[1] << ": " << r.err);
    CHECK(r.exit_code == 1);
    CHECK(has(r.err, c.says));
    CHECK(r.out.empty());
  }
}

TEST_CASE("plan: what the module would refuse is refused with the module's sentence, as the calibration is",
          "[plan][cli][gates]") {
  t::Workspace w("trueaxis-plan");
  // The ball 0.2 mm and 3 mm from the C axis: the plan and a calibration of that
  // measurement on the simulator (its ball moved there) refuse with one sentence.
  trueaxis::sim::test::SimFixture sim({"--errors", "realistic"});
  const struct {
    const char* ball;
    double x_mm, y_mm, z_mm;
    const char* says;
  } balls[] = {{"0.2,0,0.05", 0.2, 0.0, 0.05, "module error 1100 a_error_implausible: "},
               {"3,0,50", 3.0, 0.0, 50.0, "module error 1101 c_radius_implausible: "}};
  for (const auto& b : balls) {
    INFO(b.ball);
    const t::Run p = plan(w, {"rigidity", "--ball", b.ball, "--suggest", "0", "--json", w.file("p.json")});
    CHECK(p.exit_code == 3);
    CHECK(has(p.out, "the method refuses this plan: " + std::string(b.says)));
    const std::string sentence = module_sentence(p.out);
    REQUIRE_FALSE(sentence.empty());
    CHECK(has(t::slurp(w.file("p.json")), "\"refused\": \"" + sentence));
    CHECK(has(p.out, "(macro 9832; item "));  // what the gate refused: the pose, the figure, the limit
    sim.set(12021, {b.x_mm, b.y_mm, b.z_mm});  // sim_ball_x, _y, _z
    REQUIRE(sim.client().give_back_interface());
    const t::Run m = t::run({TRUEAXIS_MEASURE_BINARY, "--port", std::to_string(sim.port()), "--out", w.file("b.csv")},
                            w.file("m.err"));
    REQUIRE(m.exit_code == 0);
    const t::Run c = t::run({TRUEAXIS_CALIBRATE_BINARY, "rigidity", "--in", w.file("b.csv"), "--json", w.file("o.json"),
                             "--port", std::to_string(sim.port())},
                            w.file("c.err"));
    INFO(c.err);
    CHECK(c.exit_code == 1);
    CHECK(module_sentence(c.err) == sentence);
  }
  // The module's capacities: a plane group of 128 points, 512 rigidity samples, 32 probe points, 4 passes.
  std::string points;
  for (int i = 0; i < 33; ++i) points += std::to_string(3 * i) + "," + std::to_string((7 * i) % 20) + ";";
  const struct {
    std::vector<std::string> args;
    const char* says;
  } limits[] = {
      {{"gantry", "--pad-grid", "6"},
       "reading 129 (group bed): module error 102 too_many_points: More points were given than the module can hold. "
       "(macro 9821)"},
      {{"gantry", "--passes", "5"}, "reading 201 (group gantry_5): module error 103 argument_out_of_range"},
      {{"gantry", "--circle-points", "31"}, "reading 351 (group sp1_c): module error 102 too_many_points"},
      {{"rigidity", "--a", "-105,105,15"}, "reading 513 (A = 105, C = 80 deg): module error 402 session_full"},
      {{"level", "--points", points}, "probe point 33 (96, 4 mm): module error 402 session_full"},
  };
  for (const auto& l : limits) {
    std::vector<std::string> args = l.args;
    args.insert(args.end(), {"--suggest", "0"});
    const t::Run r = plan(w, args);
    INFO(l.args[0] << " " << l.args[1] << ": " << r.out);
    CHECK(r.exit_code == 3);
    CHECK(has(r.out, std::string("the method refuses this plan: ") + l.says));
  }
  // The plans as they are (nothing the module refuses) still predict.
  const t::Run good = plan(w, {"gantry", "--suggest", "0"});
  CHECK(good.exit_code == 0);
}
