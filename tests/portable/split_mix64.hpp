// The seeded generator of the host and portable tests; no Eigen, no heap, so the
// store tests use it too.
#pragma once

#include <cstdint>

namespace trueaxis::test {

// splitmix64 (Steele, Lea, Flood 2014): small, seedable, the same on every platform.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double sign() { return (next() & 1u) != 0 ? 1.0 : -1.0; }

 private:
  std::uint64_t state_;
};

}  // namespace trueaxis::test
