// The streaming Levenberg-Marquardt solver (levenberg_marquardt.hpp) against
// independent computations: a linear model's least-squares solution by a
// long-double QR of the stacked system, a nonlinear fit by a long-double
// Gauss-Newton on the stacked residuals, Rosenbrock's minimum; its refusals
// (a parameter combination the data cannot see, a non-finite model); its
// covariance against a Monte Carlo; no allocation; pieces of any size.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/QR>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "trueaxis/core/levenberg_marquardt.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;

namespace {

using Vec3p = Eigen::Matrix<double, 3, 1>;
using R1 = Eigen::Matrix<double, 1, 1>;
using J13 = Eigen::Matrix<double, 1, 3>;

// y = p0 exp(p1 x) + p2: the residual and its Jacobian at one sample.
void exp_block(const Vec3p& p, double x, double y, R1& r, J13& j) {
  const double e = std::exp(p(1) * x);
  r(0) = p(0) * e + p(2) - y;
  j << e, p(0) * x * e, 1.0;
}

struct Data {
  std::vector<double> x, y;
};

Data exp_data(t::Rng& rng, const Vec3p& truth, double sigma, int n = 40) {
  Data d;
  for (int i = 0; i < n; ++i) {
    const double x = 2.0 * i / (n - 1);
    d.x.push_back(x);
    d.y.push_back(truth(0) * std::exp(truth(1) * x) + truth(2) + sigma * rng.normal());
  }
  return d;
}

// Runs the solver on the data, feeding the samples in pieces of `piece`.
core::LevenbergMarquardt<3> solve_exp(const Data& d, const Vec3p& p0, std::size_t piece = 1000,
                                      core::LmOptions options = core::LmOptions()) {
  core::LevenbergMarquardt<3> lm;
  lm.start(p0, options);
  core::LmStep s;
  do {
    lm.begin_evaluation();
    for (std::size_t i0 = 0; i0 < d.x.size(); i0 += piece) {
      for (std::size_t i = i0; i < std::min(d.x.size(), i0 + piece); ++i) {
        R1 r;
        J13 j;
        exp_block(lm.point(), d.x[i], d.y[i], r, j);
        lm.add(r, j);
      }
    }
    s = lm.finish_evaluation();
  } while (s.more);
  return lm;
}

// Independent: Gauss-Newton in long double on the stacked residuals (dense QR).
Eigen::Matrix<long double, 3, 1> gauss_newton_l(const Data& d, Eigen::Matrix<long double, 3, 1> p) {
  using ML = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  using VL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  const auto n = static_cast<Eigen::Index>(d.x.size());
  for (int it = 0; it < 100; ++it) {
    ML j(n, 3);
    VL r(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const long double x = d.x[static_cast<std::size_t>(i)];
      const long double e = std::exp(p(1) * x);
      r(i) = p(0) * e + p(2) - d.y[static_cast<std::size_t>(i)];
      j.row(i) << e, p(0) * x * e, 1.0L;
    }
    const Eigen::Matrix<long double, 3, 1> dp = j.colPivHouseholderQr().solve(-r);
    p += dp;
    if (dp.norm() < 1e-17L * (1 + p.norm())) break;
  }
  return p;
}

// LM on the linear model r_i = a_i . p - b_i, from p0, to its end.
core::LevenbergMarquardt<3> solve_linear(const std::vector<Vec3p>& a, const std::vector<double>& b, const Vec3p& p0,
                                         const core::LmOptions& options) {
  core::LevenbergMarquardt<3> lm;
  lm.start(p0, options);
  core::LmStep s;
  do {
    lm.begin_evaluation();
    for (std::size_t i = 0; i < a.size(); ++i) {
      R1 r;
      r(0) = a[i].dot(lm.point()) - b[i];
      lm.add(r, J13(a[i].transpose()));
    }
    s = lm.finish_evaluation();
  } while (s.more);
  return lm;
}

}  // namespace

