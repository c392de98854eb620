// The canary's math: the sum of its values (the one core function of the
// canary method, tests/canary).
#pragma once

#include <cstddef>

namespace trueaxis::core {

// values[0] + ... + values[count - 1], in that order; 0 for none.
double canary_sum(const double* values, std::size_t count);

}  // namespace trueaxis::core
