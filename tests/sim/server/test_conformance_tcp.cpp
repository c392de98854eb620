// The conformance suite (tests/protocol/conformance.hpp) over Modbus TCP against
// a trueaxis-sim started by the test (127.0.0.1, port 0), with raw sockets and
// an MBAP framing written here: the whole PDU table, then the TCP table (bad
// protocol id and length, lengths one short and one over, a truncated frame,
// 16 requests pipelined in one packet, a frame split at every byte, a hidden
// frame behind an unknown function code). Every case reads the whole state
// before and after it, on a second connection, and allows changes only to the
// variables its served writes name.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>


#include "conformance.hpp"
#include "raw_tcp_client.hpp"
#include "sim_fixture.hpp"

namespace {

namespace c = trueaxis::conformance;
using c::Bytes;
using trueaxis::sim::test::SimFixture;
using Clock = std::chrono::steady_clock;

// | transaction id | protocol id | length | unit id | PDU |; length = 1 + PDU
// unless given.
Bytes mbap(std::uint16_t tid, std::uint8_t unit, const Bytes& pdu, std::uint32_t protocol = 0, int length = -1) {
  Bytes b;
  c::put16(b, tid);
  c::put16(b, protocol);
  c::put16(b, length < 0 ? static_cast<std::uint32_t>(pdu.size() + 1) : static_cast<std::uint32_t>(length));
  b.push_back(unit);
  b.insert(b.end(), pdu.begin(), pdu.end());
  return b;
}

Bytes joined(const std::vector<Bytes>& parts) {
  Bytes all;
  for (const Bytes& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

using Connection = trueaxis::sim::test::RawTcpClient;


// The conformance transport: one request, one reply frame, checked against the
// MBAP rules of the reply (the transaction and unit id echoed, protocol 0, the
// length of what follows).
class TcpTransport final : public c::Transport {
 public:
  explicit TcpTransport(int port) : connection_(port) {}

  bool exchange(const Bytes& pdu, Bytes& reply, std::string& why) override {
    ++tid_;
    const auto unit = static_cast<std::uint8_t>(tid_ * 7);  // any unit id is served and echoed
    connection_.send(mbap(tid_, unit, pdu));
    const Bytes r = connection_.reply();
    if (r.size() < 8) {
      why = connection_.closed() ? "closed by the server" : "no reply within 2 s";
      return false;
    }
    const Bytes head(r.begin(), r.begin() + 7);
    Bytes expected_head;
    c::put16(expected_head, tid_);
    c::put16(expected_head, 0);
    c::put16(expected_head, static_cast<std::uint32_t>(r.size() - 6));
    expected_head.push_back(unit);
    if (head != expected_head) {
      why = "MBAP header " + c::hex(head) + ", expected " + c::hex(expected_head);
      return false;
    }
    reply.assign(r.begin() + 7, r.end());
    return true;
  }

 private:
  Connection connection_;
  std::uint16_t tid_ = 0;
};

// A case of the TCP table: bytes sent on a new connection in chunks, 5 ms
// apart; the reply frames that must come back, whole and in order; whether the
// server then closes the connection; what may change.
struct FramingCase {
  std::string name;
  std::vector<Bytes> chunks;
  std::vector<Bytes> replies;
  bool closes = false;
  std::vector<std::uint16_t> changes;
  bool client_closes = false;  // the client stops sending (shuts its side) after the chunks
};

FramingCase framing(std::string name, std::vector<Bytes> chunks, std::vector<Bytes> replies, bool closes = false,
                    std::vector<std::uint16_t> changes = {}, bool client_closes = false) {
  return {std::move(name), std::move(chunks), std::move(replies), closes, std::move(changes), client_closes};
}

Bytes write_pdu(std::uint16_t number, double value) { return c::fc16_values(number, {value}); }
Bytes read_pdu(std::uint16_t number) { return c::fc3(4u * number, 4); }
Bytes echo(std::uint16_t number) {
  Bytes b = {0x10};
  c::put16(b, 4u * number);
  c::put16(b, 4);
  return b;
}
Bytes exception(std::uint8_t fc, std::uint8_t code) { return {static_cast<std::uint8_t>(fc | 0x80), code}; }

// FC23: write `value` to #number and read it back in one request.
Bytes swap_pdu(std::uint16_t number, double value) {
  Bytes b = {0x17};
  c::put16(b, 4u * number);
  c::put16(b, 4);
  c::put16(b, 4u * number);
  c::put16(b, 4);
  b.push_back(8);
  const Bytes v = c::value_bytes(value);
  b.insert(b.end(), v.begin(), v.end());
  return b;
}
Bytes swap_reply(double value) {
  Bytes b = c::fc3_reply({value});
  b[0] = 0x17;
  return b;
}

std::vector<FramingCase> framing_cases() {
  std::vector<FramingCase> t;
  const Bytes write = write_pdu(1, 99.0);
  // Refused headers: closed at once, nothing of that frame or after it runs.
  for (const auto& [protocol, length, what] :
       std::vector<std::tuple<std::uint32_t, int, std::string>>{{1, -1, "protocol id 1"},
                                                               {0xFFFF, -1, "protocol id 0xFFFF"},
                                                               {0, 0, "length 0"},
                                                               {0, 1, "length 1 (no function code)"},
                                                               {0, 255, "length 255 (past the largest frame)"},
                                                               {0, 0xFFFF, "length 0xFFFF"}}) {
    t.push_back(framing(what + ", a valid write behind it",
                 {joined({mbap(1, 1, write, protocol, length), mbap(2, 1, write_pdu(2, 98.0))})},
                 {},
                 true));
  }
  t.push_back(framing("a valid write, then a bad protocol id in the same packet",
               {joined({mbap(7, 1, write_pdu(3, 4.0)), mbap(8, 1, write_pdu(2, 5.0), 2)})},
               {mbap(7, 1, echo(3))},
               true,
               {3}));
  // The length field, not the function code, cuts the frame.
  t.push_back(framing("length one short of an FC16: its PDU is truncated (03); the byte left over opens a bad header",
               {joined({mbap(0x0001, 1, write, 0, static_cast<int>(write.size())), mbap(0x0101, 1, read_pdu(1))})},
               {mbap(0x0001, 1, exception(0x10, 0x03))},
               true));
  t.push_back(framing("length one over an FC3: it takes the next frame's first byte (03); the rest has length 1537",
               {joined({mbap(1, 1, read_pdu(1), 0, 7), mbap(2, 1, read_pdu(1))})},
               {mbap(1, 1, exception(0x03, 0x03))},
               true));
  t.push_back(framing("length 254 (the largest): an FC16 of 123 registers with one byte over (03)",
               {mbap(3, 1, [] {
                  Bytes b = {0x10, 0x0F, 0xA4, 0, 123, 246};
                  b.resize(253, 0);
                  return b;
                }())},
               {mbap(3, 1, exception(0x10, 0x03))}));
  t.push_back(framing("length 2: the function code alone (03)", {mbap(4, 1, {0x03})}, {mbap(4, 1, exception(0x03, 0x03))}));
  const Bytes whole_write = mbap(5, 1, write);
  t.push_back(framing("a truncated frame (the header and half an FC16), then the client closes",
               {Bytes(whole_write.begin(), whole_write.begin() + 12)},
               {},
               true,
               {},
               true));
  t.push_back(framing("a header alone, then the client closes", {Bytes(whole_write.begin(), whole_write.begin() + 6)}, {}, true, {}, true));
  // Hidden frames: an unknown function code whose body is a whole FC16 frame.
  for (std::uint8_t fc : {std::uint8_t{0x00}, std::uint8_t{0x41}, std::uint8_t{0x90}, std::uint8_t{0xFF}}) {
    Bytes pdu = {fc};
    const Bytes hidden = mbap(9, 1, write);
    pdu.insert(pdu.end(), hidden.begin(), hidden.end());
    t.push_back(framing("function code " + std::to_string(fc) + " hiding an FC16 frame, then a read",
                 {joined({mbap(0x1234, 0x11, pdu), mbap(0x1235, 1, read_pdu(1))})},
                 {mbap(0x1234, 0x11, exception(fc, 0x01)), mbap(0x1235, 1, c::fc3_reply({1.125}))}));
  }
  // 16 requests in one packet, each an FC23 write and read of its own variable.
  {
    FramingCase p = framing("16 requests pipelined in one packet", {}, {});
    std::vector<Bytes> frames;
    for (std::uint16_t i = 0; i < 16; ++i) {
      const auto number = static_cast<std::uint16_t>(1040 + i);
      frames.push_back(mbap(static_cast<std::uint16_t>(0x100 + i), static_cast<std::uint8_t>(i), swap_pdu(number, 7.0 + i)));
      p.replies.push_back(mbap(static_cast<std::uint16_t>(0x100 + i), static_cast<std::uint8_t>(i), swap_reply(7.0 + i)));
      p.changes.push_back(number);
    }
    p.chunks = {joined(frames)};
    t.push_back(p);
  }
  // A frame split at every byte: answered once, when its last byte arrives.
  const Bytes split = mbap(0x0A0B, 3, swap_pdu(1060, -1.5));
  for (std::size_t at = 1; at < split.size(); ++at) {
    t.push_back(framing("an FC23 frame split after byte " + std::to_string(at),
                 {Bytes(split.begin(), split.begin() + static_cast<std::ptrdiff_t>(at)),
                  Bytes(split.begin() + static_cast<std::ptrdiff_t>(at), split.end())},
                 {mbap(0x0A0B, 3, swap_reply(-1.5))},
                 false,
                 {1060}));
  }
  {
    FramingCase bytewise = framing("an FC23 frame sent one byte at a time", {}, {mbap(0x0A0B, 3, swap_reply(-1.5))}, false, {1060});
    for (std::uint8_t b : split) bytewise.chunks.push_back({b});
    t.push_back(bytewise);
  }
  return t;
}

}  // namespace

TEST_CASE("the conformance table holds over Modbus TCP against trueaxis-sim") {
  SimFixture f;
  TcpTransport t(f.port());
  const std::vector<c::Case> cases = c::pdu_cases();
  const c::Outcome out = c::run_cases(t, cases);
  for (const std::string& failure : out.failures) UNSCOPED_INFO(failure);
  CHECK(out.failures.empty());
  CHECK(out.cases == cases.size());
}

TEST_CASE("the TCP framing table: refused frames close and execute nothing, whole frames are answered once") {
  SimFixture f;
  TcpTransport control(f.port());
  // The values the table's reads expect; then the control connection gives the
  // macro interface back (module.hpp contract 8), so each case's connection may write.
  REQUIRE(c::run_cases(control, {c::pdu_cases().front()}).failures.empty());
  {
    Bytes reply;
    std::string failed;
    REQUIRE(control.exchange(c::fc16_values(9009, {0.0}), reply, failed));
    REQUIRE(reply.size() == 5);
    REQUIRE(reply[0] == 0x10);
  }
  const std::vector<FramingCase> cases = framing_cases();
  REQUIRE(cases.size() >= 40);
  std::string why;
  c::State before;
  REQUIRE(c::read_state(control, before, why));
  for (const FramingCase& fc : cases) {
    INFO(fc.name);
    Connection k(f.port());
    for (std::size_t i = 0; i < fc.chunks.size(); ++i) {
      if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      k.send(fc.chunks[i]);
    }
    if (fc.client_closes) k.shutdown_write();
    for (const Bytes& expected : fc.replies) CHECK(c::hex(k.reply()) == c::hex(expected));
    if (fc.closes) {
      CHECK(k.receive(1, 2000).empty());  // nothing more, then the close
      CHECK(k.closed());
    } else {
      CHECK(k.receive(1, 50).empty());  // nothing more
      CHECK_FALSE(k.closed());
    }
    c::State after;
    REQUIRE(c::read_state(control, after, why));
    const auto changed = c::changed_variables(before, after, fc.changes);
    std::string list;
    for (std::uint16_t n : changed) list += " #" + std::to_string(n);
    CHECK(list.empty());
    before.swap(after);
  }
}
