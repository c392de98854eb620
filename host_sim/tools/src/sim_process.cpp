#include "trueaxis/sim/tools/sim_process.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace trueaxis::sim {

bool SimProcess::start(const std::string& binary, const std::vector<std::string>& args, int timeout_ms) {
  stop();
  output_.clear();
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return false;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  // The simulator gets stdin, stdout (the pipe) and stderr, nothing else of
  // this process: a test runner's inherited descriptors would count against
  // its limits and in its /proc/<pid>/fd.
  posix_spawn_file_actions_addclosefrom_np(&actions, STDERR_FILENO + 1);
  std::vector<std::string> argv_strings;
  argv_strings.push_back(binary);
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : argv_strings) argv.push_back(s.data());
  argv.push_back(nullptr);
  const int rc = posix_spawn(&pid_, binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (rc != 0) {
    ::close(pipe_fds[0]);
    pid_ = -1;
    return false;
  }
  out_fd_ = pipe_fds[0];

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  const std::string marker = "listening on ";
  while (std::chrono::steady_clock::now() < deadline) {
    const std::size_t at = output_.find(marker);
    const std::size_t eol = at == std::string::npos ? std::string::npos : output_.find('\n', at);
    if (eol != std::string::npos) {
      const std::size_t colon = output_.rfind(':', eol);
      port_ = std::atoi(output_.c_str() + colon + 1);
      return port_ > 0;
    }
    pollfd p{out_fd_, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (::poll(&p, 1, static_cast<int>(left.count()) + 1) <= 0) continue;
    char buffer[256];
    const ssize_t n = ::read(out_fd_, buffer, sizeof buffer);
    if (n <= 0) break;  // the process closed stdout: it exited
    output_.append(buffer, static_cast<std::size_t>(n));
  }
  stop();
  return false;
}

int SimProcess::stop(int signal) {
  int result = -1;
  if (pid_ > 0) {
    ::kill(pid_, signal);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    result = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    pid_ = -1;
  }
  if (out_fd_ >= 0) ::close(out_fd_);
  out_fd_ = -1;
  port_ = 0;
  return result;
}

std::string executable_dir() {
  char path[4096];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return ".";
  std::string dir(path, static_cast<std::size_t>(n));
  const std::size_t slash = dir.rfind('/');
  return slash == std::string::npos ? "." : dir.substr(0, slash);
}

}  // namespace trueaxis::sim
