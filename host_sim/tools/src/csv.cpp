#include "trueaxis/sim/tools/csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace trueaxis::sim {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
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

CsvResult fail(const std::string& name, int line, const std::string& what) {
  CsvResult r;
  r.error = name + ":" + std::to_string(line) + ": " + what;
  return r;
}

}  // namespace

CsvResult parse_csv(const std::string& name, const std::string& text, const std::vector<CsvColumn>& columns) {
  CsvResult result;
  std::vector<int> index(columns.size(), -1);
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    const std::string content = trim(raw);
    if (content.empty() || content[0] == '#') continue;
    const std::vector<std::string> fields = split(content);
    if (result.header_line == 0) {
      result.header_line = line;
      for (std::size_t c = 0; c < columns.size(); ++c) {
        for (std::size_t f = 0; f < fields.size(); ++f) {
          if (fields[f] == columns[c].name) index[c] = static_cast<int>(f);
        }
        if (index[c] < 0) return fail(name, line, "the header has no column '" + columns[c].name + "'");
      }
      continue;
    }
    CsvRow row;
    row.line = line;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const auto f = static_cast<std::size_t>(index[c]);
      if (f >= fields.size()) {
        return fail(name, line, "too few fields: no value for '" + columns[c].name + "'");
      }
      double v = 0.0;
      if (columns[c].numeric && !parse_number(fields[f], v)) {
        return fail(name, line, "'" + columns[c].name + "' is not a finite number: '" + fields[f] + "'");
      }
      row.numbers.push_back(v);
      row.texts.push_back(fields[f]);
    }
    result.rows.push_back(std::move(row));
  }
  if (result.header_line == 0) return fail(name, line == 0 ? 1 : line, "no header row");
  result.ok = true;
  return result;
}

CsvResult read_csv(const std::string& path, const std::vector<CsvColumn>& columns) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {  // no line to name: "FILE: what"
    CsvResult r;
    r.error = path + ": cannot be read";
    return r;
  }
  std::ostringstream text;
  text << file.rdbuf();
  return parse_csv(path, text.str(), columns);
}

}  // namespace trueaxis::sim