TEST_CASE("a linear model: the least-squares solution of a long-double QR", "[lm]") {
  t::Rng rng(41);
  for (int trial = 0; trial < 200; ++trial) {
    // r_i = a_i . p - b_i with a_i random, 30 samples.
    std::vector<Vec3p> a;
    std::vector<double> b;
    Eigen::Matrix<long double, Eigen::Dynamic, 3> al(30, 3);
    Eigen::Matrix<long double, Eigen::Dynamic, 1> bl(30);
    for (int i = 0; i < 30; ++i) {
      a.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      b.push_back(rng.uniform(-10, 10));
      al.row(i) = a.back().cast<long double>().transpose();
      bl(i) = b.back();
    }
    const Eigen::Matrix<long double, 3, 1> ref = al.colPivHouseholderQr().solve(bl);
    // stat_tol 0: to the cost's rounding; the default: within stat_tol (1e-3) of
    // each parameter's 1-sigma, the promise of convention 4's statistical stop.
    int exact_evaluations = 0;
    for (const double stat_tol : {0.0, core::LmOptions().stat_tol}) {
      core::LmOptions options;
      options.stat_tol = stat_tol;
      const core::LevenbergMarquardt<3> lm = solve_linear(a, b, Vec3p(100, -50, 3), options);
      REQUIRE(lm.status() == Status::kOk);
      // Within 1e-6 of each parameter's own standard uncertainty: below that the
      // cost cannot tell two points apart (its rounding, 1e-16 F, is larger).
      const Eigen::Matrix3d cov = lm.covariance();
      const double within = stat_tol > 0.0 ? stat_tol : 1e-6;
      for (int k = 0; k < 3; ++k) {
        CHECK(std::fabs(static_cast<double>(lm.solution()(k) - ref(k))) < within * std::sqrt(cov(k, k)));
      }
      CHECK(lm.evaluations() <= 12);
      if (stat_tol == 0.0) {
        exact_evaluations = lm.evaluations();
      } else {
        CHECK(lm.evaluations() <= exact_evaluations);
      }
    }
  }
}

TEST_CASE("an exponential fit: the long-double Gauss-Newton solution, in pieces of any size", "[lm]") {
  t::Rng rng(42);
  const Vec3p truth(2.0, -1.3, 0.5);
  const Data d = exp_data(rng, truth, 0.01);
  const Eigen::Matrix<long double, 3, 1> ref = gauss_newton_l(d, truth.cast<long double>());
  core::LmOptions exact;
  exact.stat_tol = 0.0;
  const core::LevenbergMarquardt<3> whole = solve_exp(d, Vec3p(1.0, 0.0, 0.0), 1000, exact);
  REQUIRE(whole.status() == Status::kOk);
  CHECK(static_cast<double>((whole.solution().cast<long double>() - ref).norm()) < 1e-9);
  INFO("evaluations " << whole.evaluations());
  CHECK(whole.evaluations() < 40);
  CHECK(whole.residual_count() == d.x.size());
  for (const std::size_t piece : {1u, 7u, 39u}) {  // the same sums in the same order: the same bits
    const core::LevenbergMarquardt<3> pieces = solve_exp(d, Vec3p(1.0, 0.0, 0.0), piece, exact);
    CHECK(pieces.solution() == whole.solution());
    CHECK(pieces.evaluations() == whole.evaluations());
  }
}

TEST_CASE("Rosenbrock's valley: the minimum (1, 1) from (-1.2, 1)", "[lm]") {
  core::LevenbergMarquardt<2> lm;
  lm.start(Eigen::Vector2d(-1.2, 1.0));
  core::LmStep s;
  do {
    const Eigen::Vector2d p = lm.point();
    lm.begin_evaluation();
    Eigen::Vector2d r(10.0 * (p(1) - p(0) * p(0)), 1.0 - p(0));
    Eigen::Matrix2d j;
    j << -20.0 * p(0), 10.0, -1.0, 0.0;
    lm.add(r, j);
    s = lm.finish_evaluation();
  } while (s.more);
  CHECK(lm.status() == Status::kOk);
  CHECK((lm.solution() - Eigen::Vector2d(1, 1)).norm() < 1e-10);
  CHECK(lm.cost() < 1e-20);
}

