// A trueaxis-sim process started by the test itself on 127.0.0.1 port 0 with a
// temporary NV file, and a libmodbus client connected to it. Stopped (SIGTERM,
// waitpid) and the file removed when the fixture goes.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/sim_process.hpp"

namespace trueaxis::sim::test {

inline constexpr double kUnlockCode = 2718.0;

class SimFixture {
 public:
  explicit SimFixture(std::vector<std::string> extra_args = {});
  ~SimFixture();

  // Stops the sim (checking it exits 0) and starts it again on the same NV file.
  int restart();

  VariableClient& client() { return client_; }
  const std::string& nv_path() const { return nv_path_; }
  int port() const { return sim_.port(); }
  pid_t pid() const { return sim_.pid(); }  // the sim process, for /proc/<pid>

  double get(std::uint16_t number);
  void set(std::uint16_t number, double value);                     // REQUIREs success
  void set(std::uint16_t first, std::initializer_list<double> values);  // REQUIREs success
  // The Modbus exception of writing `values` at #first; 0 when it succeeded.
  int write_exception(std::uint16_t first, std::initializer_list<double> values);
  // The exception of a raw register read / write; 0 when it succeeded.
  int read_registers_exception(int address, int count);
  int write_registers_exception(int address, const std::vector<std::uint16_t>& words);

  // Probes (x, y) into `target` with the sim's probe.
  void probe(double x_mm, double y_mm, std::uint16_t target);
  // Probes an equilateral triangle of side `spread_mm` into G57, G58, G59.
  void probe_triangle(double spread_mm = 100.0);
  // Writes P1, P2, P3 straight into G57, G58, G59.
  void set_points(const double (&p)[3][3]);
  MacroOutcome run(std::uint16_t macro = 9810);

  // Everything a refused access or a failed macro must leave alone: results
  // #100..#115, configuration #500..#507, G57..G59 X, Y, Z, status #9001..#9003,
  // the simulator's table and probe state.
  std::vector<double> snapshot();

 private:
  void start();

  std::string nv_path_;
  std::vector<std::string> extra_args_;
  SimProcess sim_;
  VariableClient client_;
};

}  // namespace trueaxis::sim::test
