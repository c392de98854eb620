#include <catch2/catch.hpp>

#include <limits>

#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_compensation.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Blend;
using core::Mat3;
using core::Status;
using core::Vec3;

namespace {

// A table from noise-free samples of the reference cradle, poses unevenly spaced.
const core::RigidityTable& reference_table() {
  static const auto builder = [] {
    auto b = std::make_unique<core::RigidityBuilder>();
    t::Rng rng(501);
    const auto samples = t::measure(t::Cradle{}, t::Plan{}, rng);
    REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), {}, *b) == Status::kOk);
    return b;
  }();
  return builder->table();
}

t::Vec3L to_l(const Vec3& v) { return v.cast<long double>(); }

// Slerp of unit quaternions in long double (Eigen's), read back as a rotation vector.
t::Vec3L slerp_rotvec(const Vec3& rv0, const Vec3& rv1, long double w) {
  const auto quat = [](const t::Vec3L& rv) {
    const long double a = rv.norm();
    return a == 0.0L ? t::QuatL::Identity() : t::QuatL(t::AngleAxisL(a, rv / a));
  };
  const t::AngleAxisL aa(quat(to_l(rv0)).slerp(w, quat(to_l(rv1))));
  return aa.angle() * aa.axis();
}

// The natural cubic spline through (x_i, y_i) as 4 (n - 1) polynomial
// coefficients y = a + b s + c s^2 + d s^3, s = x - x_k, from the dense system of
// its interpolation, continuity and end conditions, solved by Gaussian
// elimination with partial pivoting in long double.
struct DenseSpline {
  std::vector<long double> x;
  std::vector<long double> coef;  // 4 per interval
  DenseSpline(const std::vector<long double>& xs, const std::vector<long double>& ys) : x(xs) {
    const std::size_t n = xs.size() - 1;
    const std::size_t size = 4 * n;
    std::vector<std::vector<long double>> m(size, std::vector<long double>(size + 1, 0.0L));
    std::size_t row = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const long double h = xs[k + 1] - xs[k];
      m[row][4 * k] = 1;
      m[row++][size] = ys[k];
      for (int j = 0; j < 4; ++j) m[row][4 * k + static_cast<std::size_t>(j)] = std::pow(h, j);
      m[row++][size] = ys[k + 1];
      if (k + 1 < n) {  // first and second derivatives continuous at x_{k+1}
        m[row][4 * k + 1] = 1;
        m[row][4 * k + 2] = 2 * h;
        m[row][4 * k + 3] = 3 * h * h;
        m[row++][4 * (k + 1) + 1] = -1;
        m[row][4 * k + 2] = 2;
        m[row][4 * k + 3] = 6 * h;
        m[row++][4 * (k + 1) + 2] = -2;
      }
    }
    m[row++][2] = 2;  // natural ends
    const long double h_last = xs[n] - xs[n - 1];
    m[row][4 * (n - 1) + 2] = 2;
    m[row++][4 * (n - 1) + 3] = 6 * h_last;
    for (std::size_t col = 0; col < size; ++col) {
      std::size_t pivot = col;
      for (std::size_t r = col + 1; r < size; ++r) {
        if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
      }
      std::swap(m[col], m[pivot]);
      for (std::size_t r = 0; r < size; ++r) {
        if (r == col) continue;
        const long double f = m[r][col] / m[col][col];
        for (std::size_t c = col; c <= size; ++c) m[r][c] -= f * m[col][c];
      }
    }
    for (std::size_t r = 0; r < size; ++r) coef.push_back(m[r][size] / m[r][r]);
  }
  long double operator()(long double at) const {
    std::size_t k = 0;
    while (k + 2 < x.size() && x[k + 1] <= at) ++k;
    const long double s = at - x[k];
    return coef[4 * k] + s * (coef[4 * k + 1] + s * (coef[4 * k + 2] + s * coef[4 * k + 3]));
  }
};

// A product of three rotations (exp(rv), the A turn, E_ref Rz(C)), each
// orthonormal to an ulp or two: a few eps off, never more.
bool orthonormal(const Mat3& r) {
  constexpr double kTol = 8 * std::numeric_limits<double>::epsilon();
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() < kTol && std::abs(r.determinant() - 1.0) < kTol;
}

constexpr Blend kBlends[] = {Blend::kLinear, Blend::kGeodesic, Blend::kCubic};

}  // namespace

