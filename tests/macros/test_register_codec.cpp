#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <limits>
#include <utility>

#include "trueaxis/modbus/register_codec.hpp"

namespace m = trueaxis::macros;

namespace {

// A VariableAccess that records what reached it.
class Recorder final : public m::VariableAccess {
 public:
  std::uint16_t first = 0;
  std::uint16_t count = 0;
  std::array<double, 64> values{};
  m::AccessFault last_fault = m::AccessFault::kNone;

 private:
  m::AccessFault do_read(std::uint16_t f, std::uint16_t n, double* out) override {
    first = f;
    count = n;
    for (std::uint16_t i = 0; i < n; ++i) out[i] = 1.0 + i;
    return m::AccessFault::kNone;
  }
  m::AccessFault do_write(std::uint16_t f, std::uint16_t n, const double* in) override {
    first = f;
    count = n;
    for (std::uint16_t i = 0; i < n; ++i) values[i] = in[i];
    return m::AccessFault::kNone;
  }
  void do_note_fault(m::AccessFault f) override { last_fault = f; }
};

}  // namespace

TEST_CASE("encodes #100 = 1.0 as 0x3FF0 0 0 0 at registers 400..403", "[codec]") {
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(1.0, w);
  CHECK(w[0] == 0x3FF0);
  CHECK(w[1] == 0);
  CHECK(w[2] == 0);
  CHECK(w[3] == 0);
  CHECK(trueaxis::modbus::register_of(100) == 400);
}

TEST_CASE("puts the most significant 16 bits first", "[codec]") {
  const double v = -123.456e-7;
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(v, w);
  CHECK(w[0] == static_cast<std::uint16_t>(bits >> 48));
  CHECK(w[3] == static_cast<std::uint16_t>(bits & 0xFFFF));
  CHECK(trueaxis::modbus::decode_double(w) == v);
}

TEST_CASE("round-trips every bit pattern class", "[codec]") {
  for (double v : {0.0, -0.0, 1e-310, std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                   3.141592653589793}) {
    std::uint16_t w[4];
    trueaxis::modbus::encode_double(v, w);
    const double back = trueaxis::modbus::decode_double(w);
    CHECK(std::memcmp(&back, &v, sizeof v) == 0);
  }
}

TEST_CASE("refuses ranges that are not whole variables", "[codec]") {
  Recorder r;
  std::array<std::uint16_t, 128> words{};
  CHECK(trueaxis::modbus::read_registers(r, 401, 4, words.data()) == m::AccessFault::kMisaligned);
  CHECK(r.last_fault == m::AccessFault::kMisaligned);
  CHECK(trueaxis::modbus::read_registers(r, 400, 3, words.data()) == m::AccessFault::kMisaligned);
  CHECK(trueaxis::modbus::read_registers(r, 400, 0, words.data()) == m::AccessFault::kMisaligned);
  CHECK(trueaxis::modbus::write_registers(r, 402, 4, words.data()) == m::AccessFault::kMisaligned);
  CHECK(trueaxis::modbus::write_registers(r, 400, 6, words.data()) == m::AccessFault::kMisaligned);
  CHECK(trueaxis::modbus::read_registers(r, 400, 128, words.data()) == m::AccessFault::kMisaligned);  // 32 variables
  CHECK(r.count == 0);
}

TEST_CASE("maps whole-variable ranges to variable numbers", "[codec]") {
  Recorder r;
  std::array<std::uint16_t, 124> words{};
  CHECK(trueaxis::modbus::read_registers(r, 4 * 5281, 12, words.data()) == m::AccessFault::kNone);
  CHECK(r.first == 5281);
  CHECK(r.count == 3);
  CHECK(trueaxis::modbus::decode_double(&words[8]) == 3.0);
  CHECK(trueaxis::modbus::read_registers(r, 0, 124, words.data()) == m::AccessFault::kNone);
  CHECK(r.count == 31);
  trueaxis::modbus::encode_double(2.5, &words[4]);
  CHECK(trueaxis::modbus::write_registers(r, 4 * 9000, 8, words.data()) == m::AccessFault::kNone);
  CHECK(r.first == 9000);
  CHECK(r.values[1] == 2.5);
}

TEST_CASE("each access fault maps to its Modbus exception", "[codec]") {
  using F = m::AccessFault;
  using E = m::ModbusException;
  CHECK(m::modbus_exception(F::kUndefined) == E::kIllegalDataAddress);
  CHECK(m::modbus_exception(F::kMisaligned) == E::kIllegalDataAddress);
  CHECK(m::modbus_exception(F::kReadOnly) == E::kIllegalDataAddress);
  CHECK(m::modbus_exception(F::kLocked) == E::kIllegalDataAddress);
  CHECK(m::modbus_exception(F::kNotFinite) == E::kIllegalDataValue);
  CHECK(m::modbus_exception(F::kOutOfRange) == E::kIllegalDataValue);
  CHECK(m::modbus_exception(F::kBadUnlockCode) == E::kIllegalDataValue);
  CHECK(m::modbus_exception(F::kBusy) == E::kServerDeviceBusy);
  CHECK(m::modbus_exception(F::kStorageFailure) == E::kServerDeviceFailure);
  CHECK(m::modbus_exception(F::kBadFunction) == E::kIllegalFunction);
  CHECK(m::modbus_exception(F::kNone) == E::kNone);
}

TEST_CASE("the Modbus exceptions carry the codes of the Modbus specification on the wire", "[codec]") {
  using F = m::AccessFault;
  using E = m::ModbusException;
  // Modbus Application Protocol V1.1b3, section 7: 01 illegal function, 02 illegal
  // data address, 03 illegal data value, 04 server device failure, 06 busy.
  CHECK(static_cast<int>(E::kNone) == 0);
  CHECK(static_cast<int>(E::kIllegalFunction) == 1);
  CHECK(static_cast<int>(E::kIllegalDataAddress) == 2);
  CHECK(static_cast<int>(E::kIllegalDataValue) == 3);
  CHECK(static_cast<int>(E::kServerDeviceFailure) == 4);
  CHECK(static_cast<int>(E::kServerDeviceBusy) == 6);
  // Every fault, as the byte a client receives (var_info.hpp's table).
  const std::pair<F, int> wire[] = {{F::kNone, 0},       {F::kUndefined, 2},      {F::kMisaligned, 2},
                                    {F::kReadOnly, 2},   {F::kLocked, 2},         {F::kNotFinite, 3},
                                    {F::kOutOfRange, 3}, {F::kBadUnlockCode, 3},  {F::kBusy, 6},
                                    {F::kStorageFailure, 4}, {F::kBadFunction, 1}, {F::kUnlockBackoff, 6}};
  for (const auto& [fault, code] : wire) {
    INFO("fault " << static_cast<int>(fault));
    CHECK(static_cast<int>(m::modbus_exception(fault)) == code);
  }
  CHECK(sizeof wire / sizeof wire[0] == static_cast<std::size_t>(F::kUnlockBackoff) + 1);  // every fault listed
}
