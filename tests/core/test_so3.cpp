// so3.hpp against long-double oracles (its convention 6's bounds, the matrix
// exponential's series, the trace-and-skew formula), over dense sweeps and
// 100,000 random axes per fixture; and its allocations. The contract checks
// that need no oracle (exactly pi, zero, hat and vee, orthonormality) are
// portable tests: tests/portable/platform_so3_test.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/so3.hpp"

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;
namespace core = trueaxis::core;
namespace t = trueaxis::test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// The bounds of so3.hpp convention 6, in units of eps.
constexpr double kExpOffDiagonal = 3.0;  // times min(theta, 1)
constexpr double kExpDiagonal = 5.0;
constexpr double kLogSeries = 1.25;  // times |w|, below the log's series switch
constexpr double kLog = 3.0;         // times |w|, anywhere up to pi
// log(exp(w)) adds exp's error to log's.
constexpr double kRoundTripSeries = 1.5;
constexpr double kRoundTrip = 4.0;

// Where so3_log leaves its series (convention 4a): 2 tan(theta / 2) = threshold.
double log_series_end() { return 2.0 * std::atan(0.5 * core::so3_taylor_threshold()); }

struct ExpError {
  double off_diagonal = 0.0;  // eps min(theta, 1)
  double diagonal = 0.0;      // eps
};

ExpError exp_error(const Vec3& w, const Mat3& r) {
  const t::Mat3L d = r.cast<long double>() - t::rodrigues_l(w.cast<long double>());
  const double scale = std::min(w.norm(), 1.0);
  ExpError e;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double abs_error = static_cast<double>(std::abs(d(i, j))) / kEps;
      if (i == j) {
        e.diagonal = std::max(e.diagonal, abs_error);
      } else if (scale > 0.0) {
        e.off_diagonal = std::max(e.off_diagonal, abs_error / scale);
      } else {
        e.off_diagonal = std::max(e.off_diagonal, abs_error == 0.0 ? 0.0 : 1e300);
      }
    }
  }
  return e;
}

// |v - w| / |w| in eps, for w != 0; exact agreement is required at w = 0.
double relative_error(const Vec3& v, const Vec3& w) {
  const long double d = (v.cast<long double>() - w.cast<long double>()).norm();
  if (w.squaredNorm() == 0.0) return d == 0.0L ? 0.0 : 1e300;
  return static_cast<double>(d / w.cast<long double>().norm()) / kEps;
}

// log of the exact rotation of w, rounded to double: the error of so3_log alone
// plus the rounding of its input, relative to |w|, in eps.
double log_error(const Vec3& w) {
  const Mat3 r = t::rodrigues_l(w.cast<long double>()).cast<double>();
  return relative_error(core::so3_log(r), w);
}

// Worst ratio error / bound over a sweep, and where it happened.
struct Worst {
  double ratio = 0.0;
  double theta = 0.0;
  void add(double error, double bound, double theta_now) {
    if (error / bound > ratio) {
      ratio = error / bound;
      theta = theta_now;
    }
  }
};

}  // namespace

TEST_CASE("exp and log meet their documented bounds densely across [0, 4 x threshold]", "[so3]") {
  const double thr = core::so3_taylor_threshold();
  const double end = log_series_end();
  std::vector<double> angles = {thr,
                                std::nextafter(thr, 0.0),
                                std::nextafter(thr, 1.0),
                                end,
                                std::nextafter(end, 0.0),
                                std::nextafter(end, 1.0),
                                2.0 * thr,
                                std::nextafter(2.0 * thr, 0.0),
                                std::nextafter(2.0 * thr, 1.0),
                                4.0 * thr,
                                1e-300,
                                1e-20};
  constexpr int kSteps = 4000;
  for (int k = 1; k < kSteps; ++k) angles.push_back(4.0 * thr * k / kSteps);
  t::Rng rng(1);
  Worst exp_off, exp_diag, log_below, log_above;
  for (double angle : angles) {
    for (int i = 0; i < 8; ++i) {
      const Vec3 w = angle * rng.unit_vector();
      const double theta = w.norm();
      const ExpError e = exp_error(w, core::so3_exp(w));
      exp_off.add(e.off_diagonal, kExpOffDiagonal, theta);
      exp_diag.add(e.diagonal, kExpDiagonal, theta);
      (theta < end ? log_below : log_above).add(log_error(w), theta < end ? kLogSeries : kLog, theta);
    }
  }
  INFO("worst error / bound: exp off-diagonal " << exp_off.ratio << " at " << exp_off.theta << ", diagonal "
                                                << exp_diag.ratio << " at " << exp_diag.theta << "; log below "
                                                << log_below.ratio << " at " << log_below.theta << ", above "
                                                << log_above.ratio << " at " << log_above.theta);
  CHECK(exp_off.ratio <= 1.0);
  CHECK(exp_diag.ratio <= 1.0);
  CHECK(log_below.ratio <= 1.0);
  CHECK(log_above.ratio <= 1.0);
  // The sweep must be tight: the bounds are not met by a wide margin.
  CHECK(log_below.ratio > 0.5);
}

