// Circle fit against independent computations: the optimum is a stationary
// minimum of the long-double geometric cost, equals a long-double Gauss-Newton on
// the point model, and its errors and reported sigmas match the Cramer-Rao bound.
#include <catch2/catch.hpp>

#include <array>

#include "circle_reference.hpp"
#include "trueaxis/core/circle_fit.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

constexpr std::size_t kSmall = 12;

struct Case {
  t::CircleModel model;
  t::Vec6L truth;
  std::array<long double, core::kMaxCirclePoints> phase;
  std::size_t n;
};

Case make_case(t::Rng& rng, long double radius, double centre_span, std::size_t n, long double arc_deg) {
  const t::TrueCircle tc = t::random_circle(rng, radius, centre_span);
  Case k{t::CircleModel(tc.n), t::Vec6L::Zero(), {}, n};
  k.truth << tc.c, 0.0L, 0.0L, radius;
  t::even_phases(k.phase, n, arc_deg, rng.uniform(-3.0, 3.0));
  return k;
}

template <std::size_t N>
void noisy_points(const Case& k, t::Rng& rng, double sigma, std::array<Vec3, N>& p) {
  for (std::size_t i = 0; i < k.n; ++i) {
    p[i] = k.model.point(k.truth, k.phase[i]).template cast<double>() +
           sigma * Vec3(rng.normal(), rng.normal(), rng.normal());
  }
}

// The fitted circle as parameters of `m` (n0 = m.n0): c, the normal's components
// along the fixed (e1, e2) (first order), r.
t::Vec6L as_params(const core::CircleFit& f, const t::CircleModel& m) {
  t::Vec6L th;
  const t::Vec3L n = f.normal.cast<long double>();
  th << f.centre_mm.cast<long double>(), n.dot(m.e1) / n.dot(m.n0), n.dot(m.e2) / n.dot(m.n0),
      static_cast<long double>(f.radius_mm);
  return th;
}

}  // namespace

TEST_CASE("the fit is a stationary minimum of the long-double geometric cost", "[circle]") {
  t::Rng rng(31);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 4 + rng.next() % (kSmall - 3);
    const long double radius = rng.uniform(10.0, 500.0);
    const Case k = make_case(rng, radius, 1000.0, n, rng.uniform(30.0, 360.0));
    std::array<Vec3, kSmall> p;
    noisy_points(k, rng, 0.002 * static_cast<double>(radius), p);
    const auto fit = core::fit_circle(p.data(), n);
    REQUIRE(fit.ok());
    // A model whose reference normal is the fitted one: the fit sits at a = b = 0.
    const t::CircleModel m(fit.value().normal.cast<long double>());
    const t::Vec6L th = as_params(fit.value(), m);
    auto cost = [&](const t::Vec6L& x) { return t::circle_cost_l(p.data(), n, x.head<3>(), m.normal(x), x(5)); };
    const long double c0 = cost(th);
    // Gradient by central differences; each component against the scale of the
    // gradient at a point that is not a minimum: 2 sqrt(cost * n) * (1 or r).
    for (int j = 0; j < 6; ++j) {
      const long double unit = (j == 3 || j == 4) ? 1.0L : radius;
      const long double h = 1e-7L * unit;
      t::Vec6L hi = th;
      t::Vec6L lo = th;
      hi(j) += h;
      lo(j) -= h;
      const long double g = (cost(hi) - cost(lo)) / (2.0L * h);
      const long double scale = 2.0L * std::sqrt(c0 * static_cast<long double>(n)) * (j == 3 || j == 4 ? radius : 1);
      CHECK(static_cast<double>(std::abs(g) / scale) < 1e-8);
    }
    for (int j = 0; j < 50; ++j) {
      t::Vec6L d;
      for (int q = 0; q < 6; ++q) d(q) = rng.normal() * ((q == 3 || q == 4) ? 1e-6L : 1e-6L * radius);
      CHECK(cost(th + d) >= c0);
    }
  }
}

