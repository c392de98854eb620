#include <catch2/catch.hpp>

#include <array>
#include <limits>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/plane_fit.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

// Reference normal: smallest eigenvector of the long-double scatter matrix (normal
// equations, a different algorithm from the core's Givens QR + SVD).
t::Vec3L reference_normal(const Vec3* p, std::size_t n) {
  t::Vec3L c = t::Vec3L::Zero();
  for (std::size_t i = 0; i < n; ++i) c += p[i].cast<long double>();
  c /= static_cast<long double>(n);
  t::Mat3L s = t::Mat3L::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const t::Vec3L q = p[i].cast<long double>() - c;
    s += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<t::Mat3L> es(s);
  return es.eigenvectors().col(0);
}

double sin_angle(const Vec3& a, const t::Vec3L& b) {
  return static_cast<double>(a.cast<long double>().cross(b).norm() / b.norm());
}

}  // namespace

TEST_CASE("recovers the exact plane through three points", "[plane]") {
  t::Rng rng(11);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p1(rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(-200, 200));
    const Vec3 p2 = p1 + Vec3(rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(-200, 200));
    const Vec3 p3 = p1 + Vec3(rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(-200, 200));
    const std::array<Vec3, 3> pts{p1, p2, p3};
    const auto fit = core::fit_plane(pts.data(), 3);
    // Independent: the cross product of the edges, in long double.
    const t::Vec3L n = (p2.cast<long double>() - p1.cast<long double>())
                           .cross(p3.cast<long double>() - p1.cast<long double>());
    const long double area2 = n.norm();
    const long double longest = std::max({(p2 - p1).norm(), (p3 - p1).norm(), (p3 - p2).norm()});
    if (area2 < 1e-3L * longest * longest) continue;  // thin triangles are tested below
    REQUIRE(fit.ok());
    CHECK(sin_angle(fit.value().normal, n) < 1e-13);
    CHECK(fit.value().flatness_mm < 1e-12);
  }
}

TEST_CASE("the least-squares normal matches a long-double eigen decomposition", "[plane]") {
  t::Rng rng(12);
  for (int i = 0; i < 3000; ++i) {
    const std::size_t n = 3 + rng.next() % (core::kMaxPlanePoints - 2);
    const Vec3 normal = rng.unit_vector();
    const Vec3 u = normal.unitOrthogonal();
    const Vec3 v = normal.cross(u);
    std::array<Vec3, core::kMaxPlanePoints> pts;
    for (std::size_t k = 0; k < n; ++k) {
      pts[k] = Vec3(10, -20, 30) + rng.uniform(-100, 100) * u + rng.uniform(-60, 60) * v +
               rng.normal() * 0.01 * normal;
    }
    const auto fit = core::fit_plane(pts.data(), n);
    REQUIRE(fit.ok());
    CHECK(sin_angle(fit.value().normal, reference_normal(pts.data(), n)) < 1e-12);
    double lo = 1e300;
    double hi = -1e300;
    for (std::size_t k = 0; k < n; ++k) {
      const double d = fit.value().normal.dot(pts[k] - fit.value().centroid_mm);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    CHECK(fit.value().flatness_mm == Approx(hi - lo).margin(1e-13));
    CHECK(fit.value().spread_u_mm >= fit.value().spread_v_mm);
    CHECK((fit.value().axis_u.cross(fit.value().axis_v) - fit.value().normal).norm() < 1e-14);
  }
}

TEST_CASE("rejects point counts outside 3 to the maximum", "[plane]") {
  std::array<Vec3, core::kMaxPlanePoints + 1> pts;
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = Vec3(double(k), double(k * k % 7), 0.0);
  CHECK(core::fit_plane(pts.data(), 2).status() == core::Status::kTooFewPoints);
  CHECK(core::fit_plane(pts.data(), 0).status() == core::Status::kTooFewPoints);
  CHECK(core::fit_plane(pts.data(), core::kMaxPlanePoints + 1).status() == core::Status::kTooManyPoints);
  CHECK(core::fit_plane(pts.data(), core::kMaxPlanePoints).ok());
}

TEST_CASE("rejects NaN and infinite coordinates", "[plane]") {
  std::array<Vec3, 3> pts{Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(0, 100, 0)};
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    for (int k = 0; k < 9; ++k) {
      auto copy = pts;
      copy[static_cast<std::size_t>(k / 3)](k % 3) = bad;
      CHECK(core::fit_plane(copy.data(), 3).status() == core::Status::kNotFinite);
    }
  }
}

TEST_CASE("rejects coincident points on either side of the threshold", "[plane]") {
  const Vec3 base(123.456, -78.9, 10.0);
  const std::array<Vec3, 3> same{base, base, base};
  CHECK(core::fit_plane(same.data(), 3).status() == core::Status::kPointsCoincident);
  const double d = core::kCoincidentSpan_mm;
  const std::array<Vec3, 3> tiny{base, base + Vec3(0.5 * d, 0, 0), base + Vec3(0, 0.5 * d, 0)};
  CHECK(core::fit_plane(tiny.data(), 3).status() == core::Status::kPointsCoincident);
  const std::array<Vec3, 3> small{base, base + Vec3(10 * d, 0, 0), base + Vec3(0, 10 * d, 0)};
  CHECK(core::fit_plane(small.data(), 3).ok());
}

TEST_CASE("rejects collinear and nearly collinear points, accepts just thicker ones", "[plane]") {
  const Vec3 a(0, 0, 0);
  const Vec3 b(100, 50, 20);
  const Vec3 mid = 0.3 * b;
  const Vec3 off = b.unitOrthogonal();
  const std::array<Vec3, 3> line{a, b, mid};
  CHECK(core::fit_plane(line.data(), 3).status() == core::Status::kPointsCollinear);
  // Width / length ratio a factor of 4 each side of kCollinearRatio.
  const double len = b.norm();
  const std::array<Vec3, 3> thin{a, b, mid + 0.25 * core::kCollinearRatio * len * off};
  CHECK(core::fit_plane(thin.data(), 3).status() == core::Status::kPointsCollinear);
  const std::array<Vec3, 3> thick{a, b, mid + 4.0 * core::kCollinearRatio * len * off};
  CHECK(core::fit_plane(thick.data(), 3).ok());
}

TEST_CASE("fitting a plane does not allocate", "[plane][alloc]") {
  std::array<Vec3, 8> pts;
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = Vec3(double(k), double((k * 3) % 5), 0.1 * double(k % 2));
  const trueaxis::test::AllocationScope scope;
  const auto fit = core::fit_plane(pts.data(), pts.size());
  CHECK(scope.count() == 0);
  CHECK(fit.ok());
}
