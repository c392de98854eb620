// The flashed image (rtu_server_target, tests/target) under QEMU with UART0 on a
// pseudo-terminal, driven by libmodbus's RTU client as a PLC on RS-485 would:
// a read, a write, macro 9810 through the handshake, exception 01, a broadcast
// write, and frames the slave must not answer (broadcast read, other address,
// bad CRC). First of all it runs the conformance suite (conformance.hpp): the
// whole PDU table and the RTU table (CRC, addresses, broadcast, short and
// over-long frames), each case with the state read before and after it.
// Bounded: the whole run is stopped by alarm() after 300 s.
//
// Usage: test_rtu_qemu IMAGE [QEMU-ARGUMENTS...]. Exit 0 when every check holds, 1 when one fails,
// 77 (ctest's SKIP_RETURN_CODE) when IMAGE does not exist.
#include <fcntl.h>
#include <modbus.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <vector>
#include <string>
#include <thread>

#include "conformance.hpp"
#include "crc16_reference.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/modbus/register_codec.hpp"
#include "trueaxis/sim/program.hpp"

namespace {

namespace m = trueaxis::macros;
namespace var = trueaxis::macros::var;

int g_failures = 0;
pid_t g_qemu = -1;
int g_qemu_output = -1;  // QEMU's stdout and stderr
int g_baud = 19200;      // as the image says when it is ready

#define CHECK(cond)                                                             \
  do {                                                                          \
    if (!(cond)) {                                                              \
      std::fprintf(stderr, "%s:%d: FAILED: %s\n", __FILE__, __LINE__, #cond);   \
      ++g_failures;                                                             \
    }                                                                           \
  } while (0)

extern "C" void on_alarm(int) {
  if (g_qemu > 0) kill(g_qemu, SIGKILL);
  static const char msg[] = "test_rtu_qemu: timed out after 300 s\n";
  (void)!write(2, msg, sizeof msg - 1);
  _exit(1);
}

// Starts QEMU with UART0 on a new pseudo-terminal; returns the terminal's path
// once QEMU has named it and the image has said it is ready ("" on failure).
std::string start_qemu(int argc, char** argv) {
  int out[2];
  if (pipe(out) != 0) return "";
  g_qemu = fork();
  if (g_qemu == 0) {
    dup2(out[1], 1);
    dup2(out[1], 2);
    close(out[0]);
    close(out[1]);
    // QEMU's arguments, then the test's extra ones (argv[2..]).
    const char* fixed[] = {"qemu-system-arm", "-M", "mps2-an500", "-nographic", "-monitor", "none", "-semihosting",
                           "-serial", "pty", "-no-reboot", "-kernel", argv[1]};
    constexpr int kFixed = sizeof fixed / sizeof fixed[0];
    char* args[kFixed + 32] = {};
    for (int i = 0; i < kFixed; ++i) args[i] = const_cast<char*>(fixed[i]);
    for (int i = 2; i < argc && kFixed + i - 2 < kFixed + 31; ++i) args[kFixed + i - 2] = argv[i];
    execvp("qemu-system-arm", args);
    _exit(127);
  }
  close(out[1]);
  g_qemu_output = out[0];
  std::string text;
  std::string pts;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{out[0], POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) continue;
    char buffer[256];
    const ssize_t n = read(out[0], buffer, sizeof buffer);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    const std::size_t at = text.find("/dev/pts/");
    if (pts.empty() && at != std::string::npos) {
      std::size_t end = at + 9;
      while (end < text.size() && text[end] >= '0' && text[end] <= '9') ++end;
      if (end < text.size()) pts = text.substr(at, end - at);
    }
    if (!pts.empty() && text.find("rtu_server: ") != std::string::npos && text.find('\n', text.find("rtu_server: ")) != std::string::npos) {
      std::fprintf(stderr, "%s", text.c_str());
      const std::string banner = text.substr(text.find("rtu_server: "));
      if (std::sscanf(banner.c_str(), "rtu_server: slave %*u, %d baud", &g_baud) != 1) g_baud = 19200;
      return pts;  // the pipe stays open: QEMU must not get SIGPIPE
    }
  }
  std::fprintf(stderr, "test_rtu_qemu: QEMU said:\n%s\n", text.c_str());
  return "";
}

// Reads and drops what arrives within 200 ms: a late reply must not be taken
// for the answer to the next request.
void drain(modbus_t* ctx);

// A request that got no reply within the time-out is sent again, at most four times,
// as a PLC on RS-485 does: on the pseudo-terminal a request can arrive torn
// when the host delays QEMU's byte delivery past the 3.5-character silence
// (2 ms), and the slave then discards both parts (bad CRC), executing nothing.
int g_retries = 0;
constexpr int kAttempts = 5;

bool read_vars(modbus_t* ctx, std::uint16_t first, int count, double* values) {
  std::uint16_t words[4 * 31];
  int attempt = 0;
  while (modbus_read_registers(ctx, 4 * first, 4 * count, words) != 4 * count) {
    std::fprintf(stderr, "read #%u x%d: %s\n", first, count, modbus_strerror(errno));
    if (errno != ETIMEDOUT || ++attempt == kAttempts) return false;
    ++g_retries;
    drain(ctx);
  }
  for (int i = 0; i < count; ++i) values[i] = trueaxis::modbus::decode_double(words + 4 * i);
  return true;
}

bool write_vars(modbus_t* ctx, std::uint16_t first, int count, const double* values) {
  std::uint16_t words[4 * 30];
  for (int i = 0; i < count; ++i) trueaxis::modbus::encode_double(values[i], words + 4 * i);
  int attempt = 0;
  while (modbus_write_registers(ctx, 4 * first, 4 * count, words) != 4 * count) {
    std::fprintf(stderr, "write #%u x%d: %s\n", first, count, modbus_strerror(errno));
    if (errno != ETIMEDOUT || ++attempt == kAttempts) return false;
    ++g_retries;
    drain(ctx);
  }
  return true;
}

// Bytes that arrive on `fd` within `wait_ms` (read and counted).
int bytes_arriving(int fd, int wait_ms) {
  int count = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return count;
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
    std::uint8_t buffer[300];
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0) count += static_cast<int>(n);
  }
}

