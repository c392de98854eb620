// Sample sets for the M3 rigidity tests, measured on a rigidity_truth.hpp cradle.
#pragma once

#include <algorithm>
#include <vector>

#include "reference.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_table.hpp"

namespace trueaxis::test {

struct Plan {
  std::vector<double> a_deg{-90.0, -60.0, -30.0, 0.0, 25.0, 50.0, 75.0};
  int c_per_pose = 8;
  double c_step_deg = 45.0;  // C_k = offset_i + k step, offset_i random in [0, step)
  double noise_mm = 0.0;     // per axis, 1 sigma
  bool shuffle = true;
};

inline std::vector<core::RigiditySample> measure(const Cradle& cradle, const Plan& plan, Rng& rng) {
  std::vector<core::RigiditySample> out;
  for (double a : plan.a_deg) {
    const double offset = rng.uniform(0.0, plan.c_step_deg);
    for (int k = 0; k < plan.c_per_pose; ++k) {
      const double c = offset + k * plan.c_step_deg;
      core::RigiditySample s;
      s.a_deg = a;
      s.c_deg = c;
      s.p_mm = cradle.ball(a, c).cast<double>();
      if (plan.noise_mm > 0.0) s.p_mm += plan.noise_mm * core::Vec3(rng.normal(), rng.normal(), rng.normal());
      out.push_back(s);
    }
  }
  if (plan.shuffle) {
    for (std::size_t i = out.size(); i > 1; --i) {
      const auto j = static_cast<std::size_t>(rng.uniform(0.0, static_cast<double>(i)));
      std::swap(out[i - 1], out[std::min(j, i - 1)]);
    }
  }
  return out;
}

}  // namespace trueaxis::test
