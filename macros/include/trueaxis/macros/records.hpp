// The product's persistent records: one list, in storage order.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/keyed_store.hpp"

namespace trueaxis::macros {

enum class RecordKey : std::uint8_t {
  kConfig = 1,
  kWorkOffsets = 2,
  kRigidityTable = 3,
  kGantryFrames = 4,
  kSpindleModel = 5,
};

inline constexpr RecordSpec kRecordSpecs[] = {
    {static_cast<std::uint8_t>(RecordKey::kConfig), 1, 1280, "config"},
    {static_cast<std::uint8_t>(RecordKey::kWorkOffsets), 1, 360, "work_offsets"},
    {static_cast<std::uint8_t>(RecordKey::kRigidityTable), 1, 4096, "rigidity_table"},
    {static_cast<std::uint8_t>(RecordKey::kGantryFrames), 1, 3072, "gantry_frames"},
    {static_cast<std::uint8_t>(RecordKey::kSpindleModel), 1, 2048, "spindle_model"},
};
inline constexpr std::size_t kRecordSpecCount = sizeof(kRecordSpecs) / sizeof(kRecordSpecs[0]);
inline constexpr std::size_t kRequiredStorageBytes = KeyedStore::required_bytes(kRecordSpecs, kRecordSpecCount);
inline constexpr std::size_t kStoreScratchBytes = KeyedStore::scratch_bytes(kRecordSpecs, kRecordSpecCount);

constexpr std::size_t record_capacity(RecordKey key) {
  for (const RecordSpec& s : kRecordSpecs) {
    if (s.key == static_cast<std::uint8_t>(key)) return s.capacity_bytes;
  }
  return 0;
}
inline constexpr std::size_t kMaxRecordPayloadBytes = record_capacity(RecordKey::kRigidityTable);
inline constexpr std::size_t kVariableRecordBytes = record_capacity(RecordKey::kConfig);

}  // namespace trueaxis::macros
