// The Modbus protocol core (modbus::ModbusCore) without a socket, over the real
// module and the simulator's variables on RAM storage: request PDUs in through
// respond(), the exception (or none) and the registers read out of the response
// PDU, put into a register image at the protocol addresses they were read from.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "fakes.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/server/simulator.hpp"
#include "trueaxis/sim/server/variable_router.hpp"

namespace {

using trueaxis::macros::ModbusException;
namespace simvar = trueaxis::sim::simvar;

struct Bench {
  trueaxis::test::ModuleRig rig;
  trueaxis::macros::Module& module = rig.module();
  trueaxis::sim::Simulator simulator{module, trueaxis::sim::FaceConfig{}, 1};
  trueaxis::sim::VariableRouter router{module, simulator};
  trueaxis::modbus::ModbusCore core{router};
  std::vector<std::uint16_t> image = std::vector<std::uint16_t>(65536);
  std::vector<std::uint8_t> response;

  // The exception of the response (kNone for a normal one); the registers a
  // served FC3 or FC23 read land in `image` at their protocol addresses.
  ModbusException run(const std::vector<std::uint8_t>& pdu) {
    std::uint8_t out[trueaxis::modbus::kMaxPduBytes];
    const std::size_t n = core.respond(pdu.data(), pdu.size(), out);
    simulator.after_request();
    response.assign(out, out + n);
    REQUIRE(n >= 2);
    if ((out[0] & 0x80) != 0) {
      REQUIRE(n == 2);
      return static_cast<ModbusException>(out[1]);
    }
    if (out[0] == 0x03 || out[0] == 0x17) {
      const std::size_t address = static_cast<std::size_t>((pdu[1] << 8) | pdu[2]);
      REQUIRE(n == 2u + out[1]);
      for (std::size_t i = 0; 2 * i < out[1]; ++i) {
        image[address + i] = static_cast<std::uint16_t>((out[2 + 2 * i] << 8) | out[3 + 2 * i]);
      }
    }
    return ModbusException::kNone;
  }
};

std::vector<std::uint8_t> read_pdu(std::uint16_t address, std::uint16_t quantity) {
  return {0x03, std::uint8_t(address >> 8), std::uint8_t(address), std::uint8_t(quantity >> 8), std::uint8_t(quantity)};
}

void put_words(std::vector<std::uint8_t>& pdu, const std::vector<std::uint16_t>& words) {
  for (std::uint16_t w : words) {
    pdu.push_back(std::uint8_t(w >> 8));
    pdu.push_back(std::uint8_t(w));
  }
}

std::vector<std::uint8_t> write_pdu(std::uint16_t address, const std::vector<std::uint16_t>& words) {
  const auto n = static_cast<std::uint16_t>(words.size());
  std::vector<std::uint8_t> pdu = {0x10, std::uint8_t(address >> 8), std::uint8_t(address), std::uint8_t(n >> 8),
                                   std::uint8_t(n), std::uint8_t(2 * n)};
  put_words(pdu, words);
  return pdu;
}

std::vector<std::uint16_t> words_of(std::initializer_list<double> values) {
  std::vector<std::uint16_t> words;
  for (double v : values) {
    std::uint16_t w[4];
    trueaxis::modbus::encode_double(v, w);
    words.insert(words.end(), w, w + 4);
  }
  return words;
}

const std::vector<std::uint16_t> kOne = {0x3FF0, 0, 0, 0};  // 1.0
const std::vector<std::uint16_t> kTwo = {0x4000, 0, 0, 0};  // 2.0

}  // namespace

TEST_CASE("a write of #1 = 1.0 reads back as 0x3FF0 0 0 0 at registers 4..7") {
  Bench b;
  REQUIRE(b.run(write_pdu(4, kOne)) == ModbusException::kNone);
  CHECK(b.module.value(1) == 1.0);
  REQUIRE(b.run(read_pdu(4, 4)) == ModbusException::kNone);
  CHECK(std::vector<std::uint16_t>(b.image.begin() + 4, b.image.begin() + 8) == kOne);
}

TEST_CASE("FC23 writes first, then reads what it wrote") {
  Bench b;
  std::vector<std::uint8_t> pdu = {0x17, 0, 4, 0, 4, 0, 4, 0, 4, 8};
  put_words(pdu, kTwo);
  REQUIRE(b.run(pdu) == ModbusException::kNone);
  CHECK(b.module.value(1) == 2.0);
  CHECK(std::vector<std::uint16_t>(b.image.begin() + 4, b.image.begin() + 8) == kTwo);
}