TEST_CASE("the fit equals a long-double Gauss-Newton on the point model", "[circle]") {
  t::Rng rng(32);
  double worst_c = 0, worst_n = 0, worst_r = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 4 + rng.next() % (kSmall - 3);
    const long double radius = rng.uniform(10.0, 500.0);
    const Case k = make_case(rng, radius, 1000.0, n, rng.uniform(20.0, 360.0));
    std::array<Vec3, kSmall> p;
    noisy_points(k, rng, 0.001 * static_cast<double>(radius), p);
    const auto fit = core::fit_circle(p.data(), n);
    REQUIRE(fit.ok());
    std::array<long double, kSmall> t0;
    for (std::size_t i = 0; i < n; ++i) t0[i] = k.phase[i];
    const t::Vec6L ref = t::reference_fit_l(k.model, p.data(), n, k.truth, t0, 100);
    const t::Vec6L got = as_params(fit.value(), k.model);
    worst_c = std::max(worst_c, static_cast<double>((got.head<3>() - ref.head<3>()).norm() / radius));
    worst_n = std::max(worst_n, static_cast<double>(t::angle_l(k.model.normal(ref), fit.value().normal.cast<long double>())));
    worst_r = std::max(worst_r, static_cast<double>(std::abs(got(5) - ref(5)) / radius));
  }
  INFO("worst relative centre " << worst_c << ", normal " << worst_n << " rad, radius " << worst_r);
  CHECK(worst_c < 1e-10);
  CHECK(worst_n < 1e-10);
  CHECK(worst_r < 1e-10);
}