TEST_CASE("exp and log round-trip at the fixtures with 100000 random axes each", "[so3]") {
  const double thr = core::so3_taylor_threshold();
  const double end = log_series_end();
  const double fixtures[] = {0.0,  1e-12, 1e-8, std::nextafter(thr, 0.0), thr, std::nextafter(thr, 1.0),
                             core::kPi - 1e-8, core::kPi};
  t::Rng rng(2);
  for (double angle : fixtures) {
    Worst exp_off, exp_diag, log_alone, round_trip;
    for (int i = 0; i < 100000; ++i) {
      const Vec3 w = angle * rng.unit_vector();
      const double theta = w.norm();
      const Mat3 r = core::so3_exp(w);
      const ExpError e = exp_error(w, r);
      exp_off.add(e.off_diagonal, kExpOffDiagonal, theta);
      exp_diag.add(e.diagonal, kExpDiagonal, theta);
      const Vec3 back = core::so3_log(r);
      if (angle < core::kPi) {
        log_alone.add(log_error(w), theta < end ? kLogSeries : kLog, theta);
        const double rt = relative_error(back, w);
        round_trip.add(rt, theta < end ? kRoundTripSeries : kRoundTrip, theta);
      } else {
        // At pi, w and -w are the same rotation (convention 2).
        const double rt = std::min(relative_error(back, w), relative_error(back, -w));
        round_trip.add(rt, kRoundTrip, theta);
      }
    }
    INFO("angle " << angle << ": worst error / bound: exp off-diagonal " << exp_off.ratio << ", diagonal "
                  << exp_diag.ratio << ", log " << log_alone.ratio << ", log(exp) " << round_trip.ratio);
    CHECK(exp_off.ratio <= 1.0);
    CHECK(exp_diag.ratio <= 1.0);
    CHECK(log_alone.ratio <= 1.0);
    CHECK(round_trip.ratio <= 1.0);
    // That exp(log(R)) at pi maps back is the portable test's (tests/portable/platform_so3_test.cpp).
  }
}

TEST_CASE("exp agrees with the long-double series of the matrix exponential beyond pi", "[so3]") {
  t::Rng rng(4);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 w = rng.uniform(0.0, 10.0) * rng.unit_vector();
    const t::Mat3L ref = t::expm_series(t::hat_l(w.cast<long double>()));
    const double d = static_cast<double>((core::so3_exp(w).cast<long double>() - ref).cwiseAbs().maxCoeff());
    INFO("d " << d << " |w| " << w.norm());
    // Beyond pi the rounding of |w| itself, eps |w| / 2, moves the rotation.
    CHECK(d < kExpDiagonal * kEps * std::max(1.0, w.norm() / core::kPi));
  }
}

TEST_CASE("log agrees with the trace-and-skew formula in long double away from 0 and pi", "[so3]") {
  t::Rng rng(6);
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

TEST_CASE("log of a matrix that is not a rotation is finite and at most pi long", "[so3]") {
  t::Rng rng(7);
  std::vector<Mat3> inputs = {Mat3::Zero(), -Mat3::Identity(), 2.0 * Mat3::Identity(),
                              Vec3(1.0, 1.0, -5.0).asDiagonal(), Vec3(-3.0, 0.5, 0.5).asDiagonal()};
  for (int i = 0; i < 1000; ++i) {
    Mat3 m;
    for (int k = 0; k < 9; ++k) m(k) = rng.uniform(-3.0, 3.0);
    inputs.push_back(m);
  }
  for (const Mat3& m : inputs) {
    const Vec3 w = core::so3_log(m);
    INFO("w " << w.x() << " " << w.y() << " " << w.z());
    CHECK(w.allFinite());
    CHECK(w.norm() <= core::kPi * (1.0 + 4.0 * kEps));
  }
}

TEST_CASE("exp and log do not allocate", "[so3][alloc]") {
  const trueaxis::test::AllocationScope scope;
  Vec3 acc = Vec3::Zero();
  for (int i = 0; i < 100; ++i) acc += core::so3_log(core::so3_exp(Vec3(0.01 * i, 0.02, -0.03)));
  CHECK(scope.count() == 0);
  CHECK(acc.allFinite());
}
