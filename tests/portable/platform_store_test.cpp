// The keyed store under power cuts, on the host and on the Cortex-M7: the CRC's
// check value; the fake storage after a cut; a power cut at every byte of a
// save of each key of the test layout under three fault models from four
// starting states, and of a work-offset save in the product's own layout
// (records of up to 4096 bytes, lengths over 255); a cut at every byte of a run
// of saves; and random cut-and-restart cycles (store_harness.hpp states the
// property; TRUEAXIS_STORE_CYCLES of them: 100,000 on the host). The store's
// other contracts are platform_store_contract_test.cpp's;
// tests/macros/test_keyed_store.cpp keeps the host's reference and allocation
// checks.
#include <cstdint>
#include <cstring>

#include "portable_test.hpp"
#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "store_harness.hpp"
#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/records.hpp"

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

// Saves a random payload to every key `rounds` times, tracking the contents.
// Returns false when a mount or save failed (recorded as a failed check).
template <std::size_t kKeys, std::size_t kCapacity>
bool fill(t::SplitMix64& rng, t::PowerCutStorage& storage, const m::RecordSpec* specs, std::uint8_t* scratch,
          std::size_t scratch_size, int rounds, t::Contents<kKeys, kCapacity>& contents) {
  m::KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
  if (!TA_CHECK(store.mount() == Status::kOk)) return false;
  static std::uint8_t payload[kCapacity];
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t i = 0; i < kKeys; ++i) {
      const std::size_t n = 1 + static_cast<std::size_t>(rng.next() % specs[i].capacity_bytes);
      t::fill_random(rng, payload, n);
      if (!TA_CHECK(store.save(specs[i].key, payload, n) == Status::kOk)) return false;
      contents.set(i, payload, n);
    }
  }
  return true;
}

// The product's layout (records.hpp).
std::uint8_t g_product_bytes[m::kRequiredStorageBytes];
std::uint8_t g_product_snapshot[m::kRequiredStorageBytes];
std::uint8_t g_product_scratch[m::kStoreScratchBytes];

}  // namespace

