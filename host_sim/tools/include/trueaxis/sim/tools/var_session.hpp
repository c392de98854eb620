// trueaxis-var's conversation with a module over an open VariableClient (TCP
// or RTU): variables read and written whole, a macro run to its end, and every
// failure as one line that names its cause. Host only.
//
// Contract
//  1. read and write send the variables that are adjacent in the order given
//     (N, N+1, ...) in one request, at most 31 read or 30 written, so a work
//     offset written as #5281, #5282, #5283 is one request, whole or refused.
//  2. run(macro, arguments, wait_ms): reads #9001..#9003, writes the arguments
//     (as write), writes the macro number to #9000 and polls #9001..#9003 until
//     #9003 (done_count) differs from what it was; then reads #9005..#9008. The
//     #9000 write is never sent again blindly: when it gets no reply, the
//     handshake is read, and the write is repeated (up to the client's retries)
//     only when the macro has neither started (#9001 = 1) nor ended (#9003
//     grown), so a request whose reply was lost does not run the macro twice.
//     true with the outcome when the macro ended, done or error; false when
//     it did not end within wait_ms or a request failed.
//  3. On false, error() is one line (no "trueaxis-var: " prefix): a refused
//     access as "#5281..#5283: locked (Modbus 02 illegal data address: MESSAGE)",
//     the reason from #9007 (read after the refusal) when it matches the
//     exception that came back, else the exception alone; a time-out as
//     "#N: no reply from ENDPOINT within T ms"; any other transport failure
//     with its errno text; a macro still busy as "macro N still busy after T ms".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::sim {

struct Assignment {
  std::uint16_t number = 0;
  double value = 0.0;
};

// What a macro left in the handshake (#9001, #9002, #9005, #9008).
struct MacroEnd {
  int status = 0;          // 2 done, 3 error
  int error = 0;           // the status code (core::Status)
  double run_time_us = 0;  // #9005
  int steps = 0;           // #9008
};

class VarSession {
 public:
  // endpoint names the module in messages ("127.0.0.1:5020", "/dev/pts/3 (slave 1)").
  VarSession(VariableClient& client, std::string endpoint, int timeout_ms, int retries);

  bool read(const std::vector<std::uint16_t>& numbers, std::vector<double>& values);
  bool write(const std::vector<Assignment>& assignments);
  bool run(std::uint16_t macro, const std::vector<Assignment>& arguments, int wait_ms, MacroEnd& end);

  const std::string& error() const { return error_; }

 private:
  bool failed(std::uint16_t first, std::uint16_t count);
  bool write_command(std::uint16_t macro, const double (&before)[3]);

  VariableClient& client_;
  std::string endpoint_;
  int timeout_ms_;
  int retries_;
  std::string error_;
};

// "#5281" or "#5281..#5283".
std::string variable_span(std::uint16_t first, std::uint16_t count);

}  // namespace trueaxis::sim
