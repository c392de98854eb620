// libFuzzer target: the persistent-record parser. A storage image is built from
// the input, then mounted by macros::KeyedStore (keyed_store.hpp) and started by
// a whole macros::Module (which loads the configuration, the work offsets and
// the three tables through their decoders).
//
// Input: | flags u8 | slot descriptions... |, each slot
//   | slot u8 (mod 2 x records) | damage u8 | sequence u32 | length u16 | payload |
// written with the layout of keyed_store.hpp (layout note 2) and a right CRC,
// unless `damage` asks otherwise: bit 0 a wrong CRC, bit 1 another key, bit 2
// another layout version, bit 3 a reserved byte not 0, bit 4 a broken magic.
// A length above the capacity is written as it is (with the payload cut at the
// slot's end). The CRC is computed here independently (IEEE 802.3).
//
// Invariants:
//  1. mount() of a full-size RAM image is kOk whatever it holds;
//  2. load() of every key is kOk with a length within the record's capacity;
//  3. for each key, save() of new contents is kOk, and a fresh mount of the
//     image loads exactly them, while every other key loads what it did before
//     (a save touches no other key's slots);
//  4. flags bit 0: Module::start() on the original image returns kOk and every
//     variable of the map is finite.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fuzz_support.hpp"
#include "trueaxis/macros/keyed_store.hpp"

namespace {

using trueaxis::core::Status;
using trueaxis::fuzz::FreshBench;
using trueaxis::fuzz::Input;
using trueaxis::fuzz::ModuleBench;
using trueaxis::macros::KeyedStore;
using trueaxis::macros::kRecordCount;
using trueaxis::macros::kRecordSpecs;
using trueaxis::macros::kRequiredStorageBytes;
using trueaxis::macros::kStoreScratchBytes;

using Image = std::array<std::uint8_t, kRequiredStorageBytes>;

std::uint32_t crc32(std::uint32_t crc, const std::uint8_t* p, std::size_t n) {
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void put_le(std::uint8_t* p, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

void write_slot(Input& in, Image& image) {
  const std::size_t index = (in.u8() % (2 * kRecordCount));
  const std::size_t record = index / 2;
  const std::uint8_t damage = in.u8();
  const std::uint32_t sequence = in.u32();
  const std::uint16_t length = in.u16();
  const std::size_t offset = KeyedStore::slot_offset(kRecordSpecs.data(), record, index % 2);
  const std::size_t room = KeyedStore::slot_bytes(kRecordSpecs[record]) - KeyedStore::kHeaderBytes;
  std::uint8_t* slot = image.data() + offset;

  std::memcpy(slot, "TAK1", 4);
  slot[4] = kRecordSpecs[record].key;
  slot[5] = 0;
  put_le(slot + 6, kRecordSpecs[record].layout_version, 2);
  put_le(slot + 8, length, 4);
  put_le(slot + 12, sequence, 4);
  put_le(slot + 16, 0, 4);
  if ((damage & 0x02) != 0) slot[4] = in.u8();
  if ((damage & 0x04) != 0) put_le(slot + 6, in.u16(), 2);
  if ((damage & 0x08) != 0) slot[5] = 1;
  if ((damage & 0x10) != 0) slot[in.u8() % 4] ^= 0x20;
  std::uint8_t* payload = slot + KeyedStore::kHeaderBytes;
  const std::size_t written = in.take(payload, length < room ? length : room);
  std::uint32_t crc = crc32(0, slot, KeyedStore::kHeaderBytes);
  crc = crc32(crc, payload, written);
  if ((damage & 0x01) != 0) crc ^= 1u << (in.u8() % 32);
  put_le(slot + 16, crc, 4);
}

struct Loaded {
  std::array<std::uint8_t, kStoreScratchBytes> bytes{};
  std::size_t length = 0;
};

// Invariant 2 for every key into `out`.
void load_all(KeyedStore& store, std::array<Loaded, kRecordCount>& out) {
  for (std::size_t i = 0; i < kRecordCount; ++i) {
    out[i].length = 0;
    FUZZ_CHECK(store.load(kRecordSpecs[i].key, out[i].bytes.data(), out[i].bytes.size(), out[i].length) ==
               Status::kOk);
    FUZZ_CHECK(out[i].length <= kRecordSpecs[i].capacity_bytes);
  }
}

bool same(const Loaded& a, const Loaded& b) {
  return a.length == b.length && std::memcmp(a.bytes.data(), b.bytes.data(), a.length) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Image original;
  static Image image;
  static std::array<std::uint8_t, kStoreScratchBytes> scratch;
  static std::array<Loaded, kRecordCount> loaded;
  static std::array<Loaded, kRecordCount> reloaded;
  static FreshBench fresh;

  Input in(data, size);
  const std::uint8_t flags = in.u8();
  original.fill(0);
  while (!in.empty()) write_slot(in, original);

  image = original;
  trueaxis::hal::RamNvStorage storage(image.data(), image.size());
  KeyedStore store(storage, kRecordSpecs.data(), kRecordCount, scratch.data(), scratch.size());
  FUZZ_CHECK(store.mount() == Status::kOk);
  load_all(store, loaded);

  for (std::size_t i = 0; i < kRecordCount; ++i) {
    // New contents: the old ones with one byte more (or one byte less at capacity), flipped.
    Loaded next = loaded[i];
    next.length = next.length < kRecordSpecs[i].capacity_bytes ? next.length + 1 : next.length - 1;
    for (std::size_t k = 0; k < next.length; ++k) next.bytes[k] = static_cast<std::uint8_t>(~next.bytes[k]);
    FUZZ_CHECK(store.save(kRecordSpecs[i].key, next.bytes.data(), next.length) == Status::kOk);
    KeyedStore again(storage, kRecordSpecs.data(), kRecordCount, scratch.data(), scratch.size());
    FUZZ_CHECK(again.mount() == Status::kOk);
    load_all(again, reloaded);
    for (std::size_t j = 0; j < kRecordCount; ++j) FUZZ_CHECK(same(reloaded[j], j == i ? next : loaded[j]));
    loaded[i] = next;
  }

  if ((flags & 0x01) != 0) {
    ModuleBench& b = fresh.make();
    b.nv = original;
    FUZZ_CHECK(b.module.start() == Status::kOk);
    for (const trueaxis::macros::VarInfo& v : trueaxis::macros::kRegisterMap) {
      for (std::uint16_t k = 0; k < v.count; ++k) {
        FUZZ_CHECK(std::isfinite(b.module.value(static_cast<std::uint16_t>(v.number + k))));
      }
    }
  }
  return 0;
}