// Sends a raw request (address, function code, data; libmodbus adds the CRC)
// and returns how many bytes came back within `wait_ms`.
int bytes_answered(modbus_t* ctx, const std::uint8_t* request, int length, int wait_ms) {
  if (modbus_send_raw_request(ctx, const_cast<std::uint8_t*>(request), length) < 0) return -1;
  return bytes_arriving(modbus_get_socket(ctx), wait_ms);
}

// A frame written to the terminal as it is (no CRC added).
int bytes_answered_verbatim(int fd, const std::uint8_t* frame, std::size_t length, int wait_ms) {
  if (write(fd, frame, length) != static_cast<ssize_t>(length)) return -1;
  return bytes_arriving(fd, wait_ms);
}

void drain(modbus_t* ctx) { static_cast<void>(bytes_arriving(modbus_get_socket(ctx), 200)); }

namespace c = trueaxis::conformance;

// | address | PDU | CRC low | CRC high |.
c::Bytes rtu_frame(std::uint8_t to, const c::Bytes& pdu) {
  c::Bytes f = {to};
  f.insert(f.end(), pdu.begin(), pdu.end());
  const std::uint16_t crc = trueaxis::test::crc16_bitwise(f);
  f.push_back(static_cast<std::uint8_t>(crc));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  return f;
}

// Up to `n` bytes from `fd` within timeout_ms.
c::Bytes read_bytes(int fd, std::size_t n, int timeout_ms) {
  c::Bytes got;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (got.size() < n) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    std::uint8_t buffer[300];
    const ssize_t r = read(fd, buffer, std::min(sizeof buffer, n - got.size()));
    if (r <= 0) break;
    got.insert(got.end(), buffer, buffer + r);
  }
  return got;
}

