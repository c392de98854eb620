// A monotonic clock handed to the firmware side; the only time it ever reads.
//
// Contract: now_us() never decreases and counts microseconds from an arbitrary
// origin; it wraps only after 2^64 us. wall_s() is the controller's wall
// clock, Unix seconds (UTC), for the measuring log's entries; 0 when the
// controller has none (the default: a client then hands the time over with
// the macro, #9015). No allocation, no exceptions.
#pragma once

#include <cstdint>

namespace trueaxis::hal {

class Clock {
 public:
  Clock(const Clock&) = delete;
  Clock& operator=(const Clock&) = delete;

  std::uint64_t now_us() { return do_now_us(); }
  std::uint32_t wall_s() { return do_wall_s(); }

 protected:
  Clock() = default;
  ~Clock() = default;

 private:
  virtual std::uint64_t do_now_us() = 0;
  virtual std::uint32_t do_wall_s() { return 0; }
};

}  // namespace trueaxis::hal
