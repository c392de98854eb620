// Raw Modbus TCP on loopback and the /proc figures of a process, for the load
// test (tests/sim/server/test_modbus_load.cpp) and bench (bench_modbus_load.cpp): no
// Catch2 and no libmodbus inside, so client threads can call them. Host only.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <unistd.h>

#include "trueaxis/modbus/register_codec.hpp"

namespace trueaxis::sim::loopback {

using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;

// --- raw sockets -------------------------------------------------------------

inline int connect_to(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  const int on = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
  return fd;
}

inline bool send_all(int fd, const std::uint8_t* data, std::size_t n) {
  while (n > 0) {
    const ssize_t sent = ::send(fd, data, n, MSG_NOSIGNAL);
    if (sent <= 0) return false;
    data += sent;
    n -= static_cast<std::size_t>(sent);
  }
  return true;
}

inline bool receive_exact(int fd, std::uint8_t* out, std::size_t n, int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  std::size_t got = 0;
  while (got < n) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    pollfd p{fd, POLLIN, 0};
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) return false;
    const ssize_t r = ::recv(fd, out + got, n - got, 0);
    if (r <= 0) return false;
    got += static_cast<std::size_t>(r);
  }
  return true;
}

// FC3 of variable #number (4 registers): 12 bytes.
inline Bytes read_frame(std::uint16_t tid, std::uint16_t number) {
  const std::uint32_t reg = trueaxis::modbus::register_of(number);
  return {static_cast<std::uint8_t>(tid >> 8), static_cast<std::uint8_t>(tid), 0, 0, 0, 6, 1, 3,
          static_cast<std::uint8_t>(reg >> 8), static_cast<std::uint8_t>(reg), 0, 4};
}

// The 17-byte reply to read_frame(tid, ...): header checked, value decoded.
inline bool read_reply(int fd, std::uint16_t tid, double& value, int timeout_ms = 2000) {
  std::uint8_t r[17];
  if (!receive_exact(fd, r, sizeof r, timeout_ms)) return false;
  const std::uint8_t head[9] = {static_cast<std::uint8_t>(tid >> 8), static_cast<std::uint8_t>(tid), 0, 0, 0, 11, 1, 3, 8};
  if (!std::equal(head, head + 9, r)) return false;
  std::uint16_t w[4];
  for (std::size_t i = 0; i < 4; ++i) w[i] = static_cast<std::uint16_t>((r[9 + 2 * i] << 8) | r[10 + 2 * i]);
  value = trueaxis::modbus::decode_double(w);
  return true;
}

inline bool read_var(int fd, std::uint16_t tid, std::uint16_t number, double& value) {
  const Bytes f = read_frame(tid, number);
  return send_all(fd, f.data(), f.size()) && read_reply(fd, tid, value);
}

// One connect/disconnect cycle: connects, reads #1 (it must be `expected`),
// then leaves in one of four ways by k % 4: a clean close; a close with 5 bytes
// of the next frame pending; a reset (SO_LINGER 0) with them pending; a close
// with a second request sent and its reply never read. False when the
// connection or the read failed.
inline bool connect_cycle(int port, int k, double expected) {
  const int fd = connect_to(port);
  if (fd < 0) return false;
  const auto tid = static_cast<std::uint16_t>(k);
  double v = 0.0;
  const bool ok = read_var(fd, tid, 1, v) && v == expected;
  const Bytes next = read_frame(static_cast<std::uint16_t>(tid + 1), 1);
  switch (k % 4) {
    case 1:
      (void)send_all(fd, next.data(), 5);
      break;
    case 2: {
      (void)send_all(fd, next.data(), 5);
      const linger reset{1, 0};
      ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
      break;
    }
    case 3:
      (void)send_all(fd, next.data(), next.size());
      break;
    default:
      break;
  }
  ::close(fd);
  return ok;
}

// --- /proc of the sim process ------------------------------------------------

inline int fd_count(pid_t pid) {
  const std::string dir = "/proc/" + std::to_string(pid) + "/fd";
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return -1;
  int n = 0;
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] != '.') ++n;
  }
  ::closedir(d);
  return n;
}

// The descriptor number the process's next open would get.
inline int lowest_free_fd(pid_t pid) {
  const std::string dir = "/proc/" + std::to_string(pid) + "/fd";
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return -1;
  std::vector<int> used;
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] != '.') used.push_back(std::atoi(e->d_name));
  }
  ::closedir(d);
  std::sort(used.begin(), used.end());
  int free_fd = 0;
  for (const int fd : used) {
    if (fd == free_fd) ++free_fd;
  }
  return free_fd;
}

// How many descriptor numbers below `limit` the process has free.
inline int free_fds_below(pid_t pid, int limit) {
  const std::string dir = "/proc/" + std::to_string(pid) + "/fd";
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return -1;
  int free_count = limit;
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] != '.' && std::atoi(e->d_name) < limit) --free_count;
  }
  ::closedir(d);
  return free_count;
}

// A "Name:   123 kB" line of /proc/<pid>/status, in kB; -1 when absent.
// The fd count once the server has dropped every closed connection: back at
// `target`, waiting at most 3 s (what it is then, otherwise).
inline int settled_fd_count(pid_t pid, int target) {
  int n = fd_count(pid);
  for (int i = 0; i < 300 && n != target; ++i) {
    ::usleep(10000);
    n = fd_count(pid);
  }
  return n;
}

inline long status_kb(pid_t pid, const std::string& name) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, name.size() + 1, name + ":") == 0) return std::stol(line.substr(name.size() + 1));
  }
  return -1;
}

// The CPU time (user + system) the process has used, in seconds.
inline double cpu_seconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const std::size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return -1.0;
  std::istringstream fields(stat.substr(paren + 2));  // from field 3, the state
  std::string skip;
  for (int i = 3; i < 14; ++i) fields >> skip;
  long user = 0;
  long system = 0;
  fields >> user >> system;
  return static_cast<double>(user + system) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

inline double percentile(std::vector<double> v, double p) {  // nearest rank
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace trueaxis::sim::loopback
