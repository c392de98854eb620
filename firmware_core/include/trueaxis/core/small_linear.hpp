// Dense linear algebra for the fixed sizes the solvers need (N up to about 12),
// in plain loops. Eigen's LDLT, triangular solves with a matrix right-hand side
// and SelfAdjointEigenSolver switch to blocked kernels from about 8 x 8 on,
// whose workspace comes from the heap where there is no alloca (the target):
// these do not, and are checked against Eigen on the host
// (tests/core/test_small_linear.cpp).
//
// Conventions
//  1. cholesky(A, L): A = L L^T for a symmetric A (its lower triangle is read),
//     L's upper triangle zero; false, L unspecified, when a pivot is not
//     positive (A not positive definite to working precision) or not finite.
//     cholesky_lower(A, L) writes L's lower triangle only (L may be A itself),
//     cholesky_in_place(A) overwrites A's.
//  2. cholesky_solve(L, b): x with L L^T x = b; cholesky_inverse(L): (L L^T)^-1.
//     The _in_place and out-parameter forms do the same arithmetic without an
//     N x N temporary (a solver's scratch instead: docs/FIGURES.md "Stack").
//  3. jacobi_eigenvalues(A): the eigenvalues of a symmetric A, ascending, by
//     cyclic Jacobi rotations until every off-diagonal entry is below
//     eps x the Frobenius norm (at most kJacobiSweeps sweeps; 6-10 are typical
//     at these sizes). Accurate to a few eps x ||A|| in absolute terms.
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace trueaxis::core {

template <int N>
using SquareMatrix = Eigen::Matrix<double, N, N>;
template <int N>
using ColumnVector = Eigen::Matrix<double, N, 1>;

inline constexpr int kJacobiSweeps = 50;

// Convention 1 into `l`'s lower triangle, which may be `a` itself: a's lower
// triangle is read (each entry before L's entry in its place is written), l's
// upper triangle is left as it was (cholesky_solve reads the lower one only).
// Neither a copy nor a second N x N matrix (docs/FIGURES.md "Stack").
template <int N>
bool cholesky_lower(const SquareMatrix<N>& a, SquareMatrix<N>& l) {
  for (int j = 0; j < N; ++j) {
    double d = a(j, j);
    for (int k = 0; k < j; ++k) d -= l(j, k) * l(j, k);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double root = std::sqrt(d);
    l(j, j) = root;
    for (int i = j + 1; i < N; ++i) {
      double s = a(i, j);
      for (int k = 0; k < j; ++k) s -= l(i, k) * l(j, k);
      l(i, j) = s / root;
    }
  }
  return true;
}

// Convention 1 in place: L overwrites a's lower triangle.
template <int N>
bool cholesky_in_place(SquareMatrix<N>& a) {
  return cholesky_lower<N>(a, a);
}

// Convention 1 with L's upper triangle zero.
template <int N>
bool cholesky(const SquareMatrix<N>& a, SquareMatrix<N>& l) {
  for (int j = 1; j < N; ++j) {
    for (int i = 0; i < j; ++i) l(i, j) = 0.0;
  }
  return cholesky_lower<N>(a, l);
}

template <int N>
ColumnVector<N> cholesky_solve(const SquareMatrix<N>& l, const ColumnVector<N>& b) {
  ColumnVector<N> y;
  for (int i = 0; i < N; ++i) {
    double s = b(i);
    for (int k = 0; k < i; ++k) s -= l(i, k) * y(k);
    y(i) = s / l(i, i);
  }
  ColumnVector<N> x;
  for (int i = N - 1; i >= 0; --i) {
    double s = y(i);
    for (int k = i + 1; k < N; ++k) s -= l(k, i) * x(k);
    x(i) = s / l(i, i);
  }
  return x;
}

// a = 0.5 (a + a^T), in place.
template <int N>
void symmetrize(SquareMatrix<N>& a) {
  for (int i = 0; i < N; ++i) {
    a(i, i) = 0.5 * (a(i, i) + a(i, i));
    for (int j = i + 1; j < N; ++j) a(i, j) = a(j, i) = 0.5 * (a(i, j) + a(j, i));
  }
}

// cholesky_inverse into `inv` (not `l`).
template <int N>
void cholesky_inverse(const SquareMatrix<N>& l, SquareMatrix<N>& inv) {
  for (int c = 0; c < N; ++c) inv.col(c) = cholesky_solve<N>(l, ColumnVector<N>::Unit(c));
  symmetrize<N>(inv);  // exactly symmetric
}

template <int N>
SquareMatrix<N> cholesky_inverse(const SquareMatrix<N>& l) {
  SquareMatrix<N> inv;
  cholesky_inverse<N>(l, inv);
  return inv;
}

// jacobi_eigenvalues on a matrix it may overwrite (no second N x N matrix).
template <int N>
ColumnVector<N> jacobi_eigenvalues_in_place(SquareMatrix<N>& a) {
  symmetrize<N>(a);
  const double norm = std::sqrt(a.cwiseAbs2().sum());
  const double tol = std::numeric_limits<double>::epsilon() * norm;
  for (int sweep = 0; sweep < kJacobiSweeps; ++sweep) {
    double off = 0.0;
    for (int p = 0; p < N; ++p) {
      for (int q = p + 1; q < N; ++q) off = std::fmax(off, std::fabs(a(p, q)));
    }
    if (!(off > tol)) break;
    for (int p = 0; p < N; ++p) {
      for (int q = p + 1; q < N; ++q) {
        const double apq = a(p, q);
        if (apq == 0.0) continue;
        // The rotation that zeroes a(p, q) (the smaller of the two angles).
        const double theta = (a(q, q) - a(p, p)) / (2.0 * apq);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0);
        const double s = t * c;
        for (int k = 0; k < N; ++k) {  // columns p, q
          const double akp = a(k, p);
          const double akq = a(k, q);
          a(k, p) = c * akp - s * akq;
          a(k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < N; ++k) {  // rows p, q
          const double apk = a(p, k);
          const double aqk = a(q, k);
          a(p, k) = c * apk - s * aqk;
          a(q, k) = s * apk + c * aqk;
        }
        a(p, q) = a(q, p) = 0.0;
      }
    }
  }
  ColumnVector<N> d = a.diagonal();
  for (int i = 1; i < N; ++i) {  // insertion sort, ascending
    const double v = d(i);
    int j = i - 1;
    while (j >= 0 && d(j) > v) {
      d(j + 1) = d(j);
      --j;
    }
    d(j + 1) = v;
  }
  return d;
}

template <int N>
ColumnVector<N> jacobi_eigenvalues(const SquareMatrix<N>& a_in) {
  SquareMatrix<N> a = a_in;
  return jacobi_eigenvalues_in_place<N>(a);
}

}  // namespace trueaxis::core
