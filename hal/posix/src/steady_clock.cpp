#include "trueaxis/hal/posix/steady_clock.hpp"

#include <chrono>

namespace trueaxis::hal {

std::uint64_t SteadyClock::do_now_us() {
  const auto since_epoch = std::chrono::steady_clock::now().time_since_epoch();
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count());
}

std::uint32_t SteadyClock::do_wall_s() {
  const auto since_epoch = std::chrono::system_clock::now().time_since_epoch();
  const auto s = std::chrono::duration_cast<std::chrono::seconds>(since_epoch).count();
  return s > 0 && s <= 0xFFFF'FFFF ? static_cast<std::uint32_t>(s) : 0U;
}

}  // namespace trueaxis::hal
