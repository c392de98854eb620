// The RTU framer (modbus::ModbusRtu) over the real module on RAM storage, with a
// clock the test sets: CRC-16/MODBUS against a bitwise reference, the silence
// that cuts frames (at and below 3.5 characters), a frame split at every byte,
// broadcast, another address, a bad CRC, short and over-long frames.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include "alloc_counter.hpp"
#include "crc16_reference.hpp"
#include "fakes.hpp"
#include "split_mix64.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/modbus/modbus_rtu.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

namespace {

namespace m = trueaxis::macros;
namespace var = trueaxis::macros::var;
using Bytes = std::vector<std::uint8_t>;
using trueaxis::test::crc16_bitwise;

constexpr std::uint32_t kBaud = 19200;
constexpr std::uint8_t kSlave = 17;

Bytes with_crc(Bytes frame) {
  const std::uint16_t crc = crc16_bitwise(frame);
  frame.push_back(static_cast<std::uint8_t>(crc));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  return frame;
}

void put16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

Bytes read_frame(std::uint8_t to, std::uint16_t variable, std::uint16_t count = 1) {
  Bytes b = {to, 0x03};
  put16(b, 4u * variable);
  put16(b, 4u * count);
  return with_crc(b);
}

Bytes write_frame(std::uint8_t to, std::uint16_t variable, double value) {
  Bytes b = {to, 0x10};
  put16(b, 4u * variable);
  put16(b, 4);
  b.push_back(8);
  std::uint16_t words[4];
  trueaxis::modbus::encode_double(value, words);
  for (std::uint16_t w : words) put16(b, w);
  return with_crc(b);
}

// The module and the framer, each with its own clock; the framer's is set by
// the test (step 0: it reads what the test put there).
struct Line {
  trueaxis::test::ModuleRig rig;
  m::Module& module = rig.module();
  trueaxis::modbus::ModbusCore core{module};
  trueaxis::test::FakeClock line_clock;
  trueaxis::modbus::ModbusRtu rtu{core, line_clock, kSlave, kBaud};
  std::uint32_t character = trueaxis::modbus::rtu_character_us(kBaud);
  std::uint32_t silence = trueaxis::modbus::rtu_silence_us(kBaud);
  std::uint8_t reply[trueaxis::modbus::kRtuMaxFrameBytes] = {};
  Bytes replies;  // every reply byte sent so far
  int reply_count = 0;

  Line() {
    line_clock.now = 1'000'000;
    line_clock.step = 0;
  }

  void take(std::size_t n) {
    if (n == 0) return;
    ++reply_count;
    replies.insert(replies.end(), reply, reply + n);
  }

  // Bytes back to back on the line (one character apart), the first one
  // `silence_before` microseconds of silence after the previous byte.
  void send(const Bytes& bytes, std::uint64_t silence_before) {
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      line_clock.now += character + (i == 0 ? silence_before : 0);
      take(rtu.receive(bytes[i], reply));
    }
  }

  // The line stays silent for `us` microseconds after the last byte; poll()
  // is asked at the end.
  void quiet(std::uint64_t us) {
    line_clock.now += character + us;
    take(rtu.poll(reply));
  }

  // A whole exchange: the frame, then the silence that ends it.
  Bytes exchange(const Bytes& frame) {
    replies.clear();
    send(frame, silence);
    quiet(silence);
    return replies;
  }
};

}  // namespace

TEST_CASE("CRC-16/MODBUS: the check value, a known frame, and the bitwise reference") {
  const Bytes check = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(trueaxis::modbus::crc16_modbus(check.data(), check.size()) == 0x4B37);
  CHECK(crc16_bitwise(check) == 0x4B37);
  // 01 03 00 00 00 0A is sent with CRC bytes C5 CD.
  const Bytes frame = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A};
  CHECK(trueaxis::modbus::crc16_modbus(frame.data(), frame.size()) == 0xCDC5);
  CHECK(trueaxis::modbus::crc16_modbus(nullptr, 0) == 0xFFFF);
  trueaxis::test::SplitMix64 rng(8);
  for (std::size_t length = 0; length <= 256; ++length) {
    Bytes data(length);
    for (auto& b : data) b = static_cast<std::uint8_t>(rng.next());
    INFO("length " << length);
    CHECK(trueaxis::modbus::crc16_modbus(data.data(), data.size()) == crc16_bitwise(data));
  }
}