// The conformance transport over the terminal, as a master on RS-485: the
// request framed with its CRC; the reply's length known from its first bytes
// (an exception 5 bytes, FC3 and FC23 3 + byte count + 2, FC16 8), its CRC and
// address checked. A request that gets no reply at all is sent again (a PLC's
// retry; see g_retries): only a torn request goes unanswered, and a torn
// request executes nothing.
class RtuTransport final : public c::Transport {
 public:
  explicit RtuTransport(int fd) : fd_(fd) {}

  bool exchange(const c::Bytes& pdu, c::Bytes& reply, std::string& why) override {
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
      if (attempt > 0) {
        ++g_retries;
        static_cast<void>(read_bytes(fd_, 1000, 200));
      }
      why.clear();
      if (once(pdu, reply, why)) return true;
      if (why != "no reply") return false;  // a wrong reply is an answer: not sent again
    }
    return false;
  }

 private:
  bool once(const c::Bytes& pdu, c::Bytes& reply, std::string& why) {
    const c::Bytes frame = rtu_frame(1, pdu);
    if (write(fd_, frame.data(), frame.size()) != static_cast<ssize_t>(frame.size())) {
      why = "write failed";
      return false;
    }
    c::Bytes r = read_bytes(fd_, 2, 1000);
    if (r.empty()) {
      why = "no reply";
      return false;
    }
    std::size_t total = 8;  // FC16's echo
    if (r.size() == 2 && (r[1] & 0x80) != 0) {
      total = 5;
    } else if (r.size() == 2 && (r[1] == 0x03 || r[1] == 0x17)) {
      const c::Bytes count = read_bytes(fd_, 1, 200);
      r.insert(r.end(), count.begin(), count.end());
      total = r.size() == 3 ? 5u + r[2] : 0;
    }
    if (r.size() < total) {
      const c::Bytes rest = read_bytes(fd_, total - r.size(), 500);
      r.insert(r.end(), rest.begin(), rest.end());
    }
    if (total == 0 || r.size() != total) {
      why = "reply cut short: " + c::hex(r);
      return false;
    }
    const c::Bytes body(r.begin(), r.end() - 2);
    const std::uint16_t crc = trueaxis::test::crc16_bitwise(body);
    if (r[0] != 1 || r[total - 2] != static_cast<std::uint8_t>(crc) || r[total - 1] != static_cast<std::uint8_t>(crc >> 8)) {
      why = "reply with a wrong address or CRC: " + c::hex(r);
      return false;
    }
    reply.assign(r.begin() + 1, r.end() - 2);
    return true;
  }

  int fd_;
};

// A case of the RTU table: the bytes written as they are, the response PDU
// expected (empty: none within 300 ms), the variables it may change, and a
// variable whose value must then be the given one.
struct RtuCase {
  std::string name;
  c::Bytes frame;
  c::Bytes reply;
  std::vector<std::uint16_t> changes;
  std::uint16_t check_number;
  double check_value;
};

