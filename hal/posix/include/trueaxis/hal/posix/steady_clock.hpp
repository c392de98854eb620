// hal::Clock from std::chrono::steady_clock: monotonic, microseconds since an
// arbitrary origin (the clock's epoch, usually boot); its wall time from
// std::chrono::system_clock.
#pragma once

#include <cstdint>

#include "trueaxis/hal/clock.hpp"

namespace trueaxis::hal {

class SteadyClock final : public Clock {
 public:
  SteadyClock() = default;
  ~SteadyClock() = default;

 private:
  std::uint64_t do_now_us() override;
  std::uint32_t do_wall_s() override;
};

}  // namespace trueaxis::hal
