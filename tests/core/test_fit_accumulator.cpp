#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "fit_clouds.hpp"
#include "trueaxis/core/fit_accumulator.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;
using t::accumulate;
using t::cross_points;
using t::far_offset;
using t::frame_around;
using t::Frame;
using t::kEps;
using t::line_cloud;
using t::mean_tolerance;
using t::Moments;
using t::plane_cloud;
using t::sin_angle;
using t::two_pass;

TEST_CASE("the one-pass sums match a long-double two-pass computation", "[accumulator]") {
  t::Rng rng(301);
  for (int i = 0; i < 500; ++i) {
    const std::size_t n = 1 + rng.next() % 200;
    std::vector<Vec3> p(n);
    const Vec3 centre = rng.uniform(0, 1) < 0.5 ? Vec3::Zero() : far_offset(rng);
    for (Vec3& q : p) q = centre + Vec3(rng.normal(), rng.normal(), rng.normal()) * rng.uniform(0.001, 100);
    const auto acc = accumulate(p);
    const Moments ref = two_pass(p);
    REQUIRE(acc.count() == n);
    const long double size = std::max(ref.scatter.norm(), 1e-300L);
    CHECK(static_cast<double>((acc.mean_mm().cast<long double>() - ref.mean).norm()) < mean_tolerance(p));
    CHECK(static_cast<double>((acc.scatter_mm2().cast<long double>() - ref.scatter).norm() / size) < 1e-13);
    CHECK((acc.scatter_mm2() == acc.scatter_mm2().transpose()));
    CHECK(static_cast<double>((acc.index_moment_mm().cast<long double>() - ref.index_moment).norm()) <
          1e-12 * std::sqrt(static_cast<double>(size)) * static_cast<double>(n));
  }
}

TEST_CASE("the plane matches the batch Givens and SVD fit", "[accumulator][plane]") {
  t::Rng rng(302);
  for (int i = 0; i < 3000; ++i) {
    const std::size_t n = 3 + rng.next() % (core::kMaxPlanePoints - 2);
    const Frame f = frame_around(rng.unit_vector());
    const auto p = plane_cloud(rng, n, Vec3(rng.uniform(-500, 500), rng.uniform(-500, 500), 0), f, 100, 40, 0.01);
    const auto batch = core::fit_plane(p.data(), n);
    const auto fit = core::fit_plane(accumulate(p));
    REQUIRE(batch.ok());
    REQUIRE(fit.ok());
    const auto& a = fit.value();
    const auto& b = batch.value();
    // Header item 6: the normal to eps (s_u / s_v)^2, the residual's square to eps s_u^2.
    const double ratio2 = (b.spread_u_mm * b.spread_u_mm) / (b.spread_v_mm * b.spread_v_mm);
    CHECK(sin_angle(a.normal, b.normal.cast<long double>()) < 4 * kEps * ratio2 + 1e-13);
    CHECK((a.centroid_mm - b.centroid_mm).norm() < 1e-12);
    CHECK(a.spread_u_mm == Approx(b.spread_u_mm).epsilon(1e-13));
    CHECK(a.spread_v_mm == Approx(b.spread_v_mm).epsilon(4 * kEps * ratio2 + 1e-13));
    const double rms_sq_diff = a.rms_residual_mm * a.rms_residual_mm - b.rms_residual_mm * b.rms_residual_mm;
    CHECK(std::abs(rms_sq_diff) * double(n) < 8 * kEps * b.spread_u_mm * b.spread_u_mm);
    CHECK(a.count == n);
    CHECK((a.axis_u.cross(a.axis_v) - a.normal).norm() < 1e-14);
    CHECK(a.spread_u_mm >= a.spread_v_mm);
  }
}

