// Load on loopback, bounded (issue 8): a trueaxis-sim started by the test
// (127.0.0.1, port 0) under 16 clients at once, 10,000 connect/disconnect
// cycles watched through /proc/<sim pid>, and a client dripping a request byte
// by byte while others read. The figures for the issue's strict bounds (p99
// under 5 ms with 15 other clients, throughput against a bare libmodbus loop)
// come from host_sim/bench/bench_modbus_load.cpp; the bounds here are loose
// enough for a loaded 2-core CI machine and still fail a server that serves one
// client at a time. A fourth case exposes a defect found on the way: the
// server spins when its descriptor limit is reached (it fails until
// modbus_server.cpp is fixed). Whole program: about 6 s.
//
// Catch2 macros are not thread-safe: the client threads only count, the main
// thread checks.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include "loopback.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/modbus/register_codec.hpp"

namespace {

using trueaxis::sim::VariableClient;
using trueaxis::sim::test::SimFixture;
using Clock = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;
using namespace trueaxis::sim::loopback;  // NOLINT: the helpers of loopback.hpp

// 16 macro arguments, one per client. #10, #12, #14, #15 and #16 are not
// defined by the map (G, L, N, O, P are no G65 arguments), so the 16 are
// #1..#9, #11, #13, #17..#21.
constexpr std::uint16_t kArgs[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 17, 18, 19, 20, 21};


}  // namespace

TEST_CASE("16 clients at once: FC16, FC3 and FC23 of their own variable, each answered; the macro interface's holder alone writes") {
  // Module contract 8: the macro interface is granted to one client at a time.
  // Client 0 takes it before the others start and keeps it (it writes all the
  // time); every write of the 15 others is answered with exception 06 and
  // changes nothing, every read of everyone is answered with the right value.
  SimFixture f;
  constexpr int kClients = 16;
  constexpr int kIterations = 300;
  std::atomic<int> connected{0};
  std::atomic<int> connect_failures{0};
  std::atomic<int> finished{0};
  std::atomic<long> errors{0};     // a failure that is not the holder's refusal of another
  std::atomic<long> refused{0};    // exception 06 to a write of a client that does not hold
  std::atomic<long> wrong{0};
  std::atomic<long> requests{0};
  std::vector<double> last(kClients, 0.0);
  std::vector<std::thread> threads;
  const auto t0 = Clock::now();
  for (int id = 0; id < kClients; ++id) {
    threads.emplace_back([&, id] {
      VariableClient c;
      const bool ok = c.connect("127.0.0.1", f.port()) && (id != 0 || c.write_one(9009, 1.0));
      if (!ok) ++connect_failures;
      ++connected;
      // All connected (and client 0 holding) before anyone starts: 16 (+ the fixture's) served at once.
      while (connected.load() < kClients) std::this_thread::yield();
      if (!ok) {
        ++finished;
        return;
      }
      const bool holder = id == 0;
      const std::uint16_t number = kArgs[id];
      const int reg = static_cast<int>(trueaxis::modbus::register_of(number));
      const auto write_failed = [&] {
        if (!holder && c.exception() == 6) {
          ++refused;
        } else {
          ++errors;
        }
      };
      for (int it = 0; it < kIterations; ++it) {
        // Client and iteration in the value; the fraction makes every bit count.
        const double sign = (it % 2 == 0) ? 1.0 : -1.0;
        const double v16 = sign * ((id + 1) * 1000.0 + it + 1.0 / 1024.0);
        const double v23 = sign * ((id + 1) * 1000.0 + it + 0.5 + 1.0 / 4096.0);
        const double expected16 = holder ? v16 : 0.0;
        double back = 0.0;
        if (!c.write_one(number, v16)) {
          write_failed();
        } else if (!holder) {
          ++wrong;  // another's write taken while client 0 holds the interface
        }
        if (!c.read_one(number, back)) {
          ++errors;
        } else if (back != expected16) {
          ++wrong;
        }
        std::uint16_t w[4];
        std::uint16_t r[4] = {};
        trueaxis::modbus::encode_double(v23, w);
        if (modbus_write_and_read_registers(c.raw(), reg, 4, w, reg, 4, r) != 4) {
          write_failed();
        } else if (!holder || trueaxis::modbus::decode_double(r) != v23) {
          ++wrong;
        }
        requests += 3;
        if (holder) last[static_cast<std::size_t>(id)] = v23;
      }
      // The holder keeps its connection (and the interface) until everyone is done.
      ++finished;
      while (holder && finished.load() < kClients) std::this_thread::yield();
    });
  }
  for (std::thread& t : threads) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("16 clients x %d iterations: %ld requests in %.2f s (%.0f/s), %ld refused (06), %ld errors, %ld wrong values\n",
              kIterations, requests.load(), seconds, static_cast<double>(requests.load()) / seconds, refused.load(),
              errors.load(), wrong.load());
  CHECK(connect_failures == 0);
  CHECK(requests == 3L * kClients * kIterations);
  CHECK(errors == 0);
  CHECK(refused == 2L * (kClients - 1) * kIterations);
  CHECK(wrong == 0);
  // Only the holder's variable changed, and it holds its last value (no macro ran).
  for (int id = 0; id < kClients; ++id) {
    INFO("client " << id << ", #" << kArgs[id]);
    CHECK(f.get(kArgs[id]) == last[static_cast<std::size_t>(id)]);
  }
}

