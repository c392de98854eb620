#include "sim_fixture.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include <unistd.h>

#include "trueaxis/sim/server/sim_map.hpp"

namespace trueaxis::sim::test {

SimFixture::SimFixture(std::vector<std::string> extra_args) : extra_args_(std::move(extra_args)) {
  char path[] = "/tmp/trueaxis-sim-test-XXXXXX";
  const int fd = mkstemp(path);
  REQUIRE(fd >= 0);
  ::close(fd);
  nv_path_ = path;
  start();
}

SimFixture::~SimFixture() {
  client_.close();
  sim_.stop();
  ::unlink(nv_path_.c_str());
}

void SimFixture::start() {
  std::vector<std::string> args = {"--host", "127.0.0.1", "--port", "0", "--nv", nv_path_};
  args.insert(args.end(), extra_args_.begin(), extra_args_.end());
  REQUIRE(sim_.start(TRUEAXIS_SIM_BINARY, args));
  REQUIRE(client_.connect("127.0.0.1", sim_.port()));
}

int SimFixture::restart() {
  client_.close();
  const int exit_code = sim_.stop();
  start();
  return exit_code;
}

double SimFixture::get(std::uint16_t number) {
  double v = 0.0;
  INFO("reading #" << number << ": " << client_.error_text());
  REQUIRE(client_.read_one(number, v));
  return v;
}

void SimFixture::set(std::uint16_t number, double value) { set(number, {value}); }

void SimFixture::set(std::uint16_t first, std::initializer_list<double> values) {
  const std::vector<double> v(values);
  INFO("writing #" << first << ": " << client_.error_text());
  REQUIRE(client_.write(first, static_cast<std::uint16_t>(v.size()), v.data()));
}

int SimFixture::write_exception(std::uint16_t first, std::initializer_list<double> values) {
  const std::vector<double> v(values);
  if (client_.write(first, static_cast<std::uint16_t>(v.size()), v.data())) return 0;
  REQUIRE(client_.exception() != 0);  // a transport failure is not an answer
  return client_.exception();
}

int SimFixture::read_registers_exception(int address, int count) {
  std::vector<std::uint16_t> words(static_cast<std::size_t>(count) + 1);
  if (modbus_read_registers(client_.raw(), address, count, words.data()) == count) return 0;
  const int code = errno - MODBUS_ENOBASE;
  REQUIRE((code > 0 && code < 16));
  return code;
}

int SimFixture::write_registers_exception(int address, const std::vector<std::uint16_t>& words) {
  const int n = static_cast<int>(words.size());
  if (modbus_write_registers(client_.raw(), address, n, words.data()) == n) return 0;
  const int code = errno - MODBUS_ENOBASE;
  REQUIRE((code > 0 && code < 16));
  return code;
}

void SimFixture::probe(double x_mm, double y_mm, std::uint16_t target) {
  set(simvar::kProbeX, {x_mm, y_mm, static_cast<double>(target)});
}

void SimFixture::probe_triangle(double spread_mm) {
  const double r = spread_mm / std::sqrt(3.0);
  const std::uint16_t targets[3] = {5281, 5301, 5321};
  for (int i = 0; i < 3; ++i) {
    const double angle = 3.14159265358979323846 * (0.5 + 2.0 * i / 3.0);
    probe(r * std::cos(angle), r * std::sin(angle), targets[i]);
  }
}

void SimFixture::set_points(const double (&p)[3][3]) {
  set(5281, {p[0][0], p[0][1], p[0][2]});
  set(5301, {p[1][0], p[1][1], p[1][2]});
  set(5321, {p[2][0], p[2][1], p[2][2]});
}

MacroOutcome SimFixture::run(std::uint16_t macro) {
  const MacroOutcome outcome = client_.run_macro(macro);
  INFO("macro " << macro << ": " << client_.error_text());
  REQUIRE(outcome.status >= 0);
  return outcome;
}

std::vector<double> SimFixture::snapshot() {
  std::vector<double> all;
  const auto grab = [&](std::uint16_t first, std::uint16_t count) {
    std::vector<double> v(count);
    INFO("snapshot of #" << first << ": " << client_.error_text());
    REQUIRE(client_.read(first, count, v.data()));
    all.insert(all.end(), v.begin(), v.end());
  };
  grab(1, 9);  // arguments A..F
  grab(11, 1);
  grab(13, 1);
  grab(17, 10);  // arguments Q..Z
  grab(100, 16);
  grab(500, 8);
  grab(5281, 3);
  grab(5301, 3);
  grab(5321, 3);
  grab(9000, 7);  // the handshake; #9007 is left out: a refusal sets it by design
  grab(simvar::kFirst, 10);  // #12000..#12009: table, probe, hold
  return all;
}

}  // namespace trueaxis::sim::test
