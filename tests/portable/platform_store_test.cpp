// The keyed store, on the host and on the Cortex-M7: the CRC's check value, a
// power cut at every byte of a save of each key under three fault models from
// four starting states, and random cut-and-restart cycles (store_harness.hpp
// states the property; TRUEAXIS_STORE_CYCLES of them: 100,000 on the host).
// tests/macros/test_keyed_store*.cpp keep the store's other checks.
#include <cstdint>

#include "portable_test.hpp"
#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "store_harness.hpp"
#include "trueaxis/macros/keyed_store.hpp"

#ifndef TRUEAXIS_STORE_CYCLES
#define TRUEAXIS_STORE_CYCLES 2000
#endif

namespace {

namespace m = trueaxis::macros;
namespace t = trueaxis::test;
using trueaxis::core::Status;

using TestContents = t::Contents<t::kTestRecordCount, t::kTestCapacity>;

// Static: the target's stack is 64 KiB and the cases run one after the other.
std::uint8_t g_bytes[t::kTestRequiredBytes];
std::uint8_t g_snapshot[t::kTestRequiredBytes];
std::uint8_t g_scratch[t::kTestScratchBytes];
std::uint8_t g_payload[t::kTestCapacity];

void clear_bytes() {
  for (std::uint8_t& b : g_bytes) b = 0;
}

}  // namespace

TA_TEST("crc32 gives the standard check value, whole and incremental, and 0 for nothing") {
  const std::uint8_t text[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  TA_CHECK_EQ(m::checksum::crc32(text, sizeof text), 0xCBF43926u);
  TA_CHECK_EQ(m::checksum::crc32(text, 0), 0u);
  TA_CHECK_EQ(m::checksum::crc32_update(m::checksum::crc32(text, 4), text + 4, 5), 0xCBF43926u);
}

TA_TEST("a cut at any byte of a save leaves each key's old or new contents") {
  t::SplitMix64 rng(0x5EED'0201);
  int case_index = 0;
  // Before the save: blank; every key saved once (the target slot blank); twice
  // (the target holds an older copy); and with garbage in every blank slot.
  for (int prior = 0; prior < 4; ++prior) {
    clear_bytes();
    TestContents before;
    t::PowerCutStorage storage(g_bytes, sizeof g_bytes);
    if (prior == 3) t::fill_random(rng, g_bytes, sizeof g_bytes);
    if (prior > 0) {
      m::KeyedStore store(storage, t::kTestSpecs, t::kTestRecordCount, g_scratch, sizeof g_scratch);
      TA_REQUIRE(store.mount() == Status::kOk);
      for (int round = 0; round < (prior == 2 ? 2 : 1); ++round) {
        for (std::size_t i = 0; i < t::kTestRecordCount; ++i) {
          const std::size_t n = 1 + static_cast<std::size_t>(rng.next() % t::kTestSpecs[i].capacity_bytes);
          t::fill_random(rng, g_payload, n);
          TA_REQUIRE(store.save(t::kTestSpecs[i].key, g_payload, n) == Status::kOk);
          before.set(i, g_payload, n);
        }
      }
    }
    for (std::size_t index = 0; index < t::kTestRecordCount; ++index) {
      for (const t::Fault fault : t::kFaults) {
        TA_CASE_INDEX(case_index++);
        const std::size_t length = static_cast<std::size_t>(rng.next() % (t::kTestSpecs[index].capacity_bytes + 1));
        t::fill_random(rng, g_payload, length);
        std::size_t failed_at = 0;
        const t::Verdict v = t::cut_every_byte(g_bytes, sizeof g_bytes, g_snapshot, t::kTestSpecs, g_scratch,
                                               sizeof g_scratch, before, index, g_payload, length, fault,
                                               rng.next(), failed_at);
        TA_CHECK_EQ(v, t::Verdict::kOk);
        if (v != t::Verdict::kOk) TA_CHECK_EQ(failed_at, std::size_t{0});  // prints the cut byte
      }
    }
  }
}

TA_TEST("random cut-and-restart cycles keep every key whole, both outcomes of a cut occurring") {
  clear_bytes();
  t::PowerCutStorage storage(g_bytes, sizeof g_bytes);
  static TestContents expected;
  t::SplitMix64 rng(0x5EED'0302);
  constexpr std::size_t kCycles = TRUEAXIS_STORE_CYCLES;
  const t::CycleReport r =
      t::random_cycles(rng, kCycles, storage, t::kTestSpecs, g_scratch, sizeof g_scratch, expected);
  TA_CASE_INDEX(r.cycle);
  TA_CHECK_EQ(r.verdict, t::Verdict::kOk);
  // Both outcomes occur, so neither branch of the check went untried.
  TA_CHECK(r.cuts > kCycles * 8 / 10);
  TA_CHECK(r.took_new > kCycles / 100);
  TA_CHECK(r.cuts - r.took_new > kCycles / 100);
}
