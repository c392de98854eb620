#include "trueaxis/sim/tools/client.hpp"

#include <cerrno>
#include <chrono>
#include <thread>

#include <poll.h>
#include <unistd.h>

#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/modbus/register_codec.hpp"

namespace trueaxis::sim {

VariableClient::~VariableClient() { close(); }

void VariableClient::drain() {
  // A reply that comes after the time-out must not be taken for the answer to
  // the request sent again: read until the line has been quiet for 100 ms.
  const int fd = modbus_get_socket(ctx_);
  std::uint8_t discard[256];
  for (pollfd p{fd, POLLIN, 0}; ::poll(&p, 1, 100) > 0 && ::read(fd, discard, sizeof discard) > 0;) {
  }
}

bool VariableClient::connect(const std::string& host, int port, int response_timeout_ms) {
  close();
  return open(modbus_new_tcp(host.c_str(), port), response_timeout_ms);
}

bool VariableClient::connect_rtu(const std::string& device, int baud, char parity, int slave,
                                 int response_timeout_ms) {
  close();
  modbus_t* ctx = modbus_new_rtu(device.c_str(), baud, parity, 8, 1);
  if (ctx != nullptr && modbus_set_slave(ctx, slave) != 0) {
    error_ = errno;
    modbus_free(ctx);
    return false;
  }
  return open(ctx, response_timeout_ms);
}

bool VariableClient::open(modbus_t* ctx, int response_timeout_ms) {
  if (ctx == nullptr) {
    error_ = errno;
    return false;
  }
  modbus_set_response_timeout(ctx, static_cast<std::uint32_t>(response_timeout_ms / 1000),
                              static_cast<std::uint32_t>((response_timeout_ms % 1000) * 1000));
  if (modbus_connect(ctx) != 0) {
    error_ = errno;
    modbus_free(ctx);
    return false;
  }
  ctx_ = ctx;
  return true;
}

void VariableClient::close() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

bool VariableClient::read(std::uint16_t first, std::uint16_t count, double* out) {
  std::uint16_t words[MODBUS_MAX_READ_REGISTERS];
  const int n = count * modbus::kRegistersPerVariable;
  if (ctx_ == nullptr || n > MODBUS_MAX_READ_REGISTERS) {
    error_ = EINVAL;
    return false;
  }
  for (int attempt = 0; modbus_read_registers(ctx_, static_cast<int>(modbus::register_of(first)), n, words) != n;
       ++attempt) {
    error_ = errno;
    if (error_ != ETIMEDOUT || attempt == retries_) return false;
    drain();
  }
  for (std::uint16_t i = 0; i < count; ++i) out[i] = modbus::decode_double(words + 4 * i);
  return true;
}

bool VariableClient::write(std::uint16_t first, std::uint16_t count, const double* values) {
  std::uint16_t words[MODBUS_MAX_WRITE_REGISTERS];
  const int n = count * modbus::kRegistersPerVariable;
  if (ctx_ == nullptr || n > MODBUS_MAX_WRITE_REGISTERS) {
    error_ = EINVAL;
    return false;
  }
  for (std::uint16_t i = 0; i < count; ++i) modbus::encode_double(values[i], words + 4 * i);
  for (int attempt = 0; modbus_write_registers(ctx_, static_cast<int>(modbus::register_of(first)), n, words) != n;
       ++attempt) {
    error_ = errno;
    if (error_ != ETIMEDOUT || attempt == retries_) return false;
    drain();
  }
  return true;
}

MacroOutcome VariableClient::run_macro(std::uint16_t number, int timeout_ms) {
  MacroOutcome outcome;
  double before[3];  // status, error, done_count
  if (!read(9001, 3, before)) return outcome;
  outcome.started = true;
  if (!write_one(9000, number)) return outcome;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  do {
    double now[3];
    if (!read(9001, 3, now)) return outcome;
    if (now[2] != before[2]) {
      outcome.status = static_cast<int>(now[0]);
      outcome.error = static_cast<int>(now[1]);
      return outcome;
    }
  } while (std::chrono::steady_clock::now() < deadline);
  error_ = ETIMEDOUT;
  return outcome;
}

int VariableClient::exception() const {
  const int code = error_ - MODBUS_ENOBASE;
  return code > 0 && code < 16 ? code : 0;
}

std::string VariableClient::error_text() const { return modbus_strerror(error_); }

// Contract 5: the refusal's cause, read from the module right after it. #9007
// is shared by every client, so its value is taken only when it gives the
// exception this client got; "held" is told by #9009 (each client's own view).
std::string VariableClient::failure_text() {
  using macros::AccessFault;
  namespace var = macros::var;
  const int error = error_;
  const int exception = this->exception();
  const std::string modbus = "Modbus: " + std::string(modbus_strerror(error));
  double fault = 0.0;
  double interface = 0.0;
  const bool read = exception != 0 && read_one(var::kAccessFault, fault) && read_one(var::kInterface, interface);
  error_ = error;
  if (!read) return modbus;
  const auto f = static_cast<AccessFault>(static_cast<int>(fault));
  if (static_cast<int>(macros::modbus_exception(f)) != exception) {
    if (exception == 6 && interface == 2.0) return "controller busy: another client holds the macro interface";
    return modbus;
  }
  double backoff = 0.0;
  switch (f) {
    case AccessFault::kInterfaceHeld:
    case AccessFault::kBusy:
      if (interface == 2.0) return "controller busy: another client holds the macro interface";
      return "controller busy: a macro is running";
    case AccessFault::kBadUnlockCode:
      read_one(var::kUnlockBackoffLeft, backoff);
      error_ = error;
      return "wrong unlock code: the controller refused it (--unlock-code must be the machine's code, #900), "
             "and takes no code for the next " + std::to_string(static_cast<int>(backoff)) + " s";
    case AccessFault::kUnlockBackoff:
      read_one(var::kUnlockBackoffLeft, backoff);
      error_ = error;
      return "the controller takes no unlock code for " + std::to_string(static_cast<int>(backoff)) +
             " s more: a wrong code was written moments ago (the back-off doubles with each wrong code, up to 64 s)";
    case AccessFault::kLocked:
      return "the controller is locked: configuration and calibration tables are written only after the "
             "unlock code (#9004)";
    default: break;
  }
  for (const macros::AccessFaultInfo& info : macros::kAccessFaultTable) {
    if (info.fault == f) return modbus + ": " + info.name + ": " + info.message;
  }
  return modbus;
}

// Contract 6.
bool VariableClient::take_interface(int wait_ms, const std::function<void()>& waiting) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_ms);
  bool told = false;
  for (;;) {
    if (write_one(macros::var::kInterface, 1.0)) return true;
    // 06: held by another client or a macro running; either passes. (#9009 may
    // already read 0 here: the holder let it go since the refusal.)
    const bool held = exception() == 6;
    if (!held || std::chrono::steady_clock::now() >= deadline) return false;
    if (!told && waiting) waiting();
    told = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace trueaxis::sim
