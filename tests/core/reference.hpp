// Independent computations the core tests compare against: other algorithms, in
// long double (x87 extended precision on the host), sharing no code with the core.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdint>

#include "fixtures.hpp"

namespace trueaxis::test {

using Vec3L = Eigen::Matrix<long double, 3, 1>;
using Mat3L = Eigen::Matrix<long double, 3, 3>;

// Deterministic generator for every randomised test: the portable tests'
// splitmix64, plus the normal deviates and directions the host tests need.
class Rng : public SplitMix64 {
 public:
  using SplitMix64::SplitMix64;
  using SplitMix64::uniform;
  double normal() {  // Box-Muller
    const double u1 = uniform(1e-300, 1.0);
    const double u2 = uniform(0.0, 1.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  Eigen::Vector3d unit_vector() {
    for (;;) {
      const Eigen::Vector3d v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double n = v.norm();
      if (n > 0.1 && n <= 1.0) return v / n;
    }
  }
};

inline Mat3L hat_l(const Vec3L& w) {
  Mat3L m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// exp of a skew matrix by scaling and squaring of the Taylor series, in long
// double: a different algorithm from Rodrigues' closed form.
inline Mat3L expm_series(const Mat3L& k) {
  int squarings = 0;
  Mat3L a = k;
  while (a.cwiseAbs().maxCoeff() > 0.125L) {
    a /= 2.0L;
    ++squarings;
  }
  Mat3L sum = Mat3L::Identity();
  Mat3L term = Mat3L::Identity();
  for (int i = 1; i < 30; ++i) {
    term = term * a / static_cast<long double>(i);
    sum += term;
  }
  for (int i = 0; i < squarings; ++i) sum = sum * sum;
  return sum;
}

// Rodrigues' formula in long double with 1 - cos(theta) = 2 sin^2(theta / 2): the
// rotation of w to long-double precision (relative, entry by entry) at any angle.
inline Mat3L rodrigues_l(const Vec3L& w) {
  const long double theta = w.norm();
  if (theta == 0.0L) return Mat3L::Identity();
  const Mat3L k = hat_l(w);
  const long double s_half = std::sin(theta / 2.0L);
  return Mat3L::Identity() + (std::sin(theta) / theta) * k + (2.0L * s_half * s_half / (theta * theta)) * (k * k);
}

inline Mat3L rot_x_l(long double a) {
  Mat3L r;
  r << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return r;
}
inline Mat3L rot_z_l(long double a) {
  Mat3L r;
  r << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return r;
}

inline long double angle_l(const Vec3L& a, const Vec3L& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

constexpr long double kPiL = 3.141592653589793238462643383279502884L;
inline long double deg_l(long double d) { return d * kPiL / 180.0L; }

}  // namespace trueaxis::test
