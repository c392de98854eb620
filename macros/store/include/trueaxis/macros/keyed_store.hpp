// Keyed persistent records in non-volatile storage, each safe against a power cut
// at any moment of its own save, each saved without touching the others.
//
// Layout
//  1. The records are listed once, as RecordSpec{key, layout version, payload
//     capacity, name} (macros/records.hpp for the product). Each record owns two
//     slots of slot_bytes(spec) = kHeaderBytes + capacity rounded up to 8 bytes,
//     side by side; the records follow each other in list order from offset 0,
//     required_bytes() in all. A record's place depends on the capacities of those
//     before it: append new records at the end, never reorder or resize in place.
//  2. A slot holds, little-endian:
//       0  magic "TAK1" (4 bytes)
//       4  key (u8)
//       5  reserved, 0 (u8)
//       6  layout version (u16)
//       8  payload length in bytes (u32), <= the record's capacity
//      12  sequence (u32)
//      16  CRC-32 (u32) of the whole record: bytes 0..19 with this field as 0,
//          then the payload
//      20  payload (length bytes); the rest of the slot is not written.
//  3. A slot is valid when its magic, key, reserved byte, layout version, length
//     and CRC are right. A record of another layout version is treated as absent
//     (the caller falls back to its defaults; the next save replaces it).
//  4. The newest valid slot of a key holds its contents: the valid one, or of two
//     valid slots the one whose sequence is newer in serial-number arithmetic
//     (a newer than b when a != b and (a - b) mod 2^32 < 2^31), so the counter may
//     wrap: 0 is newer than 0xFFFFFFFF.
//  5. save() writes the key's slot that does not hold its newest valid copy, with
//     sequence + 1, in ONE storage write of header + payload assembled in the
//     scratch buffer. A cut at any byte leaves that slot invalid (the CRC covers
//     the header too, so a new sequence over an old payload fails), or, when every
//     byte landed, valid and newest: after a restart the key holds exactly its old
//     or its new contents. Other keys' slots are never written.
//     Exception, one extra 4-byte write: when that slot does not hold a valid older
//     record (a key's first two saves, and the first save after a cut or a refused
//     write), it may hold most of an earlier failed save with the same sequence,
//     which a later cut save could complete byte by byte (bytes land in any order)
//     and bring back. So its CRC field is first overwritten, durably, with bytes
//     that differ from the CRC bytes it held, in a bit that also keeps them (and
//     any half-programmed mix) from the CRC of the bytes around them: that old
//     record can then come back only by a CRC-32 coincidence.
//  6. CRC-32 is IEEE 802.3, reflected, polynomial 0xEDB88320, initial value and
//     final XOR 0xFFFFFFFF (check value of "123456789": 0xCBF43926), driven by a
//     256-entry table built at compile time.
//
// Status codes
//   kOk                  done.
//   kStorageFailure      the storage refused, is too small, or a slot of the key
//                        could not be read at mount, or the store is not mounted.
//   kArgumentOutOfRange  an unknown key, a payload longer than the record's
//                        capacity (or than the caller's buffer on load), or an
//                        invalid spec list or scratch buffer at mount.
// Nothing allocates; the store keeps per-key state for up to kMaxRecords records.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/nv_storage.hpp"

namespace trueaxis::macros {

struct RecordSpec {
  std::uint8_t key;               // unique within a list, stored in every slot
  std::uint16_t layout_version;   // of the payload's encoding; bump it on a change
  std::size_t capacity_bytes;     // largest payload
  const char* name;               // for diagnostics
};

class KeyedStore {
 public:
  static constexpr std::size_t kHeaderBytes = 20;
  static constexpr std::size_t kSlotAlignment = 8;
  static constexpr std::size_t kMaxRecords = 16;

  static constexpr std::size_t slot_bytes(const RecordSpec& spec) {
    return (kHeaderBytes + spec.capacity_bytes + kSlotAlignment - 1) / kSlotAlignment * kSlotAlignment;
  }

  // Offset of slot 0 or 1 of specs[index] (layout note 1).
  static constexpr std::size_t slot_offset(const RecordSpec* specs, std::size_t index, std::size_t slot) {
    std::size_t offset = 0;
    for (std::size_t i = 0; i < index; ++i) offset += 2 * slot_bytes(specs[i]);
    return offset + slot * slot_bytes(specs[index]);
  }

  static constexpr std::size_t required_bytes(const RecordSpec* specs, std::size_t n) {
    return n == 0 ? 0 : slot_offset(specs, n - 1, 2);
  }

  // The largest slot: what save and load assemble or check at once.
  static constexpr std::size_t scratch_bytes(const RecordSpec* specs, std::size_t n) {
    std::size_t largest = 0;
    for (std::size_t i = 0; i < n; ++i) largest = slot_bytes(specs[i]) > largest ? slot_bytes(specs[i]) : largest;
    return largest;
  }

