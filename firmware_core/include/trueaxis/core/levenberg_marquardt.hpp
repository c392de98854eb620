// Levenberg-Marquardt for N parameters, fixed size and allocation-free, that
// never holds the data: each evaluation streams residual blocks (r_i, J_i) into
// the normal equations (J^T J, J^T r, r^T r), so the number of samples costs no
// memory, and the caller feeds the blocks in as many pieces as its step bound
// allows (M4's identification spans several module steps).
//
// Use
//     LevenbergMarquardt<N> lm;  lm.start(p0);
//     do {
//       lm.begin_evaluation();
//       for each sample: lm.add(r_i, J_i)      // at lm.point(), any pieces
//     } while (lm.finish_evaluation().more);
//     lm.status(), lm.solution(), lm.covariance(...)
//
// Conventions
//  1. Cost F(p) = 1/2 sum_i |r_i(p)|^2; m = the number of scalar residuals.
//  2. The step solves (A + lambda D) dp = -g with A = J^T J, g = J^T r and
//     D = diag(A) (Marquardt's scaling: the step does not depend on the
//     parameters' units), each entry floored at kDiagFloor times the largest.
//  3. A trial p + dp is accepted when its cost is not higher (near a minimum
//     the costs agree to rounding); then lambda /= 10
//     (not below kMinLambda), else lambda *= 10 and the step is solved again from
//     the same A and g (no new evaluation of p). A rejected step costs one
//     evaluation, like an accepted one: evaluations() counts them all. A step
//     rejected although it promised a fall below kCostRounding F (the
//     comparison is then rounding, not information) ends the solve (kOk).
//  4. Converged (kOk) when the step just taken, or the next one solved for, is
//     negligible in every parameter k: |dp_k| <= xtol (|p_k| + xtol), or it moves
//     the residuals by no more than xtol of their RMS, |dp_k| sqrt(D_k) <=
//     xtol sqrt(2 F) (a parameter near zero; no evaluation is
//     spent on it), or after an accepted step when
//     the scaled gradient max_k |g_k| / sqrt(A_kk) <= gtol sqrt(2 F).
//     (No test on the cost's fall: near a minimum it falls by the square of
//     the error left, and would stop the solver far from it.)
//     Also kOk, before a step is solved for, when the full Gauss-Newton step
//     could lower the cost by no more than stat_tol^2 s^2 / 2 (s^2 = 2 F /
//     (m - N)): g^T A^-1 g <= stat_tol^2 s^2, i.e. the minimum lies within
//     stat_tol (1e-3) of the parameters' own 1-sigma ellipsoid; iterating
//     further changes nothing the covariance can show (noise-free data, s = 0,
//     never stop here).
//     Also kOk when lambda exceeds kMaxLambda with the scaled gradient within
//     1e3 gtol: no step can lower the cost any more (a minimum at rounding).
//     kNoConvergence after max_iterations evaluations, or lambda beyond
//     kMaxLambda with a gradient left.
//  5. Identifiability: the correlation form C = D^-1/2 A D^-1/2 of the normal
//     matrix at the solution (a start point may be singular where the
//     solution is not: it is not judged); when its smallest
//     eigenvalue is below rank_tol times its largest (a parameter combination
//     the data do not determine), kNotIdentifiable. smallest_eigenvalue_ratio()
//     reports it.
//  6. Covariance at the solution: s^2 A^-1, with s^2 given (a known residual
//     noise) or from the residuals, 2 F / (m - N) (needs m > N); NaN when A is
//     not positive definite. Solves and eigenvalues by small_linear.hpp (no
//     blocked kernels: nothing from the heap on the target), in the solver's
//     own scratch matrix (no N x N temporary on the caller's stack).
//  7. A non-finite residual or Jacobian entry: kNotFinite (the caller's model
//     failed at that point); nothing is accepted from it.
#pragma once

#include <cmath>
#include <cstddef>

#include <limits>

#include <Eigen/Core>

#include "trueaxis/core/small_linear.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::core {

struct LmStep {
  Status status = Status::kOk;
  bool more = false;  // true: evaluate again at point()
};

struct LmOptions {
  int max_iterations = 200;  // evaluations
  double xtol = 1e-12;
  double gtol = 1e-12;
  double lambda0 = 1e-3;
  double rank_tol = 1e-12;
  double stat_tol = 1e-3;  // convention 4; 0 disables
};