TEST_CASE("16 clients each writing and reading back its own work offset 500 times, no macro running: 0 exceptions") {
  // Module contract 8: a work-offset write takes no macro interface, so
  // sixteen HMIs (or probing programs) on persistent connections never refuse
  // one another. Each write is saved to the NV file (fsync'ed) before it is
  // answered.
  SimFixture f;
  constexpr int kClients = 16;
  constexpr int kIterations = 500;
  std::atomic<int> connected{0};
  std::atomic<long> exceptions{0};
  std::atomic<long> failures{0};  // anything else: a transport failure, a wrong value read back
  std::vector<double> last(kClients, 0.0);
  std::vector<std::thread> threads;
  const auto t0 = Clock::now();
  for (int id = 0; id < kClients; ++id) {
    threads.emplace_back([&, id] {
      VariableClient c;
      const bool ok = c.connect("127.0.0.1", f.port());
      ++connected;
      while (connected.load() < kClients) std::this_thread::yield();
      if (!ok) {
        ++failures;
        return;
      }
      // G54 X .. G56 Y: #5221.. #5226, #5241.., #5261..
      const auto number = static_cast<std::uint16_t>(5221 + 20 * (id / 6) + id % 6);
      for (int it = 0; it < kIterations; ++it) {
        const double value = (id + 1) * 1000.0 + it + 1.0 / 1024.0;
        double back = 0.0;
        if (!c.write_one(number, value)) {
          ++(c.exception() != 0 ? exceptions : failures);
        } else if (!c.read_one(number, back)) {
          ++(c.exception() != 0 ? exceptions : failures);
        } else if (back != value) {
          ++failures;
        }
        last[static_cast<std::size_t>(id)] = value;
      }
    });
  }
  for (std::thread& t : threads) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("16 work-offset writers x %d: %d writes and reads in %.2f s, %ld exceptions, %ld other failures\n",
              kIterations, 2 * kClients * kIterations, seconds, exceptions.load(), failures.load());
  CHECK(exceptions == 0);
  CHECK(failures == 0);
  CHECK(f.get(9009) == 0.0);  // none of them took the interface
  for (int id = 0; id < kClients; ++id) {
    const auto number = static_cast<std::uint16_t>(5221 + 20 * (id / 6) + id % 6);
    INFO("client " << id << ", #" << number);
    CHECK(f.get(number) == last[static_cast<std::size_t>(id)]);
  }
}