TEST_CASE("far from the origin with micrometre noise the fits keep their digits", "[accumulator]") {
  t::Rng rng(303);
  // Header item 6: small eigenvalues to a few eps l1, eigenvectors to eps l1 / gap.
  double worst_plane = 0;
  double worst_line = 0;
  double worst_naive = 0;
  for (int i = 0; i < 300; ++i) {
    const std::size_t n = 4 + rng.next() % 60;
    const Frame f = frame_around(rng.unit_vector());
    const auto p = plane_cloud(rng, n, far_offset(rng), f, rng.uniform(5, 500), rng.uniform(5, 100), 0.001);
    const Moments ref = two_pass(p);
    const auto plane = core::fit_plane(accumulate(p));
    REQUIRE(plane.ok());
    const double l1 = static_cast<double>(ref.eigenvalues(2));
    const double gap = static_cast<double>(ref.eigenvalues(1) - ref.eigenvalues(0));
    CHECK(sin_angle(plane.value().normal, ref.eigenvectors.col(0)) < 4 * kEps * l1 / gap);
    CHECK(static_cast<double>((plane.value().centroid_mm.cast<long double>() - ref.mean).norm()) <
          mean_tolerance(p));
    const double rms = plane.value().rms_residual_mm;
    worst_plane = std::max(worst_plane, std::abs(rms * rms * double(n) - double(ref.eigenvalues(0))) / (kEps * l1));

    const auto q = line_cloud(rng, n, far_offset(rng), rng.unit_vector(), rng.uniform(1, 100), 0.001);
    const Moments lref = two_pass(q);
    const auto line = core::fit_line(accumulate(q));
    REQUIRE(line.ok());
    CHECK(sin_angle(line.value().direction, lref.eigenvectors.col(2)) < 8 * kEps);
    CHECK(static_cast<double>((line.value().point_mm.cast<long double>() - lref.mean).norm()) <
          mean_tolerance(q));
    const double lrms = line.value().rms_residual_mm;
    const double perp = static_cast<double>(lref.eigenvalues(0) + lref.eigenvalues(1));
    worst_line = std::max(worst_line, std::abs(lrms * lrms * double(n) - perp) / (kEps * double(lref.eigenvalues(2))));

    // The textbook sum p p^T - n m m^T, to show these clouds are hard.
    Eigen::Matrix3d raw = Eigen::Matrix3d::Zero();
    Vec3 sum = Vec3::Zero();
    for (const Vec3& x : p) {
      raw += x * x.transpose();
      sum += x;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(raw - sum * sum.transpose() / static_cast<double>(n));
    worst_naive = std::max(worst_naive, std::abs(es.eigenvalues()(0) - double(ref.eigenvalues(0))) / (kEps * l1));
  }
  CHECK(worst_plane < 8);   // measured 1.2
  CHECK(worst_line < 8);    // measured 2.3
  CHECK(worst_naive > 1e4);  // measured 1.1e5
}

TEST_CASE("100000 points lose no accuracy against the two-pass reference", "[accumulator]") {
  t::Rng rng(304);
  const Vec3 dir = rng.unit_vector();
  const auto p = line_cloud(rng, 100000, Vec3(2500, -1800, 900), dir, 0.04, 0.001);  // 4 m pass
  const Moments ref = two_pass(p);
  const auto acc = accumulate(p);
  CHECK(static_cast<double>((acc.mean_mm().cast<long double>() - ref.mean).norm()) < 1e-10);
  CHECK(static_cast<double>((acc.scatter_mm2().cast<long double>() - ref.scatter).norm() / ref.scatter.norm()) <
        1e-13);
  const auto line = core::fit_line(acc);
  REQUIRE(line.ok());
  // The one-pass rounding grows with n: measured 25 eps for the direction and
  // 32 eps l1 for the perpendicular eigenvalues at 1e5 points (2 at 60 points).
  CHECK(sin_angle(line.value().direction, ref.eigenvectors.col(2)) < 100 * kEps);
  CHECK(line.value().direction.dot(dir) > 0);
  CHECK(line.value().advance_per_sample_mm == Approx(0.04).epsilon(1e-6));
  const double lrms = line.value().rms_residual_mm;
  const double perp = static_cast<double>(ref.eigenvalues(0) + ref.eigenvalues(1));
  CHECK(std::abs(lrms * lrms * 1e5 - perp) < 100 * kEps * static_cast<double>(ref.eigenvalues(2)));
  CHECK(line.value().rms_residual_mm == Approx(std::sqrt(2.0) * 0.001).epsilon(0.01));

  const Frame f = frame_around(dir);
  const auto q = plane_cloud(rng, 100000, Vec3(-3000, 1200, 4000), f, 1500, 600, 0.001);
  const Moments pref = two_pass(q);
  const auto plane = core::fit_plane(accumulate(q));
  REQUIRE(plane.ok());
  CHECK(sin_angle(plane.value().normal, pref.eigenvectors.col(0)) < 100 * kEps);
  const double prms = plane.value().rms_residual_mm;
  CHECK(std::abs(prms * prms * 1e5 - static_cast<double>(pref.eigenvalues(0))) <
        100 * kEps * static_cast<double>(pref.eigenvalues(2)));
  CHECK(prms == Approx(0.001).epsilon(0.01));
}

TEST_CASE("the line's direction follows the sample order", "[accumulator][line]") {
  t::Rng rng(305);
  for (int i = 0; i < 200; ++i) {
    const Vec3 dir = rng.unit_vector();
    const double step = rng.uniform(0.1, 50);
    auto p = line_cloud(rng, 2 + rng.next() % 30, far_offset(rng), dir, step, 0.0);
    const Moments ref = two_pass(p);  // of the points as rounded to doubles
    const auto forward = core::fit_line(accumulate(p));
    std::reverse(p.begin(), p.end());
    const auto backward = core::fit_line(accumulate(p));
    REQUIRE(forward.ok());
    REQUIRE(backward.ok());
    CHECK(forward.value().direction.dot(dir) > 0);
    CHECK(backward.value().direction.dot(dir) < 0);
    CHECK(sin_angle(forward.value().direction, ref.eigenvectors.col(2)) < 8 * kEps);
    CHECK(sin_angle(backward.value().direction, ref.eigenvectors.col(2)) < 8 * kEps);
    CHECK(forward.value().advance_per_sample_mm == Approx(step).epsilon(1e-11));
    CHECK(backward.value().advance_per_sample_mm == Approx(step).epsilon(1e-11));
    // Exact points: the residual is rounding, at most sqrt(eps) s_along (header item 6).
    CHECK(forward.value().rms_residual_mm < 4 * std::sqrt(kEps) * forward.value().spread_along_mm);
    const auto& fw = forward.value();
    CHECK((fw.direction.cross(fw.axis_1) - fw.axis_2).norm() < 1e-14);
    CHECK(std::abs(fw.direction.dot(fw.axis_1)) < 1e-14);
  }
  SECTION("orient flips a direction against its hint and keeps a perpendicular one") {
    CHECK((core::orient(Vec3::UnitX(), Vec3(-1, 5, 0)) == -Vec3::UnitX()));
    CHECK((core::orient(Vec3::UnitX(), Vec3(1e-300, -5, 0)) == Vec3::UnitX()));
    CHECK((core::orient(Vec3::UnitX(), Vec3(0, 1, 0)) == Vec3::UnitX()));
  }
}

TEST_CASE("merging two accumulators equals accumulating their points in order", "[accumulator]") {
  t::Rng rng(306);
  for (int i = 0; i < 300; ++i) {
    const Vec3 dir = rng.unit_vector();
    const auto p = line_cloud(rng, 2 + rng.next() % 80, far_offset(rng), dir, rng.uniform(0.5, 20), 0.002);
    const std::size_t cut = rng.next() % (p.size() + 1);  // either part may be empty
    core::PointAccumulator a;
    core::PointAccumulator b;
    for (std::size_t k = 0; k < p.size(); ++k) (k < cut ? a : b).add(p[k]);
    a.merge(b);
    const Moments ref = two_pass(p);
    REQUIRE(a.count() == p.size());
    CHECK(static_cast<double>((a.mean_mm().cast<long double>() - ref.mean).norm()) < 1e-11);
    CHECK(static_cast<double>((a.scatter_mm2().cast<long double>() - ref.scatter).norm() / ref.scatter.norm()) <
          1e-13);
    CHECK(static_cast<double>((a.index_moment_mm().cast<long double>() - ref.index_moment).norm() /
                              (ref.index_moment.norm() + 1)) < 1e-12);
    CHECK((a.scatter_mm2() == a.scatter_mm2().transpose()));
    const auto line = core::fit_line(a);
    REQUIRE(line.ok());
    CHECK(line.value().direction.dot(dir) > 0);
  }
  SECTION("a non-finite point in either part spoils the merge") {
    core::PointAccumulator good;
    core::PointAccumulator bad;
    for (int k = 0; k < 5; ++k) good.add(Vec3(k, k * k, 1));
    bad.add(Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
    core::PointAccumulator left = good;
    left.merge(bad);
    core::PointAccumulator right = bad;
    right.merge(good);
    CHECK(core::fit_line(left).status() == core::Status::kNotFinite);
    CHECK(core::fit_line(right).status() == core::Status::kNotFinite);
  }
}

TEST_CASE("both fits reject too few points", "[accumulator]") {
  core::PointAccumulator acc;
  CHECK(core::fit_plane(acc).status() == core::Status::kTooFewPoints);
  CHECK(core::fit_line(acc).status() == core::Status::kTooFewPoints);
  acc.add(Vec3(1, 2, 3));
  CHECK(core::fit_line(acc).status() == core::Status::kTooFewPoints);
  acc.add(Vec3(4, 2, 3));
  CHECK(core::fit_plane(acc).status() == core::Status::kTooFewPoints);
  CHECK(core::fit_line(acc).ok());
  acc.add(Vec3(4, 7, 3));
  CHECK(core::fit_plane(acc).ok());
}

TEST_CASE("a non-finite point spoils the accumulator until reset", "[accumulator]") {
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    for (int axis = 0; axis < 3; ++axis) {
      core::PointAccumulator acc;
      acc.add(Vec3(0, 0, 0));
      acc.add(Vec3(100, 0, 0));
      Vec3 p(50, 60, 0);
      p(axis) = bad;
      acc.add(p);
      for (int k = 0; k < 5; ++k) acc.add(Vec3(k, 30.0 * k, 0.1 * k));
      CHECK_FALSE(acc.finite());
      CHECK(acc.count() == 7);
      CHECK(core::all_finite(acc.scatter_mm2()));
      CHECK(core::fit_plane(acc).status() == core::Status::kNotFinite);
      CHECK(core::fit_line(acc).status() == core::Status::kNotFinite);
      acc.reset();
      acc.add(Vec3(0, 0, 0));
      acc.add(Vec3(100, 0, 0));
      acc.add(Vec3(0, 100, 0));
      CHECK(core::fit_plane(acc).ok());
    }
  }
  SECTION("sums that overflow report not finite") {
    core::PointAccumulator acc;
    for (double x : {-1e300, 1e300, 0.0}) acc.add(Vec3(x, x * 0.5, 1.0));
    CHECK(acc.finite());
    CHECK(core::fit_plane(acc).status() == core::Status::kNotFinite);
    CHECK(core::fit_line(acc).status() == core::Status::kNotFinite);
  }
}

TEST_CASE("both fits reject coincident points on either side of the threshold", "[accumulator]") {
  t::Rng rng(307);
  const double d = core::kCoincidentSpan_mm;
  for (const Vec3& base : {Vec3(123.456, -78.9, 10.0), Vec3(0, 0, 0)}) {
    const Frame f = frame_around(rng.unit_vector());
    // rms distance from the centroid of (0, a u, a v) is 2a/3.
    for (double factor : {0.0, 0.5, 0.99, 1.01, 10.0}) {
      const double a = 1.5 * factor * d;
      const auto acc = accumulate({base, base + a * f.u, base + a * f.v});
      const bool coincident = factor < 1.0;
      CHECK((core::fit_plane(acc).status() == core::Status::kPointsCoincident) == coincident);
      CHECK((core::fit_line(acc).status() == core::Status::kPointsCoincident) == coincident);
    }
  }
}

TEST_CASE("rejects nearly collinear points for a plane, accepts just wider ones", "[accumulator][plane]") {
  t::Rng rng(308);
  for (int i = 0; i < 50; ++i) {
    const Frame f = frame_around(rng.unit_vector());
    const Vec3 centre = i % 2 == 0 ? Vec3(rng.uniform(-100, 100), 0, 0) : far_offset(rng);
    const double a = rng.uniform(10, 1000);
    const double b_limit = core::kCollinearRatio * a;
    CHECK(core::fit_plane(accumulate(cross_points(centre, f, a, 0.0))).status() == core::Status::kPointsCollinear);
    CHECK(core::fit_plane(accumulate(cross_points(centre, f, a, 0.99 * b_limit))).status() ==
          core::Status::kPointsCollinear);
    const auto thin = cross_points(centre, f, a, 1.01 * b_limit);
    const auto fit = core::fit_plane(accumulate(thin));
    REQUIRE(fit.ok());
    // At the limit forming S squares the conditioning: the normal is good to
    // about eps (s_u / s_v)^2 (header item 6), not to eps s_u / s_v.
    const auto batch = core::fit_plane(thin.data(), thin.size());
    REQUIRE(batch.ok());
    CHECK(sin_angle(fit.value().normal, f.w.cast<long double>()) < 4 * kEps / (1.01e-6 * 1.01e-6));  // 8.7e-4
    CHECK(sin_angle(batch.value().normal, f.w.cast<long double>()) < 1e-8);
  }
}

TEST_CASE("rejects points too wide for a line, accepts just narrower ones", "[accumulator][line]") {
  t::Rng rng(309);
  for (int i = 0; i < 50; ++i) {
    const Frame f = frame_around(rng.unit_vector());
    const Vec3 centre = i % 2 == 0 ? Vec3::Zero() : far_offset(rng);
    const double a = rng.uniform(0.01, 1000);
    const double b_limit = core::kLineWidthRatio * a;
    CHECK(core::fit_line(accumulate(cross_points(centre, f, a, 1.01 * b_limit))).status() ==
          core::Status::kPointsNotOnLine);
    CHECK(core::fit_line(accumulate(cross_points(centre, f, a, a))).status() == core::Status::kPointsNotOnLine);
    const auto fit = core::fit_line(accumulate(cross_points(centre, f, a, 0.99 * b_limit)));
    REQUIRE(fit.ok());
    CHECK(sin_angle(fit.value().direction, f.u.cast<long double>()) < 1e-12);
    CHECK(fit.value().advance_per_sample_mm == Approx(0.2 * a).epsilon(1e-9));  // slope of (a, -a, 0, 0) on k = 0..3
  }
}

TEST_CASE("the reported direction covariances match a Monte Carlo of point noise", "[accumulator][uncertainty]") {
  t::Rng rng(310);
  const int runs = 2000;
  const double sigma = 0.005;
  SECTION("the plane normal's covariance in (axis_u, axis_v)") {
    const Frame f = frame_around(Vec3(0.3, -0.2, 0.9).normalized());
    const auto truth = plane_cloud(rng, 12, Vec3(1500, -800, 300), f, 120, 25, 0.0);
    double sq_u = 0, sq_v = 0, var_u = 0, var_v = 0, mahalanobis = 0;
    for (int r = 0; r < runs; ++r) {
      core::PointAccumulator acc;
      for (const Vec3& p : truth) acc.add(p + sigma * Vec3(rng.normal(), rng.normal(), rng.normal()));
      const auto fit = core::fit_plane(acc);
      REQUIRE(fit.ok());
      const auto& v = fit.value();
      const Vec3 err = core::orient(v.normal, f.w) - f.w;
      const core::Vec2 e(err.dot(v.axis_u), err.dot(v.axis_v));
      const core::Mat2 cov = core::normal_covariance_rad2(v, sigma);
      sq_u += e(0) * e(0);
      sq_v += e(1) * e(1);
      var_u += cov(0, 0);
      var_v += cov(1, 1);
      mahalanobis += e.dot(cov.inverse() * e);
    }
    CHECK(std::sqrt(sq_u / var_u) == Approx(1.0).margin(0.1));
    CHECK(std::sqrt(sq_v / var_v) == Approx(1.0).margin(0.1));
    CHECK(mahalanobis / runs == Approx(2.0).margin(0.2));
  }
  SECTION("the line direction's and the centroid's covariances") {
    const Vec3 dir = Vec3(-0.5, 0.8, 0.2).normalized();
    const Frame f = frame_around(dir);
    const auto truth = line_cloud(rng, 15, Vec3(-2000, 3000, 1200), dir, 12.0, 0.0);
    const Vec3 centre = accumulate(truth).mean_mm();
    double sq_1 = 0, sq_2 = 0, var = 0, mahalanobis = 0, centroid_sq = 0, centroid_var = 0;
    for (int r = 0; r < runs; ++r) {
      core::PointAccumulator acc;
      for (const Vec3& p : truth) acc.add(p + sigma * Vec3(rng.normal(), rng.normal(), rng.normal()));
      const auto fit = core::fit_line(acc);
      REQUIRE(fit.ok());
      const auto& v = fit.value();
      REQUIRE(v.direction.dot(dir) > 0);  // oriented by the sample order alone
      const Vec3 err = v.direction - dir;
      const core::Vec2 e(err.dot(f.u), err.dot(f.v));  // isotropic: any perpendicular pair
      const core::Mat2 cov = core::direction_covariance_rad2(v, sigma);
      sq_1 += e(0) * e(0);
      sq_2 += e(1) * e(1);
      var += cov(0, 0);
      mahalanobis += e.dot(cov.inverse() * e);
      centroid_sq += (v.point_mm - centre).squaredNorm();
      centroid_var += core::centroid_covariance_mm2(v, sigma).trace();
    }
    CHECK(std::sqrt(sq_1 / var) == Approx(1.0).margin(0.1));
    CHECK(std::sqrt(sq_2 / var) == Approx(1.0).margin(0.1));
    CHECK(mahalanobis / runs == Approx(2.0).margin(0.2));
    CHECK(std::sqrt(centroid_sq / centroid_var) == Approx(1.0).margin(0.1));
  }
}

TEST_CASE("adding, merging and fitting do not allocate", "[accumulator][alloc]") {
  std::array<Vec3, 8> pts;
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = Vec3(double(k), double((k * 3) % 5), 0.1 * double(k % 2));
  core::PointAccumulator line;
  for (std::size_t k = 0; k < 5; ++k) line.add(Vec3(1000.0 + 3.0 * double(k), 0.001 * double(k % 2), 7.0));
  const trueaxis::test::AllocationScope scope;
  core::PointAccumulator acc;
  for (const Vec3& p : pts) acc.add(p);
  core::PointAccumulator other = acc;
  other.merge(acc);
  const auto plane = core::fit_plane(other);
  const auto fit = core::fit_line(line);
  const core::Mat2 c = core::normal_covariance_rad2(plane.value(), 0.001) +
                       core::direction_covariance_rad2(fit.value(), 0.001);
  CHECK(scope.count() == 0);
  CHECK(plane.ok());
  CHECK(fit.ok());
  CHECK(c(0, 0) > 0);
}
