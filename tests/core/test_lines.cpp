// Common perpendicular, three planes and Rigid3 against independent computations:
// the closest points from the 2x2 normal equations in long double, docs/METHODS.md
// S3's wrist-centre formula, a long-double LU solve of the three planes, and
// 4x4 homogeneous matrices.
#include <catch2/catch.hpp>

#include <Eigen/LU>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/lines.hpp"
#include "trueaxis/core/so3.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;
using t::Mat3L;
using t::Vec3L;

namespace {

Vec3L ld(const Vec3& v) { return v.cast<long double>(); }

// Closest points by minimising |p1 + s d1 - p2 - t d2|^2: the 2x2 normal
// equations, solved in long double.
struct ClosestL {
  Vec3L f1, f2;
};
ClosestL closest_l(const core::Line3& l1, const core::Line3& l2) {
  const Vec3L d1 = ld(l1.direction).normalized();
  const Vec3L d2 = ld(l2.direction).normalized();
  const Vec3L w = ld(l1.point_mm) - ld(l2.point_mm);
  const long double b = d1.dot(d2);
  const long double det = 1.0L - b * b;
  const long double s = (b * d2.dot(w) - d1.dot(w)) / det;
  const long double u = (d2.dot(w) - b * d1.dot(w)) / det;
  return {ld(l1.point_mm) + s * d1, ld(l2.point_mm) + u * d2};
}

core::Line3 random_line(t::Rng& rng, double span) {
  return {Vec3(rng.uniform(-span, span), rng.uniform(-span, span), rng.uniform(-span, span)),
          rng.uniform(0.1, 10.0) * rng.unit_vector()};
}

// `d` turned by `angle` about a unit axis perpendicular to it.
Vec3 turned(const Vec3& d, double angle, t::Rng& rng) {
  const Vec3 axis = d.cross(rng.unit_vector()).normalized();
  return core::so3_exp(angle * axis) * d;
}

}  // namespace

TEST_CASE("the common perpendicular matches the long-double normal equations", "[gantry][lines]") {
  t::Rng rng(601);
  for (int i = 0; i < 2000; ++i) {
    const core::Line3 l1 = random_line(rng, 3000.0);
    core::Line3 l2 = random_line(rng, 3000.0);
    if (i % 4 == 0) l2.direction = turned(l1.direction, rng.uniform(0.01, 0.2), rng);
    const auto r = core::common_perpendicular(l1, l2);
    REQUIRE(r.ok());
    const ClosestL ref = closest_l(l1, l2);
    const long double sin_a = ld(l1.direction).normalized().cross(ld(l2.direction).normalized()).norm();
    // The feet are conditioned by 1 / sin(angle) over the lines' offsets.
    const double tol = 1e-12 * 6000.0 / static_cast<double>(sin_a);
    CHECK(static_cast<double>((ld(r.value().foot_1_mm) - ref.f1).norm()) < tol);
    CHECK(static_cast<double>((ld(r.value().foot_2_mm) - ref.f2).norm()) < tol);
    CHECK(r.value().length_mm == Approx(static_cast<double>((ref.f2 - ref.f1).norm())).margin(tol));
    // The feet lie on their lines, and the segment is perpendicular to both.
    CHECK(core::line_distance_mm(l1, r.value().foot_1_mm) < tol);
    CHECK(core::line_distance_mm(l2, r.value().foot_2_mm) < tol);
    const Vec3 seg = r.value().foot_2_mm - r.value().foot_1_mm;
    CHECK(std::abs(seg.dot(l1.direction.normalized())) < tol);
    CHECK(std::abs(seg.dot(l2.direction.normalized())) < tol);
    CHECK(r.value().angle_deg ==
          Approx(static_cast<double>(t::angle_l(ld(l1.direction), ld(l2.direction)) * 180.0L / t::kPiL))
              .margin(1e-11));
  }
}

TEST_CASE("the foot on the first line is docs/METHODS.md S3's wrist centre", "[gantry][lines]") {
  t::Rng rng(602);
  for (int i = 0; i < 500; ++i) {
    const core::Line3 c_axis = random_line(rng, 1000.0);  // R_C + s c
    const core::Line3 a_axis = random_line(rng, 1000.0);  // R_A + t a
    const Vec3L c = ld(c_axis.direction).normalized();
    const Vec3L a = ld(a_axis.direction).normalized();
    const Vec3L n_prime = a.cross(a.cross(c)).normalized();
    const long double h = (ld(a_axis.point_mm) - ld(c_axis.point_mm)).dot(n_prime) / c.dot(n_prime);
    const Vec3L wrist = ld(c_axis.point_mm) + h * c;
    const auto r = core::common_perpendicular(c_axis, a_axis);
    REQUIRE(r.ok());
    const double tol = 1e-11 / static_cast<double>(c.cross(a).norm());
    CHECK(static_cast<double>((ld(r.value().foot_1_mm) - wrist).norm()) < tol);
  }
}

