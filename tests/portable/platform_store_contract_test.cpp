// The keyed store's contract (macros/store/include/trueaxis/macros/keyed_store.hpp),
// on the host and on the Cortex-M7: the layout, blank keys, every single-bit
// flip, damaged and foreign records, the sequence's wrap, the bytes a save
// writes, and failures that return their status and change nothing. Power cuts
// are platform_store_test.cpp's; tests/macros/test_keyed_store.cpp keeps the
// host's checks against the bitwise reference and the allocation count.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "portable_test.hpp"
#include "store_fakes.hpp"
#include "store_reference.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/records.hpp"

namespace {

namespace m = trueaxis::macros;
namespace t = trueaxis::test;
using m::KeyedStore;
using trueaxis::core::Status;

// A payload of the test layout (at most its largest capacity).
struct Bytes {
  std::uint8_t data[t::kTestCapacity] = {};
  std::size_t size = 0;

  bool empty() const { return size == 0; }
  bool operator==(const Bytes& other) const {
    return size == other.size && (size == 0 || std::memcmp(data, other.data, size) == 0);
  }
};

void fill_pattern(std::uint8_t* out, std::size_t n, std::uint8_t seed) {
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(seed + 37 * i);
}

Bytes pattern(std::size_t n, std::uint8_t seed) {
  Bytes b;
  b.size = n < sizeof b.data ? n : sizeof b.data;
  fill_pattern(b.data, b.size, seed);
  return b;
}

// Storage, scratch and specs of one device over the test layout.
struct Device {
  std::array<std::uint8_t, t::kTestRequiredBytes> bytes{};
  t::PowerCutStorage storage{bytes.data(), bytes.size()};
  std::array<std::uint8_t, t::kTestScratchBytes> scratch{};
  std::array<m::RecordSpec, t::kTestRecordCount> specs{{t::kTestSpecs[0], t::kTestSpecs[1], t::kTestSpecs[2]}};

  KeyedStore store() { return KeyedStore(storage, specs.data(), specs.size(), scratch.data(), scratch.size()); }
  std::size_t slot(std::size_t index, std::size_t s) const { return KeyedStore::slot_offset(specs.data(), index, s); }
  // A store over the device's bytes, mounted.
  KeyedStore mounted() {
    KeyedStore s = store();
    TA_CHECK_EQ(s.mount(), Status::kOk);
    return s;
  }
};

// What key loads; the load must return `expected`.
Bytes load(KeyedStore& store, std::uint8_t key, Status expected = Status::kOk) {
  Bytes out;
  std::size_t n = 99;
  TA_CHECK_EQ(store.load(key, out.data, sizeof out.data, n), expected);
  out.size = n < sizeof out.data ? n : sizeof out.data;
  return out;
}

// A new store over the device's bytes, as after a restart: what key loads.
Bytes load_fresh(Device& d, std::uint8_t key) {
  KeyedStore store = d.mounted();
  return load(store, key);
}

void save(KeyedStore& store, std::uint8_t key, const Bytes& b) {
  TA_CHECK_EQ(store.save(key, b.data, b.size), Status::kOk);
}

// The product's layout (records.hpp), static: the target's stack is 64 KiB.
std::array<std::uint8_t, m::kRequiredStorageBytes> g_product_bytes;
std::array<std::uint8_t, m::kRequiredStorageBytes> g_product_before;
std::array<std::uint8_t, m::kStoreScratchBytes> g_product_scratch;
std::uint8_t g_product_payload[m::kStoreScratchBytes];

}  // namespace

TA_TEST("store layout: slots follow the spec list, each rounded up to 8 bytes") {
  const m::RecordSpec* s = t::kTestSpecs;
  TA_CHECK_EQ(KeyedStore::slot_bytes(s[0]), std::size_t{72});
  TA_CHECK_EQ(KeyedStore::slot_bytes(s[1]), std::size_t{40});
  TA_CHECK_EQ(KeyedStore::slot_bytes(s[2]), std::size_t{120});
  TA_CHECK_EQ(KeyedStore::slot_offset(s, 1, 0), std::size_t{144});
  TA_CHECK_EQ(KeyedStore::slot_offset(s, 1, 1), std::size_t{184});
  TA_CHECK_EQ(KeyedStore::slot_offset(s, 2, 1), std::size_t{344});
}

