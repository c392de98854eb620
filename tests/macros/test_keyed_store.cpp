#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <vector>

#include "alloc_counter.hpp"
#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "store_reference.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/records.hpp"

namespace m = trueaxis::macros;
namespace t = trueaxis::test;
using trueaxis::core::Status;
using m::KeyedStore;

namespace {

using Bytes = std::vector<std::uint8_t>;

// Storage, scratch and specs of one device over the test layout.
struct Device {
  std::array<std::uint8_t, t::kTestRequiredBytes> bytes{};
  t::PowerCutStorage storage{bytes.data(), bytes.size()};
  std::array<std::uint8_t, t::kTestScratchBytes> scratch{};
  std::array<m::RecordSpec, t::kTestRecordCount> specs{{t::kTestSpecs[0], t::kTestSpecs[1], t::kTestSpecs[2]}};

  KeyedStore store() { return KeyedStore(storage, specs.data(), specs.size(), scratch.data(), scratch.size()); }
  std::size_t slot(std::size_t index, std::size_t s) const { return KeyedStore::slot_offset(specs.data(), index, s); }
};

Bytes pattern(std::size_t n, std::uint8_t seed) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(seed + 37 * i);
  return b;
}

Bytes load(KeyedStore& store, std::uint8_t key, Status expected = Status::kOk) {
  Bytes out(t::kTestCapacity);
  std::size_t n = 99;
  REQUIRE(store.load(key, out.data(), out.size(), n) == expected);
  out.resize(n);
  return out;
}

// A new store over the device's bytes, as after a restart: what key loads.
Bytes load_fresh(Device& d, std::uint8_t key) {
  KeyedStore store = d.store();
  REQUIRE(store.mount() == Status::kOk);
  return load(store, key);
}

void save(KeyedStore& store, std::uint8_t key, const Bytes& b) {
  REQUIRE(store.save(key, b.data(), b.size()) == Status::kOk);
}

}  // namespace

