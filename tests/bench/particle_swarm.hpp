// Particle swarm optimisation (PSO) over a box: the identification method of
// seed 002 (docs/METHODS.md M4), kept as the baseline that M4's Levenberg-Marquardt
// fit is measured against (bench_spindle_pso.cpp, docs/M4_BENCHMARK.md). Host
// only: the swarm lives on the heap.
//
// Use
//     PsoOptions opt;  opt.seed = 3;  opt.max_evaluations = 200000;
//     opt.target_cost = c;                        // optional: record when reached
//     const PsoResult<N> r = minimise_pso<N>(cost, lower, upper, opt);
//     r.best, r.best_cost, r.evaluations, r.first_target_evaluation
//
// Conventions
//  1. Minimises cost(x) over the box lower <= x <= upper (N parameters, fixed
//     size). cost is any callable double(const Vec&); one call is one
//     evaluation, and every call is counted.
//  2. Global-best ("gbest") swarm of S particles, constriction form of Clerc
//     and Kennedy (IEEE TEC 6(1), 2002), per particle i and component k:
//         v_ik <- w v_ik + c1 r1 (pbest_ik - x_ik) + c2 r2 (gbest_k - x_ik),
//         x_ik <- x_ik + v_ik,
//     r1, r2 drawn U(0, 1) afresh for each i, k and iteration. Defaults
//     w = 0.7298, c1 = c2 = 1.49618 (chi = 0.7298 with phi = 4.1), S = 40.
//  3. Synchronous: each iteration moves every particle with the gbest of the
//     previous iteration, evaluates all S, then updates pbest and gbest.
//  4. Start: x uniform in the box; v = (y - x) / 2 with y uniform in the box
//     (SPSO 2007). |v_k| is capped at the box's width in k.
//  5. Walls absorb: a component that leaves the box is set on the wall and its
//     velocity to zero. A position is therefore always inside the box.
//  6. Stops before an iteration that would pass max_evaluations (so
//     evaluations <= max_evaluations; the S starting evaluations always run).
//  7. first_target_evaluation: the number of evaluations done when the best
//     cost first fell to target_cost or below (counting the one that did it);
//     -1 if it never did.
//  8. Deterministic: std::mt19937_64 seeded with PsoOptions::seed, draws in a
//     fixed order (positions, then velocities, particle by particle).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Core>

namespace trueaxis::bench {

struct PsoOptions {
  int swarm = 40;
  double inertia = 0.7298;
  double c1 = 1.49618;  // towards the particle's own best
  double c2 = 1.49618;  // towards the swarm's best
  long max_evaluations = 200000;
  double target_cost = -std::numeric_limits<double>::infinity();
  std::uint64_t seed = 1;
};

template <int N>
struct PsoResult {
  Eigen::Matrix<double, N, 1> best = Eigen::Matrix<double, N, 1>::Zero();
  double best_cost = std::numeric_limits<double>::infinity();
  long evaluations = 0;
  long first_target_evaluation = -1;
  int iterations = 0;
};

template <int N, typename Cost>
PsoResult<N> minimise_pso(Cost&& cost, const Eigen::Matrix<double, N, 1>& lower,
                          const Eigen::Matrix<double, N, 1>& upper, const PsoOptions& options) {
  using Vec = Eigen::Matrix<double, N, 1>;
  struct Particle {
    Vec x, v, best;
    double best_cost;
  };
  const Vec width = upper - lower;
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uniform_in_box = [&]() {
    Vec x;
    for (int k = 0; k < N; ++k) x(k) = lower(k) + unit(rng) * width(k);
    return x;
  };

  PsoResult<N> out;
  const auto evaluate = [&](const Vec& x) {
    const double c = cost(x);
    ++out.evaluations;
    if (c < out.best_cost) {
      out.best_cost = c;
      out.best = x;
      if (out.first_target_evaluation < 0 && c <= options.target_cost) {
        out.first_target_evaluation = out.evaluations;
      }
    }
    return c;
  };

  std::vector<Particle> swarm(static_cast<std::size_t>(options.swarm));
  for (Particle& p : swarm) {
    p.x = uniform_in_box();
    p.v = 0.5 * (uniform_in_box() - p.x);
    p.best = p.x;
    p.best_cost = evaluate(p.x);
  }
  Vec gbest = out.best;  // convention 3: the previous iteration's best guides this one

  while (out.evaluations + options.swarm <= options.max_evaluations) {
    for (Particle& p : swarm) {
      for (int k = 0; k < N; ++k) {
        const double r1 = unit(rng);
        const double r2 = unit(rng);
        double v = options.inertia * p.v(k) + options.c1 * r1 * (p.best(k) - p.x(k)) +
                   options.c2 * r2 * (gbest(k) - p.x(k));
        if (v > width(k)) v = width(k);
        if (v < -width(k)) v = -width(k);
        double x = p.x(k) + v;
        if (x < lower(k) || x > upper(k)) {
          x = x < lower(k) ? lower(k) : upper(k);
          v = 0.0;
        }
        p.x(k) = x;
        p.v(k) = v;
      }
      const double c = evaluate(p.x);
      if (c < p.best_cost) {
        p.best_cost = c;
        p.best = p.x;
      }
    }
    gbest = out.best;
    ++out.iterations;
  }
  return out;
}

}  // namespace trueaxis::bench
