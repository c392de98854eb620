// A Modbus TCP proxy between a command and a trueaxis-sim that cuts the
// connection at a chosen request, to see what the command says of a transport
// failure (calibrate.hpp contract 5): it forwards each request whole, and at
// the first one `cut_at` picks it either resets the connection (SO_LINGER 0:
// the client reads "Connection reset by peer") or goes silent (the client's
// response time-out). The picked request is not forwarded. One client at a
// time, served by a thread until the destructor.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

namespace trueaxis::test {

// One Modbus TCP request as the proxy sees it.
struct ProxyRequest {
  int function = 0;
  int first_register = 0;  // of a read or write
  std::vector<double> written;  // function 16: the variables written, decoded (4 registers each)
  // True when it writes variable #number (registers 4N..) to `value`.
  bool writes(int number, double value) const {
    if (function != 16 || first_register != 4 * number || written.empty()) return false;
    return written[0] == value;
  }
};

class CuttingProxy {
 public:
  enum class Cut { kReset, kSilence };

  CuttingProxy(int upstream_port, Cut how, std::function<bool(const ProxyRequest&)> cut_at)
      : upstream_port_(upstream_port), how_(how), cut_at_(std::move(cut_at)) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(listen_fd_ >= 0);
    const int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a = address(0);
    REQUIRE(::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    REQUIRE(::listen(listen_fd_, 4) == 0);
    socklen_t n = sizeof a;
    REQUIRE(::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &n) == 0);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { serve(); });
  }
  ~CuttingProxy() {
    stop_ = true;
    thread_.join();
    ::close(listen_fd_);
  }
  CuttingProxy(const CuttingProxy&) = delete;
  CuttingProxy& operator=(const CuttingProxy&) = delete;

  int port() const { return port_; }
  bool cut() const { return cut_; }

 private:
  static sockaddr_in address(int port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return a;
  }

  static ProxyRequest parse(const std::vector<std::uint8_t>& frame) {
    ProxyRequest r;
    if (frame.size() < 8) return r;
    r.function = frame[7];
    if (frame.size() >= 10) r.first_register = frame[8] << 8 | frame[9];
    if (r.function == 16 && frame.size() >= 13) {
      for (std::size_t at = 13; at + 8 <= frame.size(); at += 8) {
        std::uint64_t bits = 0;
        for (std::size_t k = 0; k < 8; ++k) bits = bits << 8 | frame[at + k];
        double v = 0.0;
        std::memcpy(&v, &bits, sizeof v);
        r.written.push_back(v);
      }
    }
    return r;
  }

  // Serves clients one after another until stop_.
  void serve() {
    while (!stop_) {
      pollfd p{listen_fd_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const int client = ::accept(listen_fd_, nullptr, nullptr);
      if (client < 0) continue;
      const int upstream = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in a = address(upstream_port_);
      if (::connect(upstream, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(upstream);
        ::close(client);
        continue;
      }
      relay(client, upstream);
      ::close(upstream);
    }
  }

  // Requests from the client, whole, to the upstream; its answers back.
  void relay(int client, int upstream) {
    std::vector<std::uint8_t> pending;
    bool silent = false;
    while (!stop_) {
      pollfd p[2] = {{client, POLLIN, 0}, {upstream, POLLIN, 0}};
      if (::poll(p, 2, 50) <= 0) continue;
      std::uint8_t buf[4096];
      if ((p[1].revents & POLLIN) != 0) {
        const ssize_t n = ::read(upstream, buf, sizeof buf);
        if (n <= 0) break;
        if (!silent && ::write(client, buf, static_cast<std::size_t>(n)) != n) break;
      }
      if ((p[0].revents & (POLLIN | POLLHUP)) == 0) continue;
      const ssize_t n = ::read(client, buf, sizeof buf);
      if (n <= 0) break;
      if (silent) continue;
      pending.insert(pending.end(), buf, buf + n);
      while (pending.size() >= 7) {
        const std::size_t length = 6u + (static_cast<std::size_t>(pending[4]) << 8 | pending[5]);
        if (pending.size() < length) break;
        const std::vector<std::uint8_t> frame(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(length));
        pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(length));
        if (!cut_ && cut_at_(parse(frame))) {
          cut_ = true;
          if (how_ == Cut::kReset) {
            const linger hard{1, 0};
            ::setsockopt(client, SOL_SOCKET, SO_LINGER, &hard, sizeof hard);
            ::close(client);
            return;
          }
          silent = true;
          break;
        }
        if (::write(upstream, frame.data(), frame.size()) != static_cast<ssize_t>(frame.size())) return;
      }
    }
    ::close(client);
  }

  int upstream_port_;
  Cut how_;
  std::function<bool(const ProxyRequest&)> cut_at_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> cut_{false};
};

// Cuts at the n-th request `matches` picks (1-based).
inline std::function<bool(const ProxyRequest&)> nth(int n, std::function<bool(const ProxyRequest&)> matches) {
  auto seen = std::make_shared<int>(0);
  return [n, matches, seen](const ProxyRequest& r) { return matches(r) && ++*seen == n; };
}

}  // namespace trueaxis::test