TEST_CASE("every blend returns a pose's own rotation vector at its A", "[rigidity][compensation]") {
  const core::RigidityTable& table = reference_table();
  for (Blend blend : kBlends) {
    for (std::size_t i = 0; i < table.pose_count; ++i) {
      for (bool clamp : {false, true}) {
        const auto r = core::rigidity_rotvec_rad(table, table.poses[i].a_deg, blend, clamp);
        REQUIRE(r.ok());
        CHECK(r.value() == table.poses[i].rotvec_rad);
      }
    }
  }
}

TEST_CASE("the blends between poses match independent computations", "[rigidity][compensation]") {
  const core::RigidityTable& table = reference_table();
  const std::size_t m = table.pose_count;
  t::Rng rng(502);
  std::vector<long double> xs;
  std::vector<long double> ys[3];
  for (std::size_t i = 0; i < m; ++i) {
    xs.push_back(table.poses[i].a_deg);
    for (int c = 0; c < 3; ++c) ys[c].push_back(table.poses[i].rotvec_rad(c));
  }
  const DenseSpline splines[3] = {{xs, ys[0]}, {xs, ys[1]}, {xs, ys[2]}};
  long double worst[3] = {0, 0, 0};
  for (int trial = 0; trial < 300; ++trial) {
    const double a = trial < 6 ? table.poses[trial].a_deg + 1e-9 : rng.uniform(table.poses[0].a_deg, table.poses[m - 1].a_deg);
    std::size_t k = 0;
    while (k + 2 < m && table.poses[k + 1].a_deg <= a) ++k;
    const long double w = (static_cast<long double>(a) - xs[k]) / (xs[k + 1] - xs[k]);
    const t::Vec3L linear = (1.0L - w) * to_l(table.poses[k].rotvec_rad) + w * to_l(table.poses[k + 1].rotvec_rad);
    const t::Vec3L geodesic = slerp_rotvec(table.poses[k].rotvec_rad, table.poses[k + 1].rotvec_rad, w);
    const t::Vec3L cubic(splines[0](a), splines[1](a), splines[2](a));
    const t::Vec3L expected[3] = {linear, geodesic, cubic};
    for (int b = 0; b < 3; ++b) {
      const auto r = core::rigidity_rotvec_rad(table, a, kBlends[b], false);
      REQUIRE(r.ok());
      worst[b] = std::max(worst[b], (to_l(r.value()) - expected[b]).norm());
    }
  }
  // The rotation vectors are ~1.3e-4 rad (ulp 2.7e-20): a few ulps.
  CHECK(worst[0] < 2e-19L);
  CHECK(worst[1] < 2e-19L);
  CHECK(worst[2] < 2e-19L);
  WARN("worst blend errors (rad): linear " << static_cast<double>(worst[0]) << ", geodesic "
                                           << static_cast<double>(worst[1]) << ", cubic "
                                           << static_cast<double>(worst[2]));
}

TEST_CASE("the linear and geodesic blends weight e(A) and d(A) by the bracket, on non-zero offsets",
          "[rigidity][compensation]") {
  // The reference table's offsets, replaced by distinct non-zero ones per pose
  // (tens of micrometres, microradians), so that swapped weights show.
  core::RigidityTable table = reference_table();
  const std::size_t m = table.pose_count;
  for (std::size_t i = 0; i < m; ++i) {
    const double k = static_cast<double>(i);
    table.poses[i].origin_offset_mm = core::Vec3(0.010 * k, -0.004 * k * k, 0.025 - 0.003 * k);
    table.poses[i].a_error_rad = 2e-5 * k - 1e-6 * k * k;
  }
  core::prepare_rigidity_table(table);
  t::Rng rng(503);
  for (int trial = 0; trial < 200; ++trial) {
    const double a = rng.uniform(table.poses[0].a_deg, table.poses[m - 1].a_deg);
    std::size_t k = 0;
    while (k + 2 < m && table.poses[k + 1].a_deg <= a) ++k;
    const long double w = (static_cast<long double>(a) - table.poses[k].a_deg) /
                          (static_cast<long double>(table.poses[k + 1].a_deg) - table.poses[k].a_deg);
    const t::Vec3L d = (1.0L - w) * to_l(table.poses[k].origin_offset_mm) + w * to_l(table.poses[k + 1].origin_offset_mm);
    const long double e = (1.0L - w) * table.poses[k].a_error_rad + w * table.poses[k + 1].a_error_rad;
    for (Blend blend : {Blend::kLinear, Blend::kGeodesic}) {
      const auto st = core::rigidity_state(table, a, blend, false);
      REQUIRE(st.ok());
      CHECK(static_cast<double>((to_l(st.value().origin_offset_mm) - d).norm()) < 1e-15);
      CHECK(static_cast<double>(std::abs(st.value().a_error_rad - e)) < 1e-19);
    }
  }
}

