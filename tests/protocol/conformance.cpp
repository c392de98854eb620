#include "conformance.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::conformance {

namespace {

constexpr std::uint8_t kIllegalFunction = 0x01;
constexpr std::uint8_t kIllegalAddress = 0x02;
constexpr std::uint8_t kIllegalValue = 0x03;

// The variables this table reads and writes (docs/INTERFACE.md and the map).
constexpr std::uint16_t kFirstArg = 1;        // #1..#9: arguments A B C I J K D E F
constexpr std::uint16_t kArgCount = 9;        // #10 (G) is not defined
constexpr std::uint16_t kFirstPoint = 1001;   // #1001..#1096: level points
constexpr std::uint16_t kFirstResult = 100;   // read-only
constexpr std::uint16_t kFirstConfig = 500;   // a_min: configuration, locked
constexpr std::uint16_t kAccessFault = 9007;  // notes refusals by design
constexpr std::uint16_t kInterface = 9009;     // the macro interface's grant, as the asking client sees it
constexpr std::uint16_t kFailedUnlocks = 9010;
constexpr std::uint16_t kBackoffLeft = 9011;   // notes refusals (a wrong unlock code) and runs down with time
constexpr std::uint16_t kLastVariable = 9059;  // the last the product's map defines (#9059, the log's last figure value)
constexpr double kArgLimit = 100000.0;         // |#1| allowed (the map's range)

std::uint32_t reg(std::uint16_t variable) { return 4u * variable; }

double arg_value(std::uint16_t n) { return n + 0.125; }
double point_value(std::uint16_t i) { return -500.0 + 0.5 * i; }  // #1001 + i

std::vector<double> arg_values() {
  std::vector<double> v;
  for (std::uint16_t n = 0; n < kArgCount; ++n) v.push_back(arg_value(kFirstArg + n));
  return v;
}

std::vector<double> point_values(std::uint16_t count, double shift = 0.0) {
  std::vector<double> v;
  for (std::uint16_t i = 0; i < count; ++i) v.push_back(point_value(i) + shift);
  return v;
}

std::vector<std::uint16_t> numbers(std::uint16_t first, std::uint16_t count) {
  std::vector<std::uint16_t> n;
  for (std::uint16_t i = 0; i < count; ++i) n.push_back(static_cast<std::uint16_t>(first + i));
  return n;
}

Bytes exception(std::uint8_t fc, std::uint8_t code) { return {static_cast<std::uint8_t>(fc | 0x80), code}; }

// FC16 as given: | 0x10 | address | quantity | byte count | data |.
Bytes fc16_raw(std::uint32_t address, std::uint32_t quantity, std::uint32_t byte_count, const Bytes& data) {
  Bytes b = {0x10};
  put16(b, address);
  put16(b, quantity);
  b.push_back(static_cast<std::uint8_t>(byte_count));
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

// `n` data bytes of the value 2.0 repeated (0x4000 0 0 0 per variable).
Bytes twos(std::size_t n) {
  Bytes b;
  for (std::size_t i = 0; i < n; ++i) b.push_back(i % 8 == 0 ? 0x40 : 0x00);
  return b;
}

Bytes fc16_echo(std::uint32_t address, std::uint32_t quantity) {
  Bytes b = {0x10};
  put16(b, address);
  put16(b, quantity);
  return b;
}

// FC23 as given: | 0x17 | read address | read quantity | write address |
// write quantity | byte count | data |.
Bytes fc23_raw(std::uint32_t read_address, std::uint32_t read_quantity, std::uint32_t write_address,
               std::uint32_t write_quantity, std::uint32_t byte_count, const Bytes& data) {
  Bytes b = {0x17};
  put16(b, read_address);
  put16(b, read_quantity);
  put16(b, write_address);
  put16(b, write_quantity);
  b.push_back(static_cast<std::uint8_t>(byte_count));
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

Bytes values_data(const std::vector<double>& values) {
  Bytes b;
  for (double v : values) {
    const Bytes one = value_bytes(v);
    b.insert(b.end(), one.begin(), one.end());
  }
  return b;
}

Bytes fc23_reply(const std::vector<double>& values) {
  Bytes b = fc3_reply(values);
  b[0] = 0x17;
  return b;
}

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

// Every function code with the body of an FC3 read of #1: 3 is answered, the
// others refused by their own rules.
void function_codes(std::vector<Case>& t) {
  for (int fc = 0; fc <= 255; ++fc) {
    const auto code = static_cast<std::uint8_t>(fc);
    Case c;
    c.name = "function code " + std::to_string(fc);
    c.pdu = {code};
    put16(c.pdu, reg(kFirstArg));
    put16(c.pdu, 4);
    switch (fc) {
      case 0x03: c.reply = fc3_reply({arg_value(kFirstArg)}); break;
      case 0x06: c.reply = exception(code, kIllegalAddress); break;  // one register is never a variable
      case 0x10:                                                     // no byte count: too short
      case 0x17: c.reply = exception(code, kIllegalValue); break;    // too short
      default: c.reply = exception(code, kIllegalFunction); break;
    }
    t.push_back(c);
  }
}

void read_holding(std::vector<Case>& t) {
  const auto points = point_values(31);
  const std::uint32_t arg = reg(kFirstArg);
  t.push_back({"FC3 quantity 0", fc3(arg, 0), exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 quantity 1 (part of a variable)", fc3(arg, 1), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 quantity 4 (one variable)", fc3(arg, 4), fc3_reply({arg_value(kFirstArg)}), {}});
  t.push_back({"FC3 quantity 124 (31 variables)", fc3(reg(kFirstPoint), 124), fc3_reply(points), {}});
  t.push_back({"FC3 quantity 125 (the maximum, not whole variables)", fc3(reg(kFirstPoint), 125),
               exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 quantity 126 (maximum + 1)", fc3(reg(kFirstPoint), 126), exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 quantity 0xFFFF", fc3(arg, 0xFFFF), exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 quantity 0 at an undefined address (quantity first)", fc3(0, 0), exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 quantity 126 past 0xFFFF (quantity first)", fc3(0xFFF0, 126), exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 register 0 (below the map)", fc3(0, 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 2 (inside no variable's start)", fc3(2, 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 5 (misaligned)", fc3(reg(kFirstArg) + 1, 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 #1..#9 (the first variables of the map)", fc3(arg, 4 * kArgCount), fc3_reply(arg_values()), {}});
  t.push_back({"FC3 #9..#10 (runs into an undefined number)", fc3(reg(9), 8), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 #9059 (the last variable)", fc3(reg(kLastVariable), 4), fc3_reply({0.0}), {}});
  t.push_back({"FC3 #9059..#9060 (runs past the map)", fc3(reg(kLastVariable), 8), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 #9060 (after the map)", fc3(reg(kLastVariable + 1), 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 #12063 (after the simulator's variables)", fc3(reg(12063), 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 0xFFFC (the last whole variable)", fc3(0xFFFC, 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 0xFFFF quantity 1 (ends at 0xFFFF)", fc3(0xFFFF, 1), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 0xFFFD quantity 4 (past 0xFFFF)", fc3(0xFFFD, 4), exception(0x03, kIllegalAddress), {}});
  t.push_back({"FC3 register 0xFF84 quantity 125 (past 0xFFFF by 1)", fc3(0xFF84, 125), exception(0x03, kIllegalAddress), {}});
  Bytes truncated = fc3(arg, 4);
  truncated.pop_back();
  t.push_back({"FC3 truncated (4 bytes)", truncated, exception(0x03, kIllegalValue), {}});
  t.push_back({"FC3 function code alone", {0x03}, exception(0x03, kIllegalValue), {}});
  Bytes over_long = fc3(arg, 4);
  over_long.push_back(0);
  t.push_back({"FC3 over-long (6 bytes)", over_long, exception(0x03, kIllegalValue), {}});
}

void write_multiple(std::vector<Case>& t) {
  const std::uint32_t arg = reg(kFirstArg);
  const std::uint32_t points = reg(kFirstPoint);
  t.push_back({"FC16 quantity 0, byte count 0", fc16_raw(arg, 0, 0, {}), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 quantity 1 (part of a variable)", fc16_raw(arg, 1, 2, twos(2)), exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 quantity 4 (one variable)", fc16_values(kFirstArg, {-7.5}), fc16_echo(arg, 4), {kFirstArg}});
  t.push_back({"FC16 quantity 4 again (the value the table expects)", fc16_values(kFirstArg, {arg_value(kFirstArg)}),
               fc16_echo(arg, 4), {kFirstArg}});
  t.push_back({"FC16 quantity 120 (30 variables)", fc16_values(kFirstPoint, point_values(30, 1.0)),
               fc16_echo(points, 120), numbers(kFirstPoint, 30)});
  t.push_back({"FC3 reads the 30 variables written", fc3(points, 120), fc3_reply(point_values(30, 1.0)), {}});
  t.push_back({"FC16 quantity 120 back (the values the table expects)", fc16_values(kFirstPoint, point_values(30)),
               fc16_echo(points, 120), numbers(kFirstPoint, 30)});
  t.push_back({"FC16 quantity 123 (the maximum, not whole variables)", fc16_raw(points, 123, 246, twos(246)),
               exception(0x10, kIllegalAddress), {}});
  // A whole FC16 of 124 registers would be a 254-byte PDU, more than any frame
  // carries: the quantity alone decides (03), whatever follows.
  t.push_back({"FC16 quantity 124 (maximum + 1)", fc16_raw(points, 124, 248, twos(246)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 quantity 0xFFFF", fc16_raw(points, 0xFFFF, 254, twos(8)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count one short", fc16_raw(arg, 4, 7, twos(8)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count one over", fc16_raw(arg, 4, 9, twos(8)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count one over, with its byte", fc16_raw(arg, 4, 9, twos(9)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count one short, with its bytes", fc16_raw(arg, 4, 7, twos(7)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count 6 with its 6 bytes", fc16_raw(arg, 4, 6, twos(6)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 byte count 0 with quantity 4", fc16_raw(arg, 4, 0, {}), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 data one byte short (truncated)", fc16_raw(arg, 4, 8, twos(7)), exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 data one byte over (over-long)", fc16_raw(arg, 4, 8, twos(9)), exception(0x10, kIllegalValue), {}});
  Bytes header_only = fc16_raw(arg, 4, 8, {});
  header_only.pop_back();
  t.push_back({"FC16 without its byte count", header_only, exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 quantity 0 at register 0xFFFF (quantity first)", fc16_raw(0xFFFF, 0, 0, {}),
               exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 register 0 (below the map)", fc16_raw(0, 4, 8, twos(8)), exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 register 5 (misaligned)", fc16_raw(arg + 1, 4, 8, twos(8)), exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 #9..#10 (runs into an undefined number)", fc16_raw(reg(9), 8, 16, twos(16)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 #9060 (after the map)", fc16_raw(reg(kLastVariable + 1), 4, 8, twos(8)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 register 0xFFFC (the last whole variable)", fc16_raw(0xFFFC, 4, 8, twos(8)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 register 0xFFFE quantity 4 (past 0xFFFF)", fc16_raw(0xFFFE, 4, 8, twos(8)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 register 0xFF88 quantity 120 (ends at 0xFFFF)", fc16_raw(0xFF88, 120, 240, twos(240)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 register 0xFF89 quantity 120 (past 0xFFFF by 1)", fc16_raw(0xFF89, 120, 240, twos(240)),
               exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 a read-only result", fc16_raw(reg(kFirstResult), 4, 8, twos(8)), exception(0x10, kIllegalAddress), {}});
  t.push_back({"FC16 the configuration while locked", fc16_values(kFirstConfig, {-10.0}), exception(0x10, kIllegalAddress), {}});
  Bytes nan = fc16_raw(arg, 4, 8, {0x7F, 0xF8, 0, 0, 0, 0, 0, 0});
  t.push_back({"FC16 a NaN", nan, exception(0x10, kIllegalValue), {}});
  Bytes inf = fc16_raw(arg, 4, 8, {0x7F, 0xF0, 0, 0, 0, 0, 0, 0});
  t.push_back({"FC16 an infinity", inf, exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 a value just past the variable's range", fc16_values(kFirstArg, {kArgLimit * (1.0 + 1e-15)}),
               exception(0x10, kIllegalValue), {}});
  t.push_back({"FC16 the variable's limit", fc16_values(kFirstArg, {kArgLimit}), fc16_echo(arg, 4), {kFirstArg}});
  t.push_back({"FC16 #1 back", fc16_values(kFirstArg, {arg_value(kFirstArg)}), fc16_echo(arg, 4), {kFirstArg}});
  std::vector<double> last_bad = arg_values();
  last_bad.back() = 2 * kArgLimit;
  t.push_back({"FC16 nine variables, the last out of range (whole or nothing)", fc16_values(kFirstArg, last_bad),
               exception(0x10, kIllegalValue), {}});
}

void write_single(std::vector<Case>& t) {
  Bytes five = {0x06};
  put16(five, reg(kFirstArg));
  put16(five, 0x4000);
  t.push_back({"FC6 one register of #1", five, exception(0x06, kIllegalAddress), {}});
  Bytes four(five.begin(), five.end() - 1);
  t.push_back({"FC6 truncated", four, exception(0x06, kIllegalValue), {}});
  Bytes six = five;
  six.push_back(0);
  t.push_back({"FC6 over-long", six, exception(0x06, kIllegalValue), {}});
}

void read_write_multiple(std::vector<Case>& t) {
  const std::uint32_t arg = reg(kFirstArg);
  const std::uint32_t points = reg(kFirstPoint);
  const Bytes one = values_data({-3.5});
  t.push_back({"FC23 write #2, read #1..#2", fc23_raw(arg, 8, reg(2), 4, 8, values_data({-3.5})),
               fc23_reply({arg_value(1), -3.5}), {2}});
  t.push_back({"FC23 write #2 back, read it", fc23_raw(reg(2), 4, reg(2), 4, 8, values_data({arg_value(2)})),
               fc23_reply({arg_value(2)}), {2}});
  t.push_back({"FC23 read 124 (31 variables), write 120 (30)",
               fc23_raw(points, 124, points, 120, 240, values_data(point_values(30, 2.0))),
               [&] {
                 std::vector<double> v = point_values(30, 2.0);
                 v.push_back(point_value(30));
                 return fc23_reply(v);
               }(),
               numbers(kFirstPoint, 30)});
  t.push_back({"FC23 write the points back", fc23_raw(points, 4, points, 120, 240, values_data(point_values(30))),
               fc23_reply({point_value(0)}), numbers(kFirstPoint, 30)});
  t.push_back({"FC23 read quantity 0", fc23_raw(arg, 0, arg, 4, 8, one), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 read quantity 1", fc23_raw(arg, 1, arg, 4, 8, one), exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 read quantity 125 (the maximum, not whole variables)", fc23_raw(points, 125, arg, 4, 8, one),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 read quantity 126 (maximum + 1)", fc23_raw(points, 126, arg, 4, 8, one), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 write quantity 0", fc23_raw(arg, 4, arg, 0, 0, {}), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 write quantity 1", fc23_raw(arg, 4, arg, 1, 2, twos(2)), exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write quantity 121 (the maximum, not whole variables)", fc23_raw(arg, 4, points, 121, 242, twos(242)),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write quantity 122 (maximum + 1)", fc23_raw(arg, 4, points, 122, 244, twos(242)),
               exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count one short", fc23_raw(arg, 4, arg, 4, 7, twos(8)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count one over", fc23_raw(arg, 4, arg, 4, 9, twos(8)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count one over, with its byte", fc23_raw(arg, 4, arg, 4, 9, twos(9)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count one short, with its bytes", fc23_raw(arg, 4, arg, 4, 7, twos(7)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count 0 with write quantity 4", fc23_raw(arg, 4, arg, 4, 0, {}), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 byte count 6 with its 6 bytes", fc23_raw(arg, 4, arg, 4, 6, twos(6)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 data one byte short (truncated)", fc23_raw(arg, 4, arg, 4, 8, twos(7)), exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 data one byte over (over-long)", fc23_raw(arg, 4, arg, 4, 8, twos(9)), exception(0x17, kIllegalValue), {}});
  Bytes nine = fc23_raw(arg, 4, arg, 4, 8, {});
  nine.pop_back();
  t.push_back({"FC23 without its byte count", nine, exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 read below the map (the write is not done)", fc23_raw(0, 4, reg(2), 4, 8, values_data({9.0})),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 read past 0xFFFF (the write is not done)", fc23_raw(0xFFFE, 4, reg(2), 4, 8, values_data({9.0})),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write past 0xFFFF", fc23_raw(arg, 4, 0xFFFE, 4, 8, twos(8)), exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write a read-only result", fc23_raw(arg, 4, reg(kFirstResult), 4, 8, twos(8)),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write the configuration while locked", fc23_raw(arg, 4, reg(kFirstConfig), 4, 8, values_data({-10.0})),
               exception(0x17, kIllegalAddress), {}});
  t.push_back({"FC23 write a NaN", fc23_raw(arg, 4, arg, 4, 8, {0x7F, 0xF8, 0, 0, 0, 0, 0, 0}),
               exception(0x17, kIllegalValue), {}});
  t.push_back({"FC23 read and write #1 after all", fc23_raw(arg, 4, arg, 4, 8, values_data({arg_value(1)})),
               fc23_reply({arg_value(1)}), {kFirstArg}});
}

}  // namespace

std::string hex(const Bytes& b) {
  std::string s;
  char two[4];
  for (std::size_t i = 0; i < b.size(); ++i) {
    std::snprintf(two, sizeof two, "%02x", b[i]);
    if (i > 0) s += ' ';
    if (i == 24 && b.size() > 32) {
      s += "... (" + std::to_string(b.size()) + " bytes)";
      break;
    }
    s += two;
  }
  return s;
}

void put16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

Bytes value_bytes(double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  Bytes b;
  for (int shift = 56; shift >= 0; shift -= 8) b.push_back(static_cast<std::uint8_t>(bits >> shift));
  return b;
}

Bytes fc3(std::uint32_t address, std::uint32_t quantity) {
  Bytes b = {0x03};
  put16(b, address);
  put16(b, quantity);
  return b;
}

Bytes fc16_values(std::uint16_t first, const std::vector<double>& values) {
  const auto quantity = static_cast<std::uint32_t>(4 * values.size());
  return fc16_raw(reg(first), quantity, 2 * quantity, values_data(values));
}

Bytes fc3_reply(const std::vector<double>& values) {
  Bytes b = {0x03, static_cast<std::uint8_t>(8 * values.size())};
  const Bytes data = values_data(values);
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

const std::vector<Run>& state_runs() {
  static const std::vector<Run> runs = [] {
    std::vector<std::uint16_t> all;
    for (const auto& v : macros::kRegisterMap) {
      for (std::uint16_t i = 0; i < v.count; ++i) {
        const auto n = static_cast<std::uint16_t>(v.number + i);
        if (n != kAccessFault && n != kFailedUnlocks && n != kInterface && n != kBackoffLeft) all.push_back(n);
      }
    }
    std::vector<Run> out;
    for (std::uint16_t n : all) {
      if (!out.empty() && out.back().first + out.back().count == n && out.back().count < 31) {
        ++out.back().count;
      } else {
        out.push_back({n, 1});
      }
    }
    return out;
  }();
  return runs;
}

const std::vector<Run>& addressed_runs() {
  static const std::vector<Run> runs = {{kFirstArg, kArgCount}, {kFirstResult, 31}, {kFirstConfig, 9}, {kFirstPoint, 31}, {9000, 7}};
  return runs;
}

bool read_state(Transport& t, State& state, std::string& why, const std::vector<Run>& runs) {
  state.clear();
  for (const Run& r : runs) {
    Bytes reply;
    if (!t.exchange(fc3(reg(r.first), 4u * r.count), reply, why)) {
      why = "reading #" + std::to_string(r.first) + " x" + std::to_string(r.count) + ": " + why;
      return false;
    }
    if (reply.size() != 2u + 8u * r.count || reply[0] != 0x03 || reply[1] != 8u * r.count) {
      why = "reading #" + std::to_string(r.first) + " x" + std::to_string(r.count) + ": reply " + hex(reply);
      return false;
    }
    for (std::size_t i = 0; i < 4u * r.count; ++i) state.push_back(be16(reply.data() + 2 + 2 * i));
  }
  return true;
}

std::vector<std::uint16_t> changed_variables(const State& before, const State& after,
                                             const std::vector<std::uint16_t>& allowed, const std::vector<Run>& runs) {
  std::vector<std::uint16_t> changed;
  std::size_t at = 0;
  for (const Run& r : runs) {
    for (std::uint16_t i = 0; i < r.count; ++i, at += 4) {
      const auto n = static_cast<std::uint16_t>(r.first + i);
      if (std::find(allowed.begin(), allowed.end(), n) != allowed.end()) continue;
      if (at + 4 > before.size() || at + 4 > after.size() ||
          !std::equal(before.begin() + static_cast<std::ptrdiff_t>(at), before.begin() + static_cast<std::ptrdiff_t>(at + 4),
                      after.begin() + static_cast<std::ptrdiff_t>(at))) {
        changed.push_back(n);
      }
    }
  }
  return changed;
}

std::vector<Case> pdu_cases() {
  std::vector<Case> t;
  // The values every later case expects.
  t.push_back({"set #1..#9 (FC16, 9 variables)", fc16_values(kFirstArg, arg_values()), fc16_echo(reg(kFirstArg), 36),
               numbers(kFirstArg, kArgCount)});
  t.push_back({"set #1001..#1030 (FC16, 30 variables)", fc16_values(kFirstPoint, point_values(30)),
               fc16_echo(reg(kFirstPoint), 120), numbers(kFirstPoint, 30)});
  t.push_back({"set #1031", fc16_values(kFirstPoint + 30, {point_value(30)}), fc16_echo(reg(kFirstPoint + 30), 4),
               {static_cast<std::uint16_t>(kFirstPoint + 30)}});
  function_codes(t);
  read_holding(t);
  write_multiple(t);
  write_single(t);
  read_write_multiple(t);
  return t;
}

namespace {

std::string listed(const std::vector<std::uint16_t>& numbers) {
  std::string list;
  for (std::uint16_t n : numbers) list += " #" + std::to_string(n);
  return list;
}

}  // namespace

Outcome run_cases(Transport& t, const std::vector<Case>& cases, std::size_t full_every) {
  Outcome out;
  const std::vector<Run>& around = full_every > 0 ? addressed_runs() : state_runs();
  State before;
  State after;
  State whole_before;
  std::vector<std::uint16_t> since_whole;  // what the cases since the last whole read may change
  std::string why;
  if (!read_state(t, before, why, around) || (full_every > 0 && !read_state(t, whole_before, why))) {
    out.failures.push_back("the state before the first case: " + why);
    return out;
  }
  for (const Case& c : cases) {
    ++out.cases;
    Bytes reply;
    if (!t.exchange(c.pdu, reply, why)) {
      out.failures.push_back(c.name + ": no reply (" + why + ")");
    } else if (reply != c.reply) {
      out.failures.push_back(c.name + ": reply " + hex(reply) + ", expected " + hex(c.reply));
    }
    if (!read_state(t, after, why, around)) {
      out.failures.push_back(c.name + ": the state after it: " + why);
      return out;
    }
    const auto changed = changed_variables(before, after, c.changes, around);
    if (!changed.empty()) out.failures.push_back(c.name + ": changed" + listed(changed));
    before.swap(after);
    if (full_every == 0) continue;
    since_whole.insert(since_whole.end(), c.changes.begin(), c.changes.end());
    if (out.cases % full_every != 0 && out.cases != cases.size()) continue;
    State whole_after;
    if (!read_state(t, whole_after, why)) {
      out.failures.push_back(c.name + ": the whole state after it: " + why);
      return out;
    }
    const auto changed_whole = changed_variables(whole_before, whole_after, since_whole);
    if (!changed_whole.empty()) {
      out.failures.push_back("the " + std::to_string(full_every) + " cases up to " + c.name + ": changed" +
                             listed(changed_whole));
    }
    whole_before.swap(whole_after);
    since_whole.clear();
  }
  return out;
}

}  // namespace trueaxis::conformance