TA_TEST("after a cut the fake storage refuses everything until power returns") {
  std::uint8_t bytes[16] = {};
  t::PowerCutStorage storage(bytes, sizeof bytes);
  const std::uint8_t ones[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  storage.arm_cut(3, t::Fault::kStop, 1);
  TA_CHECK_EQ(storage.write(0, ones, sizeof ones), trueaxis::hal::IoStatus::kIoError);
  std::uint8_t after_cut[16];
  std::memcpy(after_cut, bytes, sizeof bytes);
  TA_CHECK_EQ(after_cut[2], 1);
  TA_CHECK_EQ(after_cut[3], 0);
  std::uint8_t out[4] = {};
  TA_CHECK_EQ(storage.read(0, out, sizeof out), trueaxis::hal::IoStatus::kIoError);
  TA_CHECK_EQ(storage.write(8, ones, sizeof ones), trueaxis::hal::IoStatus::kIoError);
  TA_CHECK(std::memcmp(bytes, after_cut, sizeof bytes) == 0);
  storage.restore_power();
  TA_CHECK_EQ(storage.write(8, ones, sizeof ones), trueaxis::hal::IoStatus::kOk);
  TA_CHECK_EQ(bytes[15], 1);
}

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

// The same property in the product's own layout: every record saved once, then
// a work-offset save (360 bytes) cut at every byte. Case index: the fault model.
TA_TEST("a cut at any byte of a work-offset save keeps every product record") {
  static t::Contents<m::kRecordCount, 4096> before;
  std::uint8_t offsets[360] = {};
  t::SplitMix64 rng(0x5EED'0202);
  for (std::uint8_t& b : g_product_bytes) b = 0;
  t::PowerCutStorage storage(g_product_bytes, sizeof g_product_bytes);
  TA_REQUIRE(fill(rng, storage, m::kRecordSpecs.data(), g_product_scratch, sizeof g_product_scratch, 1, before));
  t::fill_random(rng, offsets, sizeof offsets);
  const std::size_t index = 1;  // the work offsets: the platform's second record
  TA_REQUIRE(m::kRecordSpecs[index].key == m::record_key(m::RecordKey::kWorkOffsets));
  for (std::size_t f = 0; f < 3; ++f) {
    TA_CASE_INDEX(f);
    std::size_t failed_at = 0;
    const t::Verdict v = t::cut_every_byte(g_product_bytes, sizeof g_product_bytes, g_product_snapshot,
                                           m::kRecordSpecs.data(), g_product_scratch, sizeof g_product_scratch,
                                           before, index, offsets, sizeof offsets, t::kFaults[f], rng.next(),
                                           failed_at);
    TA_CHECK_EQ(v, t::Verdict::kOk);
    if (v != t::Verdict::kOk) TA_CHECK_EQ(failed_at, std::size_t{0});  // prints the cut byte
  }
}

// Three saves, three write() calls: the budget walks across all of them; the
// saves completed before the cut are kept. Case index: 1000 x fault + budget.
TA_TEST("a cut at any byte of a run of saves keeps the completed ones") {
  clear_bytes();
  t::SplitMix64 rng(0x5EED'0203);
  TestContents initial;
  t::PowerCutStorage storage(g_bytes, sizeof g_bytes);
  TA_REQUIRE(fill(rng, storage, t::kTestSpecs, g_scratch, sizeof g_scratch, 1, initial));
  std::memcpy(g_snapshot, g_bytes, sizeof g_bytes);
  const std::size_t keys[3] = {2, 0, 2};
  std::uint8_t payloads[3][t::kTestCapacity] = {};
  const std::size_t lengths[3] = {16, 48, 9};
  std::size_t total = 0;
  for (std::size_t s = 0; s < 3; ++s) {
    t::fill_random(rng, payloads[s], lengths[s]);
    total += m::KeyedStore::kHeaderBytes + lengths[s];
  }
  for (std::size_t f = 0; f < 3; ++f) {
    for (std::size_t budget = 0; budget <= total; ++budget) {
      TA_CASE_INDEX(1000 * f + budget);
      std::memcpy(g_bytes, g_snapshot, sizeof g_bytes);
      storage.restore_power();
      TestContents expected = initial;
      std::size_t cut_save = 3;
      {
        m::KeyedStore store(storage, t::kTestSpecs, t::kTestRecordCount, g_scratch, sizeof g_scratch);
        TA_REQUIRE(store.mount() == Status::kOk);
        storage.arm_cut(budget, t::kFaults[f], budget);
        for (std::size_t s = 0; s < 3; ++s) {
          const bool was_powered = storage.powered();
          if (store.save(t::kTestSpecs[keys[s]].key, payloads[s], lengths[s]) == Status::kOk) {
            expected.set(keys[s], payloads[s], lengths[s]);
          } else if (was_powered) {
            cut_save = s;
          }
        }
      }
      TA_REQUIRE(cut_save < 3);
      bool took_new = false;
      const t::Verdict v = t::restart_and_compare(storage, t::kTestSpecs, g_scratch, sizeof g_scratch, expected,
                                                  keys[cut_save], payloads[cut_save], lengths[cut_save], took_new);
      TA_CHECK_EQ(v, t::Verdict::kOk);
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

TA_TEST("a record file reads back its payload; every bit flipped, every shorter or longer size and another key are refused") {
  static std::uint8_t payload[200];
  for (std::size_t i = 0; i < sizeof payload; ++i) payload[i] = static_cast<std::uint8_t>(i * 37 + 11);
  static std::uint8_t file[sizeof payload + m::kRecordFileOverhead + 8];
  const std::size_t size = m::encode_record_file(3, payload, sizeof payload, file, sizeof file);
  TA_REQUIRE(size == sizeof payload + m::kRecordFileOverhead);
  TA_CHECK_EQ(m::encode_record_file(3, payload, sizeof payload, file, size - 1), 0u);  // does not fit
  const std::uint8_t* got = nullptr;
  std::size_t length = 0;
  TA_REQUIRE(m::decode_record_file(3, file, size, got, length) == m::RecordFileError::kNone);
  TA_CHECK(got == file + 16 && length == sizeof payload && std::memcmp(got, payload, length) == 0);
  TA_CHECK(m::decode_record_file(5, file, size, got, length) == m::RecordFileError::kWrongRecord);
  for (std::size_t bit = 0; bit < 8 * size; ++bit) {
    TA_CASE_INDEX(static_cast<int>(bit));
    file[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    TA_CHECK(m::decode_record_file(3, file, size, got, length) != m::RecordFileError::kNone);
    file[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
  }
  for (std::size_t n = 0; n < size + 8; ++n) {
    if (n == size) continue;
    TA_CASE_INDEX(static_cast<int>(n));
    const m::RecordFileError e = m::decode_record_file(3, file, n, got, length);
    TA_CHECK(e == (n < m::kRecordFileOverhead ? m::RecordFileError::kNotAFile : m::RecordFileError::kLength));
  }
  TA_CHECK(m::decode_record_file(3, file, size, got, length) == m::RecordFileError::kNone);
}

TA_TEST("a record file whose header breaks a rule under a valid CRC is refused by that rule: the reserved byte, the version, the key") {
  static std::uint8_t payload[40];
  for (std::size_t i = 0; i < sizeof payload; ++i) payload[i] = static_cast<std::uint8_t>(i * 13 + 5);
  static std::uint8_t file[sizeof payload + m::kRecordFileOverhead];
  const std::uint8_t* got = nullptr;
  std::size_t length = 0;
  // The file made again with byte `at` set to `value` and its CRC put right.
  const auto with = [&](std::size_t at, std::uint8_t value) -> m::RecordFileError {
    TA_CHECK(m::encode_record_file(5, payload, sizeof payload, file, sizeof file) == sizeof file);
    file[at] = value;
    trueaxis::core::put_u32(file + 16 + sizeof payload, m::checksum::crc32(file, 16 + sizeof payload));
    return m::decode_record_file(5, file, sizeof file, got, length);
  };
  TA_CHECK(with(11, 0) == m::RecordFileError::kNone);  // reserved 0: the file as written
  for (int value = 1; value < 256; ++value) {  // reserved byte 11 set, each value
    TA_CASE_INDEX(value);
    TA_CHECK(with(11, static_cast<std::uint8_t>(value)) == m::RecordFileError::kVersion);
  }
  TA_CHECK(with(8, 0) == m::RecordFileError::kVersion);  // layout version 0, 2, 257 (high byte)
  TA_CHECK(with(8, 2) == m::RecordFileError::kVersion);
  TA_CHECK(with(9, 1) == m::RecordFileError::kVersion);
  TA_CHECK(with(10, 3) == m::RecordFileError::kWrongRecord);  // the rigidity table's key, expected the spindle's
  TA_CHECK(with(10, 5) == m::RecordFileError::kNone);
  TA_CHECK(with(0, 't') == m::RecordFileError::kNotAFile);
}