std::vector<RtuCase> rtu_cases() {
  std::vector<RtuCase> t;
  const c::Bytes write = c::fc16_values(3, {11.0});
  c::Bytes bad_crc = rtu_frame(1, write);
  bad_crc.back() ^= 0x01;
  t.push_back({"a write with a bad CRC", bad_crc, {}, {}, 3, 3.125});
  c::Bytes swapped = rtu_frame(1, write);
  std::swap(swapped[swapped.size() - 1], swapped[swapped.size() - 2]);
  t.push_back({"a write with its CRC high byte first", swapped, {}, {}, 3, 3.125});
  t.push_back({"a write to address 2", rtu_frame(2, write), {}, {}, 3, 3.125});
  t.push_back({"a write to address 247", rtu_frame(247, write), {}, {}, 3, 3.125});
  t.push_back({"a write to address 248 (reserved)", rtu_frame(248, write), {}, {}, 3, 3.125});
  t.push_back({"a write to address 255", rtu_frame(255, write), {}, {}, 3, 3.125});
  t.push_back({"a broadcast write: done, not answered", rtu_frame(0, c::fc16_values(3, {12.5})), {}, {3}, 3, 12.5});
  t.push_back({"a broadcast write back", rtu_frame(0, c::fc16_values(3, {3.125})), {}, {3}, 3, 3.125});
  t.push_back({"a broadcast read: ignored", rtu_frame(0, c::fc3(4, 4)), {}, {}, 3, 3.125});
  c::Bytes swap = {0x17, 0, 12, 0, 4, 0, 12, 0, 4, 8};
  const c::Bytes v = c::value_bytes(13.0);
  swap.insert(swap.end(), v.begin(), v.end());
  t.push_back({"a broadcast FC23: a read, ignored whole (its write is not done)", rtu_frame(0, swap), {}, {}, 3, 3.125});
  t.push_back({"a broadcast write to a read-only result: refused, not answered", rtu_frame(0, c::fc16_values(100, {1.0})),
               {}, {}, 3, 3.125});
  t.push_back({"a broadcast unknown function code: not answered", rtu_frame(0, {0x41, 0, 0}), {}, {}, 3, 3.125});
  t.push_back({"three bytes: an address and a CRC", rtu_frame(1, {}), {}, {}, 3, 3.125});
  t.push_back({"two bytes", c::Bytes{1, 3}, {}, {}, 3, 3.125});
  // 1 + 254 + 2 = 257 bytes: one over the largest frame, its CRC right.
  c::Bytes long_pdu = {0x10, 0, 12, 0, 124, 248};
  for (int i = 0; i < 248; ++i) long_pdu.push_back(i % 8 == 0 ? 0x40 : 0);
  t.push_back({"257 bytes (a write of 124 registers)", rtu_frame(1, long_pdu), {}, {}, 3, 3.125});
  // 1 + 253 + 2 = 256 bytes: the largest frame, served (and refused: 03).
  c::Bytes max_pdu = {0x10, 0, 12, 0, 123, 246};
  for (int i = 0; i < 247; ++i) max_pdu.push_back(i % 8 == 0 ? 0x40 : 0);
  t.push_back({"256 bytes (the largest frame, its PDU one byte over)", rtu_frame(1, max_pdu), {0x90, 0x03}, {}, 3, 3.125});
  t.push_back({"a write to address 1 after all", rtu_frame(1, c::fc16_values(3, {3.125})), {0x10, 0, 12, 0, 4}, {3}, 3, 3.125});
  return t;
}

// The conformance suite over RTU: the PDU table, then the RTU table.
void run_conformance(int fd) {
  RtuTransport t(fd);
  const std::vector<c::Case> cases = c::pdu_cases();
  const auto started = std::chrono::steady_clock::now();
  // The addressed variables around each case, the whole state every 25 cases.
  const c::Outcome out = c::run_cases(t, cases, 25);
  for (const std::string& failure : out.failures) std::fprintf(stderr, "conformance: %s\n", failure.c_str());
  CHECK(out.failures.empty());
  CHECK(out.cases == cases.size());

  const std::vector<RtuCase> framing = rtu_cases();
  std::string why;
  c::State before;
  c::State after;
  CHECK(c::read_state(t, before, why));
  for (const RtuCase& k : framing) {
    if (write(fd, k.frame.data(), k.frame.size()) != static_cast<ssize_t>(k.frame.size())) {
      std::fprintf(stderr, "conformance: %s: write failed\n", k.name.c_str());
      ++g_failures;
      continue;
    }
    const c::Bytes answer = read_bytes(fd, k.reply.empty() ? 1 : k.reply.size() + 3, 300);
    const c::Bytes expected = k.reply.empty() ? c::Bytes{} : rtu_frame(1, k.reply);
    if (answer != expected) {
      std::fprintf(stderr, "conformance: %s: got %s, expected %s\n", k.name.c_str(), c::hex(answer).c_str(),
                   c::hex(expected).c_str());
      ++g_failures;
    }
    if (!c::read_state(t, after, why)) {
      std::fprintf(stderr, "conformance: %s: the state after it: %s\n", k.name.c_str(), why.c_str());
      ++g_failures;
      return;
    }
    for (std::uint16_t n : c::changed_variables(before, after, k.changes)) {
      std::fprintf(stderr, "conformance: %s: changed #%u\n", k.name.c_str(), n);
      ++g_failures;
    }
    c::Bytes value;
    if (!t.exchange(c::fc3(4u * k.check_number, 4), value, why) || value != c::fc3_reply({k.check_value})) {
      std::fprintf(stderr, "conformance: %s: #%u is not %g\n", k.name.c_str(), k.check_number, k.check_value);
      ++g_failures;
    }
    before.swap(after);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::fprintf(stderr, "test_rtu_qemu: conformance, %zu PDU cases and %zu RTU cases in %.1f s, %zu failed\n",
               out.cases, framing.size(), seconds, out.failures.size());
}

}  // namespace

