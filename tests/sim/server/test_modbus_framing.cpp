// Modbus TCP framing against a trueaxis-sim started by the test (127.0.0.1, port
// 0), with raw sockets: frames cut by the MBAP length whatever the function
// code, pipelined and split frames, refused headers that close the connection
// and execute nothing, and a slow client that holds up no one else.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include <sys/socket.h>


#include "raw_tcp_client.hpp"
#include "sim_fixture.hpp"
#include "trueaxis/modbus/register_codec.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;
using trueaxis::sim::test::SimFixture;
using Clock = std::chrono::steady_clock;

void put16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

// | tid | protocol | length | unit | pdu |; length = 1 + pdu size unless given.
Bytes frame(std::uint16_t tid, std::uint8_t unit, const Bytes& pdu, int protocol = 0, int length = -1) {
  Bytes b;
  put16(b, tid);
  put16(b, static_cast<std::uint32_t>(protocol));
  put16(b, length < 0 ? static_cast<std::uint32_t>(pdu.size() + 1) : static_cast<std::uint32_t>(length));
  b.push_back(unit);
  b.insert(b.end(), pdu.begin(), pdu.end());
  return b;
}

// FC16 writing #number = value (4 registers).
Bytes write_pdu(std::uint16_t number, double value) {
  Bytes b = {0x10};
  put16(b, 4u * number);
  put16(b, 4);
  b.push_back(8);
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(value, w);
  for (std::uint16_t x : w) put16(b, x);
  return b;
}

Bytes read_pdu(std::uint16_t number) {
  Bytes b = {0x03};
  put16(b, 4u * number);
  put16(b, 4);
  return b;
}

double value_in(const Bytes& reply) {  // the FC3 reply of read_pdu
  std::uint16_t w[4];
  for (std::size_t i = 0; i < 4; ++i) w[i] = static_cast<std::uint16_t>((reply[9 + 2 * i] << 8) | reply[10 + 2 * i]);
  return trueaxis::modbus::decode_double(w);
}

using RawClient = trueaxis::sim::test::RawTcpClient;


}  // namespace

TEST_CASE("three requests pipelined in one packet are answered in order, each with its transaction and unit id") {
  SimFixture f;
  RawClient c(f.port());
  Bytes packet = frame(0x0101, 0x01, write_pdu(1, 7.5));
  const Bytes read = frame(0x0202, 0xFF, read_pdu(1));
  const Bytes write = frame(0x0303, 0x00, write_pdu(3, -2.0));
  packet.insert(packet.end(), read.begin(), read.end());
  packet.insert(packet.end(), write.begin(), write.end());
  c.send(packet);
  const Bytes a = c.reply();
  const Bytes b = c.reply();
  const Bytes d = c.reply();
  REQUIRE(a.size() == 12);
  REQUIRE(b.size() == 17);
  REQUIRE(d.size() == 12);
  CHECK(Bytes(a.begin(), a.begin() + 7) == Bytes({0x01, 0x01, 0, 0, 0, 6, 0x01}));
  CHECK(Bytes(b.begin(), b.begin() + 9) == Bytes({0x02, 0x02, 0, 0, 0, 11, 0xFF, 0x03, 8}));
  CHECK(value_in(b) == 7.5);  // the write before it was done first
  CHECK(Bytes(d.begin(), d.begin() + 8) == Bytes({0x03, 0x03, 0, 0, 0, 6, 0x00, 0x10}));
  CHECK(f.get(3) == -2.0);
}

TEST_CASE("a frame split at any byte is answered once, when its last byte arrives") {
  SimFixture f;
  RawClient c(f.port());
  const std::size_t size = frame(0, 1, write_pdu(1, 0.0)).size();
  for (std::size_t cut = 1; cut < size; ++cut) {
    INFO("split after byte " << cut);
    const Bytes whole = frame(static_cast<std::uint16_t>(cut), 1, write_pdu(1, static_cast<double>(cut)));
    c.send(Bytes(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut)));
    CHECK(c.receive(1, 15).empty());  // nothing before the rest
    c.send(Bytes(whole.begin() + static_cast<std::ptrdiff_t>(cut), whole.end()));
    const Bytes r = c.reply();
    REQUIRE(r.size() == 12);
    CHECK(r[0] == 0);
    CHECK(r[1] == cut);
    // Answered once: the next reply on this connection is the next request's.
    c.send(frame(0xBEEF, 1, read_pdu(1)));
    const Bytes next = c.reply();
    REQUIRE(next.size() == 17);
    CHECK((next[0] == 0xBE && next[1] == 0xEF));
    CHECK(value_in(next) == static_cast<double>(cut));
  }
}

