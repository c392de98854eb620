// Reading G65 arguments the way every macro does: a whole number in a range, a
// 0/1 flag. Anything else (NaN included) is the macro's kArgumentOutOfRange.
#pragma once

#include <cmath>

namespace trueaxis::macros {

// True when v is a whole number in [lo, hi].
inline bool whole_in(double v, double lo, double hi) { return v >= lo && v <= hi && v == std::floor(v); }

// R-style flags: true with `flag` set when r is 0 or 1.
inline bool flag_of(double r, bool& flag) {
  if (r != 0.0 && r != 1.0) return false;
  flag = r == 1.0;
  return true;
}

}  // namespace trueaxis::macros
