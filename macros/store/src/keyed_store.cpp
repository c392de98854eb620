#include "trueaxis/macros/keyed_store.hpp"

#include "trueaxis/core/byte_order.hpp"

#include <cstring>

namespace trueaxis::macros {

namespace {

using core::get_u16;
using core::get_u32;
using core::put_u16;
using core::put_u32;

constexpr std::uint8_t kMagic[4] = {'T', 'A', 'K', '1'};
constexpr std::size_t kKeyOffset = 4;
constexpr std::size_t kReservedOffset = 5;
constexpr std::size_t kVersionOffset = 6;
constexpr std::size_t kLengthOffset = 8;
constexpr std::size_t kSequenceOffset = 12;
constexpr std::size_t kCrcOffset = 16;
static_assert(kCrcOffset + 4 == KeyedStore::kHeaderBytes, "the CRC closes the header");

struct CrcTable {
  std::uint32_t entry[256];
};

constexpr CrcTable make_crc_table() {
  CrcTable table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int b = 0; b < 8; ++b) c = (c & 1u) != 0 ? (c >> 1) ^ 0xEDB88320u : c >> 1;
    table.entry[i] = c;
  }
  return table;
}

constexpr CrcTable kCrcTable = make_crc_table();
static_assert(kCrcTable.entry[1] == 0x77073096u && kCrcTable.entry[255] == 0x2D02EF8Du,
              "CRC-32 table entries of the reflected polynomial 0xEDB88320");

bool newer(std::uint32_t a, std::uint32_t b) { return a != b && static_cast<std::uint32_t>(a - b) < 0x8000'0000u; }

}  // namespace

