// trueaxis-sim's parts served in this process for the trueaxis-calibrate
// tests (a thread, 127.0.0.1 port 0, RAM storage), and reading the module
// through its client: a variable, a module error's one line.
#pragma once

#include <pthread.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "module_rig.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/posix/steady_clock.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/server/modbus_server.hpp"
#include "trueaxis/sim/server/simulator.hpp"
#include "trueaxis/sim/server/variable_router.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::test {

inline volatile std::sig_atomic_t g_stop = 0;
extern "C" inline void on_wake(int) {}

// trueaxis-sim's parts (sim_main.cpp) on RAM storage, served by a thread until
// the destructor: it sets the stop flag and wakes the thread's ppoll with
// SIGUSR1 (blocked in that thread but while it waits, so it cannot be lost).
class InProcessSim {
 public:
  InProcessSim() {
    simulator_ = std::make_unique<sim::Simulator>(rig_.module(), sim::FaceConfig{}, 1);
    router_ = std::make_unique<sim::VariableRouter>(rig_.module(), *simulator_);
    core_ = std::make_unique<trueaxis::modbus::ModbusCore>(*router_);
    server_ = std::make_unique<sim::ModbusTcpServer>(*core_, *simulator_);
    REQUIRE(server_->listen("127.0.0.1", 0));
    struct sigaction wake {};
    wake.sa_handler = on_wake;
    sigemptyset(&wake.sa_mask);
    sigaction(SIGUSR1, &wake, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
    g_stop = 0;
    thread_ = std::thread([this] {
      sigset_t usr1, wait_mask;
      sigemptyset(&usr1);
      sigaddset(&usr1, SIGUSR1);
      pthread_sigmask(SIG_BLOCK, &usr1, &wait_mask);
      sigdelset(&wait_mask, SIGUSR1);
      server_->serve(g_stop, wait_mask);
    });
    REQUIRE(client_.connect("127.0.0.1", server_->port()));
  }
  ~InProcessSim() {
    client_.close();
    g_stop = 1;
    pthread_kill(thread_.native_handle(), SIGUSR1);
    thread_.join();
  }
  InProcessSim(const InProcessSim&) = delete;
  InProcessSim& operator=(const InProcessSim&) = delete;

  int port() const { return server_->port(); }
  sim::VariableClient& client() { return client_; }

 private:
  trueaxis::hal::SteadyClock clock_;
  ModuleRig rig_{RigOptions{}.with_clock(clock_)};  // the rig's RAM device, the host's clock
  std::unique_ptr<sim::Simulator> simulator_;
  std::unique_ptr<sim::VariableRouter> router_;
  std::unique_ptr<trueaxis::modbus::ModbusCore> core_;
  std::unique_ptr<sim::ModbusTcpServer> server_;
  std::thread thread_;
  sim::VariableClient client_;
};

// ---- the module through its client ---------------------------------------------------

inline double read_var(sim::VariableClient& client, std::uint16_t number) {
  double x = 0.0;
  REQUIRE(client.read_one(number, x));
  return x;
}

inline std::string module_error(core::Status s) {
  return "module error " + std::to_string(static_cast<int>(s)) + " " + trueaxis::macros::status_name(s) + ": " +
         trueaxis::macros::status_message(s);
}

}  // namespace trueaxis::test
