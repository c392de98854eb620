// The register codec (modbus/register_codec.hpp), on the host and on the
// Cortex-M7: a variable's double as four registers, most significant first;
// only whole-variable ranges reach the variables; every access fault as the
// Modbus exception code a client receives.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "portable_test.hpp"
#include "trueaxis/modbus/register_codec.hpp"

namespace {

namespace m = trueaxis::macros;

// A VariableAccess that records what reached it.
class Recorder final : public m::VariableAccess {
 public:
  std::uint16_t first = 0;
  std::uint16_t count = 0;
  double values[64] = {};
  m::AccessFault last_fault = m::AccessFault::kNone;

 private:
  m::AccessFault do_read(std::uint16_t f, std::uint16_t n, double* out, m::ClientId) override {
    first = f;
    count = n;
    for (std::uint16_t i = 0; i < n; ++i) out[i] = 1.0 + i;
    return m::AccessFault::kNone;
  }
  m::AccessFault do_write(std::uint16_t f, std::uint16_t n, const double* in, m::ClientId) override {
    first = f;
    count = n;
    for (std::uint16_t i = 0; i < n; ++i) values[i] = in[i];
    return m::AccessFault::kNone;
  }
  void do_note_fault(m::AccessFault f) override { last_fault = f; }
};

}  // namespace

TA_TEST("codec: encodes #100 = 1.0 as 0x3FF0 0 0 0 at registers 400..403") {
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(1.0, w);
  TA_CHECK_EQ(w[0], 0x3FF0);
  TA_CHECK_EQ(w[1], 0);
  TA_CHECK_EQ(w[2], 0);
  TA_CHECK_EQ(w[3], 0);
  TA_CHECK_EQ(trueaxis::modbus::register_of(100), 400u);
}

TA_TEST("codec: puts the most significant 16 bits first") {
  const double v = -123.456e-7;
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(v, w);
  TA_CHECK_EQ(w[0], static_cast<std::uint16_t>(bits >> 48));
  TA_CHECK_EQ(w[3], static_cast<std::uint16_t>(bits & 0xFFFF));
  TA_CHECK_EQ(trueaxis::modbus::decode_double(w), v);
}

TA_TEST("codec: round-trips every bit pattern class") {
  const double values[] = {0.0, -0.0, 1e-310, std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::infinity(), 3.141592653589793};
  for (std::size_t i = 0; i < sizeof values / sizeof values[0]; ++i) {
    TA_CASE_INDEX(i);
    const double v = values[i];
    std::uint16_t w[4];
    trueaxis::modbus::encode_double(v, w);
    const double back = trueaxis::modbus::decode_double(w);
    TA_CHECK(std::memcmp(&back, &v, sizeof v) == 0);
  }
}

TA_TEST("codec: refuses ranges that are not whole variables") {
  Recorder r;
  std::uint16_t words[128] = {};
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 401, 4, words), m::AccessFault::kMisaligned);
  TA_CHECK_EQ(r.last_fault, m::AccessFault::kMisaligned);
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 400, 3, words), m::AccessFault::kMisaligned);
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 400, 0, words), m::AccessFault::kMisaligned);
  TA_CHECK_EQ(trueaxis::modbus::write_registers(r, 402, 4, words), m::AccessFault::kMisaligned);
  TA_CHECK_EQ(trueaxis::modbus::write_registers(r, 400, 6, words), m::AccessFault::kMisaligned);
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 400, 128, words), m::AccessFault::kMisaligned);  // 32 variables
  TA_CHECK_EQ(r.count, 0);
}

TA_TEST("codec: maps whole-variable ranges to variable numbers") {
  Recorder r;
  std::uint16_t words[124] = {};
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 4 * 5281, 12, words), m::AccessFault::kNone);
  TA_CHECK_EQ(r.first, 5281);
  TA_CHECK_EQ(r.count, 3);
  TA_CHECK_EQ(trueaxis::modbus::decode_double(&words[8]), 3.0);
  TA_CHECK_EQ(trueaxis::modbus::read_registers(r, 0, 124, words), m::AccessFault::kNone);
  TA_CHECK_EQ(r.count, 31);
  trueaxis::modbus::encode_double(2.5, &words[4]);
  TA_CHECK_EQ(trueaxis::modbus::write_registers(r, 4 * 9000, 8, words), m::AccessFault::kNone);
  TA_CHECK_EQ(r.first, 9000);
  TA_CHECK_EQ(r.values[1], 2.5);
}

// Every fault, as the byte a client receives (var_info.hpp's table); this
// covers the fault-to-exception mapping too. Case index: the fault.
TA_TEST("codec: the Modbus exceptions carry the codes of the Modbus specification on the wire") {
  using F = m::AccessFault;
  using E = m::ModbusException;
  // Modbus Application Protocol V1.1b3, section 7: 01 illegal function, 02 illegal
  // data address, 03 illegal data value, 04 server device failure, 06 busy.
  TA_CHECK_EQ(static_cast<int>(E::kNone), 0);
  TA_CHECK_EQ(static_cast<int>(E::kIllegalFunction), 1);
  TA_CHECK_EQ(static_cast<int>(E::kIllegalDataAddress), 2);
  TA_CHECK_EQ(static_cast<int>(E::kIllegalDataValue), 3);
  TA_CHECK_EQ(static_cast<int>(E::kServerDeviceFailure), 4);
  TA_CHECK_EQ(static_cast<int>(E::kServerDeviceBusy), 6);
  struct Wire {
    F fault;
    int code;
  };
  const Wire wire[] = {{F::kNone, 0},       {F::kUndefined, 2},      {F::kMisaligned, 2},
                       {F::kReadOnly, 2},   {F::kLocked, 2},         {F::kNotFinite, 3},
                       {F::kOutOfRange, 3}, {F::kBadUnlockCode, 3},  {F::kBusy, 6},
                       {F::kStorageFailure, 4}, {F::kBadFunction, 1}, {F::kUnlockBackoff, 6}};
  for (const Wire& w : wire) {
    TA_CASE_INDEX(static_cast<int>(w.fault));
    TA_CHECK_EQ(static_cast<int>(m::modbus_exception(w.fault)), w.code);
  }
  TA_CASE_INDEX(-1);
  TA_CHECK_EQ(sizeof wire / sizeof wire[0], static_cast<std::size_t>(F::kUnlockBackoff) + 1);  // every fault listed
}
