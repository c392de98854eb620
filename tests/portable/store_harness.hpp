// Cut-and-restart checks of the keyed store, shared by the host (Catch2) and the
// portable tests: each returns a Verdict that the test framework checks.
//
// The property: after a power cut during a save of key K and a restart (a new
// KeyedStore over the same bytes, mount, load of every key), K holds exactly its
// contents before the save or the new ones, never a mixture and never nothing;
// every other key holds its contents before the save.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "split_mix64.hpp"
#include "store_fakes.hpp"
#include "trueaxis/macros/keyed_store.hpp"

namespace trueaxis::test {

enum class Verdict : std::uint8_t {
  kOk = 0,
  kSetupFailed = 1,       // a save without a cut did not succeed
  kCutNotReported = 2,    // the cut save returned kOk
  kMountFailed = 3,       // the restart's mount did not return kOk
  kLoadFailed = 4,        // a load after the restart did not return kOk
  kCutKeyWrong = 5,       // the cut key holds neither its old nor its new contents
  kOtherKeyWrong = 6,     // another key's contents changed
  kNewNotLoaded = 7,      // every byte of the save landed, yet the old contents loaded
};

// The expected contents of each key of a layout (length 0: none or empty).
template <std::size_t kKeys, std::size_t kCapacity>
struct Contents {
  std::uint8_t bytes[kKeys][kCapacity] = {};
  std::size_t length[kKeys] = {};

  bool equals(std::size_t index, const std::uint8_t* data, std::size_t n) const {
    return n == length[index] && (n == 0 || std::memcmp(bytes[index], data, n) == 0);
  }
  void set(std::size_t index, const std::uint8_t* data, std::size_t n) {
    length[index] = n;
    if (n != 0) std::memcpy(bytes[index], data, n);
  }
};

inline void fill_random(SplitMix64& rng, std::uint8_t* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) data[i] = static_cast<std::uint8_t>(rng.next());
}

// Restarts over `storage` (powered again) and compares every key with `before`,
// except key index `cut_index`, which may hold `before` or the new payload.
// took_new tells which it held.
template <std::size_t kKeys, std::size_t kCapacity>
Verdict restart_and_compare(PowerCutStorage& storage, const macros::RecordSpec* specs, std::uint8_t* scratch,
                            std::size_t scratch_size, const Contents<kKeys, kCapacity>& before,
                            std::size_t cut_index, const std::uint8_t* payload, std::size_t length,
                            bool& took_new) {
  took_new = false;
  storage.restore_power();
  macros::KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
  if (store.mount() != core::Status::kOk) return Verdict::kMountFailed;
  for (std::size_t i = 0; i < kKeys; ++i) {
    std::uint8_t out[kCapacity];
    std::size_t n = 0;
    if (store.load(specs[i].key, out, kCapacity, n) != core::Status::kOk) return Verdict::kLoadFailed;
    if (before.equals(i, out, n)) continue;
    if (i != cut_index) return Verdict::kOtherKeyWrong;
    if (n != length || (n != 0 && std::memcmp(out, payload, n) != 0)) return Verdict::kCutKeyWrong;
    took_new = true;
  }
  // A save whose contents equal the old ones is both: count it as new.
  if (cut_index < kKeys && before.equals(cut_index, payload, length)) took_new = true;
  return Verdict::kOk;
}

// Over `bytes` as they are, saves `payload` to specs[index] and cuts the save at
// every byte it programs (the record, and the CRC clearing before it when the
// slot needs one) under `fault`; after each cut, restarts and compares. Restores
// `bytes` after each cut. `before` holds what `bytes` store.
template <std::size_t kKeys, std::size_t kCapacity>
Verdict cut_every_byte(std::uint8_t* bytes, std::size_t size, std::uint8_t* snapshot, const macros::RecordSpec* specs,
                       std::uint8_t* scratch, std::size_t scratch_size, const Contents<kKeys, kCapacity>& before,
                       std::size_t index, const std::uint8_t* payload, std::size_t length, Fault fault,
                       std::uint64_t seed, std::size_t& failed_at) {
  std::memcpy(snapshot, bytes, size);
  std::size_t programmed = 0;  // bytes the save writes, counted on a save without a cut
  {
    PowerCutStorage storage(bytes, size);
    macros::KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
    if (store.mount() != core::Status::kOk) return Verdict::kSetupFailed;
    if (store.save(specs[index].key, payload, length) != core::Status::kOk) return Verdict::kSetupFailed;
    programmed = storage.bytes_written;
  }
  for (std::size_t cut = 0; cut <= programmed; ++cut) {
    failed_at = cut;
    std::memcpy(bytes, snapshot, size);
    PowerCutStorage storage(bytes, size);
    {
      macros::KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
      if (store.mount() != core::Status::kOk) return Verdict::kSetupFailed;
      storage.arm_cut(cut, fault, seed + cut);
      if (store.save(specs[index].key, payload, length) == core::Status::kOk) return Verdict::kCutNotReported;
    }
    bool took_new = false;
    const Verdict v =
        restart_and_compare(storage, specs, scratch, scratch_size, before, index, payload, length, took_new);
    if (v != Verdict::kOk) return v;
    if (cut == programmed && !took_new) return Verdict::kNewNotLoaded;
  }
  std::memcpy(bytes, snapshot, size);
  return Verdict::kOk;
}