TEST_CASE("the silence that ends a frame: 3.5 characters up to 19200 baud, 1750 us above") {
  CHECK(trueaxis::modbus::rtu_character_us(19200) == 573);   // 572.9 us
  CHECK(trueaxis::modbus::rtu_silence_us(19200) == 2006);    // 2005.2 us
  CHECK(trueaxis::modbus::rtu_silence_us(9600) == 4011);     // 4010.4 us
  CHECK(trueaxis::modbus::rtu_silence_us(1200) == 32084);    // 32083.3 us
  CHECK(trueaxis::modbus::rtu_silence_us(19201) == 1750);
  CHECK(trueaxis::modbus::rtu_silence_us(38400) == 1750);
  CHECK(trueaxis::modbus::rtu_silence_us(115200) == 1750);
  // Rounded up, never down: 3.5 characters of 11 bits at 19200 baud.
  CHECK(double(trueaxis::modbus::rtu_silence_us(19200)) >= 3.5 * 11.0 * 1e6 / 19200.0);
  CHECK(double(trueaxis::modbus::rtu_silence_us(19200)) - 1.0 < 3.5 * 11.0 * 1e6 / 19200.0);
}

TEST_CASE("a read of one variable is answered with its four registers") {
  Line l;
  const double one = 1.0;
  REQUIRE(l.module.write(1, 1, &one) == m::AccessFault::kNone);
  const Bytes reply = l.exchange(read_frame(kSlave, 1));
  CHECK(reply == with_crc({kSlave, 0x03, 8, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0}));
  CHECK(l.rtu.counters().served == 1);
}

TEST_CASE("a write is executed and echoed; an unknown function code is exception 01") {
  Line l;
  Bytes reply = l.exchange(write_frame(kSlave, 1, 2.5));
  CHECK(l.module.value(1) == 2.5);
  CHECK(reply == with_crc({kSlave, 0x10, 0, 4, 0, 4}));
  reply = l.exchange(with_crc({kSlave, 0x41, 0, 0, 0, 1}));
  CHECK(reply == with_crc({kSlave, 0xC1, 0x01}));
}

TEST_CASE("poll() ends the frame at a silence of exactly 3.5 characters, not one microsecond before") {
  Line l;
  const Bytes frame = read_frame(kSlave, 1);
  l.send(frame, l.silence);
  l.quiet(l.silence - 1);
  CHECK(l.reply_count == 0);
  l.line_clock.now += 1;  // now exactly 3.5 characters of silence
  l.take(l.rtu.poll(l.reply));
  CHECK(l.reply_count == 1);
  // Asked again, nothing more is due.
  l.quiet(10 * l.silence);
  CHECK(l.reply_count == 1);
}

TEST_CASE("a frame split at every byte by less than 3.5 characters is still one frame") {
  const Bytes frame = write_frame(kSlave, 1, 3.0);
  for (std::size_t k = 1; k < frame.size(); ++k) {
    Line l;
    INFO("split before byte " << k);
    l.send(Bytes(frame.begin(), frame.begin() + static_cast<long>(k)), l.silence);
    l.send(Bytes(frame.begin() + static_cast<long>(k), frame.end()), l.silence - 1);
    CHECK(l.reply_count == 0);
    l.quiet(l.silence);
    CHECK(l.reply_count == 1);
    CHECK(l.module.value(1) == 3.0);
    CHECK(l.replies == with_crc({kSlave, 0x10, 0, 4, 0, 4}));
  }
}

