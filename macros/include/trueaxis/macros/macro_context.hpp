// What a handler sees while it runs: typed access to the variables, the staged
// results, its method's state, and the persistent record it may stage.
//
// Contract
//  1. in<N>() reads #N; out<N>(v) stages result #N. Both take the number as a
//     template argument: a number the map does not define, or an out<N> outside
//     #100..#199, does not compile. The slot is computed at compile time.
//  2. in_block<First>(k) reads element k of the block that starts at #First
//     (0 for k past the block's end).
//  3. stage_record(key, length) returns a buffer of `length` bytes to fill; the
//     module commits it as `key`'s record when the macro ends with kOk, before
//     the results are published. nullptr when length exceeds the key's capacity.
//     One record per macro run; staging again replaces it.
//  4. load_record reads `key`'s newest stored record (the not-hot path: a
//     report or a restart). No allocation, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::macros {

struct Methods;

// A record a macro staged, waiting for the macro to succeed.
struct RecordStage {
  RecordKey key = RecordKey::kConfig;
  std::size_t length = 0;
  bool staged = false;
  std::uint8_t bytes[kMaxRecordPayloadBytes] = {};
};

class MacroContext {
 public:
  // values: every variable of the map, in slot order; staged_results: #100..#199.
  MacroContext(const double* values, double* staged_results, Methods& methods, RecordStage& record,
               KeyedStore& store, bool first_step)
      : values_(values), staged_(staged_results), methods_(methods), record_(record), store_(store),
        first_step_(first_step) {}

  template <std::uint16_t N>
  double in() const {
    return values_[slot<N>()];
  }

  template <std::uint16_t First>
  double in_block(std::size_t k) const {
    static_assert(find_var(First) != nullptr && find_var(First)->number == First,
                  "in_block takes the first number of a block");
    return k < find_var(First)->count ? values_[slot<First>() + k] : 0.0;
  }

  template <std::uint16_t N>
  void out(double value) {
    static_assert(N >= var::kResultFirst && N <= var::kResultLast, "results are #100..#199");
    staged_[N - var::kResultFirst] = value;
  }

  // Results #X..#X+2 from a vector, each times `scale` (a unit conversion).
  template <std::uint16_t X>
  void out3(const core::Vec3& v, double scale = 1.0) {
    out<X>(v.x() * scale);
    out<X + 1>(v.y() * scale);
    out<X + 2>(v.z() * scale);
  }

  Methods& methods() { return methods_; }
  bool first_step() const { return first_step_; }

  std::uint8_t* stage_record(RecordKey key, std::size_t length) {
    if (length > record_capacity(key)) return nullptr;
    record_.key = key;
    record_.length = length;
    record_.staged = true;
    return record_.bytes;
  }

  [[nodiscard]] core::Status load_record(RecordKey key, std::uint8_t* out, std::size_t capacity,
                                         std::size_t& length) {
    return store_.load(static_cast<std::uint8_t>(key), out, capacity, length);
  }

 private:
  const double* values_;
  double* staged_;
  Methods& methods_;
  RecordStage& record_;
  KeyedStore& store_;
  bool first_step_;
};

}  // namespace trueaxis::macros
