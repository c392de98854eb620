// core::so3_exp / so3_log (the contract checks of so3.hpp, written once): round
// trips over the whole range, orthonormality, exactly pi, hat and vee, checked against
// Eigen::AngleAxisd, at the fixtures where such code breaks: 0, tiny angles, the
// Taylor threshold +- one ulp, where log leaves its series, twice the threshold,
// pi - 1e-6, pi - 1e-8 and exactly pi. The long-double bounds of so3.hpp
// convention 6 are checked in tests/core/test_so3.cpp; here the round trip.
#include <cmath>
#include <limits>

#include "fixtures.hpp"
#include "portable_test.hpp"
#include "trueaxis/core/so3.hpp"

namespace {

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = trueaxis::core::kPi;

Mat3 reference_exp(const Vec3& w) {
  const double theta = w.norm();
  if (theta == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

// log(exp(w)) keeps the relative precision of w everywhere (so3.hpp convention 6:
// exp's error plus log's): 1.5 eps |w| where log uses its series, 4 eps |w| above.
double log_series_end() { return 2.0 * std::atan(0.5 * trueaxis::core::so3_taylor_threshold()); }
double log_tolerance(double theta) { return (theta < log_series_end() ? 1.5 : 4.0) * kEps * theta; }

double max_abs(const Mat3& m) { return m.cwiseAbs().maxCoeff(); }

// A unit vector uniform on the sphere.
Vec3 random_axis(trueaxis::test::SplitMix64& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    if (v.squaredNorm() > 1e-6 && v.squaredNorm() <= 1.0) return v.normalized();
  }
}

// The angles every check runs at.
double fixture_angle(int i) {
  const double t = trueaxis::core::so3_taylor_threshold();
  const double angles[] = {0.0,
                           1e-300,
                           1e-20,
                           1e-12,
                           1e-8,
                           std::nextafter(t, 0.0),
                           t,
                           std::nextafter(t, 1.0),
                           std::nextafter(log_series_end(), 0.0),
                           log_series_end(),
                           2.0 * t,
                           1e-3,
                           0.5,
                           1.0,
                           2.0,
                           3.0,
                           kPi - 1e-3,
                           kPi - 1e-6,
                           kPi - 1e-8,
                           std::nextafter(kPi, 0.0),
                           kPi};
  return angles[i];
}
constexpr int kFixtureCount = 21;

Vec3 fixture_axis(int j) {
  const Vec3 axes[] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), Vec3(1.0, 2.0, -3.0).normalized(),
                       Vec3(-0.3, 0.1, 0.9).normalized()};
  return axes[j];
}
constexpr int kAxisCount = 5;

TA_TEST("so3_exp matches Eigen::AngleAxisd at every fixture angle") {
  for (int i = 0; i < kFixtureCount; ++i) {
    for (int j = 0; j < kAxisCount; ++j) {
      TA_CASE_INDEX(i * kAxisCount + j);
      const Vec3 w = fixture_angle(i) * fixture_axis(j);
      const Mat3 r = trueaxis::core::so3_exp(w);
      TA_CHECK(max_abs(r - reference_exp(w)) <= 4.0 * kEps);
      TA_CHECK(max_abs(r * r.transpose() - Mat3::Identity()) <= 4.0 * kEps);
      TA_CHECK_NEAR(r.determinant(), 1.0, 4.0 * kEps);
    }
  }
}

TA_TEST("so3_log inverts so3_exp at every fixture angle below pi") {
  for (int i = 0; i < kFixtureCount - 1; ++i) {
    for (int j = 0; j < kAxisCount; ++j) {
      TA_CASE_INDEX(i * kAxisCount + j);
      const Vec3 w = fixture_angle(i) * fixture_axis(j);
      const Vec3 back = trueaxis::core::so3_log(trueaxis::core::so3_exp(w));
      TA_CHECK((back - w).norm() <= log_tolerance(w.norm()));
      TA_CHECK(back.allFinite());
    }
  }
}

TA_TEST("so3_log at exactly pi returns an angle of pi, one of the two equivalent vectors, that maps back") {
  // The fixture axes, then 200 random ones, as the rotation 2 n n^T - I.
  trueaxis::test::SplitMix64 rng(0x5EED'0005);
  for (int j = 0; j < kAxisCount + 200; ++j) {
    TA_CASE_INDEX(j);
    const Vec3 n = j < kAxisCount ? fixture_axis(j) : random_axis(rng);
    const Mat3 r = j < kAxisCount ? reference_exp(kPi * n) : Mat3(2.0 * n * n.transpose() - Mat3::Identity());
    const Vec3 w = trueaxis::core::so3_log(r);
    TA_CHECK_NEAR(w.norm(), kPi, 8.0 * kEps);
    TA_CHECK(std::fmin((w - kPi * n).norm(), (w + kPi * n).norm()) < 1e-14);
    TA_CHECK(max_abs(trueaxis::core::so3_exp(w) - r) <= 8.0 * kEps);
  }
}

TA_TEST("so3_log of the identity is exactly zero") {
  TA_CHECK(trueaxis::core::so3_log(Mat3::Identity()) == Vec3::Zero());
  TA_CHECK(trueaxis::core::so3_exp(Vec3::Zero()) == Mat3::Identity());
}

TA_TEST("so3 exp and log round-trip random rotation vectors") {
  trueaxis::test::SplitMix64 rng(0x5EED'0003);
  for (int i = 0; i < 500; ++i) {
    TA_CASE_INDEX(i);
    const Vec3 axis = Vec3(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)).normalized();
    const double theta = rng.uniform(0.0, kPi - 1e-6);
    const Vec3 w = theta * axis;
    const Mat3 r = trueaxis::core::so3_exp(w);
    TA_CHECK(max_abs(r - reference_exp(w)) <= 8.0 * kEps);
    TA_CHECK((trueaxis::core::so3_log(r) - w).norm() <= log_tolerance(theta));
  }
}

TA_TEST("hat and vee are inverse and hat(w) v is the cross product") {
  trueaxis::test::SplitMix64 rng(0x5EED'0006);
  for (int i = 0; i < 101; ++i) {
    TA_CASE_INDEX(i);
    const Vec3 w = i == 0 ? Vec3(0.3, -1.2, 2.5) : random_axis(rng) * rng.uniform(0.0, 10.0);
    const Vec3 v = i == 0 ? Vec3(-4.0, 0.5, 1.0) : random_axis(rng);
    TA_CHECK(trueaxis::core::vee(trueaxis::core::hat(w)) == w);
    TA_CHECK(((trueaxis::core::hat(w) * v) - w.cross(v)).norm() <= 4.0 * kEps * w.norm() * v.norm());
  }
}

TA_TEST("so3_exp returns orthonormal matrices with determinant one up to 7 rad") {
  trueaxis::test::SplitMix64 rng(0x5EED'0007);
  for (int i = 0; i < 2000; ++i) {
    TA_CASE_INDEX(i);
    const Mat3 r = trueaxis::core::so3_exp(rng.uniform(0.0, 7.0) * random_axis(rng));
    TA_CHECK(max_abs(r.transpose() * r - Mat3::Identity()) < 16 * kEps);
    TA_CHECK(std::fabs(r.determinant() - 1.0) < 16 * kEps);
  }
}

}  // namespace