// The check value is a portable test (tests/portable/platform_store_test.cpp).
TEST_CASE("crc32 agrees with a bitwise CRC on random messages split anywhere", "[store]") {
  t::SplitMix64 rng(0x5EED'0101);
  std::array<std::uint8_t, 300> msg{};
  for (int trial = 0; trial < 500; ++trial) {
    const std::size_t n = static_cast<std::size_t>(rng.next() % msg.size());
    for (std::size_t i = 0; i < n; ++i) msg[i] = static_cast<std::uint8_t>(rng.next());
    const std::size_t split = n == 0 ? 0 : static_cast<std::size_t>(rng.next() % (n + 1));
    const std::uint32_t whole = t::reference_crc32(msg.data(), n);
    CHECK(m::checksum::crc32(msg.data(), n) == whole);
    CHECK(m::checksum::crc32_update(m::checksum::crc32(msg.data(), split), msg.data() + split, n - split) == whole);
  }
}

TEST_CASE("the layout is the documented one", "[store]") {
  SECTION("slots follow the spec list, each rounded up to 8 bytes") {
    const m::RecordSpec* s = t::kTestSpecs;
    CHECK(KeyedStore::slot_bytes(s[0]) == 72);
    CHECK(KeyedStore::slot_bytes(s[1]) == 40);
    CHECK(KeyedStore::slot_bytes(s[2]) == 120);
    CHECK(KeyedStore::slot_offset(s, 1, 0) == 144);
    CHECK(KeyedStore::slot_offset(s, 1, 1) == 184);
    CHECK(KeyedStore::slot_offset(s, 2, 1) == 344);
  }
  SECTION("the product's records need the sizes records.hpp states") {
    CHECK(m::kRequiredStorageBytes == 2 * (1304 + 384 + 4120 + 3096 + 2072));
    CHECK(m::kStoreScratchBytes == 4120);
  }
  SECTION("saves write the documented bytes and alternate slots with rising sequence") {
    Device d;
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    for (std::uint32_t seq = 1; seq <= 4; ++seq) {
      const Bytes b = pattern(30 + seq, static_cast<std::uint8_t>(seq));
      save(store, 7, b);
      CHECK(store.sequence(7) == seq);
      std::array<std::uint8_t, 120> expected{};
      const std::size_t n = t::reference_record(7, 3, seq, b.data(), b.size(), expected.data());
      const std::size_t at = d.slot(2, (seq - 1) % 2);
      CHECK(std::memcmp(d.bytes.data() + at, expected.data(), n) == 0);
      CHECK(load_fresh(d, 7) == b);
    }
  }
}

TEST_CASE("a blank device loads every key as absent", "[store]") {
  Device d;
  KeyedStore store = d.store();
  REQUIRE(store.mount() == Status::kOk);
  for (const m::RecordSpec& s : d.specs) {
    CHECK(load(store, s.key).empty());
    CHECK(store.sequence(s.key) == 0);
  }
}

TEST_CASE("every single-bit flip of a saved record is detected", "[store]") {
  const Bytes old_payload = pattern(48, 1);
  const Bytes new_payload = pattern(48, 2);
  for (int other_slot_valid = 0; other_slot_valid < 2; ++other_slot_valid) {
    Device d;
    {
      KeyedStore store = d.store();
      REQUIRE(store.mount() == Status::kOk);
      save(store, 1, old_payload);  // slot 0
      save(store, 1, new_payload);  // slot 1, the newest
    }
    if (other_slot_valid == 0) d.bytes[d.slot(0, 0)] ^= 0xFF;  // slot 0's magic broken
    REQUIRE(load_fresh(d, 1) == new_payload);
    const auto saved = d.bytes;
    const std::size_t at = d.slot(0, 1);
    for (std::size_t bit = 0; bit < 8 * (KeyedStore::kHeaderBytes + 48); ++bit) {
      d.bytes = saved;
      d.bytes[at + bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
      INFO("bit " << bit << ", other slot valid " << other_slot_valid);
      const Bytes loaded = load_fresh(d, 1);
      CHECK(loaded == (other_slot_valid == 1 ? old_payload : Bytes{}));
    }
  }
}

TEST_CASE("a record whose CRC fails is damaged; a blank or foreign slot is absent", "[store]") {
  Device d;
  const Bytes payload = pattern(40, 3);
  {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    for (const m::RecordSpec& s : d.specs) CHECK_FALSE(store.damaged(s.key));
    save(store, 1, payload);  // slot 0, the key's only copy
    CHECK_FALSE(store.damaged(1));
  }
  const auto saved = d.bytes;
  const std::size_t at = d.slot(0, 0);
  const auto mounted = [&d]() {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    return store;
  };

  SECTION("a flipped payload bit: damaged, loads as absent, the other keys untouched") {
    d.bytes[at + KeyedStore::kHeaderBytes + 7] ^= 0x10;
    KeyedStore store = mounted();
    CHECK(store.damaged(1));
    CHECK(load(store, 1).empty());
    CHECK(store.sequence(1) == 0);
    CHECK_FALSE(store.damaged(2));
    CHECK_FALSE(store.damaged(200));  // unknown key
    SECTION("the next save replaces it, and it is no longer damaged") {
      save(store, 1, pattern(40, 4));
      CHECK_FALSE(store.damaged(1));
      KeyedStore again = mounted();
      CHECK_FALSE(again.damaged(1));
      CHECK(load(again, 1) == pattern(40, 4));
    }
  }
  SECTION("a flipped sequence or CRC bit: damaged") {
    d.bytes[at + 12] ^= 0x01;
    CHECK(mounted().damaged(1));
    d.bytes = saved;
    d.bytes[at + 19] ^= 0x80;
    CHECK(mounted().damaged(1));
  }
  SECTION("a broken magic, key or layout version: absent, not damaged") {
    for (const std::size_t byte : {std::size_t{0}, std::size_t{4}, std::size_t{6}}) {
      d.bytes = saved;
      d.bytes[at + byte] ^= 0x01;
      KeyedStore store = mounted();
      CHECK_FALSE(store.damaged(1));
      CHECK(load(store, 1).empty());
    }
  }
  SECTION("a damaged newest copy beside a valid older one: the older loads, not damaged") {
    {
      KeyedStore store = mounted();
      save(store, 1, pattern(40, 5));  // slot 1, newest
    }
    d.bytes[d.slot(0, 1) + KeyedStore::kHeaderBytes] ^= 0x02;
    KeyedStore store = mounted();
    CHECK_FALSE(store.damaged(1));
    CHECK(load(store, 1) == payload);
  }
}

TEST_CASE("a flip after mount is caught by load", "[store]") {
  Device d;
  KeyedStore store = d.store();
  REQUIRE(store.mount() == Status::kOk);
  save(store, 2, pattern(16, 5));
  d.bytes[d.slot(1, 0) + KeyedStore::kHeaderBytes + 3] ^= 0x40;
  load(store, 2, Status::kStorageFailure);
}

TEST_CASE("the sequence counter wraps", "[store]") {
  Device d;
  const Bytes a = pattern(10, 3);
  const Bytes b = pattern(12, 4);
  t::reference_record(2, 1, 0xFFFF'FFFEu, a.data(), a.size(), d.bytes.data() + d.slot(1, 0));
  t::reference_record(2, 1, 0xFFFF'FFFFu, b.data(), b.size(), d.bytes.data() + d.slot(1, 1));
  KeyedStore store = d.store();
  REQUIRE(store.mount() == Status::kOk);
  CHECK(store.sequence(2) == 0xFFFF'FFFFu);
  CHECK(load(store, 2) == b);
  const Bytes c = pattern(16, 5);
  save(store, 2, c);
  CHECK(store.sequence(2) == 0u);
  KeyedStore after = d.store();
  REQUIRE(after.mount() == Status::kOk);
  CHECK(after.sequence(2) == 0u);
  CHECK(load(after, 2) == c);
  const Bytes e = pattern(1, 6);
  save(after, 2, e);
  CHECK(after.sequence(2) == 1u);
  CHECK(load_fresh(d, 2) == e);
}

TEST_CASE("a save writes only its own key's slots, in one write once both hold a copy", "[store]") {
  static std::array<std::uint8_t, m::kRequiredStorageBytes> bytes{};
  static std::array<std::uint8_t, m::kStoreScratchBytes> scratch{};
  bytes.fill(0);
  t::PowerCutStorage storage(bytes.data(), bytes.size());
  KeyedStore store(storage, m::kRecordSpecs.data(), m::kRecordCount, scratch.data(), scratch.size());
  REQUIRE(store.mount() == Status::kOk);
  for (std::size_t i = 0; i < m::kRecordCount; ++i) {
    const m::RecordSpec& spec = m::kRecordSpecs[i];
    const Bytes payload = pattern(spec.capacity_bytes, static_cast<std::uint8_t>(i));
    const std::size_t lo = KeyedStore::slot_offset(m::kRecordSpecs.data(), i, 0);
    const std::size_t hi = KeyedStore::slot_offset(m::kRecordSpecs.data(), i, 2);
    for (int repeat = 0; repeat < 3; ++repeat) {
      const auto before = bytes;
      storage.reset_counters();
      save(store, spec.key, payload);
      INFO(spec.name << " save " << repeat << ": " << storage.bytes_written << " bytes");
      // The first save into each blank slot clears its CRC field first (4 bytes).
      const std::size_t clearing = repeat < 2 ? 4 : 0;
      CHECK(storage.write_calls == (repeat < 2 ? 2u : 1u));
      CHECK(storage.bytes_written == KeyedStore::kHeaderBytes + spec.capacity_bytes + clearing);
      CHECK(storage.lowest_written >= lo);
      CHECK(storage.highest_written_end <= hi);
      CHECK(std::memcmp(bytes.data(), before.data(), lo) == 0);
      CHECK(std::memcmp(bytes.data() + hi, before.data() + hi, bytes.size() - hi) == 0);
    }
  }
  // The work offsets are the record a probing cycle rewrites.
  storage.reset_counters();
  const Bytes offsets = pattern(360, 9);
  save(store, m::record_key(m::RecordKey::kWorkOffsets), offsets);
  CHECK(storage.bytes_written == 380);
}

TEST_CASE("failures return their status and change nothing", "[store]") {
  Device d;
  const Bytes old_payload = pattern(40, 7);
  {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    save(store, 1, pattern(48, 6));  // slot 0: an older copy, so the next save is one write
    save(store, 1, old_payload);     // slot 1: the newest
  }
  const auto saved = d.bytes;
  const Bytes next = pattern(20, 8);

  SECTION("a refused write is kStorageFailure and the old contents stay") {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    d.storage.refuse_writes = true;
    CHECK(store.save(1, next.data(), next.size()) == Status::kStorageFailure);
    CHECK(store.save(2, next.data(), 16) == Status::kStorageFailure);  // refused at its CRC clearing
    CHECK(d.bytes == saved);
    d.storage.refuse_writes = false;
    CHECK(load(store, 1) == old_payload);
    CHECK(load_fresh(d, 1) == old_payload);
    save(store, 1, next);
    CHECK(load_fresh(d, 1) == next);
  }
  SECTION("a write that lands and then fails is invalidated") {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    d.storage.land_then_fail = true;
    CHECK(store.save(1, next.data(), next.size()) == Status::kStorageFailure);
    d.storage.land_then_fail = false;
    CHECK(store.sequence(1) == 2);
    CHECK(load_fresh(d, 1) == old_payload);
  }
  SECTION("an unreadable slot at mount blocks that key until a mount succeeds") {
    d.storage.unreadable_from = d.slot(0, 1);  // the newest copy
    d.storage.unreadable_to = d.slot(0, 1) + 1;
    KeyedStore store = d.store();
    CHECK(store.mount() == Status::kStorageFailure);
    load(store, 1, Status::kStorageFailure);
    CHECK(store.save(1, next.data(), next.size()) == Status::kStorageFailure);
    CHECK(d.bytes == saved);
    save(store, 2, pattern(16, 1));  // the other keys work
    d.storage.unreadable_to = 0;
    CHECK(store.mount() == Status::kOk);
    CHECK(load(store, 1) == old_payload);
    save(store, 1, next);
    CHECK(load_fresh(d, 1) == next);
  }
  SECTION("a record of another layout version loads as absent") {
    d.specs[0].layout_version = 2;
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    CHECK(load(store, 1).empty());
    CHECK(store.sequence(1) == 0);
    CHECK(d.bytes == saved);
  }
  SECTION("a stored length over the capacity loads as absent") {
    d.specs[0].capacity_bytes = 39;  // the record holds 40; the slot stays 64 + 8
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    CHECK(load(store, 1).empty());
  }
  SECTION("a payload over the capacity, or over the caller's buffer, is kArgumentOutOfRange") {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    const Bytes big = pattern(49, 1);
    d.storage.reset_counters();
    CHECK(store.save(1, big.data(), big.size()) == Status::kArgumentOutOfRange);
    CHECK(d.storage.write_calls == 0);
    std::array<std::uint8_t, 39> small{};
    std::size_t n = 5;
    CHECK(store.load(1, small.data(), small.size(), n) == Status::kArgumentOutOfRange);
    CHECK(n == 0);
    CHECK(small == std::array<std::uint8_t, 39>{});
  }
  SECTION("an unknown key is kArgumentOutOfRange") {
    KeyedStore store = d.store();
    REQUIRE(store.mount() == Status::kOk);
    CHECK(store.save(3, next.data(), next.size()) == Status::kArgumentOutOfRange);
    load(store, 0, Status::kArgumentOutOfRange);
    CHECK(store.sequence(3) == 0);
    CHECK(d.bytes == saved);
  }
  SECTION("storage too small, bad specs, a small scratch or no mount refuse everything") {
    t::PowerCutStorage small(d.bytes.data(), d.bytes.size() - 1);
    KeyedStore too_small(small, d.specs.data(), d.specs.size(), d.scratch.data(), d.scratch.size());
    CHECK(too_small.mount() == Status::kStorageFailure);
    CHECK(too_small.save(1, next.data(), next.size()) == Status::kStorageFailure);
    load(too_small, 1, Status::kStorageFailure);
    d.specs[1].key = 1;
    CHECK(d.store().mount() == Status::kArgumentOutOfRange);
    d.specs[1].key = 2;
    KeyedStore short_scratch(d.storage, d.specs.data(), d.specs.size(), d.scratch.data(), d.scratch.size() - 1);
    CHECK(short_scratch.mount() == Status::kArgumentOutOfRange);
    KeyedStore unmounted = d.store();
    CHECK(unmounted.save(1, next.data(), next.size()) == Status::kStorageFailure);
    load(unmounted, 1, Status::kStorageFailure);
    CHECK(d.bytes == saved);
  }
}

TEST_CASE("mount, load and save allocate nothing", "[store]") {
  Device d;
  std::array<std::uint8_t, 100> payload{};
  std::array<std::uint8_t, 100> out{};
  std::size_t n = 0;
  KeyedStore store = d.store();
  t::AllocationScope scope;
  REQUIRE(store.mount() == Status::kOk);
  REQUIRE(store.save(7, payload.data(), payload.size()) == Status::kOk);
  REQUIRE(store.load(7, out.data(), out.size(), n) == Status::kOk);
  CHECK(scope.count() == 0);
}
