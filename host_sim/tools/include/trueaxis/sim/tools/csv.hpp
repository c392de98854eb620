// The CSV files of the calibration flows (docs/INTERFACE.md, "The integrator's
// command"): a header row with column names in any order (extra columns
// ignored), `#` lines are comments wherever they stand, numbers as C strtod
// reads them, a bad sample named by its physical line number (the first line is
// 1). Host only: it allocates.
//
// Contract
//  1. read_csv(path, columns) returns the rows' values in the order of `columns`
//     (text columns are kept as text), each with its physical line number.
//  2. Blank lines (only spaces, tabs, CR) are skipped like comments.
//  3. A field is a number when strtod consumes all of it but surrounding spaces
//     and the value is finite; "nan", "inf", "", "1.5x" are errors.
//  4. Errors are one line, "FILE:LINE: what", ready for stderr (a file that
//     cannot be read has no line: "FILE: cannot be read"): no header, a required column absent (named at the header's line), a row
//     with too few fields, a bad number (with the column's name).
#pragma once

#include <string>
#include <vector>

namespace trueaxis::sim {

struct CsvColumn {
  std::string name;
  bool numeric = true;
};

struct CsvRow {
  int line = 0;                      // physical line number, from 1
  std::vector<double> numbers;       // per requested column; 0 for a text column
  std::vector<std::string> texts;    // per requested column; the raw field
};

struct CsvResult {
  bool ok = false;
  std::string error;  // "FILE:LINE: what" when !ok
  int header_line = 0;
  std::vector<CsvRow> rows;
};

CsvResult read_csv(const std::string& path, const std::vector<CsvColumn>& columns);

// The same over text already in memory (`name` stands in for the file name).
CsvResult parse_csv(const std::string& name, const std::string& text, const std::vector<CsvColumn>& columns);

}  // namespace trueaxis::sim