// Cramer-Rao bound for isotropic Gaussian noise sigma per axis on the point model
//     p_i = c + r (cos t_i u(n) + sin t_i v(n)) + e_i,  e_i ~ N(0, sigma^2 I3),
// with theta = (c, a, b, r) and the phases t_i as nuisance parameters:
//     CRB(theta) = sigma^2 [ sum_i J_i^T (I - g_i g_i^T / |g_i|^2) J_i ]^-1,
//     J_i = dp_i/dtheta (3x6), g_i = dp_i/dt_i,
// the Schur complement of the full Fisher information sigma^-2 [J T]^T [J T],
// derivatives by central differences in long double at the true parameters
// (circle_reference.hpp). The test compares, along each principal direction e of
// the CRB's centre, normal and radius blocks: the Monte Carlo mean square error
// e^T MSE e against e^T CRB e (within 10%), and each run's reported 1-sigma
// sqrt(e^T Cov_fit e) against the Monte Carlo spread sqrt(e^T MSE e) (factor 1.5).
TEST_CASE("errors reach the Cramer-Rao bound and the reported sigmas match the spread", "[circle][crb]") {
  struct Config {
    const char* name;
    long double arc_deg;
    std::size_t n;
  };
  const Config configs[] = {{"full circle", 360.0L, 36}, {"60 degree arc", 60.0L, 24}};
  const int runs = 5000;
  const double sigma = 0.005;
  for (const Config& cfg : configs) {
    t::Rng rng(33);
    const Case k = make_case(rng, 100.0L, 500.0, cfg.n, cfg.arc_deg);
    const t::Mat6L crb = static_cast<long double>(sigma * sigma) *
                         k.model.reduced_information(k.truth, k.phase, k.n).inverse();

    // Principal directions of each block of the CRB, as 6-vectors.
    std::array<t::Vec6L, 6> dirs;
    std::array<const char*, 6> names{"centre 1", "centre 2", "centre 3", "normal 1", "normal 2", "radius"};
    const Eigen::SelfAdjointEigenSolver<t::Mat3L> ce(crb.topLeftCorner<3, 3>());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<long double, 2, 2>> ne(crb.block<2, 2>(3, 3));
    for (int j = 0; j < 6; ++j) dirs[static_cast<std::size_t>(j)].setZero();
    for (int j = 0; j < 3; ++j) dirs[static_cast<std::size_t>(j)].head<3>() = ce.eigenvectors().col(j);
    for (int j = 0; j < 2; ++j) dirs[static_cast<std::size_t>(3 + j)].segment<2>(3) = ne.eigenvectors().col(j);
    dirs[5](5) = 1.0L;
    if (cfg.arc_deg >= 360.0L) {
      // The bound's code against the closed form for n evenly spaced points on a
      // full circle: centre sigma^2/n along the normal and 2 sigma^2/n in the
      // plane, normal 2 sigma^2/(n r^2) per axis (r = 100 mm), radius sigma^2/n.
      const double v = sigma * sigma / static_cast<double>(cfg.n);
      CHECK(static_cast<double>(ce.eigenvalues()(0)) == Approx(v).epsilon(1e-6));
      CHECK(static_cast<double>(ce.eigenvalues()(1)) == Approx(2 * v).epsilon(1e-6));
      CHECK(static_cast<double>(ce.eigenvalues()(2)) == Approx(2 * v).epsilon(1e-6));
      CHECK(static_cast<double>(ne.eigenvalues()(0)) == Approx(2 * v / 1e4).epsilon(1e-6));
      CHECK(static_cast<double>(ne.eigenvalues()(1)) == Approx(2 * v / 1e4).epsilon(1e-6));
      CHECK(static_cast<double>(crb(5, 5)) == Approx(v).epsilon(1e-6));
    }

    t::Mat6L mse = t::Mat6L::Zero();
    t::Vec6L bias = t::Vec6L::Zero();
    static std::array<std::array<double, 6>, runs> reported;
    std::array<Vec3, 36> p;
    for (int run = 0; run < runs; ++run) {
      noisy_points(k, rng, sigma, p);
      const auto fit = core::fit_circle(p.data(), k.n);
      REQUIRE(fit.ok());
      const core::CircleFit& f = fit.value();
      const t::Vec6L err = as_params(f, k.model) - k.truth;
      mse += err * err.transpose();
      bias += err;
      // The fit's covariance, its normal block turned from (axis_u, axis_v) to (e1, e2).
      t::Mat6L b = t::Mat6L::Identity();
      const t::Vec3L u = f.axis_u.cast<long double>();
      const t::Vec3L v = f.axis_v.cast<long double>();
      b.block<2, 2>(3, 3) << k.model.e1.dot(u), k.model.e1.dot(v), k.model.e2.dot(u), k.model.e2.dot(v);
      const t::Mat6L cov = b * f.covariance.cast<long double>() * b.transpose();
      for (std::size_t j = 0; j < 6; ++j) {
        reported[static_cast<std::size_t>(run)][j] = static_cast<double>(std::sqrt(dirs[j].dot(cov * dirs[j])));
      }
    }
    mse /= static_cast<long double>(runs);
    bias /= static_cast<long double>(runs);
    for (std::size_t j = 0; j < 6; ++j) {
      const double bound = static_cast<double>(dirs[j].dot(crb * dirs[j]));
      const double measured = static_cast<double>(dirs[j].dot(mse * dirs[j]));
      const double spread = std::sqrt(measured);
      int within = 0;
      double mean_reported_variance = 0.0;
      for (const auto& r : reported) {
        within += (r[j] < 1.5 * spread && r[j] > spread / 1.5) ? 1 : 0;
        mean_reported_variance += r[j] * r[j] / runs;
      }
      INFO(cfg.name << ", " << names[j] << ": CRB sigma " << std::sqrt(bound) << ", Monte Carlo "
                    << spread << ", bias " << static_cast<double>(dirs[j].dot(bias)) << ", reported within 1.5x: "
                    << within << " of " << runs);
      CHECK(measured / bound > 0.9);
      CHECK(measured / bound < 1.1);
      CHECK(std::abs(static_cast<double>(dirs[j].dot(bias))) < 0.1 * std::sqrt(bound));
      CHECK(within >= runs * 995 / 1000);
      // sigma^2 = SSR / (2n - 6) is unbiased: the reported variance is right on average.
      CHECK(mean_reported_variance / measured > 0.9);
      CHECK(mean_reported_variance / measured < 1.1);
    }

    {  // With a known sigma the reported covariance is the bound itself.
      noisy_points(k, rng, sigma, p);
      core::CircleFitOptions o;
      o.point_sigma_mm = sigma;
      const auto fit = core::fit_circle(p.data(), k.n, o);
      REQUIRE(fit.ok());
      const core::Mat3 cc = fit.value().centre_covariance_mm2();
      for (std::size_t j = 0; j < 3; ++j) {
        const core::Vec3 e = dirs[j].head<3>().cast<double>();
        CHECK(e.dot(cc * e) / static_cast<double>(dirs[j].dot(crb * dirs[j])) == Approx(1.0).epsilon(0.05));
      }
      CHECK(fit.value().radius_variance_mm2() / static_cast<double>(crb(5, 5)) == Approx(1.0).epsilon(0.05));
    }
  }
}