namespace checksum {

std::uint32_t crc32_update(std::uint32_t crc, const std::uint8_t* data, std::size_t length) {
  crc = ~crc;
  for (std::size_t i = 0; i < length; ++i) crc = kCrcTable.entry[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::uint32_t crc32(const std::uint8_t* data, std::size_t length) { return crc32_update(0, data, length); }

}  // namespace checksum

std::size_t KeyedStore::index_of(std::uint8_t key) const {
  for (std::size_t i = 0; i < count_; ++i) {
    if (specs_[i].key == key) return i;
  }
  return count_;
}

KeyedStore::SlotState KeyedStore::read_slot(std::size_t index, std::size_t slot, std::uint32_t& sequence,
                                            std::uint32_t& length) {
  const RecordSpec& spec = specs_[index];
  const std::size_t offset = slot_offset(specs_, index, slot);
  // The header first: a blank or foreign slot costs no payload read.
  if (storage_.read(offset, scratch_, kHeaderBytes) != hal::IoStatus::kOk) return SlotState::kUnreadable;
  if (std::memcmp(scratch_, kMagic, sizeof kMagic) != 0 || scratch_[kKeyOffset] != spec.key ||
      scratch_[kReservedOffset] != 0 || get_u16(scratch_ + kVersionOffset) != spec.layout_version) {
    return SlotState::kInvalid;
  }
  const std::uint32_t n = get_u32(scratch_ + kLengthOffset);
  if (n > spec.capacity_bytes) return SlotState::kInvalid;
  if (storage_.read(offset + kHeaderBytes, scratch_ + kHeaderBytes, n) != hal::IoStatus::kOk) {
    return SlotState::kUnreadable;
  }
  const std::uint8_t zero_crc[4] = {};
  std::uint32_t crc = checksum::crc32_update(0, scratch_, kCrcOffset);
  crc = checksum::crc32_update(crc, zero_crc, sizeof zero_crc);
  crc = checksum::crc32_update(crc, scratch_ + kHeaderBytes, n);
  if (crc != get_u32(scratch_ + kCrcOffset)) return SlotState::kCrcFailed;
  sequence = get_u32(scratch_ + kSequenceOffset);
  length = n;
  return SlotState::kValid;
}

core::Status KeyedStore::clear_crc(std::size_t index, std::size_t slot) {
  const RecordSpec& spec = specs_[index];
  const std::size_t offset = slot_offset(specs_, index, slot);
  if (storage_.read(offset, scratch_, kHeaderBytes) != hal::IoStatus::kOk) return core::Status::kStorageFailure;
  // The CRC a record made of the slot's other bytes would need; as the stored CRC
  // when the slot's length field is out of range (no such record can be valid).
  std::uint8_t body_crc[4];
  std::memcpy(body_crc, scratch_ + kCrcOffset, sizeof body_crc);
  const std::uint32_t n = get_u32(scratch_ + kLengthOffset);
  if (n <= spec.capacity_bytes) {
    if (storage_.read(offset + kHeaderBytes, scratch_ + kHeaderBytes, n) != hal::IoStatus::kOk) {
      return core::Status::kStorageFailure;
    }
    const std::uint8_t zero_crc[4] = {};
    std::uint32_t crc = checksum::crc32_update(0, scratch_, kCrcOffset);
    crc = checksum::crc32_update(crc, zero_crc, sizeof zero_crc);
    put_u32(body_crc, checksum::crc32_update(crc, scratch_ + kHeaderBytes, n));
  }
  // Each new byte flips every bit of the old one but one: a bit where the old byte
  // differs from body_crc, kept, so no mix of old and new bits equals body_crc.
  std::uint8_t cleared[4];
  for (std::size_t b = 0; b < 4; ++b) {
    const std::uint8_t old_byte = scratch_[kCrcOffset + b];
    const unsigned differ = static_cast<unsigned>(old_byte ^ body_crc[b]);
    const unsigned keep = differ != 0 ? (differ & (0u - differ)) : 0u;  // lowest differing bit
    cleared[b] = static_cast<std::uint8_t>(old_byte ^ (0xFFu & ~keep));
  }
  return storage_.write(offset + kCrcOffset, cleared, sizeof cleared) == hal::IoStatus::kOk
             ? core::Status::kOk
             : core::Status::kStorageFailure;
}

core::Status KeyedStore::mount() {
  for (KeyInfo& info : keys_) info = KeyInfo{};
  if (!specs_valid(specs_, count_) || scratch_ == nullptr || scratch_size_ < scratch_bytes(specs_, count_)) {
    return core::Status::kArgumentOutOfRange;
  }
  core::Status status = core::Status::kOk;
  for (std::size_t i = 0; i < count_; ++i) {
    if (storage_.size_bytes() < slot_offset(specs_, i, 2)) {  // beyond the storage's end: stays unmounted
      status = core::Status::kStorageFailure;
      continue;
    }
    std::uint32_t seq[2] = {0, 0};
    std::uint32_t len[2] = {0, 0};
    const SlotState state[2] = {read_slot(i, 0, seq[0], len[0]), read_slot(i, 1, seq[1], len[1])};
    if (state[0] == SlotState::kUnreadable || state[1] == SlotState::kUnreadable) {
      status = core::Status::kStorageFailure;
      continue;
    }
    const bool valid[2] = {state[0] == SlotState::kValid, state[1] == SlotState::kValid};
    KeyInfo& info = keys_[i];
    if (!valid[0] && !valid[1]) {
      const bool crc_failed = state[0] == SlotState::kCrcFailed || state[1] == SlotState::kCrcFailed;
      info.state = crc_failed ? KeyState::kDamaged : KeyState::kEmpty;
      continue;
    }
    const std::uint8_t best = (valid[0] && (!valid[1] || !newer(seq[1], seq[0]))) ? 0 : 1;
    info.state = KeyState::kValid;
    info.target_clean = valid[0] && valid[1];
    info.newest_slot = best;
    info.sequence = seq[best];
    info.length = len[best];
  }
  return status;
}

core::Status KeyedStore::load(std::uint8_t key, std::uint8_t* out, std::size_t capacity, std::size_t& length) {
  length = 0;
  const std::size_t i = index_of(key);
  if (i == count_) return core::Status::kArgumentOutOfRange;
  const KeyInfo& info = keys_[i];
  if (info.state == KeyState::kUnmounted) return core::Status::kStorageFailure;
  if (info.state == KeyState::kEmpty || info.state == KeyState::kDamaged) return core::Status::kOk;
  if (info.length > capacity) return core::Status::kArgumentOutOfRange;
  std::uint32_t seq = 0;
  std::uint32_t len = 0;
  // Checked again: RAM that keeps its content can still lose a bit after mount.
  if (read_slot(i, info.newest_slot, seq, len) != SlotState::kValid || seq != info.sequence || len != info.length) {
    return core::Status::kStorageFailure;
  }
  if (len != 0) std::memcpy(out, scratch_ + kHeaderBytes, len);
  length = len;
  return core::Status::kOk;
}

core::Status KeyedStore::save(std::uint8_t key, const std::uint8_t* payload, std::size_t length) {
  const std::size_t i = index_of(key);
  if (i == count_ || length > specs_[i].capacity_bytes) return core::Status::kArgumentOutOfRange;
  KeyInfo& info = keys_[i];
  if (info.state == KeyState::kUnmounted) return core::Status::kStorageFailure;
  const std::uint8_t target = static_cast<std::uint8_t>(1 - info.newest_slot);
  const std::size_t offset = slot_offset(specs_, i, target);
  if (!info.target_clean) {
    const core::Status cleared = clear_crc(i, target);
    if (cleared != core::Status::kOk) return cleared;
    info.target_clean = true;
  }
  const std::uint32_t sequence = info.sequence + 1;
  const std::uint32_t n = static_cast<std::uint32_t>(length);
  std::memcpy(scratch_, kMagic, sizeof kMagic);
  scratch_[kKeyOffset] = key;
  scratch_[kReservedOffset] = 0;
  put_u16(scratch_ + kVersionOffset, specs_[i].layout_version);
  put_u32(scratch_ + kLengthOffset, n);
  put_u32(scratch_ + kSequenceOffset, sequence);
  put_u32(scratch_ + kCrcOffset, 0);
  if (length != 0) std::memcpy(scratch_ + kHeaderBytes, payload, length);
  put_u32(scratch_ + kCrcOffset, checksum::crc32(scratch_, kHeaderBytes + length));

  if (storage_.write(offset, scratch_, kHeaderBytes + length) != hal::IoStatus::kOk) {
    // The record may have landed whole (written, then the sync failed); the caller
    // keeps the old contents, so make sure a restart does too.
    const std::uint8_t blank[sizeof kMagic] = {};
    static_cast<void>(storage_.write(offset, blank, sizeof blank));
    info.target_clean = false;
    return core::Status::kStorageFailure;
  }
  info.target_clean = info.state == KeyState::kValid;  // the old newest copy is the next target
  info.state = KeyState::kValid;
  info.newest_slot = target;
  info.sequence = sequence;
  info.length = n;
  return core::Status::kOk;
}

std::uint32_t KeyedStore::sequence(std::uint8_t key) const {
  const std::size_t i = index_of(key);
  return i == count_ || keys_[i].state != KeyState::kValid ? 0 : keys_[i].sequence;
}

bool KeyedStore::damaged(std::uint8_t key) const {
  const std::size_t i = index_of(key);
  return i != count_ && keys_[i].state == KeyState::kDamaged;
}

}  // namespace trueaxis::macros