TEST_CASE("A outside the measured range is refused unless clamped", "[rigidity][compensation]") {
  const core::RigidityTable& table = reference_table();
  const double first = table.poses[0].a_deg;
  const double last = table.poses[table.pose_count - 1].a_deg;
  for (Blend blend : kBlends) {
    CHECK(core::rigidity_rotvec_rad(table, std::nextafter(first, -1e9), blend, false).status() ==
          Status::kOutsideMeasuredRange);
    CHECK(core::rigidity_rotvec_rad(table, std::nextafter(last, 1e9), blend, false).status() ==
          Status::kOutsideMeasuredRange);
    CHECK(core::rigidity_rotvec_rad(table, first - 50.0, blend, true).value() == table.poses[0].rotvec_rad);
    CHECK(core::rigidity_rotvec_rad(table, last + 50.0, blend, true).value() ==
          table.poses[table.pose_count - 1].rotvec_rad);
    CHECK(core::rigidity_rotvec_rad(table, first, blend, false).ok());
    CHECK(core::rigidity_rotvec_rad(table, last, blend, false).ok());
    CHECK(core::rigidity_rotvec_rad(table, std::nan(""), blend, true).status() == Status::kNotFinite);
  }
  CHECK(core::rigidity_rotvec_rad(table, 0.0, static_cast<Blend>(4), false).status() == Status::kArgumentOutOfRange);
  CHECK(core::rigidity_rotvec_rad(core::RigidityTable{}, 0.0, Blend::kLinear, true).status() == Status::kNoTable);
  CHECK(core::rigidity_frames(table, 0.0, std::nan(""), Blend::kLinear, true).status() == Status::kNotFinite);

  SECTION("clamped frames still turn with the commanded A") {
    const double beyond = last + 5.0;
    const auto f = core::rigidity_frames(table, beyond, 30.0, Blend::kLinear, true);
    REQUIRE(f.ok());
    const core::RigidityPose& end = table.poses[table.pose_count - 1];
    const t::Vec3L na = to_l(table.a_axis_direction);
    const long double theta = t::deg_l(beyond) + end.a_error_rad;
    const t::Mat3L expected = t::Cradle::rot(na, theta) * table.reference_axes.cast<long double>() *
                              t::Cradle::rot(t::Vec3L::UnitZ(), t::deg_l(30.0L));
    CHECK((f.value().machine_T_table_theory.rotation.cast<long double>() - expected).norm() < 1e-14L);
  }
}

TEST_CASE("frames at the measured poses are the cradle's true frames", "[rigidity][compensation]") {
  const t::Cradle cradle;
  const core::RigidityTable& table = reference_table();
  t::Rng rng(503);
  for (std::size_t i = 0; i < table.pose_count; ++i) {
    const double a = table.poses[i].a_deg;
    const double c = rng.uniform(-400.0, 400.0);
    const t::Vec3L q(rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(-50, 150));
    for (Blend blend : kBlends) {
      const auto f = core::rigidity_frames(table, a, c, blend, false);
      REQUIRE(f.ok());
      const Vec3 qd = q.cast<double>();
      CHECK((to_l(f.value().machine_T_table_actual.point(qd)) - cradle.point(a, c, q)).norm() < 1e-10L);
      const t::Vec3L theory = cradle.origin(a) + cradle.theory_rotation(a, c) * q;
      CHECK((to_l(f.value().machine_T_table_theory.point(qd)) - theory).norm() < 1e-10L);
    }
  }
}

