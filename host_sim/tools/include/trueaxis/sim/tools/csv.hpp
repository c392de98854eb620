// The CSV files of the calibration flows (docs/INTERFACE.md, "The integrator's
// command"): a header row with column names in any order (extra columns
// ignored), `#` lines are comments wherever they stand, numbers as C strtod
// reads them, a bad sample named by its physical line number (the first line is
// 1). Host only: it allocates.
//
// Contract
//  1. read_csv(path, columns) returns the rows' values in the order of `columns`
//     (text columns are kept as text), each with its physical line number.
//     CsvReader gives the same rows one at a time, holding one line in
//     memory whatever the file's length (the samples files).
//  2. Blank lines (only spaces, tabs, CR) are skipped like comments; a UTF-8
//     byte-order mark at the start of the file is skipped.
//  3. Fields are separated by commas and trimmed of spaces and tabs; a field
//     enclosed in double quotes (RFC 4180: R's write.csv quotes the header and
//     the text, a spreadsheet's "quote all" every field) is read without its
//     quotes, "" inside it stands for one ", and a comma inside it belongs to
//     it. A field is a number when strtod consumes all of it but surrounding
//     spaces and the value is finite; "nan", "inf", "", "1.5x" and "1,5" (a
//     decimal comma, named as such) are errors, quoted or not.
//  4. Errors are one line, "FILE:LINE: what", ready for stderr (a file that
//     cannot be read has no line: "FILE: cannot be read"): no header, a
//     required column absent (named at the header's line; a header split by
//     ';' or tabs is named as such: "the file uses ';' as separator; trueaxis
//     reads ','"; a UTF-16 file likewise), a row with too few fields, a bad
//     number (with the column's name), a quote not closed or followed by text.
//  5. An optional column may be absent from the header, and its field empty in
//     a row: its number is then NaN (not given) and its text "".
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace trueaxis::sim {

struct CsvColumn {
  std::string name;
  bool numeric = true;
  // Contract 5: a column the header may leave out, a field a row may leave empty.
  bool optional = false;
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

// The lines of one file, in order, turned into rows (contracts 2-4).
class CsvLines {
 public:
  enum class Kind { kSkip, kHeader, kRow, kError };
  CsvLines(std::string name, std::vector<CsvColumn> columns) : name_(std::move(name)), columns_(std::move(columns)) {}
  // Line `raw` (without its '\n'), the next physical line: a row into `row`
  // (kRow), or kError with error() set.
  Kind feed(std::string raw, CsvRow& row);
  // At the end of the file: "" when a header was seen, else the error.
  std::string finish() const;
  const std::string& error() const { return error_; }
  int line() const { return line_; }
  int header_line() const { return header_line_; }

 private:
  Kind fail(const std::string& what);
  std::string name_;
  std::vector<CsvColumn> columns_;
  std::vector<int> index_;
  std::string error_;
  int line_ = 0;
  int header_line_ = 0;
};

// A samples file read one row at a time (contract 1).
class CsvReader {
 public:
  CsvReader(const std::string& path, const std::vector<CsvColumn>& columns);
  // The next row; false at the end of the file or on an error (error() then
  // says which, "" at the end). The header is read on the first call.
  bool next(CsvRow& row);
  const std::string& error() const { return error_; }
  int line() const { return lines_.line(); }
  int header_line() const { return lines_.header_line(); }
  std::uint64_t bytes_read() const { return bytes_; }
  std::uint64_t size_bytes() const { return size_; }

 private:
  std::ifstream file_;
  CsvLines lines_;
  std::string error_;
  std::string raw_;
  std::uint64_t bytes_ = 0;
  std::uint64_t size_ = 0;
  bool done_ = false;
};

}  // namespace trueaxis::sim
