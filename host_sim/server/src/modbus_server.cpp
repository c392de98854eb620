#include "trueaxis/sim/server/modbus_server.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

namespace trueaxis::sim {

namespace {

constexpr std::size_t kHeaderBytes = 6;  // transaction id, protocol id, length
constexpr std::size_t kMinLength = 2;    // unit id + function code
constexpr std::size_t kMaxLength = 1 + modbus::kMaxPduBytes;

std::size_t be16(const std::uint8_t* p) { return static_cast<std::size_t>((p[0] << 8) | p[1]); }

}  // namespace

ModbusTcpServer::ModbusTcpServer(modbus::ModbusCore& core, Simulator& simulator, const ServerLimits& limits)
    : core_(core), simulator_(simulator), limits_(limits) {
  clients_.reserve(limits_.max_clients);
  polled_.reserve(limits_.max_clients + 1);
}

ModbusTcpServer::~ModbusTcpServer() {
  for (const Connection& c : clients_) ::close(c.fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
}

bool ModbusTcpServer::listen(const char* host, int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  if (port < 0 || port > 65535 || ::inet_pton(AF_INET, host, &address.sin_addr) != 1) {
    errno = EINVAL;
    return false;
  }
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) return false;
  const int on = 1;
  ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
  if (::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(listen_fd_, 64) != 0) {
    return false;
  }
  socklen_t size = sizeof address;
  if (::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &size) != 0) return false;
  port_ = ntohs(address.sin_port);
  return true;
}

void ModbusTcpServer::serve(volatile std::sig_atomic_t& stop, const sigset_t& wait_mask) {
  while (stop == 0) {
    polled_.clear();
    // While out of descriptors the listening socket is not polled: it stays
    // readable, and polling it would only spin (contract 5).
    const bool accepting = Clock::now() >= accept_paused_until_;
    polled_.push_back(pollfd{listen_fd_, static_cast<short>(accepting ? POLLIN : 0), 0});
    for (const Connection& c : clients_) {
      // A client whose replies wait is not read until they are gone (contract 3).
      polled_.push_back(pollfd{c.fd, static_cast<short>(c.out_used > 0 ? POLLOUT : POLLIN), 0});
    }
    timespec storage{};
    const int n = ::ppoll(polled_.data(), polled_.size(), next_timeout(Clock::now(), storage), &wait_mask);
    if (n < 0) continue;  // EINTR: the loop condition looks at `stop`
    const Clock::time_point now = Clock::now();
    // From the back: drop() moves the last client into the hole, one already served.
    for (std::size_t i = clients_.size(); i-- > 0;) {
      Connection& c = clients_[i];
      const short events = polled_[i + 1].revents;
      bool keep = true;
      if ((events & POLLOUT) != 0) {
        keep = flush(c) && serve_frames(c, now);
      } else if ((events & POLLIN) != 0) {
        keep = receive(c, now) && serve_frames(c, now);
      } else if ((events & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        keep = false;
      }
      if (!keep || timed_out(c, now)) drop(i);
    }
    if ((polled_[0].revents & POLLIN) != 0) accept_clients(now);
  }
}

void ModbusTcpServer::accept_clients(Clock::time_point now) {
  // A bounded number per wake-up, so a flood of connections cannot starve the others.
  for (int k = 0; k < 16; ++k) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        accept_paused_until_ = now + std::chrono::milliseconds(kAcceptPauseMs);
      }
      return;
    }
    if (clients_.size() >= limits_.max_clients) {  // contract 5: accepted and closed
      ::close(fd);
      continue;
    }
    // Replies are whole frames sent at once: Nagle would only hold them back.
    const int on = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
    clients_.emplace_back();
    Connection& c = clients_.back();
    c.fd = fd;
    c.client = next_client_++;
    if (next_client_ < macros::kFirstTcpClient) next_client_ = macros::kFirstTcpClient;  // after 2^32 connections
    c.last_frame = now;
  }
}

