// A Modbus client for trueaxis variables over TCP or RTU (libmodbus
// underneath), for the host tools, the benches and the tests. Host only: it
// allocates and uses errno.
//
// Contract
//  1. Variables are transferred as docs/INTERFACE.md "Encoding" says: #N is registers
//     4N..4N+3, most significant word first (modbus::encode_double).
//  2. read/write return true on success; on failure, error() is the errno
//     libmodbus left (EMBXILADD etc. for an exception reply: exception() gives
//     the bare code, 0 for a transport failure).
//  3. run_macro writes #9000 and polls #9001..#9003 until done_count has grown,
//     at most `timeout_ms`; it returns the final status (2 done, 3 error) with the
//     error code, or status -1 on a transport failure or timeout.
//  4. connect_rtu opens a serial device as a Modbus RTU master (8 data bits,
//     1 stop bit) addressing one slave. set_retries(n): a read or write that
//     gets no reply within the response time-out is sent again, at most n
//     times, once the line has been quiet for 100 ms, as a PLC on RS-485 does
//     (a request torn on the line is discarded by the slave and executes
//     nothing). 0 by default.
//  5. failure_text() is the last failure as one sentence for an operator: a
//     refusal is told by its cause, read from the module (#9007, and #9011 for
//     the unlock back-off): another client holding the macro interface, a
//     macro running, a wrong unlock code, the back-off with its seconds, a
//     locked controller; a transport failure by libmodbus's text.
//  6. take_interface() takes the module's macro interface (#9009 = 1,
//     module.hpp contract 8). While another client holds it (or a macro
//     runs: any refusal 06, since the holder may let it go between the refusal
//     and the look at #9009), it calls `waiting` once, then tries again every
//     200 ms for at most `wait_ms`; false when it could not, failure_text()
//     then saying why.
//     give_back_interface() writes #9009 = 0 (closing the connection gives it
//     back too).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include <modbus/modbus.h>

namespace trueaxis::sim {

struct MacroOutcome {
  int status = -1;  // #9001 after the macro: 2 done, 3 error; -1 not finished / transport failure
  int error = 0;    // #9002
  // The write of the macro number to #9000 was attempted: past this point a
  // transport failure leaves it unknown whether the macro ran.
  bool started = false;
};

class VariableClient {
 public:
  VariableClient() = default;
  ~VariableClient();
  VariableClient(const VariableClient&) = delete;
  VariableClient& operator=(const VariableClient&) = delete;

  bool connect(const std::string& host, int port, int response_timeout_ms = 2000);
  // Contract 4; parity 'N', 'E' or 'O'.
  bool connect_rtu(const std::string& device, int baud, char parity, int slave, int response_timeout_ms = 1000);
  void set_retries(int retries) { retries_ = retries; }
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
  // Contract 5.
  std::string failure_text();

  // Contract 6.
  bool take_interface(int wait_ms, const std::function<void()>& waiting);
  bool give_back_interface() { return write_one(9009, 0.0); }  // module.hpp contract 8

 private:
  bool open(modbus_t* ctx, int response_timeout_ms);
  void drain();

  modbus_t* ctx_ = nullptr;
  int error_ = 0;
  int retries_ = 0;
};

}  // namespace trueaxis::sim
