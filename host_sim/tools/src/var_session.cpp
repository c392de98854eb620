#include "trueaxis/sim/tools/var_session.hpp"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <utility>

#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::sim {

namespace var = macros::var;

namespace {

// Contract 1: where each request starts and how many variables it takes.
std::vector<std::pair<std::size_t, std::uint16_t>> runs(const std::vector<std::uint16_t>& numbers,
                                                         std::uint16_t most) {
  std::vector<std::pair<std::size_t, std::uint16_t>> out;
  for (std::size_t i = 0; i < numbers.size();) {
    std::uint16_t n = 1;
    while (i + n < numbers.size() && n < most && numbers[i + n] == numbers[i] + n) ++n;
    out.emplace_back(i, n);
    i += n;
  }
  return out;
}

// Modbus Application Protocol V1.1b3, section 7.
const char* exception_name(int code) {
  switch (code) {
    case 1: return "illegal function";
    case 2: return "illegal data address";
    case 3: return "illegal data value";
    case 4: return "server device failure";
    case 6: return "server device busy";
    default: return "exception";
  }
}

}  // namespace

std::string variable_span(std::uint16_t first, std::uint16_t count) {
  return "#" + std::to_string(first) + (count > 1 ? "..#" + std::to_string(first + count - 1) : "");
}

VarSession::VarSession(VariableClient& client, std::string endpoint, int timeout_ms, int retries)
    : client_(client), endpoint_(std::move(endpoint)), timeout_ms_(timeout_ms), retries_(retries) {
  client_.set_retries(retries);
}

bool VarSession::failed(std::uint16_t first, std::uint16_t count) {
  const std::string what = variable_span(first, count);
  const int exception = client_.exception();
  if (exception == 0) {
    error_ = client_.error() == ETIMEDOUT
                 ? what + ": no reply from " + endpoint_ + " within " + std::to_string(timeout_ms_) + " ms"
                 : what + ": " + endpoint_ + ": " + client_.error_text();
    return false;
  }
  char code[4];
  std::snprintf(code, sizeof code, "%02d", exception % 100);
  const std::string modbus = std::string("Modbus ") + code + " " + exception_name(exception);
  error_ = what + ": " + modbus;
  double fault = 0.0;
  if (client_.read_one(var::kAccessFault, fault)) {
    for (const macros::AccessFaultInfo& f : macros::kAccessFaultTable) {
      if (static_cast<double>(f.fault) == fault && static_cast<int>(macros::modbus_exception(f.fault)) == exception) {
        error_ = what + ": " + f.name + " (" + modbus + ": " + f.message + ")";
      }
    }
  }
  return false;
}

bool VarSession::read(const std::vector<std::uint16_t>& numbers, std::vector<double>& values) {
  values.assign(numbers.size(), 0.0);
  for (const auto& [at, count] : runs(numbers, 31)) {
    if (!client_.read(numbers[at], count, values.data() + at)) return failed(numbers[at], count);
  }
  return true;
}

bool VarSession::write(const std::vector<Assignment>& assignments) {
  std::vector<std::uint16_t> numbers;
  for (const Assignment& a : assignments) numbers.push_back(a.number);
  for (const auto& [at, count] : runs(numbers, 30)) {
    std::vector<double> values;
    for (std::size_t k = at; k < at + count; ++k) values.push_back(assignments[k].value);
    if (!client_.write(numbers[at], count, values.data())) return failed(numbers[at], count);
  }
  return true;
}

bool VarSession::write_command(std::uint16_t macro, const double (&before)[3]) {
  client_.set_retries(0);
  bool written = false;
  for (int attempt = 0; attempt <= retries_ && !written; ++attempt) {
    written = client_.write_one(var::kCmd, macro);
    if (written || client_.exception() != 0 || client_.error() != ETIMEDOUT) break;
    // No reply: the module may have taken it all the same (contract 2).
    client_.set_retries(retries_);
    double now[3];
    if (!client_.read(var::kStatus, 3, now)) break;
    written = now[0] == static_cast<double>(macros::MacroState::kBusy) || now[2] != before[2];
    client_.set_retries(0);
  }
  client_.set_retries(retries_);
  return written || failed(var::kCmd, 1);
}

bool VarSession::run(std::uint16_t macro, const std::vector<Assignment>& arguments, int wait_ms, MacroEnd& end) {
  double before[3];  // status, error, done_count
  if (!client_.read(var::kStatus, 3, before)) return failed(var::kStatus, 3);
  if (!write(arguments) || !write_command(macro, before)) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_ms);
  double now[3];
  for (;;) {
    if (!client_.read(var::kStatus, 3, now)) return failed(var::kStatus, 3);
    if (now[2] != before[2]) break;
    if (std::chrono::steady_clock::now() > deadline) {
      error_ = "macro " + std::to_string(macro) + " still busy after " + std::to_string(wait_ms) +
               " ms (#9001 = " + std::to_string(static_cast<int>(now[0])) + ")";
      return false;
    }
  }
  double after[4];  // run_time, interface_version, access_fault, step_count
  if (!client_.read(var::kRunTime, 4, after)) return failed(var::kRunTime, 4);
  end.status = static_cast<int>(now[0]);
  end.error = static_cast<int>(now[1]);
  end.run_time_us = after[0];
  end.steps = static_cast<int>(after[3]);
  return true;
}

}  // namespace trueaxis::sim
