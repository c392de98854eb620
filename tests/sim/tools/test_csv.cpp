#include <catch2/catch.hpp>

#include "trueaxis/sim/tools/csv.hpp"

using trueaxis::sim::parse_csv;

namespace {
const std::vector<trueaxis::sim::CsvColumn> kCols = {{"a_deg"}, {"c_deg"}, {"x_mm"}};
}

TEST_CASE("reads columns in any order, ignores extra columns, comments and blank lines", "[csv]") {
  const auto r = parse_csv("f.csv", "# made by a tracker\n\nx_mm,extra,c_deg,a_deg\r\n1.5,zz,2,-3e1\n# mid comment\n  4 , q, 5 ,6\n",
                           kCols);
  REQUIRE(r.ok);
  CHECK(r.header_line == 3);
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[0].line == 4);
  CHECK(r.rows[0].numbers == std::vector<double>{-30.0, 2.0, 1.5});
  CHECK(r.rows[1].line == 6);
  CHECK(r.rows[1].numbers == std::vector<double>{6.0, 5.0, 4.0});
}

TEST_CASE("names the physical line of a bad sample", "[csv]") {
  SECTION("not a number") {
    const auto r = parse_csv("f.csv", "a_deg,c_deg,x_mm\n0,0,1\n#c\n0,abc,1\n", kCols);
    CHECK_FALSE(r.ok);
    CHECK(r.error == "f.csv:4: 'c_deg' is not a finite number: 'abc'");
  }
  SECTION("trailing garbage, nan, inf and an empty field") {
    for (const char* bad : {"1.5x", "nan", "inf", "-INF", ""}) {
      const auto r = parse_csv("g.csv", std::string("a_deg,c_deg,x_mm\n0,0,") + bad + "\n", kCols);
      CHECK_FALSE(r.ok);
      CHECK(r.error.rfind("g.csv:2: 'x_mm'", 0) == 0);
    }
  }
  SECTION("too few fields") {
    const auto r = parse_csv("f.csv", "a_deg,c_deg,x_mm\n\n0,1\n", kCols);
    CHECK(r.error == "f.csv:3: too few fields: no value for 'x_mm'");
  }
  SECTION("a missing column is named at the header's line") {
    const auto r = parse_csv("f.csv", "#x\na_deg,x_mm\n0,1\n", kCols);
    CHECK(r.error == "f.csv:2: the header has no column 'c_deg'");
  }
  SECTION("a file that cannot be read is named without a line") {
    const auto r = trueaxis::sim::read_csv("/nonexistent/dir/samples.csv", kCols);
    CHECK_FALSE(r.ok);
    CHECK(r.error == "/nonexistent/dir/samples.csv: cannot be read");
  }
  SECTION("no header at all") {
    CHECK(parse_csv("f.csv", "# only a comment\n", kCols).error == "f.csv:1: no header row");
    CHECK(parse_csv("f.csv", "", kCols).error == "f.csv:1: no header row");
  }
}

TEST_CASE("keeps text columns as text", "[csv]") {
  const auto r = parse_csv("m.csv", "name,value\nswing_mm,250.5\n", {{"name", false}, {"value"}});
  REQUIRE(r.ok);
  CHECK(r.rows[0].texts[0] == "swing_mm");
  CHECK(r.rows[0].numbers[1] == 250.5);
}
