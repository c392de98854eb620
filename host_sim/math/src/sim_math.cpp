#include "trueaxis/sim/sim_math.hpp"

#include <cmath>

namespace trueaxis::sim {

std::uint64_t SimRng::next_u64() {
  state_ += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double SimRng::uniform01() {
  // 53 random bits, shifted by one so the result is never 0 (log below).
  return (static_cast<double>(next_u64() >> 11) + 1.0) * 0x1.0p-53;
}

double SimRng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double r = std::sqrt(-2.0 * std::log(uniform01()));
  const double phi = 2.0 * core::kPi * uniform01();
  spare_ = r * std::sin(phi);
  has_spare_ = true;
  return r * std::cos(phi);
}

}  // namespace trueaxis::sim
