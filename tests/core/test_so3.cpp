#include <catch2/catch.hpp>

#include <limits>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/so3.hpp"

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;
namespace core = trueaxis::core;
namespace t = trueaxis::test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

double max_abs_diff(const Mat3& a, const t::Mat3L& b) {
  return static_cast<double>((a.cast<long double>() - b).cwiseAbs().maxCoeff());
}

// The fixtures every property runs over: zero, tiny, the Taylor threshold and one
// ulp either side, ordinary, and the neighbourhood of pi.
std::vector<double> angle_fixtures() {
  const double thr = core::so3_taylor_threshold();
  return {0.0,
          1e-300,
          1e-12,
          1e-8,
          std::nextafter(thr, 0.0),
          thr,
          std::nextafter(thr, 1.0),
          1e-2,
          0.5,
          2.0,
          core::kPi - 1e-3,
          core::kPi - 1e-6,
          core::kPi - 1e-9,
          core::kPi};
}

}  // namespace

TEST_CASE("exp agrees with a long-double Taylor series of the matrix exponential", "[so3]") {
  t::Rng rng(1);
  for (double angle : angle_fixtures()) {
    for (int i = 0; i < 50; ++i) {
      const Vec3 w = angle * rng.unit_vector();
      const Mat3 r = core::so3_exp(w);
      const t::Mat3L ref = t::expm_series(t::hat_l(w.cast<long double>()));
      INFO("angle " << angle);
      CHECK(max_abs_diff(r, ref) < 4 * kEps * (1.0 + angle));
    }
  }
  for (int i = 0; i < 2000; ++i) {
    const Vec3 w = rng.uniform(0.0, 10.0) * rng.unit_vector();
    const double d = max_abs_diff(core::so3_exp(w), t::expm_series(t::hat_l(w.cast<long double>())));
    INFO("d " << d << " |w| " << w.norm());
    CHECK(d < 4 * kEps * (1.0 + w.norm()));
  }
}

TEST_CASE("exp returns orthonormal matrices with determinant one", "[so3]") {
  t::Rng rng(2);
  for (int i = 0; i < 2000; ++i) {
    const Mat3 r = core::so3_exp(rng.uniform(0.0, 7.0) * rng.unit_vector());
    INFO("orth " << (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() << " det " << r.determinant() - 1.0);
    CHECK((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < 16 * kEps);
    CHECK(std::abs(r.determinant() - 1.0) < 16 * kEps);
  }
}

TEST_CASE("log inverts exp for angles in [0, pi)", "[so3]") {
  t::Rng rng(3);
  for (double angle : angle_fixtures()) {
    if (angle >= core::kPi) continue;
    for (int i = 0; i < 50; ++i) {
      const Vec3 w = angle * rng.unit_vector();
      // Build R in long double by the series so log is not checked against exp alone.
      const Mat3 r = t::expm_series(t::hat_l(w.cast<long double>())).cast<double>();
      const Vec3 back = core::so3_log(r);
      INFO("angle " << angle);
      // Near pi, rounding R to double moves the angle by ~eps; the axis stays exact.
      CHECK((back - w).norm() < 4e-15 * (1.0 + angle));
    }
  }
}

TEST_CASE("log at exactly pi returns one of the two equivalent vectors", "[so3]") {
  t::Rng rng(4);
  for (int i = 0; i < 200; ++i) {
    const Vec3 n = rng.unit_vector();
    const Mat3 r = 2.0 * n * n.transpose() - Mat3::Identity();  // rotation by pi about n
    const Vec3 w = core::so3_log(r);
    CHECK(std::abs(w.norm() - core::kPi) < 1e-14);
    CHECK(std::min((w - core::kPi * n).norm(), (w + core::kPi * n).norm()) < 1e-14);
    CHECK((core::so3_exp(w) - r).cwiseAbs().maxCoeff() < 1e-15);
  }
}

// The trace formula loses digits as theta nears pi (acos near -1), so the
// comparison stays where it is well conditioned; near pi see the tests above.
TEST_CASE("log agrees with the trace-and-skew formula in long double away from 0 and pi", "[so3]") {
  t::Rng rng(5);
  for (int i = 0; i < 2000; ++i) {
    const Mat3 r = core::so3_exp(rng.uniform(0.1, 2.5) * rng.unit_vector());
    const t::Mat3L rl = r.cast<long double>();
    const long double theta = std::acos((rl.trace() - 1.0L) / 2.0L);
    const t::Vec3L axis = t::Vec3L(rl(2, 1) - rl(1, 2), rl(0, 2) - rl(2, 0), rl(1, 0) - rl(0, 1)) /
                          (2.0L * std::sin(theta));
    const Vec3 ref = (theta * axis).cast<double>();
    INFO("err " << (core::so3_log(r) - ref).norm() << " theta " << static_cast<double>(theta));
    CHECK((core::so3_log(r) - ref).norm() < 16 * kEps * (1.0 + static_cast<double>(theta)));
  }
}

TEST_CASE("hat and vee are inverse and hat is the cross product", "[so3]") {
  t::Rng rng(6);
  for (int i = 0; i < 100; ++i) {
    const Vec3 a = rng.unit_vector() * rng.uniform(0, 10);
    const Vec3 b = rng.unit_vector();
    CHECK((core::vee(core::hat(a)) - a).norm() == 0.0);
    CHECK((core::hat(a) * b - a.cross(b)).norm() < 1e-15 * (1 + a.norm()));
  }
}

TEST_CASE("exp and log do not allocate", "[so3][alloc]") {
  const trueaxis::test::AllocationScope scope;
  Vec3 acc = Vec3::Zero();
  for (int i = 0; i < 100; ++i) acc += core::so3_log(core::so3_exp(Vec3(0.01 * i, 0.02, -0.03)));
  CHECK(scope.count() == 0);
  CHECK(acc.allFinite());
}
