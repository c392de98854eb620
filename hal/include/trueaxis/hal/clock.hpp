// A monotonic clock handed to the firmware side; the only time it ever reads.
//
// Contract: now_us() never decreases and counts microseconds from an arbitrary
// origin; it wraps only after 2^64 us. No allocation, no exceptions.
#pragma once

#include <cstdint>

namespace trueaxis::hal {

class Clock {
 public:
  Clock(const Clock&) = delete;
  Clock& operator=(const Clock&) = delete;

  std::uint64_t now_us() { return do_now_us(); }

 protected:
  Clock() = default;
  ~Clock() = default;

 private:
  virtual std::uint64_t do_now_us() = 0;
};

}  // namespace trueaxis::hal