TEST_CASE("a bad protocol id or length closes the connection without a reply and executes nothing") {
  SimFixture f;
  struct Bad {
    int protocol;
    int length;
  };
  for (const Bad bad : {Bad{1, -1}, Bad{0xFFFF, -1}, Bad{0, 0}, Bad{0, 1}, Bad{0, 255}, Bad{0, 0xFFFF}}) {
    INFO("protocol id " << bad.protocol << ", length " << bad.length);
    RawClient c(f.port());
    // The refused frame, and a valid write behind it in the same packet.
    Bytes packet = frame(1, 1, write_pdu(1, 99.0), bad.protocol, bad.length);
    const Bytes behind = frame(2, 1, write_pdu(3, 98.0));
    packet.insert(packet.end(), behind.begin(), behind.end());
    c.send(packet);
    CHECK(c.closed_silently());
  }
  CHECK(f.get(1) == 0.0);
  CHECK(f.get(3) == 0.0);
  // A valid frame before a refused one in the same packet is still answered
  // (a work offset: an argument would be cleared when its connection closes,
  // module.hpp contract 8).
  RawClient c(f.port());
  Bytes packet = frame(7, 1, write_pdu(5281, 4.0));
  const Bytes bad = frame(8, 1, write_pdu(3, 5.0), 2);
  packet.insert(packet.end(), bad.begin(), bad.end());
  c.send(packet);
  const Bytes r = c.reply();
  REQUIRE(r.size() == 12);
  CHECK(r[1] == 7);
  CHECK(c.closed_silently());
  CHECK(f.get(5281) == 4.0);
  CHECK(f.get(3) == 0.0);
}

TEST_CASE("an unknown function code whose length covers a whole FC16 frame is exception 01 and the hidden write is not done") {
  SimFixture f;
  RawClient c(f.port());
  const Bytes hidden = frame(9, 1, write_pdu(1, 55.0));
  for (std::uint8_t fc : {std::uint8_t{0x41}, std::uint8_t{0x64}, std::uint8_t{0x90}, std::uint8_t{0xFF}}) {
    INFO("function code " << int{fc});
    Bytes pdu = {fc};
    pdu.insert(pdu.end(), hidden.begin(), hidden.end());
    c.send(frame(0x1234, 0x11, pdu));
    const Bytes r = c.reply();
    CHECK(r == Bytes({0x12, 0x34, 0, 0, 0, 3, 0x11, static_cast<std::uint8_t>(fc | 0x80), 0x01}));
    // The connection stays in step: the next request gets the next reply.
    c.send(frame(0x4321, 1, read_pdu(1)));
    const Bytes next = c.reply();
    REQUIRE(next.size() == 17);
    CHECK((next[0] == 0x43 && next[1] == 0x21));
    CHECK(value_in(next) == 0.0);
  }
  CHECK(f.get(1) == 0.0);
}