constexpr const char* kHelp =
    "usage: test_rtu_qemu IMAGE [QEMU-ARGUMENTS...]\n"
    "  Runs IMAGE (rtu_server_qemu_target of the Cortex-M7 build) under QEMU with UART0 on a\n"
    "  pseudo-terminal and drives it over Modbus RTU: the conformance suite, then libmodbus's\n"
    "  RTU client. Exit 0 when every check holds, 1 when one fails, 77 when IMAGE is missing.\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "test_rtu_qemu", kHelp)) return 0;
  if (argc < 2) {
    std::fprintf(stderr, "usage: test_rtu_qemu IMAGE [QEMU-ARGUMENTS...]\n");
    return 2;
  }
  struct stat st {};
  if (stat(argv[1], &st) != 0) {
    std::fprintf(stderr, "test_rtu_qemu: no image %s (build rtu_server_target for the target); skipped\n", argv[1]);
    return 77;
  }
  signal(SIGALRM, on_alarm);
  alarm(300);
  const std::string pts = start_qemu(argc, argv);
  if (pts.empty()) {
    if (g_qemu > 0) kill(g_qemu, SIGKILL);
    return 1;
  }
  std::fprintf(stderr, "test_rtu_qemu: UART0 on %s\n", pts.c_str());

  modbus_t* ctx = modbus_new_rtu(pts.c_str(), g_baud, 'N', 8, 1);
  CHECK(ctx != nullptr);
  if (ctx == nullptr || modbus_connect(ctx) != 0) {
    std::fprintf(stderr, "connect %s: %s\n", pts.c_str(), modbus_strerror(errno));
    kill(g_qemu, SIGKILL);
    return 1;
  }
  modbus_set_response_timeout(ctx, 1, 0);
  modbus_set_slave(ctx, 1);
  // QEMU notices that the terminal was opened only on its next check (once a
  // second, chardev/char-pty.c) and reads nothing from it before: wait for it.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));

  run_conformance(modbus_get_socket(ctx));

  // A read and a write.
  double x[3] = {-1.0, -1.0, -1.0};
  CHECK(read_vars(ctx, 1, 1, x) && x[0] == 1.125);  // as the conformance table left it
  const double two_and_a_half = 2.5;
  CHECK(write_vars(ctx, 1, 1, &two_and_a_half));
  CHECK(read_vars(ctx, 1, 1, x) && x[0] == 2.5);

  // Macro 9810 through the handshake: a face tilted 30 degrees, probed at
  // A = #1 = 0.
  const double zero = 0.0;
  CHECK(write_vars(ctx, 1, 1, &zero));
  const double p1[3] = {0.0, 0.0, 0.0};
  const double p2[3] = {100.0, 0.0, 0.0};
  const double p3[3] = {0.0, 86.602540378443865, 50.0};
  CHECK(write_vars(ctx, var::kG57, 3, p1));
  CHECK(write_vars(ctx, var::kG58, 3, p2));
  CHECK(write_vars(ctx, var::kG59, 3, p3));
  const double cmd = 9810.0;
  CHECK(write_vars(ctx, var::kCmd, 1, &cmd));
  double handshake[4] = {};
  for (int i = 0; i < 100; ++i) {
    if (!read_vars(ctx, var::kCmd, 4, handshake)) break;
    if (handshake[1] != 1.0) break;  // not busy
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(handshake[1] == 2.0);  // done
  CHECK(handshake[2] == 0.0);  // no error
  CHECK(handshake[3] == 1.0);  // done_count
  double tilt = 0.0;
  CHECK(read_vars(ctx, 107, 1, &tilt) && std::fabs(tilt - 30.0) < 1e-9);

  // Exception 01 for an unknown function code.
  const std::uint8_t unknown[] = {1, 0x41, 0, 0, 0, 1};
  std::uint8_t confirmation[MODBUS_RTU_MAX_ADU_LENGTH];
  // modbus_receive_confirmation returns the reply as it came: | 1 | 0xC1 | 01 | CRC |.
  int confirmation_bytes = -1;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    CHECK(modbus_send_raw_request(ctx, const_cast<std::uint8_t*>(unknown), sizeof unknown) > 0);
    confirmation_bytes = modbus_receive_confirmation(ctx, confirmation);
    if (confirmation_bytes != -1 || errno != ETIMEDOUT) break;
    ++g_retries;
    drain(ctx);
  }
  CHECK(confirmation_bytes == 5 && confirmation[0] == 1 && confirmation[1] == 0xC1 && confirmation[2] == 0x01);

  // Broadcast: a write executed without a reply, a read ignored.
  std::uint16_t seven[4];
  trueaxis::modbus::encode_double(7.0, seven);
  std::uint8_t broadcast_write[15] = {0, 0x10, 0, 8, 0, 4, 8};  // #2, 8 data bytes
  for (int i = 0; i < 4; ++i) {
    broadcast_write[7 + 2 * i] = static_cast<std::uint8_t>(seven[i] >> 8);
    broadcast_write[8 + 2 * i] = static_cast<std::uint8_t>(seven[i]);
  }
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    CHECK(bytes_answered(ctx, broadcast_write, 15, 300) == 0);
    CHECK(read_vars(ctx, 2, 1, x));
    if (x[0] == 7.0) break;
    ++g_retries;  // torn on the way: nothing executed, sent again
  }
  CHECK(x[0] == 7.0);
  const std::uint8_t broadcast_read[] = {0, 0x03, 0, 8, 0, 4};
  CHECK(bytes_answered(ctx, broadcast_read, sizeof broadcast_read, 300) == 0);

  // Frames the slave must not answer nor execute: another address, a bad CRC.
  std::uint8_t other[15];
  std::memcpy(other, broadcast_write, sizeof other);
  other[0] = 2;
  trueaxis::modbus::encode_double(9.0, seven);
  other[7] = static_cast<std::uint8_t>(seven[0] >> 8);
  other[8] = static_cast<std::uint8_t>(seven[0]);
  CHECK(bytes_answered(ctx, other, 15, 300) == 0);
  const int fd = modbus_get_socket(ctx);
  const std::uint8_t bad_crc[] = {1, 0x03, 0, 4, 0, 4, 0x00, 0x00};
  CHECK(bytes_answered_verbatim(fd, bad_crc, sizeof bad_crc, 300) == 0);
  CHECK(read_vars(ctx, 2, 1, x) && x[0] == 7.0);

  // Many requests in a row: none lost.
  int lost = 0;
  for (int i = 0; i < 100; ++i) {
    const double v = i;
    if (!write_vars(ctx, 3, 1, &v) || !read_vars(ctx, 3, 1, x) || x[0] != v) ++lost;
  }
  std::fprintf(stderr, "test_rtu_qemu: 200 requests in a row, %d lost; %d requests sent again in the whole run\n",
               lost, g_retries);
  CHECK(lost == 0);
  CHECK(g_retries <= 40);  // 1 in 6 requests: beyond it the line is not usable

  modbus_close(ctx);
  modbus_free(ctx);
  kill(g_qemu, SIGTERM);
  waitpid(g_qemu, nullptr, 0);
  if (g_failures != 0) {  // what QEMU and the image said after start-up
    char buffer[4096];
    for (ssize_t n; (n = read(g_qemu_output, buffer, sizeof buffer)) > 0;) fwrite(buffer, 1, static_cast<std::size_t>(n), stderr);
  }
  std::fprintf(stderr, "test_rtu_qemu: %s\n", g_failures == 0 ? "all checks hold" : "FAILED");
  return g_failures == 0 ? 0 : 1;
}
