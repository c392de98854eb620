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
//     accepted record encodes back to exactly its own bytes;
//  3. except a record of an older layout the decoder still reads (the
//     gantry's layout 1, kGantryTableBytesV1): it encodes in the current
//     layout, which keeps its bytes after the version field and appends the
//     new figures; those bytes decode to the same table and encode to
//     themselves again.
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

// Decode, check 1 to 3; Table is the decoded type, capacity the encoder's
// room, older_size the size of an older layout the decoder reads (0: none).
template <typename Table, std::size_t kCapacity, typename Decode, typename Encode>
void round_trip(const std::uint8_t* bytes, std::size_t size, Decode decode, Encode encode,
                std::size_t older_size = 0) {
  static Table table;
  static Table again;
  static std::array<unsigned char, sizeof(Table)> before;
  static std::array<std::uint8_t, kCapacity> encoded;
  static std::array<std::uint8_t, kCapacity> encoded_again;
  std::memcpy(before.data(), static_cast<const void*>(&table), sizeof table);
  if (decode(bytes, size, table) != Status::kOk) {
    FUZZ_CHECK(std::memcmp(before.data(), static_cast<const void*>(&table), sizeof table) == 0);
    return;
  }
  const std::size_t n = encode(table, encoded.data(), encoded.size());
  if (older_size == 0 || size != older_size) {
    FUZZ_CHECK(n == size);
    FUZZ_CHECK(std::memcmp(encoded.data(), bytes, size) == 0);
    return;
  }
  FUZZ_CHECK(n > size);
  FUZZ_CHECK(std::memcmp(encoded.data() + 2, bytes + 2, size - 2) == 0);  // all but the version field
  FUZZ_CHECK(decode(encoded.data(), n, again) == Status::kOk);
  FUZZ_CHECK(encode(again, encoded_again.data(), encoded_again.size()) == n);
  FUZZ_CHECK(std::memcmp(encoded_again.data(), encoded.data(), n) == 0);
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
          bytes, n, trueaxis::core::decode_gantry_table, trueaxis::core::encode_gantry_table,
          trueaxis::core::kGantryTableBytesV1);
      break;
    default:
      round_trip<trueaxis::core::SpindleModel, trueaxis::core::kSpindleModelBytes>(
          bytes, n, trueaxis::core::decode_spindle_model, trueaxis::core::encode_spindle_model);
      break;
  }
  return 0;
}
