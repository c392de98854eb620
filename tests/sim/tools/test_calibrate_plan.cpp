// trueaxis-calibrate plan (planner.hpp; docs/INTERFACE.md "Planning a
// measurement") as a user runs it: the table and PLAN.json, the exit codes
// (0, 3 when the method would refuse the plan, 1 on bad usage), and the
// mistakes people make: angles in radians, a pose list given twice over, an
// option out of its range, a directory for PLAN.json.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "calibrate_support.hpp"

namespace {

namespace t = trueaxis::test;

t::Run plan(const t::Workspace& w, std::vector<std::string> args) {
  args.insert(args.begin(), {TRUEAXIS_CALIBRATE_BINARY, "plan"});
  return t::run(args, w.file("stderr"));
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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
