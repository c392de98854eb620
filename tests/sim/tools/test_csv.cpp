#include <catch2/catch.hpp>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

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

TEST_CASE("a UTF-8 byte-order mark is skipped; another separator or UTF-16 is named as such", "[csv]") {
  const auto bom = parse_csv("f.csv", "\xEF\xBB\xBF" "a_deg,c_deg,x_mm\n1,2,3\n", kCols);
  REQUIRE(bom.ok);
  CHECK(bom.header_line == 1);
  CHECK(bom.rows[0].numbers == std::vector<double>{1.0, 2.0, 3.0});
  CHECK(parse_csv("f.csv", "# x\na_deg;c_deg;x_mm\n1;2;3\n", kCols).error ==
        "f.csv:2: the file uses ';' as separator; trueaxis reads ','");
  CHECK(parse_csv("f.csv", "\xEF\xBB\xBF" "a_deg\tc_deg\tx_mm\n", kCols).error ==
        "f.csv:1: the file uses tabs as separator; trueaxis reads ','");
  CHECK(parse_csv("f.csv", std::string("\xFF\xFE" "a\0_\0", 6), kCols).error ==
        "f.csv:1: the file is UTF-16; trueaxis reads UTF-8 (or ASCII) text");
  // A BOM elsewhere than the start is no BOM: the header then lacks its first column.
  CHECK(parse_csv("f.csv", "#\n\xEF\xBB\xBF" "a_deg,c_deg,x_mm\n", kCols).error == "f.csv:2: the header has no column 'a_deg'");
}

TEST_CASE("CsvReader gives read_csv's rows one at a time, and its errors", "[csv]") {
  char path[] = "/tmp/trueaxis-csv-XXXXXX";
  const int fd = ::mkstemp(path);
  REQUIRE(fd >= 0);
  ::close(fd);
  const std::string text = "# c\nx_mm,a_deg,c_deg\n1,2,3\n\n4,5,6\n7,8,x\n";
  std::ofstream(path, std::ios::binary) << text;
  trueaxis::sim::CsvReader reader(path, kCols);
  trueaxis::sim::CsvRow row;
  REQUIRE(reader.next(row));
  CHECK(row.line == 3);
  CHECK(row.numbers == std::vector<double>{2.0, 3.0, 1.0});
  REQUIRE(reader.next(row));
  CHECK(row.line == 5);
  CHECK_FALSE(reader.next(row));
  CHECK(reader.error() == std::string(path) + ":6: 'c_deg' is not a finite number: 'x'");
  CHECK_FALSE(reader.next(row));  // it stays at the error
  CHECK(reader.bytes_read() == text.size());
  CHECK(reader.size_bytes() == text.size());
  std::remove(path);
}

TEST_CASE("quoted fields (RFC 4180): a quoted header, quoted numbers and text read; a bad quote is named", "[csv]") {
  // R's write.csv quotes the header and the text; a spreadsheet's "quote all" every field.
  const auto r = parse_csv("q.csv", "\"x_mm\",\"extra\",\"c_deg\",\"a_deg\"\n\"1.5\", \"a, \"\"b\"\"\" ,2,\"-3e1\"\n",
                           kCols);
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(r.rows[0].numbers == std::vector<double>{-30.0, 2.0, 1.5});
  const auto text = parse_csv("m.csv", "\"name\",\"value\"\n\"ball_1_mm\",50\n", {{"name", false}, {"value"}});
  REQUIRE(text.ok);
  CHECK(text.rows[0].texts[0] == "ball_1_mm");
  const auto spaced = parse_csv("m.csv", "name,value\n  \"a,b\"  ,  2 \n", {{"name", false}, {"value"}});
  REQUIRE(spaced.ok);
  CHECK(spaced.rows[0].texts[0] == "a,b");
  CHECK(spaced.rows[0].numbers[1] == 2.0);
  // A quoted number with a decimal comma is one field, and not a number.
  CHECK(parse_csv("q.csv", "a_deg,c_deg,x_mm\n0,\"1,5\",2\n", kCols).error ==
        "q.csv:2: 'c_deg' is not a finite number: '1,5' (a decimal comma? trueaxis reads '.')");
  CHECK(parse_csv("q.csv", "a_deg,c_deg,x_mm\n0,\"1.5,2\n", kCols).error ==
        "q.csv:2: field 2: the quote at column 3 is not closed");
  CHECK(parse_csv("q.csv", "\"a_deg\"x,c_deg,x_mm\n", kCols).error == "q.csv:1: field 1: text after its closing quote");
  // An empty quoted field is an empty field.
  CHECK(parse_csv("q.csv", "a_deg,c_deg,x_mm\n0,\"\",2\n", kCols).error == "q.csv:2: 'c_deg' is not a finite number: ''");
}