template <int N>
class LevenbergMarquardt {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  static constexpr double kDiagFloor = 1e-12;
  static constexpr double kMinLambda = 1e-15;
  static constexpr double kMaxLambda = 1e16;
  static constexpr double kCostRounding = 1e-13;  // relative rounding of a sum of squares

  void start(const Vec& p0, const LmOptions& options = LmOptions()) {
    options_ = options;
    p_ = p0;
    trial_ = p0;
    lambda_ = options.lambda0;
    have_current_ = false;
    done_ = false;
    status_ = Status::kOk;
    evaluations_ = 0;
    iterations_ = 0;
    ratio_ = 1.0;
  }

  // Where the evaluation under way must compute its residuals.
  const Vec& point() const { return trial_; }

  void begin_evaluation() {
    a_trial_.setZero();
    g_trial_.setZero();
    cost_trial_ = 0.0;
    m_trial_ = 0;
    finite_ = true;
  }

  template <int M>
  void add(const Eigen::Matrix<double, M, 1>& r, const Eigen::Matrix<double, M, N>& j) {
    if (!r.allFinite() || !j.allFinite()) finite_ = false;
    // lazyProduct: coefficient-wise, never Eigen's blocked product (whose
    // workspace would come from the heap on the target at these sizes).
    a_trial_.noalias() += j.transpose().lazyProduct(j);
    g_trial_.noalias() += j.transpose().lazyProduct(r);
    cost_trial_ += 0.5 * r.squaredNorm();
    m_trial_ += static_cast<std::size_t>(M);
  }

  LmStep finish_evaluation() {
    if (done_) return {status_, false};
    ++evaluations_;
    if (!finite_) return finish(Status::kNotFinite);
    if (!have_current_) {  // the first evaluation, at p0
      accept_trial();
      if (scaled_gradient() <= options_.gtol * std::sqrt(2.0 * cost_)) return converge();
      return next_trial();
    }
    if (cost_trial_ <= cost_) {
      const Vec dp = trial_ - p_;
      accept_trial();
      lambda_ = std::fmax(lambda_ / 10.0, kMinLambda);
      ++iterations_;
      if (small(dp) || scaled_gradient() <= options_.gtol * std::sqrt(2.0 * cost_)) {
        return converge();
      }
    } else {
      // Rejected: when the fall the step promised is below what the cost's
      // rounding can show, no step can be judged any more (a minimum).
      const Vec dp = trial_ - p_;
      const double promised = -g_.dot(dp) - 0.5 * dp.dot(a_ * dp);
      if (promised <= kCostRounding * cost_) return converge();
      lambda_ *= 10.0;
      if (lambda_ > kMaxLambda) {
        return scaled_gradient() <= 1e3 * options_.gtol * std::sqrt(2.0 * cost_) + 1e-300 ? converge()
                                                                                      : finish(Status::kNoConvergence);
      }
    }
    if (evaluations_ >= options_.max_iterations) return finish(Status::kNoConvergence);
    return next_trial();
  }

  Status status() const { return status_; }
  bool done() const { return done_; }
  const Vec& solution() const { return p_; }
  double cost() const { return cost_; }
  std::size_t residual_count() const { return m_; }
  int evaluations() const { return evaluations_; }
  int iterations() const { return iterations_; }  // accepted steps
  double smallest_eigenvalue_ratio() const { return ratio_; }
  const Mat& normal_matrix() const { return a_; }

  // Convention 6: sigma2 > 0 a known residual variance, else from the residuals
  // (a zero matrix when m <= N).
  Mat covariance(double sigma2 = 0.0) const {
    Mat out;
    Mat l;
    covariance(sigma2, out, l);
    return out;
  }

