// The flashed image (rtu_server_target, tests/target) under QEMU with UART0 on a
// pseudo-terminal, driven by libmodbus's RTU client as a PLC on RS-485 would:
// a read, a write, macro 9810 through the handshake, exception 01, a broadcast
// write, and frames the slave must not answer (broadcast read, other address,
// bad CRC). Bounded: the whole run is stopped by alarm() after 60 s.
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
#include <string>
#include <thread>

#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/register_codec.hpp"

namespace {

namespace m = trueaxis::macros;
namespace var = trueaxis::macros::var;

int g_failures = 0;
pid_t g_qemu = -1;
int g_qemu_output = -1;  // QEMU's stdout and stderr

#define CHECK(cond)                                                             \
  do {                                                                          \
    if (!(cond)) {                                                              \
      std::fprintf(stderr, "%s:%d: FAILED: %s\n", __FILE__, __LINE__, #cond);   \
      ++g_failures;                                                             \
    }                                                                           \
  } while (0)

extern "C" void on_alarm(int) {
  if (g_qemu > 0) kill(g_qemu, SIGKILL);
  static const char msg[] = "test_rtu_qemu: timed out after 60 s\n";
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
  for (int i = 0; i < count; ++i) values[i] = m::decode_double(words + 4 * i);
  return true;
}

bool write_vars(modbus_t* ctx, std::uint16_t first, int count, const double* values) {
  std::uint16_t words[4 * 30];
  for (int i = 0; i < count; ++i) m::encode_double(values[i], words + 4 * i);
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

}  // namespace

int main(int argc, char** argv) {
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
  alarm(60);
  const std::string pts = start_qemu(argc, argv);
  if (pts.empty()) {
    if (g_qemu > 0) kill(g_qemu, SIGKILL);
    return 1;
  }
  std::fprintf(stderr, "test_rtu_qemu: UART0 on %s\n", pts.c_str());

  modbus_t* ctx = modbus_new_rtu(pts.c_str(), 19200, 'N', 8, 1);
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

  // A read and a write.
  double x[3] = {-1.0, -1.0, -1.0};
  CHECK(read_vars(ctx, 1, 1, x) && x[0] == 0.0);
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
  m::encode_double(7.0, seven);
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
  m::encode_double(9.0, seven);
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
