// Point clouds and independent references for the streaming-fit tests: seeded
// planes, lines and crosses, and a long-double two-pass computation of the sums
// that shares no code with firmware_core's one-pass update.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "reference.hpp"
#include "trueaxis/core/fit_accumulator.hpp"

namespace trueaxis::test {

// Two-pass mean, scatter and index co-moment in long double: the reference the
// one-pass sums must agree with.
struct Moments {
  Vec3L mean = Vec3L::Zero();
  Mat3L scatter = Mat3L::Zero();
  Vec3L index_moment = Vec3L::Zero();
  Vec3L eigenvalues;  // ascending
  Mat3L eigenvectors;
};

inline Moments two_pass(const std::vector<core::Vec3>& p) {
  Moments m;
  for (const core::Vec3& q : p) m.mean += q.cast<long double>();
  const long double n = static_cast<long double>(p.size());
  m.mean /= n;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Vec3L d = p[k].cast<long double>() - m.mean;
    m.scatter += d * d.transpose();
    m.index_moment += (static_cast<long double>(k) - 0.5L * (n - 1)) * d;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3L> es(m.scatter);
  m.eigenvalues = es.eigenvalues();
  m.eigenvectors = es.eigenvectors();
  return m;
}

inline core::PointAccumulator accumulate(const std::vector<core::Vec3>& p) {
  core::PointAccumulator acc;
  for (const core::Vec3& q : p) acc.add(q);
  return acc;
}

inline double sin_angle(const core::Vec3& a, const Vec3L& b) {
  return static_cast<double>(a.cast<long double>().cross(b).norm() / b.norm());
}

// Orthonormal (u, v, w) with w = `normal`.
struct Frame {
  core::Vec3 u, v, w;
};

inline Frame frame_around(const core::Vec3& normal) {
  const core::Vec3 u = normal.unitOrthogonal();
  return {u, normal.cross(u), normal};
}

// n points on a plane through `centre`: in-plane extents half_u x half_v (mm,
// uniform), normal noise sigma (mm, Gaussian).
inline std::vector<core::Vec3> plane_cloud(Rng& rng, std::size_t n, const core::Vec3& centre, const Frame& f,
                                           double half_u, double half_v, double sigma) {
  std::vector<core::Vec3> p(n);
  for (core::Vec3& q : p) {
    q = centre + rng.uniform(-half_u, half_u) * f.u + rng.uniform(-half_v, half_v) * f.v + sigma * rng.normal() * f.w;
  }
  return p;
}

// n points stepping along `dir` from `start` (step mm), Gaussian noise sigma (mm) per axis.
inline std::vector<core::Vec3> line_cloud(Rng& rng, std::size_t n, const core::Vec3& start, const core::Vec3& dir,
                                          double step, double sigma) {
  std::vector<core::Vec3> p(n);
  for (std::size_t k = 0; k < n; ++k) {
    p[k] = start + (step * static_cast<double>(k)) * dir + sigma * core::Vec3(rng.normal(), rng.normal(), rng.normal());
  }
  return p;
}

// Four points (+-a, 0, 0), (0, +-b, 0) in frame f about `centre`: scatter
// diag(2a^2, 2b^2, 0), so s_2 / s_1 = b / a exactly.
inline std::vector<core::Vec3> cross_points(const core::Vec3& centre, const Frame& f, double a, double b) {
  return {centre + a * f.u, centre - a * f.u, centre + b * f.v, centre - b * f.v};
}

inline constexpr double kEps = std::numeric_limits<double>::epsilon();

// The mean is a double (half an ulp of |m|) plus the one-pass rounding of the
// running mean relative to the first point, a few ulps of the points' reach from it.
inline double mean_tolerance(const std::vector<core::Vec3>& p) {
  double reach = 0;
  for (const core::Vec3& q : p) reach = std::max(reach, (q - p.front()).norm());
  core::Vec3 m = core::Vec3::Zero();
  for (const core::Vec3& q : p) m += q;
  return 2 * kEps * (m / static_cast<double>(p.size())).norm() + 16 * kEps * reach;
}

inline core::Vec3 far_offset(Rng& rng) {
  return std::exp(rng.uniform(std::log(1e3), std::log(1e4))) * rng.unit_vector();
}

}  // namespace trueaxis::test
