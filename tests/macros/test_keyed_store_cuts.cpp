// Power cuts during saves of the keyed store (tests/portable/store_harness.hpp
// states the property): the fake storage itself, a cut in a work-offset save
// of the product's own layout, and in a run of saves. A cut at every byte of
// one save and the random cut-and-restart cycles are portable tests
// (tests/portable/platform_store_test.cpp).
#include <catch2/catch.hpp>

#include <array>
#include <cstring>

#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "store_harness.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/records.hpp"

namespace m = trueaxis::macros;
namespace t = trueaxis::test;
using trueaxis::core::Status;
using m::KeyedStore;

namespace {

using TestContents = t::Contents<t::kTestRecordCount, t::kTestCapacity>;

const char* fault_name(t::Fault f) {
  switch (f) {
    case t::Fault::kStop: return "stop";
    case t::Fault::kTornWord: return "torn word";
    case t::Fault::kScattered: return "scattered";
  }
  return "?";
}

// Saves a random payload to every key `rounds` times, tracking the contents.
template <std::size_t kKeys, std::size_t kCapacity>
void fill(t::SplitMix64& rng, t::PowerCutStorage& storage, const m::RecordSpec* specs, std::uint8_t* scratch,
          std::size_t scratch_size, int rounds, t::Contents<kKeys, kCapacity>& contents) {
  KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
  REQUIRE(store.mount() == Status::kOk);
  static std::array<std::uint8_t, kCapacity> payload{};
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t i = 0; i < kKeys; ++i) {
      const std::size_t n = 1 + static_cast<std::size_t>(rng.next() % specs[i].capacity_bytes);
      t::fill_random(rng, payload.data(), n);
      REQUIRE(store.save(specs[i].key, payload.data(), n) == Status::kOk);
      contents.set(i, payload.data(), n);
    }
  }
}

}  // namespace

TEST_CASE("after a cut the fake storage refuses everything until power returns", "[store][powercut]") {
  std::array<std::uint8_t, 16> bytes{};
  t::PowerCutStorage storage(bytes.data(), bytes.size());
  const std::array<std::uint8_t, 8> ones{1, 1, 1, 1, 1, 1, 1, 1};
  storage.arm_cut(3, t::Fault::kStop, 1);
  CHECK(storage.write(0, ones.data(), ones.size()) == trueaxis::hal::IoStatus::kIoError);
  const auto after_cut = bytes;
  CHECK(after_cut[2] == 1);
  CHECK(after_cut[3] == 0);
  std::array<std::uint8_t, 4> out{};
  CHECK(storage.read(0, out.data(), out.size()) == trueaxis::hal::IoStatus::kIoError);
  CHECK(storage.write(8, ones.data(), ones.size()) == trueaxis::hal::IoStatus::kIoError);
  CHECK(bytes == after_cut);
  storage.restore_power();
  CHECK(storage.write(8, ones.data(), ones.size()) == trueaxis::hal::IoStatus::kOk);
  CHECK(bytes[15] == 1);
}

TEST_CASE("a cut at any byte of a work-offset save keeps every product record", "[store][powercut]") {
  static std::array<std::uint8_t, m::kRequiredStorageBytes> bytes{};
  static std::array<std::uint8_t, m::kRequiredStorageBytes> snapshot{};
  static std::array<std::uint8_t, m::kStoreScratchBytes> scratch{};
  static t::Contents<m::kRecordCount, 4096> before;
  std::array<std::uint8_t, 360> offsets{};
  t::SplitMix64 rng(0x5EED'0202);
  t::PowerCutStorage storage(bytes.data(), bytes.size());
  fill(rng, storage, m::kRecordSpecs.data(), scratch.data(), scratch.size(), 1, before);
  t::fill_random(rng, offsets.data(), offsets.size());
  for (const t::Fault fault : t::kFaults) {
    std::size_t failed_at = 0;
    const t::Verdict v = t::cut_every_byte(bytes.data(), bytes.size(), snapshot.data(), m::kRecordSpecs.data(),
                                           scratch.data(), scratch.size(), before, 1, offsets.data(),
                                           offsets.size(), fault, rng.next(), failed_at);
    INFO(fault_name(fault) << ", cut at byte " << failed_at);
    CHECK(v == t::Verdict::kOk);
  }
}

TEST_CASE("a cut at any byte of a run of saves keeps the completed ones", "[store][powercut]") {
  // Three saves, three write() calls; the budget walks across all of them.
  std::array<std::uint8_t, t::kTestRequiredBytes> bytes{};
  std::array<std::uint8_t, t::kTestRequiredBytes> snapshot{};
  std::array<std::uint8_t, t::kTestScratchBytes> scratch{};
  t::SplitMix64 rng(0x5EED'0203);
  TestContents initial;
  t::PowerCutStorage storage(bytes.data(), bytes.size());
  fill(rng, storage, t::kTestSpecs, scratch.data(), scratch.size(), 1, initial);
  snapshot = bytes;
  const std::size_t keys[3] = {2, 0, 2};
  std::array<std::array<std::uint8_t, t::kTestCapacity>, 3> payloads{};
  const std::size_t lengths[3] = {16, 48, 9};
  std::size_t total = 0;
  for (std::size_t s = 0; s < 3; ++s) {
    t::fill_random(rng, payloads[s].data(), lengths[s]);
    total += KeyedStore::kHeaderBytes + lengths[s];
  }
  for (const t::Fault fault : t::kFaults) {
    for (std::size_t budget = 0; budget <= total; ++budget) {
      bytes = snapshot;
      storage.restore_power();
      TestContents expected = initial;
      std::size_t cut_save = 3;
      {
        KeyedStore store(storage, t::kTestSpecs, t::kTestRecordCount, scratch.data(), scratch.size());
        REQUIRE(store.mount() == Status::kOk);
        storage.arm_cut(budget, fault, budget);
        for (std::size_t s = 0; s < 3; ++s) {
          const bool was_powered = storage.powered();
          if (store.save(t::kTestSpecs[keys[s]].key, payloads[s].data(), lengths[s]) == Status::kOk) {
            expected.set(keys[s], payloads[s].data(), lengths[s]);
          } else if (was_powered) {
            cut_save = s;
          }
        }
      }
      INFO(fault_name(fault) << ", budget " << budget << ", cut in save " << cut_save);
      REQUIRE(cut_save < 3);
      bool took_new = false;
      CHECK(t::restart_and_compare(storage, t::kTestSpecs, scratch.data(), scratch.size(), expected,
                                   keys[cut_save], payloads[cut_save].data(), lengths[cut_save],
                                   took_new) == t::Verdict::kOk);
    }
  }
}
