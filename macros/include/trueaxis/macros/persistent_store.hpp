// Persistent variables in non-volatile storage, safe against a power cut at any
// moment of a save.
//
// Layout: two slots of kSlotBytes at offsets 0 and kSlotBytes. A slot is
//   magic "TAX1" (4 bytes) | layout version (u16) | entry count (u16) |
//   sequence (u32) | CRC-32 of the whole record with this field as 0 (u32) |
//   count x { variable number (u16) | value (IEEE-754 binary64) }
// all little-endian. A save writes the slot that does not hold the newest valid
// copy, with sequence + 1, so the newest valid copy survives a cut at any byte of
// the save. Load takes the valid slot with the larger sequence (serial-number
// arithmetic, so the counter may wrap). Entries are looked up by variable number,
// so a later map that adds variables still loads an older table; numbers the map
// no longer holds as persistent, and values the map would refuse, are skipped.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::macros {

struct PersistentEntry {
  std::uint16_t number = 0;
  double value = 0.0;
};

class PersistentStore {
 public:
  static constexpr std::uint16_t kLayoutVersion = 1;
  static constexpr std::size_t kHeaderBytes = 16;
  static constexpr std::size_t kEntryBytes = 10;
  static constexpr std::size_t kSlotBytes = kHeaderBytes + kEntryBytes * kPersistentCount;
  static constexpr std::size_t kRequiredBytes = 2 * kSlotBytes;

  explicit PersistentStore(hal::NvStorage& storage) : storage_(storage) {}

  // Reads both slots; on kOk, `entries`/`count` hold the newest valid copy, or
  // count == 0 when neither slot is valid (a new device). kStorageFailure when
  // the device is too small or a slot cannot be read; save() then refuses until a
  // later load succeeds, so an unreadable newest copy is never overwritten.
  [[nodiscard]] core::Status load(PersistentEntry* entries, std::size_t capacity, std::size_t& count);

  // Writes `count` entries as the new newest copy. kStorageFailure when the
  // device refused (the slot written is then invalidated, best effort, in case the
  // bytes landed anyway) or no load has succeeded; the previous copy is then still
  // the newest valid one.
  [[nodiscard]] core::Status save(const PersistentEntry* entries, std::size_t count);

 private:
  enum class SlotState : std::uint8_t { kValid, kInvalid, kUnreadable };
  SlotState read_slot(std::size_t slot, std::uint32_t& sequence, std::size_t& count);

  hal::NvStorage& storage_;
  std::uint8_t buffer_[kSlotBytes] = {};
  std::uint32_t sequence_ = 0;
  std::size_t newest_slot_ = 1;  // so the first save goes to slot 0
  bool loaded_ = false;
};

std::uint32_t crc32(const std::uint8_t* data, std::size_t length);

}  // namespace trueaxis::macros
