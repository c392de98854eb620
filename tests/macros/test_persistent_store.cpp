#include <catch2/catch.hpp>

#include <array>
#include <initializer_list>

#include "fakes.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/persistent_store.hpp"

namespace m = trueaxis::macros;
using trueaxis::core::Status;

namespace {

using Entries = std::array<m::PersistentEntry, m::kPersistentCount>;

std::array<m::PersistentEntry, 3> table(double base) {
  return {{{500, base}, {501, base + 1}, {5281, base + 2}}};
}

// What a store that has just been constructed over `storage` loads.
struct Loaded {
  Status status = Status::kOk;
  Entries entries{};
  std::size_t count = 0;
};
Loaded load_fresh(trueaxis::hal::NvStorage& storage) {
  m::PersistentStore store(storage);
  Loaded l;
  l.status = store.load(l.entries.data(), l.entries.size(), l.count);
  return l;
}

// Loads (as start-up does), then saves table(base) for each base in turn.
void load_and_save(m::PersistentStore& store, std::initializer_list<double> bases) {
  Entries scratch{};
  std::size_t n = 0;
  REQUIRE(store.load(scratch.data(), scratch.size(), n) == Status::kOk);
  for (double base : bases) {
    const auto t = table(base);
    REQUIRE(store.save(t.data(), t.size()) == Status::kOk);
  }
}

}  // namespace

TEST_CASE("crc32 matches the standard check value", "[store]") {
  const std::uint8_t text[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(m::crc32(text, sizeof text) == 0xCBF43926u);
}

TEST_CASE("blank storage loads as no entries", "[store]") {
  trueaxis::test::FlakyStorage storage;
  const Loaded l = load_fresh(storage);
  REQUIRE(l.status == Status::kOk);
  CHECK(l.count == 0);
}

TEST_CASE("the newest save wins and alternates slots", "[store]") {
  trueaxis::test::FlakyStorage storage;
  m::PersistentStore store(storage);
  load_and_save(store, {});
  for (int i = 0; i < 5; ++i) {
    const auto t = table(10.0 * i);
    REQUIRE(store.save(t.data(), t.size()) == Status::kOk);
    const Loaded l = load_fresh(storage);
    REQUIRE(l.status == Status::kOk);
    REQUIRE(l.count == 3);
    CHECK(l.entries[0].value == 10.0 * i);
    CHECK(l.entries[2].number == 5281);
  }
}

TEST_CASE("a power cut at any byte of a save keeps the previous table", "[store][powercut]") {
  for (long cut = 0; cut < static_cast<long>(m::PersistentStore::kSlotBytes); cut += 1) {
    trueaxis::test::FlakyStorage storage;
    {
      m::PersistentStore store(storage);
      load_and_save(store, {1.0, 2.0});
      storage.cut_after_bytes = cut;
      const auto c = table(3.0);
      CHECK(store.save(c.data(), c.size()) == Status::kStorageFailure);
    }
    storage.cut_after_bytes = -1;
    m::PersistentStore after(storage);
    Entries out{};
    std::size_t n = 0;
    REQUIRE(after.load(out.data(), out.size(), n) == Status::kOk);
    REQUIRE(n == 3);
    // The previous table, or the new one when every byte that differs had been
    // written before the cut; never a mixture of the two.
    CHECK((out[0].value == 2.0 || out[0].value == 3.0));
    if (cut <= 8) CHECK(out[0].value == 2.0);  // the new sequence number never landed
    CHECK(out[1].value == out[0].value + 1.0);
    CHECK(out[2].value == out[0].value + 2.0);
    // And the store goes on working after the cut.
    const auto d = table(4.0);
    REQUIRE(after.save(d.data(), d.size()) == Status::kOk);
    const Loaded again = load_fresh(storage);
    REQUIRE(again.status == Status::kOk);
    CHECK(again.entries[0].value == 4.0);
  }
}

TEST_CASE("a corrupted newest slot falls back to the other", "[store]") {
  trueaxis::test::FlakyStorage storage;
  m::PersistentStore store(storage);
  load_and_save(store, {1.0, 2.0});  // slot 0, then slot 1
  storage.bytes[m::PersistentStore::kSlotBytes + m::PersistentStore::kHeaderBytes + 3] ^= 0x10;
  const Loaded l = load_fresh(storage);
  REQUIRE(l.status == Status::kOk);
  CHECK(l.entries[0].value == 1.0);
}

TEST_CASE("the module skips stored numbers it no longer holds as persistent", "[store]") {
  trueaxis::test::FlakyStorage storage;
  {
    m::PersistentStore store(storage);
    load_and_save(store, {});
    const std::array<m::PersistentEntry, 4> entries{{{1, 7.0}, {500, -60.0}, {504, 0.25}, {4000, 1.0}}};
    REQUIRE(store.save(entries.data(), entries.size()) == Status::kOk);
  }
  trueaxis::test::FakeClock clock;
  m::Module module(storage, clock);
  REQUIRE(module.start() == Status::kOk);
  CHECK(module.value(1) == 0.0);        // an argument is never loaded
  CHECK(module.value(500) == -60.0);    // a known configuration value is
  CHECK(module.value(504) == 1.0);      // a value the map would refuse keeps the default
}

TEST_CASE("a read failure at start-up is reported and no save may overwrite the unread table", "[store]") {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  {
    m::Module module(storage, clock);
    REQUIRE(module.start() == Status::kOk);
    const double offsets[2] = {4.0, 5.0};
    REQUIRE(module.write(5221, 2, offsets) == m::AccessFault::kNone);
  }
  const auto stored = storage.bytes;
  {
    storage.refuse_reads = true;
    m::Module blind(storage, clock);
    CHECK(blind.start() == Status::kStorageFailure);
    storage.refuse_reads = false;
    const double value = 42.0;
    CHECK(blind.write(5222, 1, &value) == m::AccessFault::kStorageFailure);
    CHECK(storage.bytes == stored);
  }
  m::Module again(storage, clock);
  REQUIRE(again.start() == Status::kOk);
  CHECK(again.value(5221) == 4.0);
  CHECK(again.value(5222) == 5.0);
}

TEST_CASE("a refused save that landed anyway is not loaded after a restart", "[store]") {
  trueaxis::test::FlakyStorage storage;
  trueaxis::test::FakeClock clock;
  {
    m::Module module(storage, clock);
    REQUIRE(module.start() == Status::kOk);
    const double v = 1.0;
    REQUIRE(module.write(5221, 1, &v) == m::AccessFault::kNone);
    storage.land_then_fail = true;
    const double w = 2.0;
    CHECK(module.write(5221, 1, &w) == m::AccessFault::kStorageFailure);
    CHECK(module.value(5221) == 1.0);
    storage.land_then_fail = false;
  }
  m::Module again(storage, clock);
  REQUIRE(again.start() == Status::kOk);
  CHECK(again.value(5221) == 1.0);
}
