// A Modbus TCP client for trueaxis variables (libmodbus underneath), for the
// host tools, the bench and the tests. Host only: it allocates and uses errno.
//
// Contract
//  1. Variables are transferred as INTERFACE.md "Encoding" says: #N is registers
//     4N..4N+3, most significant word first (modbus::encode_double).
//  2. read/write return true on success; on failure, error() is the errno
//     libmodbus left (EMBXILADD etc. for an exception reply: exception() gives
//     the bare code, 0 for a transport failure).
//  3. run_macro writes #9000 and polls #9001..#9003 until done_count has grown,
//     at most `timeout_ms`; it returns the final status (2 done, 3 error) with the
//     error code, or status -1 on a transport failure or timeout.
#pragma once

#include <cstdint>
#include <string>

#include <modbus/modbus.h>

namespace trueaxis::sim {

struct MacroOutcome {
  int status = -1;  // #9001 after the macro: 2 done, 3 error; -1 not finished / transport failure
  int error = 0;    // #9002
};

class VariableClient {
 public:
  VariableClient() = default;
  ~VariableClient();
  VariableClient(const VariableClient&) = delete;
  VariableClient& operator=(const VariableClient&) = delete;

  bool connect(const std::string& host, int port, int response_timeout_ms = 2000);
  void close();
  modbus_t* raw() { return ctx_; }

  bool read(std::uint16_t first, std::uint16_t count, double* out);
  bool write(std::uint16_t first, std::uint16_t count, const double* values);
  bool read_one(std::uint16_t number, double& out) { return read(number, 1, &out); }
  bool write_one(std::uint16_t number, double value) { return write(number, 1, &value); }

  MacroOutcome run_macro(std::uint16_t number, int timeout_ms = 5000);

  int error() const { return error_; }
  // The Modbus exception code of the last failure, 0 when it was not an exception.
  int exception() const;
  std::string error_text() const;

 private:
  modbus_t* ctx_ = nullptr;
  int error_ = 0;
};

}  // namespace trueaxis::sim