TEST_CASE("a frame split at every byte by exactly 3.5 characters is two frames, both discarded") {
  const Bytes frame = write_frame(kSlave, 1, 3.0);
  for (std::size_t k = 1; k < frame.size(); ++k) {
    Line l;
    INFO("split before byte " << k);
    l.send(Bytes(frame.begin(), frame.begin() + static_cast<long>(k)), l.silence);
    l.send(Bytes(frame.begin() + static_cast<long>(k), frame.end()), l.silence);
    l.quiet(l.silence);
    CHECK(l.reply_count == 0);
    CHECK(l.module.value(1) == 0.0);
    const trueaxis::modbus::RtuCounters& c = l.rtu.counters();
    CHECK(c.bad_crc + c.too_short + c.other_address == 2);
    CHECK(c.served == 0);
  }
}

TEST_CASE("two frames 3.5 characters apart: the second one's first byte closes the first") {
  Line l;
  l.send(write_frame(kSlave, 1, 4.0), l.silence);
  CHECK(l.reply_count == 0);
  l.send(read_frame(kSlave, 1), l.silence);
  CHECK(l.reply_count == 1);  // the write's reply, due when the read began
  CHECK(l.module.value(1) == 4.0);
  l.quiet(l.silence);
  CHECK(l.reply_count == 2);
  Bytes expected = with_crc({kSlave, 0x10, 0, 4, 0, 4});
  const Bytes read = with_crc({kSlave, 0x03, 8, 0x40, 0x10, 0, 0, 0, 0, 0, 0});
  expected.insert(expected.end(), read.begin(), read.end());
  CHECK(l.replies == expected);
}

TEST_CASE("broadcast: a write is executed without a reply, a read is ignored") {
  Line l;
  CHECK(l.exchange(write_frame(trueaxis::modbus::kRtuBroadcast, 1, 5.0)).empty());
  CHECK(l.module.value(1) == 5.0);
  CHECK(l.rtu.counters().broadcasts == 1);
  CHECK(l.exchange(read_frame(trueaxis::modbus::kRtuBroadcast, 1)).empty());
  // FC23 reads too: ignored, its write not executed.
  Bytes fc23 = {trueaxis::modbus::kRtuBroadcast, 0x17, 0, 4, 0, 4, 0, 4, 0, 4, 8, 0x40, 0x20, 0, 0, 0, 0, 0, 0};
  CHECK(l.exchange(with_crc(fc23)).empty());
  CHECK(l.module.value(1) == 5.0);
  CHECK(l.rtu.counters().ignored_reads == 2);
  CHECK(l.rtu.counters().served == 0);
}

TEST_CASE("a frame for another address is discarded silently and not executed") {
  Line l;
  for (std::uint8_t to : {std::uint8_t{1}, std::uint8_t{16}, std::uint8_t{18}, std::uint8_t{247},
                          std::uint8_t{248}, std::uint8_t{255}}) {
    CHECK(l.exchange(write_frame(to, 1, 6.0)).empty());
  }
  CHECK(l.module.value(1) == 0.0);
  CHECK(l.rtu.counters().other_address == 6);
}

TEST_CASE("a frame with a bad CRC is discarded silently and not executed") {
  Line l;
  const Bytes good = write_frame(kSlave, 1, 7.0);
  for (std::size_t i = 0; i < good.size(); ++i) {
    Bytes bad = good;
    bad[i] ^= 0x01;
    INFO("bit 0 of byte " << i << " flipped");
    CHECK(l.exchange(bad).empty());
  }
  CHECK(l.module.value(1) == 0.0);
  // Byte 0 flipped (address 16) is a CRC fault too: the CRC is checked first.
  CHECK(l.rtu.counters().bad_crc == good.size());
  CHECK(l.exchange(good).size() == 8);
  CHECK(l.module.value(1) == 7.0);
}

TEST_CASE("frames shorter than 4 bytes are discarded") {
  Line l;
  CHECK(l.exchange({kSlave}).empty());
  CHECK(l.exchange({kSlave, 0x03}).empty());
  CHECK(l.exchange({kSlave, 0x03, 0x00}).empty());
  CHECK(l.rtu.counters().too_short == 3);
  // Four bytes with a good CRC: a PDU of one byte, exception 03 from the core.
  CHECK(l.exchange(with_crc({kSlave, 0x03})) == with_crc({kSlave, 0x83, 0x03}));
}