TEST_CASE("conversions round-trip and frames stay orthonormal", "[rigidity][compensation]") {
  const core::RigidityTable& table = reference_table();
  t::Rng rng(504);
  double worst_point = 0.0;
  double worst_direction = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const double a = rng.uniform(table.poses[0].a_deg, table.poses[table.pose_count - 1].a_deg);
    const double c = rng.uniform(-720.0, 720.0);
    const Blend blend = kBlends[trial % 3];
    const auto f = core::rigidity_frames(table, a, c, blend, false);
    const auto corr = core::rigidity_correction(table, a, c, blend, false);
    REQUIRE(f.ok());
    REQUIRE(corr.ok());
    CHECK(orthonormal(f.value().machine_T_table_theory.rotation));
    CHECK(orthonormal(f.value().machine_T_table_actual.rotation));
    const Vec3 p(rng.uniform(-300, 300), rng.uniform(-300, 300), rng.uniform(-300, 300));
    const Vec3 d = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    // theory -> actual -> theory, and table -> machine -> table.
    worst_point = std::max(worst_point, (corr.value().inverse().point(corr.value().point(p)) - p).norm());
    worst_direction =
        std::max(worst_direction, (corr.value().inverse().direction(corr.value().direction(d)) - d).norm());
    const core::RigidTransform& act = f.value().machine_T_table_actual;
    worst_point = std::max(worst_point, (act.inverse().point(act.point(p)) - p).norm());
    // The correction is the actual frame after the theory frame's inverse.
    const Vec3 q = f.value().machine_T_table_theory.inverse().point(p);
    CHECK((corr.value().point(p) - act.point(q)).norm() < 1e-12);
    // It moves points by the rigidity's size: tens of um here, not zero.
    CHECK((corr.value().point(p) - p).norm() < 0.2);
  }
  CHECK(worst_point < 1e-12);
  CHECK(worst_direction < 1e-14);
  WARN("round trips: points " << worst_point << " mm, directions " << worst_direction);
}

TEST_CASE("queries allocate nothing", "[rigidity][compensation][alloc]") {
  const core::RigidityTable& table = reference_table();
  const t::AllocationScope scope;
  for (Blend blend : kBlends) {
    CHECK(core::rigidity_rotvec_rad(table, 12.5, blend, false).ok());
    CHECK(core::rigidity_frames(table, -40.0, 10.0, blend, false).ok());
    CHECK(core::rigidity_correction(table, 60.0, 10.0, blend, false).ok());
  }
  CHECK(scope.count() == 0);
}

TEST_CASE("the not-a-knot blend reproduces a cubic law exactly, the natural one does not", "[rigidity][compensation]") {
  // A table whose rotation vector, A error and origin offset follow cubics in A:
  // a not-a-knot spline through 4 or more knots is that cubic itself (a closed
  // form), while the natural spline bends it to zero curvature at the ends.
  for (const std::size_t m : {3u, 4u, 7u, 16u}) {
    CAPTURE(m);
    core::RigidityTable t;
    t.pose_count = m;
    t.reference = 0;
    const auto law = [](double a, double k) { return 1e-6 * k * (2.0 + 0.3 * a + 0.01 * a * a + (1e-4 * a * a * a)); };
    const auto quad = [](double a, double k) { return 1e-6 * k * (2.0 + 0.3 * a + 0.01 * a * a); };
    const bool cubic_law = m >= 4;  // three knots fix a parabola, not a cubic
    const auto f = [&](double a, double k) { return cubic_law ? law(a, k) : quad(a, k); };
    for (std::size_t i = 0; i < m; ++i) {
      const double a = -90.0 + 180.0 * static_cast<double>(i) / static_cast<double>(m - 1) + (i % 2 ? 3.0 : 0.0);
      t.poses[i].a_deg = a;
      t.poses[i].rotvec_rad = Vec3(f(a, 1), f(a, -2), f(a, 0.5));
      t.poses[i].a_error_rad = f(a, 3);
      t.poses[i].origin_offset_mm = Vec3(f(a, 1e3), f(a, 2e3), f(a, -1e3));
      t.poses[i].c_direction = Vec3::UnitZ();
      t.poses[i].c_x_axis = Vec3::UnitX();
    }
    core::prepare_rigidity_table(t);
    double worst_knot = 0.0, worst_e = 0.0, worst_d = 0.0, worst_natural = 0.0;
    for (double a = t.poses[0].a_deg; a <= t.poses[m - 1].a_deg; a += 0.37) {
      const auto knot = core::rigidity_state(t, a, Blend::kCubicNotAKnot, false);
      const auto natural = core::rigidity_rotvec_rad(t, a, Blend::kCubic, false);
      REQUIRE(knot.ok());
      REQUIRE(natural.ok());
      const Vec3 want(f(a, 1), f(a, -2), f(a, 0.5));
      worst_knot = std::fmax(worst_knot, (knot.value().rotvec_rad - want).norm());
      worst_e = std::fmax(worst_e, std::fabs(knot.value().a_error_rad - f(a, 3)));
      worst_d = std::fmax(worst_d, (knot.value().origin_offset_mm - Vec3(f(a, 1e3), f(a, 2e3), f(a, -1e3))).norm());
      worst_natural = std::fmax(worst_natural, (natural.value() - want).norm());
    }
    CHECK(worst_knot < 1e-15);
    CHECK(worst_e < 1e-15);
    CHECK(worst_d < 1e-12);
    if (cubic_law) CHECK(worst_natural > 1e-9);  // the natural ends really differ
  }
}
