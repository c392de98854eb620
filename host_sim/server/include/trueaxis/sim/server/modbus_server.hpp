// The socket side of trueaxis-sim: a Modbus TCP server that serves several
// clients at once from one thread (so requests never race), framed by the MBAP
// header, every connection buffered and non-blocking. The requests themselves
// are decided by the transport-free core (macros/modbus_core.hpp).
//
// Contract
//  1. listen(host, port) binds and listens; port 0 picks a free port, which
//     port() then returns. host is a dotted IPv4 address.
//  2. Framing (Modbus Messaging on TCP/IP Implementation Guide V1.0b, 3.1.3 and
//     4.4.1): a frame is | transaction id u16 | protocol id u16 | length u16 |
//     unit id u8 | PDU |, length counting the unit id and the PDU. The frame
//     ends where its length field says, whatever its function code. Protocol id
//     not 0, or length outside 2..254, closes the connection at once without a
//     reply: nothing of that frame or after it is executed. The reply echoes the
//     transaction id and the unit id (any unit id is served).
//  3. Each connection has its own receive buffer (one frame, 260 bytes) and
//     reply buffer. Several frames in one packet are served in order; a partial
//     frame waits for the rest without holding up anyone else. The replies to
//     the frames one receive brought go out in one send. A client that does not
//     take its replies is not read from, nor served, until it does.
//  4. After every request served, Simulator::after_request() runs (it steps
//     the module).
//  5. Limits (ServerLimits): at most max_clients connections; the next one is
//     accepted and closed at once, with no reply. A connection holding a partial
//     frame or an unsent reply for longer than frame_timeout_ms is closed; with
//     idle_timeout_ms > 0, so is one that has sent no whole frame for that long.
//     When the process runs out of descriptors (accept fails with EMFILE,
//     ENFILE, ENOBUFS or ENOMEM), new connections wait in the listen backlog:
//     the server stops accepting for kAcceptPauseMs or until one of its
//     connections closes, whichever comes first, and serves the others
//     meanwhile (it does not spin on the listening socket).
//  6. serve() returns when `stop` becomes non-zero. The caller blocks the stop
//     signals and passes in `wait_mask` the mask to use while waiting (ppoll), so
//     a signal can never be lost between test and wait.
//  7. No allocation per request: buffers are sized when a client connects.
//  8. Access control (module.hpp contracts 7 and 8): each connection is its
//     own client (a ClientId the server numbers from kFirstTcpClient up; never
//     reused while the server runs), named in every request it sends to the core. When a
//     connection closes (the client's close, a refused frame, a time-out), the
//     server tells the module (Module::disconnected): the macro interface it
//     held is free, the unlock it opened closes. Other connections closing
//     change nothing.
#pragma once

#include <chrono>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <poll.h>

#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/server/simulator.hpp"

namespace trueaxis::sim {

struct ServerLimits {
  std::size_t max_clients = 32;
  int frame_timeout_ms = 5000;
  int idle_timeout_ms = 0;  // 0: an idle connection stays open
};

// MBAP header (7 bytes) plus the largest PDU.
inline constexpr std::size_t kMaxAduBytes = 7 + modbus::kMaxPduBytes;

class ModbusTcpServer {
 public:
  ModbusTcpServer(modbus::ModbusCore& core, Simulator& simulator, const ServerLimits& limits = ServerLimits{});
  ~ModbusTcpServer();
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  // false with errno set when the address cannot be parsed or bound.
  bool listen(const char* host, int port);
  int port() const { return port_; }

  void serve(volatile std::sig_atomic_t& stop, const sigset_t& wait_mask);

 private:
  // tests/fuzz/fuzz_tcp_framer.cpp drives one connection's receive and framing
  // without a listening socket.
  friend class ModbusTcpServerFuzzPeer;
  using Clock = std::chrono::steady_clock;

  struct Connection {
    int fd = -1;
    macros::ClientId client = macros::kNoClient;
    std::size_t in_used = 0;
    std::size_t out_used = 0;
    std::size_t out_sent = 0;
    Clock::time_point stalled_since{};  // a partial frame or an unsent reply since then
    Clock::time_point last_frame{};
    std::uint8_t in[kMaxAduBytes] = {};
    // Replies wait here until sent; a frame is served only while the largest
    // reply still fits.
    std::uint8_t out[8 * kMaxAduBytes] = {};
  };

  void accept_clients(Clock::time_point now);
  // Each returns false when the connection must be closed.
  bool receive(Connection& c, Clock::time_point now);
  bool serve_frames(Connection& c, Clock::time_point now);
  bool flush(Connection& c);
  bool timed_out(const Connection& c, Clock::time_point now) const;
  // The ppoll timeout until the earliest time-out; nullptr when there is none.
  const timespec* next_timeout(Clock::time_point now, timespec& storage) const;
  void drop(std::size_t index);

  static constexpr int kAcceptPauseMs = 100;

  modbus::ModbusCore& core_;
  Simulator& simulator_;
  ServerLimits limits_;
  int listen_fd_ = -1;
  int port_ = 0;
  Clock::time_point accept_paused_until_{};  // contract 5: out of descriptors until then
  macros::ClientId next_client_ = macros::kFirstTcpClient;  // contract 8
  std::vector<Connection> clients_;
  std::vector<pollfd> polled_;
};

}  // namespace trueaxis::sim