TEST_CASE("what the data cannot see is refused: not_identifiable", "[lm]") {
  t::Rng rng(43);
  SECTION("two parameters that only enter as their sum") {
    core::LevenbergMarquardt<3> lm;
    lm.start(Vec3p(1, 2, 3));
    std::vector<double> xs;
    for (int i = 0; i < 20; ++i) xs.push_back(rng.uniform(-1, 1));
    core::LmStep s;
    do {
      lm.begin_evaluation();
      for (const double x : xs) {
        R1 r;
        r(0) = (lm.point()(0) + lm.point()(1)) * x + lm.point()(2) - 1.0;
        lm.add(r, J13(x, x, 1.0));
      }
      s = lm.finish_evaluation();
    } while (s.more);
    CHECK(s.status == Status::kNotIdentifiable);
    CHECK(lm.smallest_eigenvalue_ratio() < 1e-15);
  }
  SECTION("just identifiable: a second parameter seen 1e-5 as strongly is still fitted") {
    core::LevenbergMarquardt<2> lm;
    lm.start(Eigen::Vector2d(0, 0));
    core::LmStep s;
    do {
      lm.begin_evaluation();
      for (int i = 0; i < 20; ++i) {
        const double x = -1.0 + 0.1 * i;
        Eigen::Matrix<double, 1, 2> j(x, x + 1e-5 * x * x);
        R1 r;
        r(0) = j.dot(lm.point()) - (3.0 * x + 2.0 * (x + 1e-5 * x * x));
        lm.add(r, j);
      }
      s = lm.finish_evaluation();
    } while (s.more);
    CHECK(lm.status() == Status::kOk);
    CHECK(lm.smallest_eigenvalue_ratio() > 1e-12);
    CHECK((lm.solution() - Eigen::Vector2d(3, 2)).norm() < 1e-3);
  }
}

TEST_CASE("a non-finite model is refused and nothing from it accepted", "[lm]") {
  t::Rng rng(44);
  const Data d = exp_data(rng, Vec3p(2.0, -1.3, 0.5), 0.01);
  core::LevenbergMarquardt<3> lm;
  lm.start(Vec3p(1, 0, 0));
  lm.begin_evaluation();
  R1 r;
  r(0) = NAN;
  lm.add(r, J13(1, 0, 0));
  CHECK(lm.finish_evaluation().status == Status::kNotFinite);
  CHECK(lm.solution() == Vec3p(1, 0, 0));
  CHECK(lm.point() == Vec3p(1, 0, 0));
  CHECK(lm.finish_evaluation().status == Status::kNotFinite);  // done stays done
}

TEST_CASE("too few evaluations allowed: no_convergence", "[lm]") {
  t::Rng rng(45);
  const Data d = exp_data(rng, Vec3p(2.0, -1.3, 0.5), 0.01);
  core::LmOptions o;
  o.max_iterations = 3;
  CHECK(solve_exp(d, Vec3p(1, 0, 0), 1000, o).status() == Status::kNoConvergence);
}

TEST_CASE("the covariance from the residuals matches a Monte Carlo of 2,000 fits", "[lm]") {
  t::Rng rng(46);
  const Vec3p truth(2.0, -1.3, 0.5);
  const double sigma = 0.01;
  Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d reported = Eigen::Matrix3d::Zero();
  const int runs = 2000;
  for (int run = 0; run < runs; ++run) {
    const Data d = exp_data(rng, truth, sigma);
    const core::LevenbergMarquardt<3> lm = solve_exp(d, Vec3p(1, 0, 0));
    REQUIRE(lm.status() == Status::kOk);
    const Vec3p e = lm.solution() - truth;
    sq += e * e.transpose() / runs;
    reported += lm.covariance() / runs;
  }
  for (int k = 0; k < 3; ++k) {
    INFO("parameter " << k << ": reported sigma / Monte-Carlo RMS = " << std::sqrt(reported(k, k) / sq(k, k)));
    CHECK(std::sqrt(reported(k, k) / sq(k, k)) == Approx(1.0).margin(0.1));
  }
}