TEST_CASE("a known configuration gives its closed form", "[gantry][lines]") {
  // Line 1 along x through the origin; line 2 along (0, cos b, sin b) through (7, 3, d).
  const double d = 0.037;
  const double b = core::deg_to_rad(30.0);
  const core::Line3 l1{Vec3(0, 0, 0), Vec3(5, 0, 0)};
  const core::Line3 l2{Vec3(7, 3, d), Vec3(0, std::cos(b), std::sin(b))};
  const auto r = core::common_perpendicular(l1, l2);
  REQUIRE(r.ok());
  // Closest points: (7, 0, 0) on line 1, and on line 2 the point with y cos b + z sin b minimal.
  CHECK((r.value().foot_1_mm - Vec3(7, 0, 0)).norm() < 1e-14);
  const Vec3 q = l2.point_mm - (3 * std::cos(b) + d * std::sin(b)) * l2.direction;
  CHECK((r.value().foot_2_mm - q).norm() < 1e-14);
  CHECK(r.value().length_mm == Approx(std::abs(-3 * std::sin(b) + d * std::cos(b))).epsilon(1e-14));
  CHECK(r.value().angle_deg == Approx(90.0).epsilon(1e-14));
  CHECK(r.value().s_1_mm == Approx(7.0).epsilon(1e-14));
}

TEST_CASE("parallel and nearly parallel lines are refused at the threshold", "[gantry][lines]") {
  t::Rng rng(603);
  const core::Line3 l1{Vec3(10, 20, 30), Vec3(0.3, -0.4, 0.5)};
  const Vec3 d = l1.direction.normalized();
  SECTION("exactly parallel and antiparallel lines are parallel") {
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), d}).status() == core::Status::kAxesParallel);
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), -d}).status() == core::Status::kAxesParallel);
    CHECK(core::common_perpendicular(l1, l1).status() == core::Status::kAxesParallel);
  }
  SECTION("the threshold is on the sine of the angle, on both sides of 0 and 180 degrees") {
    for (const double base : {0.0, core::kPi}) {
      const Vec3 below = turned(d, base + 0.999 * core::kMinLineSin, rng);
      const Vec3 above = turned(d, base + 1.001 * core::kMinLineSin, rng);
      CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), below}).status() == core::Status::kAxesParallel);
      CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), above}).ok());
    }
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), turned(d, 1e-6, rng)}, 1e-7).ok());
  }
  SECTION("bad arguments have their own codes") {
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), Vec3::Zero()}).status() ==
          core::Status::kArgumentOutOfRange);
    CHECK(core::common_perpendicular(l1, {Vec3(1, NAN, 3), Vec3::UnitX()}).status() == core::Status::kNotFinite);
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), Vec3(INFINITY, 0, 0)}).status() ==
          core::Status::kNotFinite);
    CHECK(core::common_perpendicular(l1, {Vec3(1, 2, 3), Vec3::UnitX()}, 0.0).status() ==
          core::Status::kArgumentOutOfRange);
  }
}

TEST_CASE("three planes meet where a long-double LU solve says", "[gantry][lines]") {
  t::Rng rng(604);
  for (int i = 0; i < 2000; ++i) {
    core::Plane3 p[3];
    Mat3L a;
    Vec3L b;
    for (int k = 0; k < 3; ++k) {
      p[k] = {Vec3(rng.uniform(-3000, 3000), rng.uniform(-3000, 3000), rng.uniform(-3000, 3000)),
              rng.uniform(0.5, 3.0) * rng.unit_vector()};
      const Vec3L n = ld(p[k].normal).normalized();
      a.row(k) = n.transpose();
      b(k) = n.dot(ld(p[k].point_mm));
    }
    const long double det = a.determinant();
    const auto r = core::three_plane_point(p[0], p[1], p[2]);
    if (std::abs(det) < 1e-3L) {
      CHECK(r.status() == core::Status::kPlanesDegenerate);
      continue;
    }
    REQUIRE(r.ok());
    const Vec3L ref = a.fullPivLu().solve(b);
    const double tol = 1e-12 * 6000.0 / static_cast<double>(std::abs(det));
    CHECK(static_cast<double>((ld(r.value()) - ref).norm()) < tol);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(p[k].normal.normalized().dot(r.value() - p[k].point_mm)) < tol);
  }
}