TEST_CASE("a client sending one byte every 50 ms does not delay another client by more than a few ms") {
  SimFixture f;
  RawClient slow(f.port());
  RawClient fast(f.port());
  const Bytes drip = frame(0x5150, 1, write_pdu(5281, 12.5));
  std::thread dripper([&] {
    for (const std::uint8_t& b : drip) {  // no Catch2 macros here: they are not thread-safe
      (void)::send(slow.fd(), &b, 1, MSG_NOSIGNAL);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  std::vector<double> latencies_ms;
  const auto end = Clock::now() + std::chrono::milliseconds(50 * static_cast<int>(drip.size()) - 100);
  std::uint16_t tid = 0;
  bool all_right = true;
  while (Clock::now() < end && latencies_ms.size() < 2000) {
    const auto t0 = Clock::now();
    fast.send(frame(++tid, 1, read_pdu(9006)));
    const Bytes r = fast.reply();
    latencies_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    all_right = all_right && r.size() == 17 && r[1] == static_cast<std::uint8_t>(tid) && value_in(r) == 1.0;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  dripper.join();
  std::sort(latencies_ms.begin(), latencies_ms.end());
  INFO(latencies_ms.size() << " requests while the slow client dripped; median "
                           << latencies_ms[latencies_ms.size() / 2] << " ms, max " << latencies_ms.back() << " ms");
  CHECK(all_right);
  CHECK(latencies_ms.size() > 100);
  CHECK(latencies_ms.back() < 25.0);
  // The slow client's request, once whole, is served too.
  const Bytes r = slow.reply();
  CHECK(r == Bytes({0x51, 0x50, 0, 0, 0, 6, 1, 0x10, 0x52, 0x84, 0, 4}));
  CHECK(f.get(5281) == 12.5);
}

TEST_CASE("a partial frame held past --frame-timeout closes its connection and no other") {
  SimFixture f({"--frame-timeout", "300"});
  RawClient stalled(f.port());
  const Bytes whole = frame(1, 1, write_pdu(1, 3.0));
  const auto t0 = Clock::now();
  stalled.send(Bytes(whole.begin(), whole.begin() + 10));
  CHECK(stalled.closed_silently(3000));
  const double waited_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  CHECK(waited_ms > 250.0);
  CHECK(waited_ms < 2000.0);
  CHECK(f.get(1) == 0.0);
  CHECK(f.get(9006) == 1.0);  // the fixture's idle client is still served
}

TEST_CASE("with --max-clients 2 a third connection is closed at once and the first two are still served") {
  SimFixture f({"--max-clients", "2"});  // the fixture's own client is the first
  RawClient second(f.port());
  RawClient third(f.port());
  third.send(frame(1, 1, write_pdu(1, 3.0)));
  CHECK(third.closed_silently());
  second.send(frame(2, 1, read_pdu(9006)));
  const Bytes r = second.reply();
  REQUIRE(r.size() == 17);
  CHECK(value_in(r) == 1.0);
  CHECK(f.get(1) == 0.0);
}

TEST_CASE("with --idle-timeout a connection that sends nothing is closed") {
  SimFixture f({"--idle-timeout", "300"});
  RawClient idle(f.port());
  const auto t0 = Clock::now();
  CHECK(idle.closed_silently(3000));
  const double waited_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  CHECK(waited_ms > 250.0);
  CHECK(waited_ms < 2000.0);
}

TEST_CASE("a frame dripped a byte every 100 ms is closed --frame-timeout after its first byte, not after its last") {
  // 23 bytes at 100 ms would take 2.2 s; each byte must not restart the clock.
  SimFixture f({"--frame-timeout", "300"});
  RawClient dripping(f.port());
  const Bytes whole = frame(1, 1, write_pdu(1, 3.0));
  const auto t0 = Clock::now();
  bool closed = false;
  for (std::size_t i = 0; i < whole.size() && !closed; ++i) {
    if (::send(dripping.fd(), whole.data() + i, 1, MSG_NOSIGNAL) != 1) break;
    closed = dripping.closed_silently(100);
  }
  const double waited_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  CHECK(closed);
  CHECK(waited_ms > 250.0);
  CHECK(waited_ms < 1500.0);
  CHECK(f.get(1) == 0.0);
}

TEST_CASE("with --idle-timeout a client that sends a request every 100 ms stays open") {
  SimFixture f({"--idle-timeout", "300"});
  RawClient busy(f.port());
  int answered = 0;
  for (std::uint16_t i = 0; i < 15; ++i) {
    busy.send(frame(i, 1, read_pdu(9006)));
    const Bytes r = busy.reply();
    if (r.size() == 17 && value_in(r) == 1.0) ++answered;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK(answered == 15);  // 1.5 s, five times the idle time-out
  CHECK_FALSE(busy.closed());
}
