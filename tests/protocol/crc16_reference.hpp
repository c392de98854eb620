// CRC-16/MODBUS by the specification's bit loop (Modbus over Serial Line V1.02,
// 6.2.2): the reference the RTU tests hold the product's table-driven
// crc16_modbus (modbus_rtu.hpp) and the image's replies against
// (test_modbus_rtu.cpp, test_rtu_qemu.cpp, tests/fuzz/fuzz_rtu_framer.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace trueaxis::test {

inline std::uint16_t crc16_bitwise(const std::uint8_t* data, std::size_t n) {
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) {
      const bool lsb = (crc & 1u) != 0;
      crc = static_cast<std::uint16_t>(crc >> 1);
      if (lsb) crc ^= 0xA001;
    }
  }
  return crc;
}

inline std::uint16_t crc16_bitwise(const std::vector<std::uint8_t>& data) {
  return crc16_bitwise(data.data(), data.size());
}

}  // namespace trueaxis::test
