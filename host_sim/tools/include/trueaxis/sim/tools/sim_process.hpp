// Starting and stopping a trueaxis-sim process from a test, a tool or the bench:
// posix_spawn with its stdout on a pipe, the port read from the `listening on
// HOST:PORT` line, SIGTERM and waitpid at the end. No sleeps, no fixed ports.
#pragma once

#include <csignal>
#include <string>
#include <vector>

#include <sys/types.h>

namespace trueaxis::sim {

class SimProcess {
 public:
  SimProcess() = default;
  ~SimProcess() { stop(); }
  SimProcess(const SimProcess&) = delete;
  SimProcess& operator=(const SimProcess&) = delete;

  // Spawns `binary` with `args` and waits at most timeout_ms for the listening
  // line. false (and the process killed) when it does not come.
  bool start(const std::string& binary, const std::vector<std::string>& args, int timeout_ms = 10000);

  // Sends `signal` (SIGTERM unless told), then waitpid. The exit status as
  // WEXITSTATUS, 128 + signal when killed by one, -1 when nothing was running.
  int stop(int signal = SIGTERM);

  bool running() const { return pid_ > 0; }
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  const std::string& output() const { return output_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  int port_ = 0;
  std::string output_;
};

// The directory of the running executable (from /proc/self/exe), for finding
// trueaxis-sim beside the tools in build/host/bin.
std::string executable_dir();

}  // namespace trueaxis::sim