TEST_CASE("10,000 connect/disconnect cycles leave the sim's descriptors and memory where they were") {
  SimFixture f;
  const pid_t pid = f.pid();
  REQUIRE(pid > 0);
  f.set(1, 31.25);
  long failures = 0;
  // Each connection reads #1 (so it is served), then closes in one of four ways:
  // a clean close; a partial frame (5 bytes) left pending; a reset (SO_LINGER
  // 0) with a partial frame pending; a request sent and the reply never read.
  const auto cycle = [&](int k) {
    if (!connect_cycle(f.port(), k, 31.25)) ++failures;
  };
  const auto settled_fds = [&](int target) { return settled_fd_count(pid, target); };

  const int fds_idle = fd_count(pid);
  REQUIRE(fds_idle > 0);
  for (int k = 0; k < 200 && failures < 3; ++k) cycle(k);  // warm-up: first-touch pages, lazily bound code
  const int fds_before = settled_fds(fds_idle);
  (void)f.get(1);
  const long rss_before = status_kb(pid, "VmRSS");
  const long data_before = status_kb(pid, "VmData");
  const auto t0 = Clock::now();
  int done = 0;
  for (; done < 10000 && failures < 3; ++done) cycle(done);  // bounded when the server stops serving
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const int fds_after = settled_fds(fds_before);
  CHECK(f.get(1) == 31.25);  // still serving
  const long rss_after = status_kb(pid, "VmRSS");
  const long data_after = status_kb(pid, "VmData");
  std::printf("%d connect/disconnect cycles in %.2f s: fds %d -> %d, VmRSS %ld -> %ld kB, VmData %ld -> %ld kB\n",
              done, seconds, fds_before, fds_after, rss_before, rss_after, data_before, data_after);
  CHECK(failures == 0);
  CHECK(done == 10000);
  CHECK(fds_before == fds_idle);
  CHECK(fds_after == fds_before);
  REQUIRE(rss_before > 0);
  REQUIRE(data_before > 0);
  // The server allocates nothing per connection (its connection table is
  // reserved for --max-clients at start). A leak of even one malloc chunk (32
  // bytes) per connection would be 312 kB here; the bound is two pages, for a
  // page of stack or libc data first touched late.
  CHECK(data_after == data_before);
  CHECK(rss_after - rss_before <= 8);
}

