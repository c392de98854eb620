// Storage fakes for the keyed store (macros/keyed_store.hpp): heap-free, so the
// portable tests use them on the Cortex-M7 too.
//
// PowerCutStorage models a device that loses power in the middle of programming:
//  1. arm_cut(budget, fault, seed): the next `budget` bytes written (counted over
//     every write() call, so a cut can fall in any write of a run of saves) are
//     programmed; the write that reaches the budget is cut and returns kIoError.
//     A budget equal to the rest of a write lands it whole and still cuts: the
//     power died before the write could report.
//  2. The write that is cut leaves, by the fault model:
//       kStop       its first (budget) bytes programmed, in order, the rest old;
//       kTornWord   as kStop up to the 4-byte word holding the cut byte; that
//                   word's bytes (within the write) a random mix of old and new
//                   bits; the rest old;
//       kScattered  a random subset of (budget) of its bytes programmed, the
//                   order of programming being unknown.
//  3. After the cut the power is off: every read and write fails with kIoError
//     and changes nothing, until restore_power() (the restart).
//  4. Besides: refuse_writes (kIoError, nothing written), land_then_fail (written,
//     then kIoError, as a failed fsync), unreadable [from, to) (reads touching it
//     fail), and counters of the writes made.
#pragma once

#include <cstddef>
#include <cstdint>

#include "split_mix64.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/keyed_store.hpp"

namespace trueaxis::test {

enum class Fault : std::uint8_t { kStop, kTornWord, kScattered };
inline constexpr Fault kFaults[] = {Fault::kStop, Fault::kTornWord, Fault::kScattered};

class PowerCutStorage final : public hal::NvStorage {
 public:
  PowerCutStorage(std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}

  bool refuse_writes = false;
  bool land_then_fail = false;
  std::size_t unreadable_from = 0;
  std::size_t unreadable_to = 0;  // empty range: every byte reads

  // Counters since reset_counters().
  std::size_t write_calls = 0;
  std::size_t bytes_written = 0;
  std::size_t lowest_written = static_cast<std::size_t>(-1);
  std::size_t highest_written_end = 0;

  void arm_cut(std::size_t budget, Fault fault, std::uint64_t seed) {
    armed_ = true;
    budget_ = budget;
    fault_ = fault;
    rng_ = SplitMix64(seed);
  }
  bool powered() const { return powered_; }
  void restore_power() {
    powered_ = true;
    armed_ = false;
  }
  void reset_counters() {
    write_calls = 0;
    bytes_written = 0;
    lowest_written = static_cast<std::size_t>(-1);
    highest_written_end = 0;
  }

 private:
  std::size_t do_size_bytes() const override { return size_; }

  hal::IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) override {
    if (!powered_) return hal::IoStatus::kIoError;
    if (offset < unreadable_to && unreadable_from < offset + length) return hal::IoStatus::kIoError;
    for (std::size_t i = 0; i < length; ++i) out[i] = bytes_[offset + i];
    return hal::IoStatus::kOk;
  }

  hal::IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    if (!powered_ || refuse_writes) return hal::IoStatus::kIoError;
    ++write_calls;
    bytes_written += length;
    if (offset < lowest_written) lowest_written = offset;
    if (offset + length > highest_written_end) highest_written_end = offset + length;
    if (armed_ && budget_ <= length) {
      cut(offset, data, length);
      powered_ = false;
      return hal::IoStatus::kIoError;
    }
    if (armed_) budget_ -= length;
    for (std::size_t i = 0; i < length; ++i) bytes_[offset + i] = data[i];
    return land_then_fail ? hal::IoStatus::kIoError : hal::IoStatus::kOk;
  }

  void cut(std::size_t offset, const std::uint8_t* data, std::size_t length) {
    std::uint8_t* dst = bytes_ + offset;
    if (fault_ == Fault::kScattered) {
      // Selection sampling (Knuth, TAOCP 3.4.2, algorithm S): exactly budget_ of
      // the length bytes, each subset equally likely, without an index array.
      std::size_t chosen = 0;
      for (std::size_t i = 0; i < length && chosen < budget_; ++i) {
        if (rng_.next() % (length - i) < budget_ - chosen) {
          dst[i] = data[i];
          ++chosen;
        }
      }
      return;
    }
    std::size_t landed = budget_;
    if (fault_ == Fault::kTornWord && budget_ < length) {
      landed = (offset + budget_) / 4 * 4 - offset;  // start of the torn word, may precede offset
      if (landed > budget_) landed = 0;               // the word began before this write
      const std::size_t word_end = (offset + budget_) / 4 * 4 + 4 - offset;
      for (std::size_t i = landed; i < word_end && i < length; ++i) {
        const std::uint8_t mask = static_cast<std::uint8_t>(rng_.next());
        dst[i] = static_cast<std::uint8_t>((dst[i] & ~mask) | (data[i] & mask));
      }
    }
    for (std::size_t i = 0; i < landed; ++i) dst[i] = data[i];
  }

  std::uint8_t* bytes_;
  std::size_t size_;
  bool powered_ = true;
  bool armed_ = false;
  std::size_t budget_ = 0;
  Fault fault_ = Fault::kStop;
  SplitMix64 rng_{0};
};

// A small layout for the cut tests: keys not in order of number (7 after 2), a
// version other than 1, capacities whose slots need rounding.
//   key 1: 48 B -> slot 72;  key 2: 16 B -> slot 40;  key 7: 100 B -> slot 120
inline constexpr macros::RecordSpec kTestSpecs[] = {
    {1, 1, 48, "one"},
    {2, 1, 16, "two"},
    {7, 3, 100, "seven"},
};
inline constexpr std::size_t kTestRecordCount = 3;
inline constexpr std::size_t kTestCapacity = 100;       // the largest
inline constexpr std::size_t kTestRequiredBytes = 464;  // 2 x (72 + 40 + 120), by hand
inline constexpr std::size_t kTestScratchBytes = 120;
static_assert(macros::KeyedStore::required_bytes(kTestSpecs, kTestRecordCount) == kTestRequiredBytes);
static_assert(macros::KeyedStore::scratch_bytes(kTestSpecs, kTestRecordCount) == kTestScratchBytes);

}  // namespace trueaxis::test
