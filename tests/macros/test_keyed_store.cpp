// The keyed store against the host's oracles: crc32 against a bitwise CRC on
// random messages, and the bytes a save writes against an independent writer
// (store_reference.hpp, tests/portable); and its allocation count. The store's
// contracts and its power cuts are portable tests, run on the host and on the
// Cortex-M7 (tests/portable/platform_store_contract_test.cpp,
// tests/portable/platform_store_test.cpp).
#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <vector>

#include "alloc_counter.hpp"
#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "store_reference.hpp"
#include "trueaxis/macros/keyed_store.hpp"

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

// The layout's sizes are a portable test (tests/portable/platform_store_contract_test.cpp).
TEST_CASE("saves write the documented bytes and alternate slots with rising sequence", "[store]") {
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