TEST_CASE("the solver does not allocate", "[lm][alloc]") {
  t::Rng rng(47);
  const Data d = exp_data(rng, Vec3p(2.0, -1.3, 0.5), 0.01);
  trueaxis::test::AllocationScope heap;
  const core::LevenbergMarquardt<3> lm = solve_exp(d, Vec3p(1, 0, 0), 7);
  const Eigen::Matrix3d cov = lm.covariance();
  CHECK(cov(0, 0) > 0.0);
  CHECK(heap.count() == 0);
}

TEST_CASE("identifiability is judged in correlation form: units do not matter", "[lm]") {
  // A parameter in metres beside one in nanometres: the raw normal matrix's
  // eigenvalues are 1e18 apart, its correlation form is well conditioned.
  core::LevenbergMarquardt<2> lm;
  lm.start(Eigen::Vector2d(0, 0));
  core::LmStep s;
  do {
    lm.begin_evaluation();
    for (int i = 0; i < 20; ++i) {
      const double x = -1.0 + 0.1 * i;
      const Eigen::Matrix<double, 1, 2> j(x, 1e-9 * (1.0 + x * x));
      R1 r;
      r(0) = j.dot(lm.point() - Eigen::Vector2d(0.25, 4e8));
      lm.add(r, j);
    }
    s = lm.finish_evaluation();
  } while (s.more);
  CHECK(lm.status() == Status::kOk);
  CHECK(lm.smallest_eigenvalue_ratio() > 0.1);
  CHECK(std::fabs(lm.solution()(0) - 0.25) < 1e-9);
  CHECK(std::fabs(lm.solution()(1) - 4e8) < 1e-1);
}

// --- proposed (review of M4) ---

TEST_CASE("the statistical stop holds at stat_tol of the 1-sigma ellipsoid, not before", "[lm]") {
  // A linear model started k s / sqrt(A_00) from its solution along parameter 0,
  // where g^T A^-1 g = k^2 s^2: k = stat_tol / 2 stops at the start, 2 stat_tol steps.
  t::Rng rng(48);
  std::vector<Vec3p> a;
  std::vector<double> b;
  for (int i = 0; i < 30; ++i) {
    a.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    b.push_back(rng.uniform(-10, 10));
  }
  auto solve = [&](const Vec3p& p0, const core::LmOptions& options) { return solve_linear(a, b, p0, options); };
  core::LmOptions exact;
  exact.stat_tol = 0.0;
  const core::LevenbergMarquardt<3> best = solve(Vec3p::Zero(), exact);
  REQUIRE(best.status() == Status::kOk);
  const double s = std::sqrt(2.0 * best.cost() / (30.0 - 3.0));
  const double tol = core::LmOptions().stat_tol;
  for (const double k : {0.5 * tol, 2.0 * tol}) {
    CAPTURE(k);
    const core::LevenbergMarquardt<3> lm =
        solve(best.solution() + Vec3p(k * s / std::sqrt(best.normal_matrix()(0, 0)), 0, 0), core::LmOptions());
    REQUIRE(lm.status() == Status::kOk);
    if (k < tol) {
      CHECK(lm.evaluations() == 1);
    } else {
      CHECK(lm.evaluations() > 1);
    }
  }
}

TEST_CASE("the covariance from the residuals is 2F / (m - N) times A^-1", "[lm]") {
  t::Rng rng(49);
  const Data d = exp_data(rng, Vec3p(2.0, -1.3, 0.5), 0.01);
  const core::LevenbergMarquardt<3> lm = solve_exp(d, Vec3p(1, 0, 0));
  REQUIRE(lm.status() == Status::kOk);
  const double s2 = 2.0 * lm.cost() / static_cast<double>(d.x.size() - 3);
  const Eigen::Matrix3d want = s2 * lm.covariance(1.0);
  CHECK((lm.covariance() - want).cwiseAbs().maxCoeff() <= 1e-12 * want.cwiseAbs().maxCoeff());
}