TEST_CASE("three planes: a bed corner and its degenerate neighbours", "[gantry][lines]") {
  const core::Plane3 bed{Vec3(500, 400, 12.5), Vec3(0, 0, 2)};
  const core::Plane3 side_1{Vec3(-3, 50, 0), Vec3(1, 0, 0)};
  const core::Plane3 side_2{Vec3(80, 7, -40), Vec3(0, -1, 0)};
  const auto r = core::three_plane_point(bed, side_1, side_2);
  REQUIRE(r.ok());
  CHECK((r.value() - Vec3(-3, 7, 12.5)).norm() < 1e-13);
  SECTION("two parallel planes are degenerate") {
    CHECK(core::three_plane_point(bed, side_1, {Vec3(9, 9, 9), Vec3(-1, 0, 0)}).status() ==
          core::Status::kPlanesDegenerate);
  }
  SECTION("three planes through one line are degenerate") {
    const core::Plane3 tilted{Vec3(-3, 7, 0), Vec3(1, -1, 0)};
    CHECK(core::three_plane_point(side_1, side_2, tilted).status() == core::Status::kPlanesDegenerate);
  }
  SECTION("the threshold is on the normals' determinant") {
    const Vec3 below = core::so3_exp(0.999 * core::kMinPlanesDet * Vec3::UnitZ()) * Vec3::UnitX();
    const Vec3 above = core::so3_exp(1.001 * core::kMinPlanesDet * Vec3::UnitZ()) * Vec3::UnitX();
    CHECK(core::three_plane_point(bed, side_1, {Vec3(1, 1, 1), below}).status() ==
          core::Status::kPlanesDegenerate);
    CHECK(core::three_plane_point(bed, side_1, {Vec3(1, 1, 1), above}).ok());
  }
  SECTION("bad arguments have their own codes") {
    CHECK(core::three_plane_point(bed, side_1, {Vec3(1, 1, 1), Vec3::Zero()}).status() ==
          core::Status::kArgumentOutOfRange);
    CHECK(core::three_plane_point(bed, side_1, {Vec3(NAN, 1, 1), Vec3::UnitY()}).status() ==
          core::Status::kNotFinite);
  }
}

TEST_CASE("Rigid3 composes, inverts and applies like 4x4 homogeneous matrices", "[gantry][lines]") {
  t::Rng rng(606);
  for (int i = 0; i < 200; ++i) {
    const core::Rigid3 a_T_b{core::so3_exp(rng.uniform(0, 3) * rng.unit_vector()),
                             Vec3(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3))};
    const core::Rigid3 b_T_c{core::so3_exp(rng.uniform(0, 3) * rng.unit_vector()),
                             Vec3(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3))};
    const Vec3 p_c(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3));
    const core::Rigid3 a_T_c = core::compose(a_T_b, b_T_c);
    const core::Mat4 m = core::homogeneous(a_T_b) * core::homogeneous(b_T_c);
    CHECK((core::homogeneous(a_T_c) - m).cwiseAbs().maxCoeff() < 1e-11);
    const Eigen::Vector4d ph(p_c.x(), p_c.y(), p_c.z(), 1.0);
    CHECK((core::apply_point(a_T_c, p_c) - (m * ph).head<3>()).norm() < 1e-11);
    CHECK((core::apply_point(core::inverse(a_T_c), core::apply_point(a_T_c, p_c)) - p_c).norm() < 1e-11);
    CHECK((core::homogeneous(core::inverse(a_T_b)) * core::homogeneous(a_T_b) - core::Mat4::Identity())
              .cwiseAbs()
              .maxCoeff() < 1e-12);
    // A direction ignores the translation.
    CHECK((core::apply_direction(a_T_b, Vec3::UnitX()) - a_T_b.R.col(0)).norm() == 0.0);
  }
}

TEST_CASE("lines and planes allocate nothing", "[gantry][lines]") {
  const t::AllocationScope scope;
  const auto cp = core::common_perpendicular({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 1, 1), Vec3(0, 1, 0)});
  const auto pt = core::three_plane_point({Vec3::Zero(), Vec3::UnitX()}, {Vec3::Zero(), Vec3::UnitY()},
                                          {Vec3::Zero(), Vec3::UnitZ()});
  const core::Rigid3 r = core::inverse(core::compose(core::Rigid3{}, core::Rigid3{}));
  CHECK(cp.ok());
  CHECK(pt.ok());
  CHECK(r.t.norm() == 0.0);
  CHECK(scope.count() == 0);
}