TEST_CASE("while one client drips a request a byte every 20 ms, four others are answered without waiting for it") {
  SimFixture f;
  constexpr int kReaders = 4;
  for (int i = 0; i < kReaders + 1; ++i) f.set(kArgs[i], 100.0 + i);
  std::atomic<bool> dripping{true};
  std::atomic<bool> reading{true};
  std::atomic<int> drip_ok{0};
  std::atomic<int> drip_bad{0};
  std::thread dripper([&] {
    const int fd = connect_to(f.port());
    if (fd < 0) {
      ++drip_bad;
      return;
    }
    for (std::uint16_t tid = 1; dripping.load(); ++tid) {
      const Bytes frame = read_frame(tid, kArgs[kReaders]);
      bool ok = true;
      for (const std::uint8_t& b : frame) {
        ok = ok && ::send(fd, &b, 1, MSG_NOSIGNAL) == 1;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      double v = 0.0;
      if (ok && read_reply(fd, tid, v) && v == 100.0 + kReaders) {
        ++drip_ok;
      } else {
        ++drip_bad;
        break;
      }
    }
    ::close(fd);
  });
  std::vector<std::vector<double>> latencies(kReaders);
  std::vector<long> bad(kReaders, 0);
  std::vector<std::thread> readers;
  for (int id = 0; id < kReaders; ++id) {
    readers.emplace_back([&, id] {
      auto& mine = latencies[static_cast<std::size_t>(id)];
      mine.reserve(4000);
      const int fd = connect_to(f.port());
      if (fd < 0) {
        ++bad[static_cast<std::size_t>(id)];
        return;
      }
      for (std::uint16_t tid = 1; reading.load() && mine.size() < 4000; ++tid) {
        double v = 0.0;
        const auto t0 = Clock::now();
        const bool ok = read_var(fd, tid, kArgs[id], v);
        mine.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        if (!ok || v != 100.0 + id) {
          ++bad[static_cast<std::size_t>(id)];
          if (!ok) break;  // the connection is out of step
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      ::close(fd);
    });
  }
  std::this_thread::sleep_for(std::chrono::seconds(3));
  dripping = false;
  dripper.join();  // ends with its current request answered
  reading = false;
  for (std::thread& t : readers) t.join();

  std::vector<double> all;
  for (int id = 0; id < kReaders; ++id) {
    const auto& mine = latencies[static_cast<std::size_t>(id)];
    all.insert(all.end(), mine.begin(), mine.end());
    std::printf("drip test, reader %d: %zu requests, p50 %.3f ms, p99 %.3f ms, max %.3f ms\n", id, mine.size(),
                percentile(mine, 0.5), percentile(mine, 0.99), percentile(mine, 1.0));
  }
  const double p99 = percentile(all, 0.99);
  std::printf("drip test, %d readers: %zu requests, p50 %.3f ms, p99 %.3f ms, max %.3f ms; %d dripped requests answered\n",
              kReaders, all.size(), percentile(all, 0.5), p99, percentile(all, 1.0), drip_ok.load());
  for (int id = 0; id < kReaders; ++id) {
    INFO("reader " << id);
    CHECK(bad[static_cast<std::size_t>(id)] == 0);
    CHECK(latencies[static_cast<std::size_t>(id)].size() > 200);
  }
  CHECK(drip_bad == 0);
  CHECK(drip_ok >= 10);  // 3 s at 12 bytes x 20 ms per request
  // A server that waits for the dripped frame to be whole before serving anyone
  // holds every reader for up to 240 ms per dripped request: its p99 is far
  // above this. This server's is well under 5 ms (bench_modbus_load); 50 ms
  // leaves room for a loaded CI machine.
  CHECK(p99 < 50.0);
}

// Found while writing these tests (issue 8): when the sim has as many
// descriptors open as its RLIMIT_NOFILE allows (fewer than --max-clients + its
// own), accept4 fails with EMFILE, the waiting connection stays in the listen
// backlog, the listening socket stays readable and ppoll returns at once: the
// server spins a core until a descriptor frees. Here the limit is lowered so
// that 4 more descriptors fit, and 10 clients connect.
TEST_CASE("with its descriptor limit reached, the sim does not spin while connections wait in the backlog") {
  SimFixture f;
  const pid_t pid = f.pid();
  (void)f.get(1);  // the fixture's connection accepted
  const int base = lowest_free_fd(pid);  // the limit caps descriptor numbers
  REQUIRE(base > 0);
  const rlimit limit{static_cast<rlim_t>(base + 4), static_cast<rlim_t>(base + 4)};
  REQUIRE(::prlimit(pid, RLIMIT_NOFILE, &limit, nullptr) == 0);
  // The descriptor numbers below the limit still free: that many clients are
  // accepted, the rest wait (4 unless something holds a number in between).
  const int fit = free_fds_below(pid, base + 4);
  REQUIRE(fit >= 1);
  REQUIRE(fit <= 4);
  std::vector<int> fds;
  for (int i = 0; i < 10; ++i) {
    const int fd = connect_to(f.port());  // the backlog takes the ones not accepted
    REQUIRE(fd >= 0);
    fds.push_back(fd);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double cpu0 = cpu_seconds(pid);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const double cpu1 = cpu_seconds(pid);
  double v = -1.0;
  const bool first_served = read_var(fds.front(), 1, 1, v) && v == 0.0;
  std::printf("descriptor limit %d reached: the sim used %.2f s of CPU in 1 s with 10 clients connected (%d fds)\n",
              base + 4, cpu1 - cpu0, fd_count(pid));
  CHECK(first_served);      // the accepted ones are served
  CHECK(f.get(1) == 0.0);   // and so is the fixture's client
  CHECK(cpu1 - cpu0 < 0.2);  // an idle server uses none
  // Clients 0..fit-1 were accepted, fit..9 wait in the backlog. Each time an
  // accepted one closes, the first waiting is accepted and served at once, not
  // after the rest of the 100 ms pause: five rounds, each well under it (a
  // server that kept pausing would be late by 0..100 ms in each, and under
  // 40 ms in all five with odds of 1 in 100). An accepted client closes first
  // in each round: round k closes client k, or, once those are gone, the one
  // accepted in round k - fit.
  double slowest_ms = 0.0;
  int served = 0;
  for (int round = 0; round < 5; ++round) {
    ::close(fds[static_cast<std::size_t>(round)]);  // clients 0..4 are all accepted by then
    fds[static_cast<std::size_t>(round)] = -1;
    const auto t0 = Clock::now();
    double waited = -1.0;
    if (read_var(fds[static_cast<std::size_t>(fit + round)], 1, 1, waited) && waited == 0.0) ++served;
    slowest_ms = std::max(slowest_ms, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::printf("each of 5 waiting clients served %.1f ms at most after an accepted one closed\n", slowest_ms);
  CHECK(served == 5);
  CHECK(slowest_ms < 40.0);
  for (const int fd : fds) {
    if (fd >= 0) ::close(fd);
  }
}
