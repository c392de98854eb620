// The module's persistent records: the one list of what lives in non-volatile
// storage, and how much room each takes (macros/store/include/trueaxis/macros/
// keyed_store.hpp, layout note 1). The platform's two records come first; each
// built method that stores a table adds its record (its descriptor's
// Table::kRecord), in the order of the method list. With every method built:
//
//   key  record          payload capacity                           slot    2 slots
//   1    config          1280 B = 128 x (u16 number + f64 value)   1304 B   2608 B
//   2    work offsets     360 B =  36 x (u16 number + f64 value)    384 B    768 B
//   3    rigidity table  4096 B                                    4120 B   8240 B
//   4    gantry frames   3072 B                                    3096 B   6192 B
//   5    spindle model   2048 B                                    2072 B   4144 B
//   9    measuring log   3264 B = 32 x 102-byte entries            3288 B   6576 B
//                                                    kRequiredStorageBytes 28528 B
// A slot is the 20-byte header plus the capacity, rounded up to 8 bytes;
// kStoreScratchBytes (the largest slot) is the scratch buffer a KeyedStore over
// this list needs.
//
// The measuring log (measuring_log.hpp) comes last, and only in a module
// with a method that logs; its place moves with the tables before it, as
// theirs do.
//
// Append new records at the end; never reorder, remove or resize one in place
// (that moves every later record's slots, which then load as absent). A change to
// a payload's encoding bumps its layout version, which makes the old record load
// as absent. A module built with fewer methods keeps the platform's records in
// their places; its tables' records follow them, so a controller that changes
// its method set keeps its configuration and work offsets and stores its
// tables again.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/measuring_log.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::macros {

// The platform's records.
enum class RecordKey : std::uint8_t {
  kConfig = 1,
  kWorkOffsets = 2,
  kMeasuringLog = 9,  // after the tables (records 3.. are the methods')
};

// Bytes of one persistent variable in a config or work-offset payload: number (u16)
// and value (IEEE-754 binary64).
inline constexpr std::size_t kVariableEntryBytes = 10;

inline constexpr RecordSpec kPlatformRecords[] = {
    {static_cast<std::uint8_t>(RecordKey::kConfig), 1, 128 * kVariableEntryBytes, "config"},
    {static_cast<std::uint8_t>(RecordKey::kWorkOffsets), 1, 36 * kVariableEntryBytes, "work_offsets"},
};

inline constexpr RecordSpec kLogRecord{static_cast<std::uint8_t>(RecordKey::kMeasuringLog), 1, kLogBytes,
                                       "measuring_log"};
inline constexpr bool kHasLog = BuiltMethods::kAnyLogs;

namespace detail {
inline constexpr std::size_t kPlatformRecordCount = sizeof kPlatformRecords / sizeof kPlatformRecords[0];
inline constexpr std::size_t kAllRecordCount = kPlatformRecordCount + BuiltMethods::kTableCount + (kHasLog ? 1 : 0);
constexpr std::array<RecordSpec, kAllRecordCount> record_specs() {
  std::array<RecordSpec, kAllRecordCount> out{};
  std::size_t n = 0;
  for (const RecordSpec& s : kPlatformRecords) out[n++] = s;
  for (const RecordSpec& s : BuiltMethods::table_records()) out[n++] = s;
  if (kHasLog) out[n++] = kLogRecord;
  return out;
}
}  // namespace detail

inline constexpr auto kRecordSpecs = detail::record_specs();
inline constexpr std::size_t kRecordCount = kRecordSpecs.size();

inline constexpr std::size_t kRequiredStorageBytes = KeyedStore::required_bytes(kRecordSpecs.data(), kRecordCount);
inline constexpr std::size_t kStoreScratchBytes = KeyedStore::scratch_bytes(kRecordSpecs.data(), kRecordCount);

static_assert(KeyedStore::specs_valid(kRecordSpecs.data(), kRecordCount), "record keys must be unique");

constexpr std::uint8_t record_key(RecordKey key) { return static_cast<std::uint8_t>(key); }

// The payload capacity of a record; 0 for a key not in the list.
constexpr std::size_t record_capacity(std::uint8_t key) {
  for (const RecordSpec& s : kRecordSpecs) {
    if (s.key == key) return s.capacity_bytes;
  }
  return 0;
}
constexpr std::size_t record_capacity(RecordKey key) { return record_capacity(record_key(key)); }

// The largest variable record, and the largest table record a macro can stage.
inline constexpr std::size_t kVariableRecordBytes = record_capacity(RecordKey::kConfig);
inline constexpr std::size_t kMaxRecordPayloadBytes = BuiltMethods::kTableRecordBytes;

}  // namespace trueaxis::macros
