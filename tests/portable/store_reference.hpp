// An independent writer of keyed-store records (macros/keyed_store.hpp, layout
// note 2), with a bitwise CRC-32: the tests forge records with it (any sequence,
// any version) and check that the store writes the documented bytes.
// Heap-free: the portable tests forge records with it on the Cortex-M7 too
// (platform_store_contract_test.cpp); the host's oracle checks are in
// tests/macros/test_keyed_store.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace trueaxis::test {

// CRC-32 bit by bit from the polynomial's definition (reflected 0xEDB88320).
inline std::uint32_t reference_crc32(const std::uint8_t* data, std::size_t length) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < length; ++i) {
    for (int b = 0; b < 8; ++b) {
      const std::uint32_t bit = ((crc ^ (static_cast<std::uint32_t>(data[i]) >> b)) & 1u);
      crc = (crc >> 1) ^ (bit != 0 ? 0xEDB88320u : 0u);
    }
  }
  return crc ^ 0xFFFFFFFFu;
}

inline void put_le(std::uint8_t* p, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Writes a whole record into out (20 + length bytes); returns its size.
inline std::size_t reference_record(std::uint8_t key, std::uint16_t version, std::uint32_t sequence,
                                    const std::uint8_t* payload, std::size_t length, std::uint8_t* out) {
  const std::uint8_t magic[4] = {'T', 'A', 'K', '1'};
  std::memcpy(out, magic, 4);
  out[4] = key;
  out[5] = 0;
  put_le(out + 6, version, 2);
  put_le(out + 8, length, 4);
  put_le(out + 12, sequence, 4);
  put_le(out + 16, 0, 4);
  if (length != 0) std::memcpy(out + 20, payload, length);
  put_le(out + 16, reference_crc32(out, 20 + length), 4);
  return 20 + length;
}

}  // namespace trueaxis::test
