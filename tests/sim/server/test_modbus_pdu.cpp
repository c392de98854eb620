// The protocol core's respond(): request PDU in, response or exception PDU bytes
// out, over the real module on RAM storage. The order of the checks is the Modbus
// Application Protocol's (V1.1b3, 6.3, 6.12, 6.17): quantity and byte count (03)
// before the address (02) before the map.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include "alloc_counter.hpp"
#include "fakes.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "trueaxis/sim/server/simulator.hpp"
#include "trueaxis/sim/server/variable_router.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Core {
  trueaxis::test::ModuleRig rig;
  trueaxis::macros::Module& module = rig.module();
  trueaxis::sim::Simulator simulator{module, trueaxis::sim::FaceConfig{}, 1};
  trueaxis::sim::VariableRouter router{module, simulator};
  trueaxis::modbus::ModbusCore core{router};

  Bytes run(const Bytes& pdu) {
    std::uint8_t response[trueaxis::modbus::kMaxPduBytes];
    const std::size_t n = core.respond(pdu.data(), pdu.size(), response);
    simulator.after_request();
    return Bytes(response, response + n);
  }
};

void put16(Bytes& b, std::uint32_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

Bytes fc3(std::uint32_t address, std::uint32_t quantity) {
  Bytes b = {0x03};
  put16(b, address);
  put16(b, quantity);
  return b;
}

// FC16 of `quantity` registers each 0x4000 0 0 0 (2.0 per variable), with the
// byte count and the data length as given (defaults: consistent).
Bytes fc16(std::uint32_t address, std::uint32_t quantity, int byte_count = -1, int data_bytes = -1) {
  Bytes b = {0x10};
  put16(b, address);
  put16(b, quantity);
  b.push_back(static_cast<std::uint8_t>(byte_count < 0 ? 2 * quantity : static_cast<std::uint32_t>(byte_count)));
  const std::uint32_t n = data_bytes < 0 ? 2 * quantity : static_cast<std::uint32_t>(data_bytes);
  for (std::uint32_t i = 0; i < n; ++i) b.push_back(i % 8 == 0 ? 0x40 : 0x00);
  return b;
}

Bytes fc23(std::uint32_t read_address, std::uint32_t read_quantity, std::uint32_t write_address,
           std::uint32_t write_quantity, int byte_count = -1) {
  Bytes b = {0x17};
  put16(b, read_address);
  put16(b, read_quantity);
  put16(b, write_address);
  put16(b, write_quantity);
  b.push_back(static_cast<std::uint8_t>(byte_count < 0 ? 2 * write_quantity : static_cast<std::uint32_t>(byte_count)));
  for (std::uint32_t i = 0; i < 2 * write_quantity; ++i) b.push_back(i % 8 == 0 ? 0x40 : 0x00);
  return b;
}

Bytes exception(std::uint8_t fc, std::uint8_t code) { return {static_cast<std::uint8_t>(fc | 0x80), code}; }

}  // namespace

TEST_CASE("FC3 answers the byte count and the registers, most significant byte first") {
  Core c;
  REQUIRE(c.run(fc16(4, 4)) == Bytes({0x10, 0, 4, 0, 4}));
  CHECK(c.run(fc3(4, 4)) == Bytes({0x03, 8, 0x40, 0, 0, 0, 0, 0, 0, 0}));
  // 31 variables, the most a read may carry: 124 registers, 248 bytes.
  const Bytes big = c.run(fc3(4 * 1001, 124));
  REQUIRE(big.size() == 2u + 248u);
  CHECK(big[1] == 248);
}

TEST_CASE("FC16 answers the echo of its address and quantity") {
  Core c;
  CHECK(c.run(fc16(4 * 5281, 12)) == Bytes({0x10, 0x52, 0x84, 0, 12}));
  CHECK(c.module.value(5283) == 2.0);
  CHECK(c.run(fc16(4 * 1001, 120)) == Bytes({0x10, 0x0F, 0xA4, 0, 120}));
  CHECK(c.module.value(1030) == 2.0);
}

TEST_CASE("FC23 answers what the module holds after the write, not the words written") {
  Core c;
  Bytes pdu = {0x17, 0x8C, 0xB0, 0, 4, 0x8C, 0xB0, 0, 4, 8};  // read and write #9004
  std::uint16_t w[4];
  trueaxis::modbus::encode_double(trueaxis::macros::kUnlockCode, w);
  for (std::uint16_t x : w) put16(pdu, x);
  CHECK(c.run(pdu) == Bytes({0x17, 8, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0}));
  CHECK(c.module.unlocked());
}

TEST_CASE("every function code but 3, 6, 16 and 23 is exception 01 with the top bit of the code set") {
  Core c;
  for (int fc = 0; fc < 256; ++fc) {
    const auto code = static_cast<std::uint8_t>(fc);
    if (code == 0x03 || code == 0x06 || code == 0x10 || code == 0x17) continue;
    INFO("function code " << fc);
    CHECK(c.run({code, 0, 4, 0, 4}) == exception(code, 0x01));
    CHECK(c.run({code}) == exception(code, 0x01));
  }
  CHECK(c.run({0x06, 0, 4, 0x40, 0}) == exception(0x06, 0x02));
  CHECK(c.module.value(1) == 0.0);
}

