// libFuzzer target: the Modbus TCP framer of trueaxis-sim (host_sim/src/
// modbus_server.cpp), its own receive(), serve_frames() and flush() on one
// connection whose socket is one end of a socketpair: no listening socket, no
// poll, the same code path as a POLLIN on a real client.
//
// Input: up to kMaxChunks chunks, each | length u8 | bytes |; each chunk is
// written to the client end and the connection is served until the socket is
// empty, so frames arrive split and pipelined at every possible boundary.
//
// Oracle: an independent reading of the framing rule (modbus_server.hpp
// contract 2) over the same byte stream, and a second module that serves the
// frames that rule cuts out, in order, through its own ModbusCore. Checked:
//  1. the replies are exactly one per whole frame before the first refused
//     header, in order, each | same transaction id | 0 | length | same unit id |
//     followed by the PDU the reference core answered for that frame's PDU;
//  2. the server closes the connection exactly when the stream holds a refused
//     header (protocol id not 0, length outside 2..254), and serves nothing
//     after it;
//  3. the module behind the server ends in the same state as the reference
//     (every variable and the storage), so no hidden frame was executed.
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "fuzz_support.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/server/modbus_server.hpp"
#include "trueaxis/sim/server/simulator.hpp"
#include "trueaxis/sim/server/variable_router.hpp"

namespace trueaxis::sim {

// The friend modbus_server.hpp names: reaches one connection of the server.
class ModbusTcpServerFuzzPeer {
 public:
  using Connection = ModbusTcpServer::Connection;
  static bool receive(ModbusTcpServer& s, Connection& c) { return s.receive(c, std::chrono::steady_clock::now()); }
  static bool serve_frames(ModbusTcpServer& s, Connection& c) {
    return s.serve_frames(c, std::chrono::steady_clock::now());
  }
};

}  // namespace trueaxis::sim

namespace {

constexpr trueaxis::macros::ClientId kFuzzClient = 7;


using trueaxis::fuzz::FreshBench;
using trueaxis::fuzz::Input;
using trueaxis::fuzz::ModuleBench;
using trueaxis::fuzz::Snapshot;
using trueaxis::sim::ModbusTcpServerFuzzPeer;

constexpr int kMaxChunks = 32;
constexpr std::size_t kHeaderBytes = 6;

std::size_t be16(const std::uint8_t* p) { return static_cast<std::size_t>((p[0] << 8) | p[1]); }

// The module as trueaxis-sim serves it: module, simulator, router, core.
struct SimStack {
  ModuleBench& bench;
  trueaxis::sim::Simulator simulator;
  trueaxis::sim::VariableRouter router;
  trueaxis::modbus::ModbusCore core;

  explicit SimStack(ModuleBench& b)
      : bench(b), simulator(b.module, trueaxis::sim::FaceConfig{}, 1), router(b.module, simulator), core(router) {}
};

// Contract 2 of modbus_server.hpp read independently: the frames of `stream`
// as (offset, length field), and whether a refused header ends it.
struct Cut {
  std::vector<std::pair<std::size_t, std::size_t>> frames;
  bool refused = false;
};

Cut cut_frames(const std::vector<std::uint8_t>& stream) {
  Cut cut;
  std::size_t at = 0;
  while (stream.size() - at >= kHeaderBytes) {
    const std::size_t length = be16(&stream[at + 4]);
    if (be16(&stream[at + 2]) != 0 || length < 2 || length > 254) {
      cut.refused = true;
      break;
    }
    if (stream.size() - at < kHeaderBytes + length) break;
    cut.frames.emplace_back(at, length);
    at += kHeaderBytes + length;
  }
  return cut;
}

void drain(int fd, std::vector<std::uint8_t>& replies) {
  std::uint8_t buffer[4096];
  for (;;) {
    const ssize_t got = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (got <= 0) return;
    replies.insert(replies.end(), buffer, buffer + got);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static FreshBench served_bench;
  static FreshBench reference_bench;
  static Snapshot served_state;
  static Snapshot reference_state;

  ModuleBench& served_module = served_bench.make();
  FUZZ_CHECK(served_module.module.start() == trueaxis::core::Status::kOk);
  SimStack served(served_module);
  trueaxis::sim::ModbusTcpServer server(served.core, served.simulator);

  int fds[2];
  FUZZ_CHECK(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) == 0);
  ModbusTcpServerFuzzPeer::Connection c;
  c.fd = fds[0];
  c.client = kFuzzClient;  // the server numbers its connections; the reference names the same client

  std::vector<std::uint8_t> stream;
  std::vector<std::uint8_t> replies;
  bool closed = false;
  Input in(data, size);
  for (int k = 0; k < kMaxChunks && !in.empty() && !closed; ++k) {
    std::uint8_t chunk[256];
    const std::size_t n = in.take(chunk, in.u8());
    FUZZ_CHECK(::send(fds[1], chunk, n, MSG_NOSIGNAL) == static_cast<ssize_t>(n));
    stream.insert(stream.end(), chunk, chunk + n);
    // POLLIN until the socket is empty. Each round serves every whole frame in
    // the buffer and frees it, so a chunk (< 256 bytes) takes at most two
    // rounds; more would be a server that stopped taking bytes.
    for (int round = 0;; ++round) {
      FUZZ_CHECK(round < 4);
      if (!ModbusTcpServerFuzzPeer::receive(server, c) || !ModbusTcpServerFuzzPeer::serve_frames(server, c)) {
        closed = true;
      }
      drain(fds[1], replies);
      if (closed) break;
      std::uint8_t next = 0;
      if (::recv(fds[0], &next, 1, MSG_PEEK | MSG_DONTWAIT) < 0) break;  // all taken
    }
  }
  ::close(fds[0]);
  ::close(fds[1]);

  const Cut cut = cut_frames(stream);
  FUZZ_CHECK(closed == cut.refused);

  // The reference: the same frames, in order, through a core of its own.
  ModuleBench& reference_module = reference_bench.make();
  FUZZ_CHECK(reference_module.module.start() == trueaxis::core::Status::kOk);
  SimStack reference(reference_module);
  std::size_t at = 0;
  for (const auto& [offset, length] : cut.frames) {
    const std::uint8_t* frame = &stream[offset];
    std::uint8_t pdu[trueaxis::modbus::kMaxPduBytes + 16];
    const std::size_t pdu_bytes = reference.core.respond(frame + 7, length - 1, pdu, kFuzzClient);
    reference.simulator.after_request();
    FUZZ_CHECK(replies.size() - at >= 7 + pdu_bytes);
    const std::uint8_t* reply = &replies[at];
    FUZZ_CHECK(reply[0] == frame[0] && reply[1] == frame[1]);
    FUZZ_CHECK(reply[2] == 0 && reply[3] == 0);
    FUZZ_CHECK(be16(reply + 4) == pdu_bytes + 1);
    FUZZ_CHECK(reply[6] == frame[6]);
    FUZZ_CHECK(std::memcmp(reply + 7, pdu, pdu_bytes) == 0);
    at += 7 + pdu_bytes;
  }
  FUZZ_CHECK(at == replies.size());

  served_state.take(served_module);
  reference_state.take(reference_module);
  FUZZ_CHECK(Snapshot::first_changed(served_state, reference_state) == 0);
  FUZZ_CHECK(served_state.nv == reference_state.nv);
  return 0;
}
