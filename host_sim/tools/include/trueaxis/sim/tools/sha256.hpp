// SHA-256 (FIPS 180-4) of bytes in memory, as lowercase hex: what names a
// stored calibration on a check's page (the record the module exports, 9837
// or 9847), the same digest sha256sum gives. Host only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace trueaxis::sim {

// The 64 hex digits of SHA-256(data[0, size)).
std::string sha256_hex(const std::uint8_t* data, std::size_t size);
inline std::string sha256_hex(const std::string& bytes) {
  return sha256_hex(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace trueaxis::sim