// Convention 5 of the header, computed independently: sigma^2 (J^T J)^-1 with J
// the long-double central-difference Jacobian of the residuals (h_i, rho_i - r)
// over (c, a, b, r), the normal n(a, b) = (n + a u + b v) / |.| about the fitted
// normal along the fit's (axis_u, axis_v). Noisy points (5% of the radius) so
// that the terms of J proportional to the residuals matter.
TEST_CASE("the reported covariance is sigma^2 (J^T J)^-1 of a long-double numeric Jacobian", "[circle]") {
  t::Rng rng(34);
  for (int trial = 0; trial < 50; ++trial) {
    const std::size_t n = 4 + rng.next() % (kSmall - 3);
    const long double radius = rng.uniform(10.0, 500.0);
    const Case k = make_case(rng, radius, 1000.0, n, rng.uniform(60.0, 360.0));
    std::array<Vec3, kSmall> p;
    noisy_points(k, rng, 0.05 * static_cast<double>(radius), p);
    core::CircleFitOptions o;
    o.point_sigma_mm = 0.1;
    const auto fit = core::fit_circle(p.data(), n, o);
    REQUIRE(fit.ok());
    const core::CircleFit& f = fit.value();
    t::CircleModel m(f.normal.cast<long double>());
    m.e1 = f.axis_u.cast<long double>();
    m.e2 = f.axis_v.cast<long double>();
    t::Vec6L th;
    th << f.centre_mm.cast<long double>(), 0.0L, 0.0L, static_cast<long double>(f.radius_mm);
    auto residuals = [&](const t::Vec6L& x, std::size_t i) {
      const t::Vec3L nn = m.normal(x);
      const t::Vec3L d = p[i].cast<long double>() - x.head<3>();
      const long double h = nn.dot(d);
      return Eigen::Matrix<long double, 2, 1>(h, (d - h * nn).norm() - x(5));
    };
    t::Mat6L jtj = t::Mat6L::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Matrix<long double, 2, 6> j;
      for (int q = 0; q < 6; ++q) {
        const long double h = (q == 3 || q == 4) ? 1e-7L : 1e-7L * radius;
        t::Vec6L hi = th;
        t::Vec6L lo = th;
        hi(q) += h;
        lo(q) -= h;
        j.col(q) = (residuals(hi, i) - residuals(lo, i)) / (2.0L * h);
      }
      jtj += j.transpose() * j;
    }
    const t::Mat6L expected = 0.01L * jtj.inverse();
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) {
        const long double scale = std::sqrt(expected(r, r) * expected(c, c));
        CHECK(static_cast<double>(std::abs(static_cast<long double>(f.covariance(r, c)) - expected(r, c)) / scale) <
              1e-6);
      }
    }
  }
}