TEST_CASE("FC23 whose write is refused reads nothing and changes nothing") {
  Bench b;
  std::vector<std::uint8_t> pdu = {0x17, 0, 4, 0, 4, 0x01, 0x90, 0, 4, 8};  // write #100 (read-only)
  put_words(pdu, kTwo);
  CHECK(b.run(pdu) == ModbusException::kIllegalDataAddress);
  CHECK(b.module.value(100) == 0.0);
}

TEST_CASE("FC23 whose read is refused writes nothing") {
  Bench b;
  // Read #10 (undefined), write #1 = 2.0.
  std::vector<std::uint8_t> pdu = {0x17, 0, 40, 0, 4, 0, 4, 0, 4, 8};
  put_words(pdu, kTwo);
  CHECK(b.run(pdu) == ModbusException::kIllegalDataAddress);
  CHECK(b.module.value(1) == 0.0);
}

// The protocol's own refusals (function codes, quantities, byte counts, the
// register range) are test_modbus_pdu.cpp's; here only what it has no case for.
TEST_CASE("an empty PDU is exception 03") {
  Bench b;
  CHECK(b.run({}) == ModbusException::kIllegalDataValue);
  CHECK(b.module.value(1) == 0.0);
}

TEST_CASE("the simulator's variables are reached through the same decoder") {
  Bench b;
  REQUIRE(b.run(write_pdu(4 * simvar::kAxisA, kTwo)) == ModbusException::kNone);
  CHECK(b.simulator.value(simvar::kAxisA) == 2.0);
  // Reads of the simulator's variables land in the image as the module's do.
  REQUIRE(b.run(read_pdu(4 * simvar::kAxisA, 8)) == ModbusException::kNone);
  CHECK(std::vector<std::uint16_t>(b.image.begin() + 4 * simvar::kAxisA, b.image.begin() + 4 * simvar::kAxisA + 4) ==
        kTwo);
  CHECK(std::vector<std::uint16_t>(b.image.begin() + 4 * simvar::kAxisC, b.image.begin() + 4 * simvar::kAxisC + 4) ==
        std::vector<std::uint16_t>({0, 0, 0, 0}));
  // The default face (12.5 deg at azimuth 30 deg): normal z = cos 12.5 deg.
  REQUIRE(b.run(read_pdu(4 * simvar::kTrueNormalZ, 8)) == ModbusException::kNone);
  const double nz = trueaxis::modbus::decode_double(&b.image[4 * simvar::kTrueNormalZ]);
  CHECK(nz == b.simulator.value(simvar::kTrueNormalZ));
  CHECK(nz == Approx(std::cos(12.5 * 3.14159265358979323846 / 180.0)).epsilon(1e-15));
  // The tilt at the table's present position, A = 2 deg, is no longer 12.5 deg.
  const double tilt = trueaxis::modbus::decode_double(&b.image[4 * simvar::kTrueTilt]);
  CHECK(tilt == b.simulator.value(simvar::kTrueTilt));
  CHECK(std::abs(tilt - 12.5) > 0.1);
}

TEST_CASE("a range spanning the simulator's variables and another number is exception 02") {
  Bench b;
  CHECK(b.run(read_pdu(4 * (simvar::kFirst - 1), 8)) == ModbusException::kIllegalDataAddress);
  CHECK(b.run(read_pdu(4 * simvar::kLast, 8)) == ModbusException::kIllegalDataAddress);
  CHECK(b.run(write_pdu(4 * (simvar::kFirst - 1), {0, 0, 0, 0, 0x4000, 0, 0, 0})) ==
        ModbusException::kIllegalDataAddress);
  CHECK(b.simulator.value(simvar::kAxisA) == 0.0);
}

TEST_CASE("probing stores the touch point into a work offset through the module") {
  Bench b;
  REQUIRE(b.run(write_pdu(4 * simvar::kProbeX, words_of({10.0, -5.0, 5281.0}))) == ModbusException::kNone);
  CHECK(b.module.value(5281) == Approx(10.0).margin(0.01));
  CHECK(b.module.value(5282) == Approx(-5.0).margin(0.01));
  CHECK(b.module.value(5283) == Approx(b.simulator.value(simvar::kLastProbeZ)));
  CHECK(b.module.value(5283) > 30.0);
}

TEST_CASE("probing into a number that is not a work offset or point-list X is exception 03 (the request handler alone)") {
  Bench b;
  for (double target : {5282.0, 5222.0, 1002.0, 100.0, 0.0}) {
    CHECK(b.run(write_pdu(4 * simvar::kProbeInto, words_of({target}))) == ModbusException::kIllegalDataValue);
  }
  CHECK(b.simulator.value(simvar::kProbeInto) == 0.0);
  CHECK(b.module.value(5281) == 0.0);
}
