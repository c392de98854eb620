// The socket side of trueaxis-sim: a Modbus TCP server (libmodbus) that serves
// several clients at once from one thread, so requests never race.
//
// Contract
//  1. listen(host, port) binds and listens; port 0 picks a free port, which
//     port() then returns. host is a dotted IPv4 address.
//  2. serve() waits (pselect) on the listening socket and every client socket,
//     accepts new clients, and for each complete request: strips the MBAP header
//     (modbus_get_header_length), lets the RequestHandler decide, answers with
//     modbus_reply over the register image or with modbus_reply_exception, then
//     calls Simulator::after_request(). A client that closes, sends garbage
//     libmodbus cannot frame, or stalls mid-frame longer than the byte timeout
//     (0.5 s) is disconnected; the others wait at most that long.
//  3. serve() returns when `stop` becomes non-zero. The caller blocks the stop
//     signals and passes in `wait_mask` the mask to use while waiting (the usual
//     pselect pattern), so a signal can never be lost between test and wait.
#pragma once

#include <csignal>
#include <cstdint>
#include <vector>

#include <modbus/modbus.h>

#include "trueaxis/sim/request_handler.hpp"
#include "trueaxis/sim/simulator.hpp"

namespace trueaxis::sim {

class ModbusTcpServer {
 public:
  ModbusTcpServer(RequestHandler& handler, Simulator& simulator);
  ~ModbusTcpServer();
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  // false with errno set when the address cannot be bound.
  bool listen(const char* host, int port);
  int port() const { return port_; }

  void serve(volatile std::sig_atomic_t& stop, const sigset_t& wait_mask);

 private:
  void accept_client();
  // false when the client must be dropped.
  bool serve_one(int fd);

  RequestHandler& handler_;
  Simulator& simulator_;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* image_ = nullptr;
  int listen_fd_ = -1;
  int port_ = 0;
  std::vector<int> clients_;
};

}  // namespace trueaxis::sim
