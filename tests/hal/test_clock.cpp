#include <catch2/catch.hpp>

#include "trueaxis/hal/posix/steady_clock.hpp"

TEST_CASE("the host clock never goes backwards", "[hal]") {
  trueaxis::hal::SteadyClock clock;
  std::uint64_t last = clock.now_us();
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t now = clock.now_us();
    REQUIRE(now >= last);
    last = now;
  }
}
