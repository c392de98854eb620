// A streaming session: samples that arrive one macro at a time, kept in a
// fixed-capacity buffer that the module owns (one per method).
//
// Contract
//  1. Capacity is a compile-time constant, stated in the register map.
//  2. add() on a full session returns kSessionFull and changes nothing; it
//     never overwrites a sample.
//  3. find_if() scans the samples in order: at most Capacity calls of `same`
//     (a method refuses a sample given twice with it, kDuplicateSample).
//  4. Sessions are macro inputs, not results: a failed compute leaves the
//     session as it was, so the operator can add what was missing and compute
//     again. clear() empties it.
#pragma once

#include <cstddef>

#include "trueaxis/core/status.hpp"

namespace trueaxis::macros {

template <typename Sample, std::size_t Capacity>
class Session {
 public:
  static constexpr std::size_t kCapacity = Capacity;

  void clear() { count_ = 0; }

  [[nodiscard]] core::Status add(const Sample& s) {
    if (count_ == Capacity) return core::Status::kSessionFull;
    samples_[count_++] = s;
    return core::Status::kOk;
  }

  // The first sample for which same(sample) holds, or nullptr (contract 3).
  template <typename Same>
  const Sample* find_if(Same same) const {
    for (std::size_t i = 0; i < count_; ++i) {
      if (same(samples_[i])) return &samples_[i];
    }
    return nullptr;
  }

  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  const Sample* data() const { return samples_; }
  const Sample& operator[](std::size_t i) const { return samples_[i]; }

 private:
  Sample samples_[Capacity] = {};
  std::size_t count_ = 0;
};

}  // namespace trueaxis::macros