TEST_CASE("a 256-byte frame is served; 257 bytes and more are discarded, nothing executed") {
  Line l;
  Bytes longest = {kSlave, 0x41};
  longest.resize(254, 0xAA);  // address + a PDU of 253 bytes
  longest = with_crc(longest);
  REQUIRE(longest.size() == trueaxis::modbus::kRtuMaxFrameBytes);
  CHECK(l.exchange(longest) == with_crc({kSlave, 0xC1, 0x01}));

  // A valid write padded to 257 bytes, then with its own CRC at the end.
  Bytes over = write_frame(kSlave, 1, 8.0);
  over.resize(255, 0x00);
  over = with_crc(over);
  REQUIRE(over.size() == 257);
  CHECK(l.exchange(over).empty());
  Bytes far_over(1000, 0x55);
  CHECK(l.exchange(far_over).empty());
  CHECK(l.rtu.counters().too_long == 2);
  CHECK(l.module.value(1) == 0.0);
  // The framer has recovered: the next frame is served.
  CHECK(l.exchange(write_frame(kSlave, 1, 9.0)).size() == 8);
  CHECK(l.module.value(1) == 9.0);
}

TEST_CASE("macro 9810 through the handshake over RTU") {
  Line l;
  const double p[3][3] = {{0.0, 0.0, 0.0}, {100.0, 0.0, 0.0}, {0.0, 86.602540378443865, 50.0}};
  const std::uint16_t at[3] = {var::kG57, var::kG58, var::kG59};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) REQUIRE(l.exchange(write_frame(kSlave, std::uint16_t(at[i] + k), p[i][k])).size() == 8);
  }
  REQUIRE(l.exchange(write_frame(kSlave, var::kCmd, 9810.0)).size() == 8);
  for (int i = 0; i < 100000 && l.module.busy(); ++i) l.module.step();
  const Bytes status = l.exchange(read_frame(kSlave, var::kStatus, 4));
  REQUIRE(status.size() == 3 + 2 + 32);
  std::uint16_t words[16];
  for (std::size_t i = 0; i < 16; ++i) words[i] = static_cast<std::uint16_t>((status[3 + 2 * i] << 8) | status[4 + 2 * i]);
  CHECK(trueaxis::modbus::decode_double(words) == 2.0);       // done
  CHECK(trueaxis::modbus::decode_double(words + 4) == 0.0);   // no error
  CHECK(trueaxis::modbus::decode_double(words + 8) == 1.0);   // done_count
  CHECK(l.module.value(107) == Approx(30.0).margin(1e-9));  // tilt of the face: atan(50/86.6)
}

TEST_CASE("the slave address is 1..247") {
  Line l;
  CHECK_FALSE(l.rtu.set_address(0));
  CHECK_FALSE(l.rtu.set_address(248));
  CHECK(l.rtu.address() == kSlave);
  CHECK(l.rtu.set_address(247));
  CHECK(l.exchange(read_frame(247, 1)).size() == 13);
  CHECK(l.exchange(read_frame(kSlave, 1)).empty());
  trueaxis::modbus::ModbusRtu zero{l.core, l.line_clock, 0, kBaud};
  CHECK(zero.address() == 1);
}

TEST_CASE("the framer allocates nothing") {
  Line l;
  const Bytes write = write_frame(kSlave, 1, 1.5);
  const Bytes read = read_frame(kSlave, 1);
  l.replies.reserve(4096);
  trueaxis::test::AllocationScope scope;
  for (int i = 0; i < 10; ++i) {
    l.send(write, l.silence);
    l.send(read, l.silence);
    l.quiet(l.silence);
  }
  CHECK(scope.count() == 0);
  CHECK(l.rtu.counters().served == 20);
}
