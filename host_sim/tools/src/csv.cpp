#include "trueaxis/sim/tools/csv.hpp"

#include <limits>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace trueaxis::sim {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

// The fields of `line` (RFC 4180): separated by commas, each trimmed of
// spaces and tabs; a field enclosed in double quotes is unquoted ("" inside
// stands for one ", a comma inside belongs to the field). "" when they are
// read, else what is wrong with the quotes.
std::string split(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::size_t at = 0;
  for (;;) {
    while (at < line.size() && (line[at] == ' ' || line[at] == '\t')) ++at;
    std::string field;
    if (at < line.size() && line[at] == '"') {
      const std::size_t open = at++;
      for (;;) {
        if (at >= line.size()) {
          return "field " + std::to_string(fields.size() + 1) + ": the quote at column " + std::to_string(open + 1) +
                 " is not closed";
        }
        if (line[at] == '"') {
          if (at + 1 < line.size() && line[at + 1] == '"') {
            field += '"';
            at += 2;
            continue;
          }
          ++at;
          break;
        }
        field += line[at++];
      }
      while (at < line.size() && (line[at] == ' ' || line[at] == '\t' || line[at] == '\r')) ++at;
      if (at < line.size() && line[at] != ',') {
        return "field " + std::to_string(fields.size() + 1) + ": text after its closing quote";
      }
    } else {
      const std::size_t comma = line.find(',', at);
      field = trim(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
      at = comma == std::string::npos ? line.size() : comma;
    }
    fields.push_back(field);
    if (at >= line.size()) return "";
    ++at;  // the comma
  }
}

bool parse_number(const std::string& field, double& out) {
  if (field.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(field.c_str(), &end);
  if (end == field.c_str() || *end != '\0' || !std::isfinite(v)) return false;
  out = v;
  return true;
}

constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";

// Why a header lacks a column, when its form says more than the column's name.
std::string header_form(const std::string& header) {
  if (header.find(',') == std::string::npos) {
    if (header.find(';') != std::string::npos) return "the file uses ';' as separator; trueaxis reads ','";
    if (header.find('\t') != std::string::npos) return "the file uses tabs as separator; trueaxis reads ','";
  }
  if (header.find('\0') != std::string::npos) return "the file is UTF-16; trueaxis reads UTF-8 (or ASCII) text";
  return "";
}

}  // namespace

CsvLines::Kind CsvLines::fail(const std::string& what) {
  error_ = name_ + ":" + std::to_string(line_) + ": " + what;
  return Kind::kError;
}

CsvLines::Kind CsvLines::feed(std::string raw, CsvRow& row) {
  ++line_;
  if (line_ == 1 && raw.compare(0, 3, kUtf8Bom) == 0) raw.erase(0, 3);
  if (line_ == 1 && raw.size() >= 2 && ((raw[0] == '\xFF' && raw[1] == '\xFE') || (raw[0] == '\xFE' && raw[1] == '\xFF'))) {
    return fail("the file is UTF-16; trueaxis reads UTF-8 (or ASCII) text");
  }
  const std::string content = trim(raw);
  if (content.empty() || content[0] == '#') return Kind::kSkip;
  std::vector<std::string> fields;
  const std::string quotes = split(content, fields);
  if (!quotes.empty()) return fail(quotes);
  if (header_line_ == 0) {
    header_line_ = line_;
    index_.assign(columns_.size(), -1);
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      for (std::size_t f = 0; f < fields.size(); ++f) {
        if (fields[f] == columns_[c].name) index_[c] = static_cast<int>(f);
      }
      if (index_[c] < 0 && !columns_[c].optional) {
        const std::string form = header_form(content);
        return fail(!form.empty() ? form : "the header has no column '" + columns_[c].name + "'");
      }
    }
    return Kind::kHeader;
  }
  row.line = line_;
  row.numbers.clear();
  row.texts.clear();
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (columns_[c].optional &&
        (index_[c] < 0 || static_cast<std::size_t>(index_[c]) >= fields.size() || fields[static_cast<std::size_t>(index_[c])].empty())) {
      row.numbers.push_back(std::numeric_limits<double>::quiet_NaN());  // contract 5: not given
      row.texts.emplace_back();
      continue;
    }
    const auto f = static_cast<std::size_t>(index_[c]);
    if (f >= fields.size()) return fail("too few fields: no value for '" + columns_[c].name + "'");
    double v = 0.0;
    if (columns_[c].numeric && !parse_number(fields[f], v)) {
      const bool comma = fields[f].find(',') != std::string::npos;
      return fail("'" + columns_[c].name + "' is not a finite number: '" + fields[f] + "'" +
                  (comma ? " (a decimal comma? trueaxis reads '.')" : ""));
    }
    row.numbers.push_back(v);
    row.texts.push_back(fields[f]);
  }
  return Kind::kRow;
}

std::string CsvLines::finish() const {
  if (header_line_ != 0) return "";
  return name_ + ":" + std::to_string(line_ == 0 ? 1 : line_) + ": no header row";
}

CsvResult parse_csv(const std::string& name, const std::string& text, const std::vector<CsvColumn>& columns) {
  CsvResult result;
  CsvLines lines(name, columns);
  std::istringstream in(text);
  std::string raw;
  CsvRow row;
  while (std::getline(in, raw)) {
    const CsvLines::Kind kind = lines.feed(raw, row);
    if (kind == CsvLines::Kind::kError) {
      result.error = lines.error();
      return result;
    }
    if (kind == CsvLines::Kind::kRow) result.rows.push_back(row);
  }
  result.error = lines.finish();
  result.header_line = lines.header_line();
  result.ok = result.error.empty();
  if (!result.ok) result.rows.clear();
  return result;
}

CsvResult read_csv(const std::string& path, const std::vector<CsvColumn>& columns) {
  CsvResult result;
  CsvReader reader(path, columns);
  CsvRow row;
  while (reader.next(row)) result.rows.push_back(row);
  result.error = reader.error();
  result.header_line = reader.header_line();
  result.ok = result.error.empty();
  if (!result.ok) result.rows.clear();
  return result;
}

CsvReader::CsvReader(const std::string& path, const std::vector<CsvColumn>& columns)
    : file_(path, std::ios::binary), lines_(path, columns) {
  if (!file_) {  // no line to name: "FILE: what"
    error_ = path + ": cannot be read";
    done_ = true;
    return;
  }
  file_.seekg(0, std::ios::end);
  size_ = static_cast<std::uint64_t>(file_.tellg());
  file_.seekg(0, std::ios::beg);
}

bool CsvReader::next(CsvRow& row) {
  while (!done_ && std::getline(file_, raw_)) {
    bytes_ += raw_.size() + 1;
    const CsvLines::Kind kind = lines_.feed(raw_, row);
    if (kind == CsvLines::Kind::kRow) return true;
    if (kind == CsvLines::Kind::kError) {
      error_ = lines_.error();
      done_ = true;
      return false;
    }
  }
  if (!done_) error_ = lines_.finish();
  done_ = true;
  return false;
}

}  // namespace trueaxis::sim