  // The same into `out`, with `l` (distinct from `out`) as the caller's
  // scratch: no N x N temporary on the stack.
  void covariance(double sigma2, Mat& out, Mat& l) const {
    double s2 = sigma2;
    if (!(s2 > 0.0)) {
      if (m_ <= static_cast<std::size_t>(N)) {
        out.setZero();
        return;
      }
      s2 = 2.0 * cost_ / static_cast<double>(m_ - static_cast<std::size_t>(N));
    }
    if (!cholesky_lower<N>(a_, l)) {
      out.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    cholesky_inverse<N>(l, out);
    out *= s2;
  }

 private:
  void accept_trial() {
    p_ = trial_;
    a_ = a_trial_;
    g_ = g_trial_;
    cost_ = cost_trial_;
    m_ = m_trial_;
    have_current_ = true;
  }

  bool small(const Vec& dp) const {
    const Vec d = diag();
    const double rms = std::sqrt(2.0 * cost_);
    for (int k = 0; k < N; ++k) {
      const double step = std::fabs(dp(k));
      if (!(step <= options_.xtol * (std::fabs(p_(k)) + options_.xtol) ||
            step * std::sqrt(d(k)) <= options_.xtol * rms)) {
        return false;
      }
    }
    return true;
  }

  Vec diag() const {
    Vec d = a_.diagonal();
    const double floor = kDiagFloor * d.maxCoeff();
    for (int k = 0; k < N; ++k) d(k) = std::fmax(d(k), floor);
    return d;
  }

  double scaled_gradient() const {
    const Vec d = diag();
    double worst = 0.0;
    for (int k = 0; k < N; ++k) worst = std::fmax(worst, std::fabs(g_(k)) / std::sqrt(d(k)));
    return worst;
  }

  // Of the normal matrix a_; work_ is its scratch.
  double smallest_ratio() {
    Vec s = a_.diagonal();
    for (int k = 0; k < N; ++k) s(k) = s(k) > 0.0 ? 1.0 / std::sqrt(s(k)) : 0.0;
    work_ = s.asDiagonal() * a_ * s.asDiagonal();  // diagonal scalings: no blocked product
    const Vec e = jacobi_eigenvalues_in_place<N>(work_);
    const double largest = e(N - 1);
    return largest > 0.0 ? e(0) / largest : 0.0;
  }

  // Convention 4's statistical test: g^T A^-1 g <= stat_tol^2 s^2.
  bool within_noise() {
    if (m_ <= static_cast<std::size_t>(N) || !(options_.stat_tol > 0.0)) return false;
    if (!cholesky_lower<N>(a_, work_)) return false;
    const double s2 = 2.0 * cost_ / static_cast<double>(m_ - static_cast<std::size_t>(N));
    return g_.dot(cholesky_solve<N>(work_, g_)) <= options_.stat_tol * options_.stat_tol * s2;
  }

  LmStep next_trial() {
    if (within_noise()) return converge();
    const Vec d = diag();
    work_ = a_;
    for (int k = 0; k < N; ++k) work_(k, k) += lambda_ * d(k);
    if (!cholesky_in_place<N>(work_)) return finish(Status::kNotIdentifiable);
    const Vec dp = -cholesky_solve<N>(work_, g_);
    if (!dp.allFinite()) return finish(Status::kNotIdentifiable);
    if (small(dp)) return converge();  // nothing left worth an evaluation
    trial_ = p_ + dp;
    return {Status::kOk, true};
  }

  LmStep converge() {
    ratio_ = smallest_ratio();
    return finish(ratio_ >= options_.rank_tol ? Status::kOk : Status::kNotIdentifiable);
  }

  LmStep finish(Status s) {
    done_ = true;
    status_ = s;
    trial_ = p_;
    return {s, false};
  }

  LmOptions options_;
  Vec p_ = Vec::Zero();
  Vec trial_ = Vec::Zero();
  Mat a_ = Mat::Zero();
  Vec g_ = Vec::Zero();
  double cost_ = 0.0;
  std::size_t m_ = 0;
  Mat a_trial_ = Mat::Zero();
  Vec g_trial_ = Vec::Zero();
  double cost_trial_ = 0.0;
  std::size_t m_trial_ = 0;
  bool finite_ = true;
  bool have_current_ = false;
  bool done_ = false;
  Status status_ = Status::kOk;
  double lambda_ = 1e-3;
  double ratio_ = 1.0;
  int evaluations_ = 0;
  int iterations_ = 0;
  // Factorisations and the scaled matrix: off the stack (docs/FIGURES.md
  // "Stack"). Last, so that the members add() touches on every residual keep
  // their offsets (within reach of a Cortex-M7 load's immediate).
  Mat work_ = Mat::Zero();
};

}  // namespace trueaxis::core
