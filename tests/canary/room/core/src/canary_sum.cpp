#include "trueaxis/core/canary_sum.hpp"

namespace trueaxis::core {

double canary_sum(const double* values, std::size_t count) {
  double sum = 0.0;
  for (std::size_t i = 0; i < count; ++i) sum += values[i];
  return sum;
}

}  // namespace trueaxis::core
