// libFuzzer target: the decoders of the three calibration tables' records, the
// bytes a module reads from storage at start: core::decode_rigidity_table
// (rigidity_codec.hpp), decode_gantry_table (gantry_table.hpp) and
// decode_spindle_model (spindle_correction.hpp).
//
// Input: | decoder u8 (mod 3) | record bytes |.
//
// Invariants (each header's "Validation on decode" and layout notes):
//  1. a refused record leaves `out` untouched, byte for byte;
//  2. each layout stores every field and decode recomputes the rest, so an
//     accepted record encodes back to exactly its own bytes.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_support.hpp"
#include "trueaxis/core/gantry_table.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/spindle_correction.hpp"

namespace {

using trueaxis::core::Status;

// Decode, check 1 and 2; Table is the decoded type, capacity the encoder's room.
template <typename Table, std::size_t kCapacity, typename Decode, typename Encode>
void round_trip(const std::uint8_t* bytes, std::size_t size, Decode decode, Encode encode) {
  static Table table;
  static std::array<unsigned char, sizeof(Table)> before;
  static std::array<std::uint8_t, kCapacity> encoded;
  std::memcpy(before.data(), static_cast<const void*>(&table), sizeof table);
  if (decode(bytes, size, table) != Status::kOk) {
    FUZZ_CHECK(std::memcmp(before.data(), static_cast<const void*>(&table), sizeof table) == 0);
    return;
  }
  const std::size_t n = encode(table, encoded.data(), encoded.size());
  FUZZ_CHECK(n == size);
  FUZZ_CHECK(std::memcmp(encoded.data(), bytes, size) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t* bytes = data + 1;
  const std::size_t n = size - 1;
  switch (data[0] % 3) {
    case 0:
      round_trip<trueaxis::core::RigidityTable, trueaxis::core::kRigidityTableMaxBytes>(
          bytes, n, trueaxis::core::decode_rigidity_table, trueaxis::core::encode_rigidity_table);
      break;
    case 1:
      round_trip<trueaxis::core::GantryTable, trueaxis::core::kGantryTableBytes>(
          bytes, n, trueaxis::core::decode_gantry_table, trueaxis::core::encode_gantry_table);
      break;
    default:
      round_trip<trueaxis::core::SpindleModel, trueaxis::core::kSpindleModelBytes>(
          bytes, n, trueaxis::core::decode_spindle_model, trueaxis::core::encode_spindle_model);
      break;
  }
  return 0;
}
