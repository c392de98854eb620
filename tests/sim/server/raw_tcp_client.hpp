// A raw TCP connection to 127.0.0.1 for the Modbus TCP tests that write frames
// byte by byte (test_modbus_framing.cpp, test_conformance_tcp.cpp): no MBAP
// rules of its own but reading a reply's length field.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace trueaxis::sim::test {

class RawTcpClient {
 public:
  using Bytes = std::vector<std::uint8_t>;

  explicit RawTcpClient(int port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    REQUIRE(fd_ >= 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    const int on = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
  }
  ~RawTcpClient() { ::close(fd_); }
  RawTcpClient(const RawTcpClient&) = delete;
  RawTcpClient& operator=(const RawTcpClient&) = delete;

  int fd() const { return fd_; }

  void send(const Bytes& b) { REQUIRE(::send(fd_, b.data(), b.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(b.size())); }
  void shutdown_write() { ::shutdown(fd_, SHUT_WR); }

  // Up to `n` bytes, waiting at most timeout_ms in all; fewer when the peer
  // closes (closed()) or the time is up.
  Bytes receive(std::size_t n, int timeout_ms = 2000) {
    Bytes got;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (got.size() < n && !closed_) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
      pollfd p{fd_, POLLIN, 0};
      if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) break;
      std::uint8_t buffer[512];
      const ssize_t r = ::recv(fd_, buffer, std::min(sizeof buffer, n - got.size()), 0);
      if (r <= 0) {
        closed_ = true;
        break;
      }
      got.insert(got.end(), buffer, buffer + r);
    }
    return got;
  }

  // One whole reply frame, its MBAP length read first; what came when it is cut short.
  Bytes reply(int timeout_ms = 2000) {
    Bytes head = receive(6, timeout_ms);
    if (head.size() < 6) return head;
    const Bytes rest = receive(static_cast<std::size_t>((head[4] << 8) | head[5]), timeout_ms);
    head.insert(head.end(), rest.begin(), rest.end());
    return head;
  }

  bool closed() const { return closed_; }

  // True when the server closes the connection within timeout_ms having sent nothing.
  bool closed_silently(int timeout_ms = 2000) { return receive(1, timeout_ms).empty() && closed_; }

 private:
  int fd_ = -1;
  bool closed_ = false;
};

}  // namespace trueaxis::sim::test
