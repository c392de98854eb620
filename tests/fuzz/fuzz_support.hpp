// What the fuzz targets share: a reader over the fuzzer's bytes, the module on
// RAM storage built afresh for every input (so a reproducer replays alone), a
// snapshot of every variable and of the storage, and a check that aborts.
//
// Conventions
//  1. A target checks its invariants with FUZZ_CHECK: on failure it prints the
//     condition and aborts, which libFuzzer reports as a crash and saves the
//     input (crash-<sha1>) as the reproducer.
//  2. Past the end of the input, Input reads zeros: every input is valid and a
//     truncation only shortens what follows.
//  3. Nothing here is product code; the targets call the product's own headers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "fakes.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"

#define FUZZ_CHECK(condition)                                                               \
  do {                                                                                      \
    if (!(condition)) {                                                                     \
      std::fprintf(stderr, "%s:%d: invariant failed: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                         \
    }                                                                                       \
  } while (false)

namespace trueaxis::fuzz {

// Convention 2.
class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return at_ >= size_; }
  std::size_t left() const { return at_ < size_ ? size_ - at_ : 0; }
  std::uint8_t u8() { return at_ < size_ ? data_[at_++] : 0; }
  std::uint16_t u16() {
    const std::uint16_t hi = u8();
    return static_cast<std::uint16_t>((hi << 8) | u8());
  }
  std::uint32_t u32() {
    const std::uint32_t hi = u16();
    return (hi << 16) | u16();
  }
  // Up to n bytes (fewer at the end of the input) into out; the count copied.
  std::size_t take(std::uint8_t* out, std::size_t n) {
    const std::size_t k = n < left() ? n : left();
    if (k > 0) std::memcpy(out, data_ + at_, k);
    at_ += k;
    return k;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

// The module on RAM storage, as trueaxis-sim and the firmware image run it.
struct ModuleBench {
  std::array<std::uint8_t, macros::kRequiredStorageBytes> nv{};
  hal::RamNvStorage storage{nv.data(), nv.size()};
  test::FakeClock clock;
  macros::Module module{storage, clock};
};

// A ModuleBench in static storage, the same freshly constructed (not started)
// bench for every input, so each input starts from one state.
//
// Constructing a Module costs far more than a request (hundreds of KB of Eigen
// members set one coefficient at a time under the fuzzer's instrumentation), so
// the bench is constructed once and its bytes are kept; make() copies them back
// over the same address. That is sound for this bench and no other: it owns no
// heap and holds no pointer but into itself (the storage's bytes, the module's
// storage, clock and scratch), all at the same addresses after the copy.
class FreshBench {
 public:
  FreshBench() {
    bench_ = new (storage_) ModuleBench();
    std::memcpy(pristine_, storage_, sizeof storage_);
  }
  FreshBench(const FreshBench&) = delete;
  FreshBench& operator=(const FreshBench&) = delete;
  ~FreshBench() { bench_->~ModuleBench(); }

  static constexpr std::size_t kBytes = sizeof(ModuleBench);

  ModuleBench& make() {
    std::memcpy(storage_, pristine_, sizeof storage_);
    return *bench_;
  }
  // The present state's bytes, and putting such bytes back (same argument).
  void save(unsigned char* out) const { std::memcpy(out, storage_, sizeof storage_); }
  void restore(const unsigned char* in) { std::memcpy(storage_, in, sizeof storage_); }
  bool same_as(const unsigned char* bytes) const { return std::memcmp(storage_, bytes, sizeof storage_) == 0; }

 private:
  alignas(ModuleBench) unsigned char storage_[sizeof(ModuleBench)] = {};
  unsigned char pristine_[sizeof(ModuleBench)] = {};
  ModuleBench* bench_ = nullptr;
};

// Every variable of the map, bit for bit, and the whole storage.
struct Snapshot {
  std::array<std::uint64_t, macros::kVariableCount> bits{};
  std::array<std::uint8_t, macros::kRequiredStorageBytes> nv{};
  bool unlocked = false;

  void take(const ModuleBench& b) {
    std::size_t i = 0;
    for (const macros::VarInfo& v : macros::kRegisterMap) {
      for (std::uint16_t k = 0; k < v.count; ++k) {
        const auto number = static_cast<std::uint16_t>(v.number + k);
        // #9011 runs down with the clock, which differs between benches: not state.
        const double value = number == macros::var::kUnlockBackoffLeft ? 0.0 : b.module.value(number);
        std::memcpy(&bits[i++], &value, sizeof value);
      }
    }
    nv = b.nv;
    unlocked = b.module.unlocked();
  }

  // The first variable number that differs between a and b, ignoring the ones
  // a refusal is documented to change (#9007 the last fault, #9010 the failed
  // unlocks) and the ones the clock changes by itself (#9009 the interface's
  // grant lapses, #9011 the back-off runs down); 0 when none does.
  static std::uint16_t first_changed(const Snapshot& a, const Snapshot& b) {
    std::size_t i = 0;
    for (const macros::VarInfo& v : macros::kRegisterMap) {
      for (std::uint16_t k = 0; k < v.count; ++k, ++i) {
        const auto number = static_cast<std::uint16_t>(v.number + k);
        if (number == macros::var::kAccessFault || number == macros::var::kFailedUnlocks ||
            number == macros::var::kInterface || number == macros::var::kUnlockBackoffLeft) {
          continue;
        }
        if (a.bits[i] != b.bits[i]) return number;
      }
    }
    return 0;
  }
};

}  // namespace trueaxis::fuzz
