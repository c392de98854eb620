// small_linear.hpp against Eigen's own LLT and SelfAdjointEigenSolver on the
// host (a different algorithm: Householder tridiagonalisation and QR), on
// random symmetric matrices of the solvers' sizes, well conditioned and next to
// singular, and on the exact boundaries of Cholesky (zero, negative and
// non-finite pivots).
#include <catch2/catch.hpp>

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "reference.hpp"
#include "trueaxis/core/small_linear.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;

namespace {

template <int N>
core::SquareMatrix<N> random_spd(t::Rng& rng, double condition) {
  core::SquareMatrix<N> m;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) m(i, j) = rng.normal();
  }
  const Eigen::HouseholderQR<core::SquareMatrix<N>> qr(m);
  const core::SquareMatrix<N> q = qr.householderQ();
  core::ColumnVector<N> d;
  for (int i = 0; i < N; ++i) d(i) = std::pow(condition, -static_cast<double>(i) / (N - 1));
  return q * d.asDiagonal() * q.transpose();
}

template <int N>
void check_size(t::Rng& rng) {
  for (double condition : {1.0, 1e3, 1e8, 1e13}) {
    for (int trial = 0; trial < 50; ++trial) {
      const core::SquareMatrix<N> a = random_spd<N>(rng, condition) * rng.uniform(1e-6, 1e6);
      core::SquareMatrix<N> l;
      REQUIRE(core::cholesky<N>(a, l));
      // Backward stable: L L^T reproduces A to rounding; the factor itself agrees
      // with Eigen's to its condition (eps x cond(A)).
      CHECK((l * l.transpose() - a).norm() <= 1e-14 * N * a.norm());
      const core::SquareMatrix<N> eigen_l = a.llt().matrixL();
      CHECK((l - eigen_l).norm() <= 1e-15 * N * condition * eigen_l.norm());
      // The other forms do the same arithmetic: L exactly, in place and into a
      // matrix whose upper triangle they leave alone.
      core::SquareMatrix<N> in_place = a;
      REQUIRE(core::cholesky_in_place<N>(in_place));
      core::SquareMatrix<N> lower = core::SquareMatrix<N>::Constant(7.0);
      REQUIRE(core::cholesky_lower<N>(a, lower));
      for (int i = 0; i < N; ++i) {
        for (int j = 0; j < N; ++j) {
          if (i >= j) {
            CHECK(in_place(i, j) == l(i, j));
            CHECK(lower(i, j) == l(i, j));
          } else {
            CHECK(l(i, j) == 0.0);
            CHECK(in_place(i, j) == a(i, j));
            CHECK(lower(i, j) == 7.0);
          }
        }
      }
      const core::ColumnVector<N> b = core::ColumnVector<N>::Random();
      const core::ColumnVector<N> x = core::cholesky_solve<N>(l, b);
      CHECK((a * x - b).norm() <= 1e-12 * condition * b.norm());
      const core::SquareMatrix<N> inv = core::cholesky_inverse<N>(l);
      CHECK((a * inv - core::SquareMatrix<N>::Identity()).norm() <= 1e-11 * condition);
      CHECK(bool(inv == inv.transpose()));
      const core::ColumnVector<N> ours = core::jacobi_eigenvalues<N>(a);
      const Eigen::SelfAdjointEigenSolver<core::SquareMatrix<N>> es(a, Eigen::EigenvaluesOnly);
      const double scale = es.eigenvalues()(N - 1);
      CHECK((ours - es.eigenvalues()).cwiseAbs().maxCoeff() <= 1e-13 * N * scale);
      CHECK(ours(0) / scale == Approx(1.0 / condition).epsilon(condition > 1e10 ? 0.2 : 1e-3));
    }
  }
}

}  // namespace

TEST_CASE("Cholesky, solve, inverse and Jacobi eigenvalues against Eigen", "[small_linear]") {
  t::Rng rng(101);
  check_size<3>(rng);
  check_size<6>(rng);
  check_size<9>(rng);
  check_size<12>(rng);
}

TEST_CASE("Cholesky refuses at the exact boundary: a zero, negative or non-finite pivot", "[small_linear]") {
  core::SquareMatrix<3> l;
  core::SquareMatrix<3> a = core::SquareMatrix<3>::Identity();
  CHECK(core::cholesky<3>(a, l));
  a(2, 2) = 0.0;
  CHECK_FALSE(core::cholesky<3>(a, l));
  a(2, 2) = -1e-300;
  CHECK_FALSE(core::cholesky<3>(a, l));
  a(2, 2) = 1e-300;
  CHECK(core::cholesky<3>(a, l));
  a(2, 2) = NAN;
  CHECK_FALSE(core::cholesky<3>(a, l));
  a(2, 2) = INFINITY;
  CHECK_FALSE(core::cholesky<3>(a, l));
  // Rank one: the second pivot cancels to exactly 0.
  const core::ColumnVector<3> v(1.0, 2.0, 4.0);
  CHECK_FALSE(core::cholesky<3>(v * v.transpose(), l));
}

TEST_CASE("Jacobi: diagonal, repeated and zero eigenvalues", "[small_linear]") {
  core::SquareMatrix<4> d = core::ColumnVector<4>(3, -1, 2, 2).asDiagonal();
  CHECK(bool(core::jacobi_eigenvalues<4>(d) == core::ColumnVector<4>(-1, 2, 2, 3)));
  CHECK(bool(core::jacobi_eigenvalues<4>(core::SquareMatrix<4>::Zero()) == core::ColumnVector<4>::Zero()));
  const core::ColumnVector<4> v(1, 1, 1, 1);
  const core::ColumnVector<4> e = core::jacobi_eigenvalues<4>(v * v.transpose());
  CHECK(std::fabs(e(0)) < 1e-15);
  CHECK(e(3) == Approx(4.0).epsilon(1e-15));
}
