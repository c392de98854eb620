// The product's persistent records: the one list of what lives in non-volatile
// storage, and how much room each takes (macros/keyed_store.hpp, layout note 1).
//
//   key  record          payload capacity                           slot    2 slots
//   1    config          1280 B = 128 x (u16 number + f64 value)   1304 B   2608 B
//   2    work offsets     360 B =  36 x (u16 number + f64 value)    384 B    768 B
//   3    rigidity table  4096 B                                    4120 B   8240 B
//   4    gantry frames   3072 B                                    3096 B   6192 B
//   5    spindle model   2048 B                                    2072 B   4144 B
//                                                    kRequiredStorageBytes 21952 B
// A slot is the 20-byte header plus the capacity, rounded up to 8 bytes;
// kStoreScratchBytes (4120 B, the rigidity table's slot) is the scratch buffer a
// KeyedStore over this list needs.
//
// Append new records at the end; never reorder, remove or resize one in place
// (that moves every later record's slots, which then load as absent). A change to
// a payload's encoding bumps its layout version, which makes the old record load
// as absent.
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

// Bytes of one persistent variable in a config or work-offset payload: number (u16)
// and value (IEEE-754 binary64).
inline constexpr std::size_t kVariableEntryBytes = 10;

inline constexpr RecordSpec kRecordSpecs[] = {
    {static_cast<std::uint8_t>(RecordKey::kConfig), 1, 128 * kVariableEntryBytes, "config"},
    {static_cast<std::uint8_t>(RecordKey::kWorkOffsets), 1, 36 * kVariableEntryBytes, "work_offsets"},
    {static_cast<std::uint8_t>(RecordKey::kRigidityTable), 1, 4096, "rigidity_table"},
    {static_cast<std::uint8_t>(RecordKey::kGantryFrames), 1, 3072, "gantry_frames"},
    {static_cast<std::uint8_t>(RecordKey::kSpindleModel), 1, 2048, "spindle_model"},
};
inline constexpr std::size_t kRecordCount = sizeof(kRecordSpecs) / sizeof(kRecordSpecs[0]);

inline constexpr std::size_t kRequiredStorageBytes = KeyedStore::required_bytes(kRecordSpecs, kRecordCount);
inline constexpr std::size_t kStoreScratchBytes = KeyedStore::scratch_bytes(kRecordSpecs, kRecordCount);

static_assert(KeyedStore::specs_valid(kRecordSpecs, kRecordCount), "record keys must be unique");
static_assert(kRequiredStorageBytes == 21952 && kStoreScratchBytes == 4120,
              "the sizes in this header's table are out of date");

constexpr std::uint8_t record_key(RecordKey key) { return static_cast<std::uint8_t>(key); }

// The payload capacity of a record; 0 for a key not in the list.
constexpr std::size_t record_capacity(RecordKey key) {
  for (const RecordSpec& s : kRecordSpecs) {
    if (s.key == record_key(key)) return s.capacity_bytes;
  }
  return 0;
}

// The largest table payload a macro can stage, and the largest variable record.
inline constexpr std::size_t kMaxRecordPayloadBytes = record_capacity(RecordKey::kRigidityTable);
inline constexpr std::size_t kVariableRecordBytes = record_capacity(RecordKey::kConfig);

}  // namespace trueaxis::macros
