// A calibration table the controller's real-time task reads while the
// background task replaces it: two buffers and a sequence count per buffer (a
// seqlock), so a reader never sees half a table.
//
// Contract
//  1. One writer (the background task: a macro's commit or start()), any number
//     of readers (the real-time task), no locks, no allocation.
//  2. publish(t) copies t into the buffer that is not live, marks it stable,
//     and makes it the live one in one atomic store. The previous live buffer
//     stays untouched until the next publish.
//  3. read(f) calls f(const T&) on the live table and returns true when no
//     publish overwrote that buffer while f ran; otherwise it tries again, at
//     most kMaxAttempts times, and returns false (so does a table never
//     published). A retry needs two publishes during one read: on a single-core
//     controller whose real-time task preempts the background task it cannot
//     happen, and f runs once. f must only compute into its own locals: its
//     result is the caller's only when read returns true.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "trueaxis/core/status.hpp"

namespace trueaxis::macros {

template <typename T>
class LiveTable {
 public:
  static constexpr int kMaxAttempts = 4;
  static constexpr std::uint8_t kNone = 2;

  LiveTable() = default;
  LiveTable(const LiveTable&) = delete;
  LiveTable& operator=(const LiveTable&) = delete;

  void publish(const T& table) {
    const std::uint8_t live = live_.load(std::memory_order_relaxed);
    const std::uint8_t target = live == 0 ? 1 : 0;
    const std::uint32_t s = sequence_[target].load(std::memory_order_relaxed);
    sequence_[target].store(s + 1, std::memory_order_relaxed);  // odd: being written
    std::atomic_thread_fence(std::memory_order_release);
    buffer_[target] = table;
    sequence_[target].store(s + 2, std::memory_order_release);  // even: stable
    live_.store(target, std::memory_order_release);
  }

  // Forget the live table (reads return false until the next publish).
  void clear() { live_.store(kNone, std::memory_order_release); }

  bool has_table() const { return live_.load(std::memory_order_acquire) != kNone; }

  template <typename F>
  bool read(F&& f) const {
    for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
      const std::uint8_t live = live_.load(std::memory_order_acquire);
      if (live == kNone) return false;
      const std::uint32_t before = sequence_[live].load(std::memory_order_acquire);
      if ((before & 1u) != 0) continue;
      f(buffer_[live]);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (sequence_[live].load(std::memory_order_relaxed) == before) return true;
    }
    return false;
  }

 private:
  T buffer_[2] = {};
  std::atomic<std::uint32_t> sequence_[2] = {};
  std::atomic<std::uint8_t> live_{kNone};
};

// f(table) on the live table, or `missing` when there is none: the one shape of
// a query on a method's stored table. f returns a type built from a status too
// (core::Result<V>, MacroStep); it may run more than once (convention 3).
template <typename T, typename F>
auto read_or(const LiveTable<T>& live, core::Status missing, F f) -> decltype(f(std::declval<const T&>())) {
  decltype(f(std::declval<const T&>())) result = missing;
  if (!live.read([&](const T& t) { result = f(t); })) return missing;
  return result;
}

// A method's stored record at start(): decode(bytes, length, scratch) into
// `scratch`, then publish it; a record that does not decode publishes nothing
// and sets `missing` to kTableInvalid (the queries then say so, not kNoTable).
// An empty record (length 0: none stored) changes nothing.
template <typename T, typename Decode>
void load_stored(LiveTable<T>& live, T& scratch, core::Status& missing, const std::uint8_t* bytes,
                 std::size_t length, Decode decode) {
  if (length == 0) return;
  if (decode(bytes, length, scratch) != core::Status::kOk) {
    missing = core::Status::kTableInvalid;
    return;
  }
  live.publish(scratch);
}

}  // namespace trueaxis::macros