bool ModbusTcpServer::receive(Connection& c, Clock::time_point now) {
  if (c.in_used == sizeof c.in) return true;  // a whole frame waits for its reply to fit
  const ssize_t got = ::recv(c.fd, c.in + c.in_used, sizeof c.in - c.in_used, 0);
  if (got == 0) return false;  // the client closed
  if (got < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
  if (c.in_used == 0) c.stalled_since = now;
  c.in_used += static_cast<std::size_t>(got);
  return true;
}

bool ModbusTcpServer::serve_frames(Connection& c, Clock::time_point now) {
  std::size_t at = 0;
  bool ok = true;
  while (c.in_used - at >= kHeaderBytes) {
    const std::uint8_t* frame = c.in + at;
    const std::size_t length = be16(frame + 4);
    if (be16(frame + 2) != 0 || length < kMinLength || length > kMaxLength) {
      ok = false;  // contract 2: closed without a reply, nothing after it runs
      break;
    }
    if (c.in_used - at < kHeaderBytes + length) break;  // the rest has not arrived
    if (sizeof c.out - c.out_used < kMaxAduBytes && !flush(c)) return false;
    if (sizeof c.out - c.out_used < kMaxAduBytes) break;  // replies not taken yet: wait for POLLOUT
    std::uint8_t* reply = c.out + c.out_used;
    std::copy(frame, frame + 4, reply);  // transaction id, protocol id
    reply[6] = frame[6];                 // unit id
    const std::size_t pdu_bytes = core_.respond(frame + 7, length - 1, reply + 7, c.client);
    reply[4] = static_cast<std::uint8_t>((pdu_bytes + 1) >> 8);
    reply[5] = static_cast<std::uint8_t>(pdu_bytes + 1);
    c.out_used += 7 + pdu_bytes;
    simulator_.after_request();
    at += kHeaderBytes + length;
    c.last_frame = now;
    c.stalled_since = now;
  }
  if (at > 0) {
    std::memmove(c.in, c.in + at, c.in_used - at);
    c.in_used -= at;
  }
  // The replies already built go out even when a bad frame follows them.
  const bool flushed = flush(c);
  return ok && flushed;
}

bool ModbusTcpServer::flush(Connection& c) {
  if (c.out_used == 0) return true;
  const ssize_t sent = ::send(c.fd, c.out + c.out_sent, c.out_used - c.out_sent, MSG_NOSIGNAL);
  if (sent < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
  c.out_sent += static_cast<std::size_t>(sent);
  if (c.out_sent == c.out_used) c.out_used = c.out_sent = 0;
  return true;
}

bool ModbusTcpServer::timed_out(const Connection& c, Clock::time_point now) const {
  const bool stalled = c.in_used > 0 || c.out_used > 0;
  if (stalled && now - c.stalled_since >= std::chrono::milliseconds(limits_.frame_timeout_ms)) return true;
  return limits_.idle_timeout_ms > 0 && now - c.last_frame >= std::chrono::milliseconds(limits_.idle_timeout_ms);
}

const timespec* ModbusTcpServer::next_timeout(Clock::time_point now, timespec& storage) const {
  bool any = now < accept_paused_until_;
  Clock::time_point earliest = any ? accept_paused_until_ : Clock::time_point::max();
  for (const Connection& c : clients_) {
    if (c.in_used > 0 || c.out_used > 0) {
      earliest = std::min(earliest, c.stalled_since + std::chrono::milliseconds(limits_.frame_timeout_ms));
      any = true;
    }
    if (limits_.idle_timeout_ms > 0) {
      earliest = std::min(earliest, c.last_frame + std::chrono::milliseconds(limits_.idle_timeout_ms));
      any = true;
    }
  }
  if (!any) return nullptr;
  const auto wait = std::max(Clock::duration::zero(), earliest - now);
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(wait);
  storage.tv_sec = static_cast<time_t>(seconds.count());
  storage.tv_nsec = static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(wait - seconds).count());
  return &storage;
}

void ModbusTcpServer::drop(std::size_t index) {
  simulator_.module().disconnected(clients_[index].client);  // contract 8
  ::close(clients_[index].fd);
  accept_paused_until_ = Clock::time_point{};  // a descriptor is free again
  if (index + 1 != clients_.size()) clients_[index] = clients_.back();
  clients_.pop_back();
}

}  // namespace trueaxis::sim