  // At most kMaxRecords specs, keys unique: what mount() accepts.
  static constexpr bool specs_valid(const RecordSpec* specs, std::size_t n) {
    if (n > kMaxRecords) return false;
    for (std::size_t i = 0; i < n; ++i) {
      if (specs[i].capacity_bytes > 0xFFFF'FFFFu - kHeaderBytes) return false;
      for (std::size_t j = i + 1; j < n; ++j) {
        if (specs[i].key == specs[j].key) return false;
      }
    }
    return true;
  }

  // specs and scratch must outlive the store; nothing is read until mount().
  KeyedStore(hal::NvStorage& storage, const RecordSpec* specs, std::size_t n, std::uint8_t* scratch,
             std::size_t scratch_size)
      : storage_(storage), specs_(specs), count_(n), scratch_(scratch), scratch_size_(scratch_size) {}

  // Reads and checks both slots of every key once and remembers, per key, its
  // newest valid slot and sequence. kArgumentOutOfRange for specs that fail
  // specs_valid() or a scratch buffer under scratch_bytes(); kStorageFailure when
  // a slot could not be read: that key then refuses load and save (its unread slot
  // may hold the newest copy, which a save could overwrite) until a later mount
  // reads it; the other keys work. Likewise when the storage is under
  // required_bytes(): the keys whose slots end beyond it refuse load and save, the
  // others mount (a record appended to the list, on storage sized for the list
  // before it, leaves every earlier record readable).
  [[nodiscard]] core::Status mount();

  // Copies the key's newest payload into out[0, length); length = 0 when the key
  // has no valid record (an empty payload loads the same). kArgumentOutOfRange for
  // an unknown key or a payload longer than capacity; kStorageFailure when the key
  // was not mounted or its slot no longer reads back as mounted. out is untouched
  // unless kOk.
  [[nodiscard]] core::Status load(std::uint8_t key, std::uint8_t* out, std::size_t capacity,
                                  std::size_t& length);

  // Makes payload[0, length) the key's newest contents (layout note 5), or changes
  // nothing the next mount sees as newest. kArgumentOutOfRange for an unknown key
  // or length over the capacity (nothing written); kStorageFailure when the key is
  // not mounted or the storage refused the write. A refused write may have landed
  // anyway, so the slot's magic is then overwritten, best effort; if that is
  // refused too and the record had landed whole, the next mount sees it as newest.
  [[nodiscard]] core::Status save(std::uint8_t key, const std::uint8_t* payload, std::size_t length);

  // The sequence of the key's newest valid slot; 0 for a key without one or unknown.
  std::uint32_t sequence(std::uint8_t key) const;

  // True when the last mount found no valid slot of the key but a slot whose
  // header names it (magic, key, layout version and length right) and whose CRC
  // fails: a record was written there and is damaged (a bit lost, or its save cut
  // before any record of the key was complete). load() treats the key as empty
  // and save() replaces it as usual; this only lets the owner tell "damaged"
  // from "never stored". False for an unknown or unmounted key.
  bool damaged(std::uint8_t key) const;

 private:
  enum class KeyState : std::uint8_t { kUnmounted, kEmpty, kDamaged, kValid };
  enum class SlotState : std::uint8_t { kValid, kInvalid, kCrcFailed, kUnreadable };
  struct KeyInfo {
    KeyState state = KeyState::kUnmounted;
    std::uint8_t newest_slot = 1;  // so the first save of a key goes to slot 0
    bool target_clean = false;     // the slot a save writes holds a valid older record
    std::uint32_t sequence = 0;
    std::uint32_t length = 0;
  };

  std::size_t index_of(std::uint8_t key) const;  // count_ when unknown
  SlotState read_slot(std::size_t index, std::size_t slot, std::uint32_t& sequence, std::uint32_t& length);
  core::Status clear_crc(std::size_t index, std::size_t slot);

  hal::NvStorage& storage_;
  const RecordSpec* specs_;
  std::size_t count_;
  std::uint8_t* scratch_;
  std::size_t scratch_size_;
  KeyInfo keys_[kMaxRecords] = {};
};

// The store's CRC-32 (layout note 6).
namespace checksum {

// CRC-32 of data[0, length).
std::uint32_t crc32(const std::uint8_t* data, std::size_t length);

// The CRC-32 of a message extended by data[0, length), given the CRC-32 of the
// message so far (0 for the empty message): crc32_update(crc32(a), b) == crc32(a b).
std::uint32_t crc32_update(std::uint32_t crc, const std::uint8_t* data, std::size_t length);

}  // namespace checksum

}  // namespace trueaxis::macros