struct CycleReport {
  Verdict verdict = Verdict::kOk;
  std::size_t cycle = 0;  // the failing one
  std::size_t cuts = 0;   // cycles that cut a save
  std::size_t took_new = 0;
};

// `cycles` power cycles over the test layout on `storage` (which the caller
// starts blank): each mounts, makes 0..3 saves of random keys, lengths and
// contents, the cut (if any) armed at a random byte of the run of saves under a
// random fault model, then restarts and compares. One cycle in eight has no cut.
template <std::size_t kKeys, std::size_t kCapacity>
CycleReport random_cycles(SplitMix64& rng, std::size_t cycles, PowerCutStorage& storage,
                          const macros::RecordSpec* specs, std::uint8_t* scratch, std::size_t scratch_size,
                          Contents<kKeys, kCapacity>& expected) {
  CycleReport report;
  for (std::size_t c = 0; c < cycles; ++c) {
    report.cycle = c;
    const std::size_t saves = 1 + static_cast<std::size_t>(rng.next() % 3);
    std::size_t keys[3] = {};
    std::size_t lengths[3] = {};
    std::uint8_t payloads[3][kCapacity];
    std::size_t total = 0;
    for (std::size_t s = 0; s < saves; ++s) {
      keys[s] = static_cast<std::size_t>(rng.next() % kKeys);
      lengths[s] = static_cast<std::size_t>(rng.next() % (specs[keys[s]].capacity_bytes + 1));
      fill_random(rng, payloads[s], lengths[s]);
      total += macros::KeyedStore::kHeaderBytes + lengths[s];
    }
    const bool cut = rng.next() % 8 != 0;
    std::size_t cut_save = saves;  // none
    {
      macros::KeyedStore store(storage, specs, kKeys, scratch, scratch_size);
      if (store.mount() != core::Status::kOk) {
        report.verdict = Verdict::kMountFailed;
        return report;
      }
      if (cut) {
        const Fault fault = kFaults[rng.next() % 3];
        storage.arm_cut(static_cast<std::size_t>(rng.next() % (total + 1)), fault, rng.next());
      }
      for (std::size_t s = 0; s < saves; ++s) {
        const bool was_powered = storage.powered();
        const core::Status st = store.save(specs[keys[s]].key, payloads[s], lengths[s]);
        if (st == core::Status::kOk) {
          if (!storage.powered()) {
            report.verdict = Verdict::kCutNotReported;
            return report;
          }
          expected.set(keys[s], payloads[s], lengths[s]);
        } else if (was_powered && storage.powered()) {
          report.verdict = Verdict::kSetupFailed;
          return report;
        } else if (was_powered) {
          cut_save = s;
        }
      }
    }
    // A budget equal to the whole run cuts the last save after it landed; a cut
    // that fell on no save leaves the power on.
    bool took_new = false;
    const std::size_t cut_index = cut_save < saves ? keys[cut_save] : kKeys;
    const Verdict v = restart_and_compare(storage, specs, scratch, scratch_size, expected, cut_index,
                                          cut_save < saves ? payloads[cut_save] : nullptr,
                                          cut_save < saves ? lengths[cut_save] : 0, took_new);
    if (v != Verdict::kOk) {
      report.verdict = v;
      return report;
    }
    if (cut_save < saves) {
      ++report.cuts;
      if (took_new) {
        ++report.took_new;
        expected.set(keys[cut_save], payloads[cut_save], lengths[cut_save]);
      }
    }
  }
  return report;
}

}  // namespace trueaxis::test
