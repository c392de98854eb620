#include "trueaxis/sim/modbus_server.hpp"

#include <algorithm>
#include <cerrno>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

namespace trueaxis::sim {

ModbusTcpServer::ModbusTcpServer(RequestHandler& handler, Simulator& simulator)
    : handler_(handler), simulator_(simulator) {}

ModbusTcpServer::~ModbusTcpServer() {
  for (int fd : clients_) ::close(fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (image_ != nullptr) modbus_mapping_free(image_);
  if (ctx_ != nullptr) modbus_free(ctx_);
}

bool ModbusTcpServer::listen(const char* host, int port) {
  ctx_ = modbus_new_tcp(host, port);
  if (ctx_ == nullptr) return false;
  image_ = modbus_mapping_new_start_address(0, 0, 0, 0, 0, static_cast<unsigned>(kImageRegisters), 0, 0);
  if (image_ == nullptr) return false;
  modbus_set_indication_timeout(ctx_, 2, 0);
  modbus_set_byte_timeout(ctx_, 0, 500000);
  listen_fd_ = modbus_tcp_listen(ctx_, 16);
  if (listen_fd_ < 0) return false;
  sockaddr_in bound{};
  socklen_t size = sizeof bound;
  if (::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &size) != 0) return false;
  port_ = ntohs(bound.sin_port);
  return true;
}

void ModbusTcpServer::serve(volatile std::sig_atomic_t& stop, const sigset_t& wait_mask) {
  while (stop == 0) {
    fd_set readable;
    FD_ZERO(&readable);
    FD_SET(listen_fd_, &readable);
    int max_fd = listen_fd_;
    for (int fd : clients_) {
      FD_SET(fd, &readable);
      max_fd = std::max(max_fd, fd);
    }
    const int n = ::pselect(max_fd + 1, &readable, nullptr, nullptr, nullptr, &wait_mask);
    if (n < 0) continue;  // EINTR: the loop condition looks at `stop`
    if (FD_ISSET(listen_fd_, &readable)) accept_client();
    // From the back: dropping client i moves none of those still to be served.
    for (std::size_t i = clients_.size(); i-- > 0;) {
      const int fd = clients_[i];
      if (!FD_ISSET(fd, &readable)) continue;
      if (!serve_one(fd)) {
        ::close(fd);
        clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(i));
      }
    }
  }
}

void ModbusTcpServer::accept_client() {
  const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) return;
  if (fd >= FD_SETSIZE) {  // select cannot watch it
    ::close(fd);
    return;
  }
  clients_.push_back(fd);
}

bool ModbusTcpServer::serve_one(int fd) {
  std::uint8_t adu[MODBUS_TCP_MAX_ADU_LENGTH];
  modbus_set_socket(ctx_, fd);
  const int length = modbus_receive(ctx_, adu);
  if (length < 0) return false;
  if (length == 0) return true;  // a frame for another unit: ignored
  const int header = modbus_get_header_length(ctx_);
  if (length <= header) return false;
  const macros::ModbusException e =
      handler_.handle(adu + header, static_cast<std::size_t>(length - header), image_->tab_registers);
  if (e == macros::ModbusException::kNone) {
    RequestHandler::prepare_read_write_reply(adu + header, static_cast<std::size_t>(length - header),
                                             image_->tab_registers);
  }
  const int sent = e == macros::ModbusException::kNone
                       ? modbus_reply(ctx_, adu, length, image_)
                       : modbus_reply_exception(ctx_, adu, static_cast<unsigned>(e));
  simulator_.after_request();
  return sent >= 0;
}

}  // namespace trueaxis::sim