TEST_CASE("FC3 refuses a bad quantity with 03 before it looks at the address") {
  Core c;
  CHECK(c.run(fc3(4, 0)) == exception(0x03, 0x03));
  CHECK(c.run(fc3(4, 126)) == exception(0x03, 0x03));
  CHECK(c.run(fc3(65535, 0)) == exception(0x03, 0x03));
  CHECK(c.run(fc3(65535, 126)) == exception(0x03, 0x03));
  // In the specification's range but not whole variables, or past the last register: 02.
  CHECK(c.run(fc3(4, 125)) == exception(0x03, 0x02));
  CHECK(c.run(fc3(65532, 8)) == exception(0x03, 0x02));
  CHECK(c.run(fc3(65535, 1)) == exception(0x03, 0x02));
  // Truncated or over-long PDUs.
  CHECK(c.run({0x03, 0, 4, 0}) == exception(0x03, 0x03));
  CHECK(c.run({0x03, 0, 4, 0, 4, 0}) == exception(0x03, 0x03));
}

TEST_CASE("FC16 refuses a bad quantity or byte count with 03 and writes nothing") {
  Core c;
  CHECK(c.run(fc16(4, 0)) == exception(0x10, 0x03));
  CHECK(c.run(fc16(4, 124)) == exception(0x10, 0x03));
  CHECK(c.run(fc16(65532, 124)) == exception(0x10, 0x03));
  CHECK(c.run(fc16(4, 4, 7, 8)) == exception(0x10, 0x03));   // byte count one short
  CHECK(c.run(fc16(4, 4, 9, 8)) == exception(0x10, 0x03));   // byte count one over
  CHECK(c.run(fc16(4, 4, 8, 7)) == exception(0x10, 0x03));   // truncated data
  CHECK(c.run(fc16(4, 4, 8, 9)) == exception(0x10, 0x03));   // one byte too many
  CHECK(c.run(fc16(4, 4, 0, 0)) == exception(0x10, 0x03));   // byte count zero
  CHECK(c.run({0x10, 0, 4, 0, 4}) == exception(0x10, 0x03));
  CHECK(c.module.value(1) == 0.0);
  // In range, but 121 registers are not whole variables; past the last register.
  CHECK(c.run(fc16(4 * 1001, 121)) == exception(0x10, 0x02));
  CHECK(c.run(fc16(65532, 8)) == exception(0x10, 0x02));
  CHECK(c.module.value(1001) == 0.0);
}

TEST_CASE("FC23 checks both quantities and the byte count before any address, and writes nothing when refused") {
  Core c;
  CHECK(c.run(fc23(4, 0, 4, 4)) == exception(0x17, 0x03));
  CHECK(c.run(fc23(4, 126, 4, 4)) == exception(0x17, 0x03));
  CHECK(c.run(fc23(4, 4, 4, 0)) == exception(0x17, 0x03));
  CHECK(c.run(fc23(4, 4, 4, 122)) == exception(0x17, 0x03));
  CHECK(c.run(fc23(4, 4, 4, 4, 9)) == exception(0x17, 0x03));
  CHECK(c.run(fc23(65535, 126, 4, 4)) == exception(0x17, 0x03));
  CHECK(c.module.value(1) == 0.0);
  CHECK(c.run(fc23(65532, 8, 4, 4)) == exception(0x17, 0x02));  // read past the end
  CHECK(c.run(fc23(4, 4, 65532, 8)) == exception(0x17, 0x02));  // write past the end
  CHECK(c.run(fc23(40, 4, 4, 4)) == exception(0x17, 0x02));     // read of undefined #10
  CHECK(c.module.value(1) == 0.0);
  CHECK(c.run(fc23(4, 4, 4, 4)) == Bytes({0x17, 8, 0x40, 0, 0, 0, 0, 0, 0, 0}));
  CHECK(c.module.value(1) == 2.0);
}

TEST_CASE("a malformed quantity is not noted in #9007; a map fault is") {
  Core c;
  REQUIRE(c.run(fc3(4 * 10, 4)) == exception(0x03, 0x02));
  const Bytes undefined = c.run(fc3(4 * 9007, 4));
  REQUIRE(c.run(fc3(4, 0)) == exception(0x03, 0x03));
  CHECK(c.run(fc3(4 * 9007, 4)) == undefined);
  CHECK(undefined == Bytes({0x03, 8, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0}));  // 1: undefined
}

TEST_CASE("a range that ends exactly at register 0xFFFF reaches the map; one past it is undefined before the map") {
  // Both are exception 02; #9007 tells which check refused them.
  Core c;
  const Bytes misaligned = {0x03, 8, 0x40, 0, 0, 0, 0, 0, 0, 0};  // 2.0
  const Bytes undefined = {0x03, 8, 0x3F, 0xF0, 0, 0, 0, 0, 0, 0};  // 1.0
  CHECK(c.run(fc3(0xFFFF, 1)) == exception(0x03, 0x02));  // ends at 0xFFFF: the map sees part of a variable
  CHECK(c.run(fc3(4 * 9007, 4)) == misaligned);
  CHECK(c.run(fc3(0xFFFC, 8)) == exception(0x03, 0x02));  // one variable past 0xFFFF
  CHECK(c.run(fc3(4 * 9007, 4)) == undefined);
  CHECK(c.run(fc16(0xFFFD, 3)) == exception(0x10, 0x02));  // ends at 0xFFFF
  CHECK(c.run(fc3(4 * 9007, 4)) == misaligned);
  CHECK(c.run(fc16(0xFFFE, 3)) == exception(0x10, 0x02));  // ends at 0x10000
  CHECK(c.run(fc3(4 * 9007, 4)) == undefined);
}

TEST_CASE("respond() allocates nothing") {
  Core c;
  const Bytes write = fc16(4 * 5281, 12);
  const Bytes read = fc3(4 * 5281, 12);
  std::uint8_t response[trueaxis::modbus::kMaxPduBytes];
  trueaxis::test::AllocationScope scope;
  for (int i = 0; i < 10; ++i) {
    (void)c.core.respond(write.data(), write.size(), response);
    (void)c.core.respond(read.data(), read.size(), response);
  }
  CHECK(scope.count() == 0);
}
