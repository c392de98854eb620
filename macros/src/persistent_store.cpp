#include "trueaxis/macros/persistent_store.hpp"

#include <cstring>

namespace trueaxis::macros {

namespace {

constexpr std::uint8_t kMagic[4] = {'T', 'A', 'X', '1'};
constexpr std::size_t kCrcOffset = 12;

void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void put_u64(std::uint8_t* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint16_t get_u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
std::uint64_t get_u64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

// a is newer than b in serial-number arithmetic (RFC 1982 style, 32 bits).
bool newer(std::uint32_t a, std::uint32_t b) { return a != b && static_cast<std::uint32_t>(a - b) < 0x80000000u; }

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t length) {
  // CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), bitwise: small and
  // fast enough for a table of a few kilobytes written by an integrator.
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < length; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

PersistentStore::SlotState PersistentStore::read_slot(std::size_t slot, std::uint32_t& sequence, std::size_t& count) {
  if (storage_.read(slot * kSlotBytes, buffer_, kSlotBytes) != hal::IoStatus::kOk) return SlotState::kUnreadable;
  if (std::memcmp(buffer_, kMagic, sizeof kMagic) != 0) return SlotState::kInvalid;
  if (get_u16(buffer_ + 4) != kLayoutVersion) return SlotState::kInvalid;
  count = get_u16(buffer_ + 6);
  if (count > kPersistentCount) return SlotState::kInvalid;
  const std::uint32_t stored_crc = get_u32(buffer_ + kCrcOffset);
  put_u32(buffer_ + kCrcOffset, 0);
  if (crc32(buffer_, kHeaderBytes + count * kEntryBytes) != stored_crc) return SlotState::kInvalid;
  sequence = get_u32(buffer_ + 8);
  return SlotState::kValid;
}

core::Status PersistentStore::load(PersistentEntry* entries, std::size_t capacity, std::size_t& count) {
  count = 0;
  if (storage_.size_bytes() < kRequiredBytes) return core::Status::kStorageFailure;
  std::uint32_t seq[2] = {0, 0};
  std::size_t n[2] = {0, 0};
  const SlotState state[2] = {read_slot(0, seq[0], n[0]), read_slot(1, seq[1], n[1])};
  // A slot that could not be read may hold the newest table: saving over the other
  // one would then lose it, so the store stays unusable until a load succeeds.
  if (state[0] == SlotState::kUnreadable || state[1] == SlotState::kUnreadable) return core::Status::kStorageFailure;
  const bool valid[2] = {state[0] == SlotState::kValid, state[1] == SlotState::kValid};
  loaded_ = true;
  if (!valid[0] && !valid[1]) {
    newest_slot_ = 1;
    sequence_ = 0;
    return core::Status::kOk;
  }
  const std::size_t best = (valid[0] && (!valid[1] || newer(seq[0], seq[1]))) ? 0 : 1;
  if (read_slot(best, seq[best], n[best]) != SlotState::kValid) {
    loaded_ = false;
    return core::Status::kStorageFailure;
  }
  newest_slot_ = best;
  sequence_ = seq[best];
  count = n[best] < capacity ? n[best] : capacity;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* p = buffer_ + kHeaderBytes + i * kEntryBytes;
    entries[i].number = get_u16(p);
    const std::uint64_t bits = get_u64(p + 2);
    std::memcpy(&entries[i].value, &bits, sizeof bits);
  }
  return core::Status::kOk;
}

core::Status PersistentStore::save(const PersistentEntry* entries, std::size_t count) {
  if (!loaded_ || count > kPersistentCount || storage_.size_bytes() < kRequiredBytes) {
    return core::Status::kStorageFailure;
  }
  const std::uint32_t sequence = sequence_ + 1;
  std::memset(buffer_, 0, kSlotBytes);
  std::memcpy(buffer_, kMagic, sizeof kMagic);
  put_u16(buffer_ + 4, kLayoutVersion);
  put_u16(buffer_ + 6, static_cast<std::uint16_t>(count));
  put_u32(buffer_ + 8, sequence);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint8_t* p = buffer_ + kHeaderBytes + i * kEntryBytes;
    put_u16(p, entries[i].number);
    std::uint64_t bits = 0;
    std::memcpy(&bits, &entries[i].value, sizeof bits);
    put_u64(p + 2, bits);
  }
  // The CRC covers the whole record, header included, with its own field as zero:
  // a cut that leaves a new sequence number over an old payload must not pass.
  put_u32(buffer_ + kCrcOffset, crc32(buffer_, kHeaderBytes + count * kEntryBytes));

  const std::size_t target = 1 - newest_slot_;
  if (storage_.write(target * kSlotBytes, buffer_, kSlotBytes) != hal::IoStatus::kOk) {
    // The refused record may have landed whole (written, then the sync failed);
    // the caller keeps the old values, so make sure a restart does too.
    const std::uint8_t blank[sizeof kMagic] = {};
    (void)storage_.write(target * kSlotBytes, blank, sizeof blank);
    return core::Status::kStorageFailure;
  }
  newest_slot_ = target;
  sequence_ = sequence;
  return core::Status::kOk;
}

}  // namespace trueaxis::macros
