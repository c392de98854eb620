#include "trueaxis/hal/posix/steady_clock.hpp"

#include <chrono>

namespace trueaxis::hal {

std::uint64_t SteadyClock::do_now_us() {
  const auto since_epoch = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count());
}

}  // namespace trueaxis::hal