// records.hpp states the sizes with every method built (six records: the
// platform's two, three tables, the measuring log); a set with fewer methods
// has fewer records, and nothing to check here.
TA_TEST("store layout: with every method built the product's records need the sizes records.hpp states") {
  if (m::kRecordCount != 6) return;
  TA_CHECK_EQ(m::kRequiredStorageBytes, std::size_t{2 * (1304 + 384 + 4120 + 3096 + 2072 + 3288)});
  TA_CHECK_EQ(m::kStoreScratchBytes, std::size_t{4120});
}

TA_TEST("a blank device loads every key as absent") {
  Device d;
  KeyedStore store = d.store();
  TA_REQUIRE(store.mount() == Status::kOk);
  for (const m::RecordSpec& s : d.specs) {
    TA_CHECK(load(store, s.key).empty());
    TA_CHECK_EQ(store.sequence(s.key), 0u);
  }
}

TA_TEST("every single-bit flip of a saved record is detected") {
  const Bytes old_payload = pattern(48, 1);
  const Bytes new_payload = pattern(48, 2);
  for (int other_slot_valid = 0; other_slot_valid < 2; ++other_slot_valid) {
    TA_CASE_INDEX(other_slot_valid * 1000);  // 1000 x (other slot valid) + the flipped bit
    Device d;
    {
      KeyedStore store = d.store();
      TA_REQUIRE(store.mount() == Status::kOk);
      save(store, 1, old_payload);  // slot 0
      save(store, 1, new_payload);  // slot 1, the newest
    }
    if (other_slot_valid == 0) d.bytes[d.slot(0, 0)] ^= 0xFF;  // slot 0's magic broken
    TA_REQUIRE(load_fresh(d, 1) == new_payload);
    const auto saved = d.bytes;
    const std::size_t at = d.slot(0, 1);
    const Bytes expected = other_slot_valid == 1 ? old_payload : Bytes{};
    for (std::size_t bit = 0; bit < 8 * (KeyedStore::kHeaderBytes + 48); ++bit) {
      TA_CASE_INDEX(static_cast<std::size_t>(other_slot_valid) * 1000 + bit);
      d.bytes = saved;
      d.bytes[at + bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
      TA_CHECK(load_fresh(d, 1) == expected);
    }
  }
}

namespace {

// The start of each part of the next case: key 1 saved once (slot 0, its only copy).
struct DamagedFixture {
  Device d;
  Bytes payload = pattern(40, 3);
  std::array<std::uint8_t, t::kTestRequiredBytes> saved{};
  std::size_t at = 0;

  DamagedFixture() {
    {
      KeyedStore store = d.mounted();
      for (const m::RecordSpec& s : d.specs) TA_CHECK(!store.damaged(s.key));
      save(store, 1, payload);
      TA_CHECK(!store.damaged(1));
    }
    saved = d.bytes;
    at = d.slot(0, 0);
  }
};

}  // namespace

TA_TEST("a record whose CRC fails is damaged; a blank or foreign slot is absent") {
  {  // a flipped payload bit: damaged, loads as absent, the other keys untouched
    DamagedFixture f;
    f.d.bytes[f.at + KeyedStore::kHeaderBytes + 7] ^= 0x10;
    KeyedStore store = f.d.mounted();
    TA_CHECK(store.damaged(1));
    TA_CHECK(load(store, 1).empty());
    TA_CHECK_EQ(store.sequence(1), 0u);
    TA_CHECK(!store.damaged(2));
    TA_CHECK(!store.damaged(200));  // unknown key
    // the next save replaces it, and it is no longer damaged
    save(store, 1, pattern(40, 4));
    TA_CHECK(!store.damaged(1));
    KeyedStore again = f.d.mounted();
    TA_CHECK(!again.damaged(1));
    TA_CHECK(load(again, 1) == pattern(40, 4));
  }
  {  // a flipped sequence or CRC bit: damaged
    DamagedFixture f;
    f.d.bytes[f.at + 12] ^= 0x01;
    TA_CHECK(f.d.mounted().damaged(1));
    f.d.bytes = f.saved;
    f.d.bytes[f.at + 19] ^= 0x80;
    TA_CHECK(f.d.mounted().damaged(1));
  }
  {  // a broken magic, key or layout version: absent, not damaged
    DamagedFixture f;
    for (const std::size_t byte : {std::size_t{0}, std::size_t{4}, std::size_t{6}}) {
      TA_CASE_INDEX(byte);
      f.d.bytes = f.saved;
      f.d.bytes[f.at + byte] ^= 0x01;
      KeyedStore store = f.d.mounted();
      TA_CHECK(!store.damaged(1));
      TA_CHECK(load(store, 1).empty());
    }
    TA_CASE_INDEX(-1);
  }
  {  // a damaged newest copy beside a valid older one: the older loads, not damaged
    DamagedFixture f;
    {
      KeyedStore store = f.d.mounted();
      save(store, 1, pattern(40, 5));  // slot 1, newest
    }
    f.d.bytes[f.d.slot(0, 1) + KeyedStore::kHeaderBytes] ^= 0x02;
    KeyedStore store = f.d.mounted();
    TA_CHECK(!store.damaged(1));
    TA_CHECK(load(store, 1) == f.payload);
  }
}

TA_TEST("a flip after mount is caught by load") {
  Device d;
  KeyedStore store = d.store();
  TA_REQUIRE(store.mount() == Status::kOk);
  save(store, 2, pattern(16, 5));
  d.bytes[d.slot(1, 0) + KeyedStore::kHeaderBytes + 3] ^= 0x40;
  load(store, 2, Status::kStorageFailure);
}

TA_TEST("the sequence counter wraps") {
  Device d;
  const Bytes a = pattern(10, 3);
  const Bytes b = pattern(12, 4);
  t::reference_record(2, 1, 0xFFFF'FFFEu, a.data, a.size, d.bytes.data() + d.slot(1, 0));
  t::reference_record(2, 1, 0xFFFF'FFFFu, b.data, b.size, d.bytes.data() + d.slot(1, 1));
  KeyedStore store = d.store();
  TA_REQUIRE(store.mount() == Status::kOk);
  TA_CHECK_EQ(store.sequence(2), 0xFFFF'FFFFu);
  TA_CHECK(load(store, 2) == b);
  const Bytes c = pattern(16, 5);
  save(store, 2, c);
  TA_CHECK_EQ(store.sequence(2), 0u);
  KeyedStore after = d.store();
  TA_REQUIRE(after.mount() == Status::kOk);
  TA_CHECK_EQ(after.sequence(2), 0u);
  TA_CHECK(load(after, 2) == c);
  const Bytes e = pattern(1, 6);
  save(after, 2, e);
  TA_CHECK_EQ(after.sequence(2), 1u);
  TA_CHECK(load_fresh(d, 2) == e);
}

TA_TEST("a save writes only its own key's slots, in one write once both hold a copy") {
  g_product_bytes.fill(0);
  t::PowerCutStorage storage(g_product_bytes.data(), g_product_bytes.size());
  KeyedStore store(storage, m::kRecordSpecs.data(), m::kRecordCount, g_product_scratch.data(),
                   g_product_scratch.size());
  TA_REQUIRE(store.mount() == Status::kOk);
  for (std::size_t i = 0; i < m::kRecordCount; ++i) {
    const m::RecordSpec& spec = m::kRecordSpecs[i];
    fill_pattern(g_product_payload, spec.capacity_bytes, static_cast<std::uint8_t>(i));
    const std::size_t lo = KeyedStore::slot_offset(m::kRecordSpecs.data(), i, 0);
    const std::size_t hi = KeyedStore::slot_offset(m::kRecordSpecs.data(), i, 2);
    for (int repeat = 0; repeat < 3; ++repeat) {
      TA_CASE_INDEX(3 * i + static_cast<std::size_t>(repeat));  // record i's save `repeat`
      g_product_before = g_product_bytes;
      storage.reset_counters();
      TA_CHECK_EQ(store.save(spec.key, g_product_payload, spec.capacity_bytes), Status::kOk);
      // The first save into each blank slot clears its CRC field first (4 bytes).
      const std::size_t clearing = repeat < 2 ? 4 : 0;
      TA_CHECK_EQ(storage.write_calls, std::size_t{repeat < 2 ? 2u : 1u});
      TA_CHECK_EQ(storage.bytes_written, KeyedStore::kHeaderBytes + spec.capacity_bytes + clearing);
      TA_CHECK(storage.lowest_written >= lo);
      TA_CHECK(storage.highest_written_end <= hi);
      TA_CHECK(std::memcmp(g_product_bytes.data(), g_product_before.data(), lo) == 0);
      TA_CHECK(std::memcmp(g_product_bytes.data() + hi, g_product_before.data() + hi, g_product_bytes.size() - hi) ==
               0);
    }
  }
  TA_CASE_INDEX(-1);
  // The work offsets are the record a probing cycle rewrites.
  storage.reset_counters();
  fill_pattern(g_product_payload, 360, 9);
  TA_CHECK_EQ(store.save(m::record_key(m::RecordKey::kWorkOffsets), g_product_payload, 360), Status::kOk);
  TA_CHECK_EQ(storage.bytes_written, std::size_t{380});
}

namespace {

// The start of each part of the next case: key 1 holds an older copy (slot 0)
// and the newest (slot 1), so the next save of key 1 is one write.
struct FailureFixture {
  Device d;
  Bytes old_payload = pattern(40, 7);
  std::array<std::uint8_t, t::kTestRequiredBytes> saved{};
  Bytes next = pattern(20, 8);

  FailureFixture() {
    {
      KeyedStore store = d.mounted();
      save(store, 1, pattern(48, 6));  // slot 0: an older copy, so the next save is one write
      save(store, 1, old_payload);     // slot 1: the newest
    }
    saved = d.bytes;
  }
};

}  // namespace

TA_TEST("failures return their status and change nothing") {
  {  // a refused write is kStorageFailure and the old contents stay
    FailureFixture f;
    Device& d = f.d;
    KeyedStore store = d.mounted();
    d.storage.refuse_writes = true;
    TA_CHECK_EQ(store.save(1, f.next.data, f.next.size), Status::kStorageFailure);
    TA_CHECK_EQ(store.save(2, f.next.data, 16), Status::kStorageFailure);  // refused at its CRC clearing
    TA_CHECK(d.bytes == f.saved);
    d.storage.refuse_writes = false;
    TA_CHECK(load(store, 1) == f.old_payload);
    TA_CHECK(load_fresh(d, 1) == f.old_payload);
    save(store, 1, f.next);
    TA_CHECK(load_fresh(d, 1) == f.next);
  }
  {  // a write that lands and then fails is invalidated
    FailureFixture f;
    Device& d = f.d;
    KeyedStore store = d.mounted();
    d.storage.land_then_fail = true;
    TA_CHECK_EQ(store.save(1, f.next.data, f.next.size), Status::kStorageFailure);
    d.storage.land_then_fail = false;
    TA_CHECK_EQ(store.sequence(1), 2u);
    TA_CHECK(load_fresh(d, 1) == f.old_payload);
  }
  {  // an unreadable slot at mount blocks that key until a mount succeeds
    FailureFixture f;
    Device& d = f.d;
    d.storage.unreadable_from = d.slot(0, 1);  // the newest copy
    d.storage.unreadable_to = d.slot(0, 1) + 1;
    KeyedStore store = d.store();
    TA_CHECK_EQ(store.mount(), Status::kStorageFailure);
    load(store, 1, Status::kStorageFailure);
    TA_CHECK_EQ(store.save(1, f.next.data, f.next.size), Status::kStorageFailure);
    TA_CHECK(d.bytes == f.saved);
    save(store, 2, pattern(16, 1));  // the other keys work
    d.storage.unreadable_to = 0;
    TA_CHECK_EQ(store.mount(), Status::kOk);
    TA_CHECK(load(store, 1) == f.old_payload);
    save(store, 1, f.next);
    TA_CHECK(load_fresh(d, 1) == f.next);
  }
  {  // a record of another layout version loads as absent
    FailureFixture f;
    Device& d = f.d;
    d.specs[0].layout_version = 2;
    KeyedStore store = d.mounted();
    TA_CHECK(load(store, 1).empty());
    TA_CHECK_EQ(store.sequence(1), 0u);
    TA_CHECK(d.bytes == f.saved);
  }
  {  // a stored length over the capacity loads as absent
    FailureFixture f;
    Device& d = f.d;
    d.specs[0].capacity_bytes = 39;  // the record holds 40; the slot stays 64 + 8
    KeyedStore store = d.mounted();
    TA_CHECK(load(store, 1).empty());
  }
  {  // a payload over the capacity, or over the caller's buffer, is kArgumentOutOfRange
    FailureFixture f;
    Device& d = f.d;
    KeyedStore store = d.mounted();
    const Bytes big = pattern(49, 1);
    d.storage.reset_counters();
    TA_CHECK_EQ(store.save(1, big.data, big.size), Status::kArgumentOutOfRange);
    TA_CHECK_EQ(d.storage.write_calls, std::size_t{0});
    std::array<std::uint8_t, 39> small{};
    std::size_t n = 5;
    TA_CHECK_EQ(store.load(1, small.data(), small.size(), n), Status::kArgumentOutOfRange);
    TA_CHECK_EQ(n, std::size_t{0});
    TA_CHECK(small == (std::array<std::uint8_t, 39>{}));
  }
  {  // an unknown key is kArgumentOutOfRange
    FailureFixture f;
    Device& d = f.d;
    KeyedStore store = d.mounted();
    TA_CHECK_EQ(store.save(3, f.next.data, f.next.size), Status::kArgumentOutOfRange);
    load(store, 0, Status::kArgumentOutOfRange);
    TA_CHECK_EQ(store.sequence(3), 0u);
    TA_CHECK(d.bytes == f.saved);
  }
  {  // storage too small: the keys whose slots end beyond it refuse everything, the
     // others work; bad specs, a small scratch or no mount refuse everything
    FailureFixture f;
    Device& d = f.d;
    const std::uint8_t last = d.specs[d.specs.size() - 1].key;
    const std::uint8_t first = d.specs[0].key;
    t::PowerCutStorage small(d.bytes.data(), d.bytes.size() - 1);
    KeyedStore too_small(small, d.specs.data(), d.specs.size(), d.scratch.data(), d.scratch.size());
    TA_CHECK_EQ(too_small.mount(), Status::kStorageFailure);
    TA_CHECK_EQ(too_small.save(last, f.next.data, f.next.size), Status::kStorageFailure);
    load(too_small, last, Status::kStorageFailure);
    TA_CHECK(d.bytes == f.saved);  // nothing written so far
    load(too_small, first, Status::kOk);
    TA_CHECK(KeyedStore::slot_offset(d.specs.data(), d.specs.size() - 1, 2) > d.bytes.size() - 1);
    t::PowerCutStorage tiny(d.bytes.data(), 0);
    KeyedStore none(tiny, d.specs.data(), d.specs.size(), d.scratch.data(), d.scratch.size());
    TA_CHECK_EQ(none.mount(), Status::kStorageFailure);
    load(none, first, Status::kStorageFailure);
    d.specs[1].key = 1;
    TA_CHECK_EQ(d.store().mount(), Status::kArgumentOutOfRange);
    d.specs[1].key = 2;
    KeyedStore short_scratch(d.storage, d.specs.data(), d.specs.size(), d.scratch.data(), d.scratch.size() - 1);
    TA_CHECK_EQ(short_scratch.mount(), Status::kArgumentOutOfRange);
    KeyedStore unmounted = d.store();
    TA_CHECK_EQ(unmounted.save(1, f.next.data, f.next.size), Status::kStorageFailure);
    load(unmounted, 1, Status::kStorageFailure);
    TA_CHECK(d.bytes == f.saved);
  }
}

namespace {

// A device whose next writes do what a script says, one act per write() call:
// land whole (kLand), land and report failure (kLandThenFail, a failed sync),
// be refused with nothing written (kRefuse), or program only their first
// `cut` bytes and fail (kCut). Writes beyond the script land.
class ScriptedStorage final : public trueaxis::hal::NvStorage {
 public:
  enum class Act : std::uint8_t { kLand, kLandThenFail, kRefuse, kCut };
  struct Step {
    Act act;
    std::size_t cut;
  };

  ScriptedStorage(std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}
  template <std::size_t N>
  void script(const Step (&steps)[N]) {
    steps_ = steps;
    count_ = N;
    next_ = 0;
  }

 private:
  std::size_t do_size_bytes() const override { return size_; }
  trueaxis::hal::IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) override {
    std::memcpy(out, bytes_ + offset, length);
    return trueaxis::hal::IoStatus::kOk;
  }
  trueaxis::hal::IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    const Step step = next_ < count_ ? steps_[next_++] : Step{Act::kLand, 0};
    switch (step.act) {
      case Act::kLand:
        std::memcpy(bytes_ + offset, data, length);
        return trueaxis::hal::IoStatus::kOk;
      case Act::kLandThenFail:
        std::memcpy(bytes_ + offset, data, length);
        return trueaxis::hal::IoStatus::kIoError;
      case Act::kRefuse:
        return trueaxis::hal::IoStatus::kIoError;
      case Act::kCut:
        std::memcpy(bytes_ + offset, data, step.cut < length ? step.cut : length);
        return trueaxis::hal::IoStatus::kIoError;
    }
    return trueaxis::hal::IoStatus::kIoError;
  }

  std::uint8_t* bytes_;
  std::size_t size_;
  const Step* steps_ = nullptr;
  std::size_t count_ = 0;
  std::size_t next_ = 0;
};

}  // namespace

TA_TEST("a save that reported failure does not come back when the next save is cut after its sequence field") {
  // X is stored. Y's save clears the other slot's CRC (a slot never written
  // since the mount), lands whole but reports failure, and the write that
  // would blank it is refused: Y sits valid (sequence 2) in the other slot, and
  // the store must clear that slot's CRC before it writes there again. Z, as
  // long as Y, is then cut after 16 bytes: magic .. sequence (Z's sequence is
  // Y's, 2), not its CRC, and the power is gone (the blanking write after it
  // fails). Y's CRC must stay cleared: after a restart X loads.
  using Act = ScriptedStorage::Act;
  static std::array<std::uint8_t, t::kTestRequiredBytes> bytes{};
  bytes.fill(0);
  ScriptedStorage storage(bytes.data(), bytes.size());
  std::array<std::uint8_t, t::kTestScratchBytes> scratch{};
  const m::RecordSpec* specs = t::kTestSpecs;
  const Bytes x = pattern(30, 1), y = pattern(30, 2), z = pattern(30, 3);
  {
    KeyedStore store(storage, specs, t::kTestRecordCount, scratch.data(), scratch.size());
    TA_REQUIRE(store.mount() == Status::kOk);
    save(store, 1, x);
    static const ScriptedStorage::Step y_fails[] = {{Act::kLand, 0}, {Act::kLandThenFail, 0}, {Act::kRefuse, 0}};
    storage.script(y_fails);
    TA_CHECK_EQ(store.save(1, y.data, y.size), Status::kStorageFailure);
    TA_CHECK(load(store, 1) == x);
    {
      KeyedStore look(storage, specs, t::kTestRecordCount, scratch.data(), scratch.size());
      TA_REQUIRE(look.mount() == Status::kOk);
      TA_CHECK(load(look, 1) == y);  // the scene: a restart now would find Y (its save was cut: allowed)
    }
    static const ScriptedStorage::Step z_cut[] = {{Act::kLand, 0}, {Act::kCut, 16}, {Act::kRefuse, 0}};
    storage.script(z_cut);
    TA_CHECK_EQ(store.save(1, z.data, z.size), Status::kStorageFailure);
  }
  KeyedStore restarted(storage, specs, t::kTestRecordCount, scratch.data(), scratch.size());
  TA_REQUIRE(restarted.mount() == Status::kOk);
  TA_CHECK(load(restarted, 1) == x);
}
