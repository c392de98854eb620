// Independent circle computations for the circle-fit tests, in long double and
// sharing no code with firmware_core: the POINT model
//     p_i = c + r (cos t_i u(n) + sin t_i v(n))
// with the phases t_i as nuisance parameters, numeric derivatives, and a
// parameterisation of the normal that is not the core's (a FIXED tangent basis
// (e1, e2) at a reference normal n0, never re-based):
//     n(a, b) = (n0 + a e1 + b e2) / |n0 + a e1 + b e2|,
//     u(n) = (e1 - (e1 . n) n) / |e1 - (e1 . n) n|,   v(n) = n x u(n).
// Parameters theta = (c_x, c_y, c_z, a, b, r).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Cholesky>

#include "reference.hpp"

namespace trueaxis::test {

using Vec6L = Eigen::Matrix<long double, 6, 1>;
using Mat6L = Eigen::Matrix<long double, 6, 6>;
using Mat36L = Eigen::Matrix<long double, 3, 6>;

struct CircleModel {
  Vec3L n0;
  Vec3L e1;
  Vec3L e2;

  explicit CircleModel(const Vec3L& normal) : n0(normal.normalized()) {
    e1 = n0.cross(std::abs(n0.x()) < 0.6L ? Vec3L::UnitX() : Vec3L::UnitY()).normalized();
    e2 = n0.cross(e1);
  }

  Vec3L normal(const Vec6L& th) const { return (n0 + th(3) * e1 + th(4) * e2).normalized(); }

  Vec3L point(const Vec6L& th, long double t) const {
    const Vec3L n = normal(th);
    const Vec3L u = (e1 - e1.dot(n) * n).normalized();
    const Vec3L v = n.cross(u);
    return th.head<3>() + th(5) * (std::cos(t) * u + std::sin(t) * v);
  }

  // d p / d theta (3x6) and d p / d t, by central differences.
  void derivatives(const Vec6L& th, long double t, Mat36L& j, Vec3L& g) const {
    const long double scale = std::max(1.0L, th(5));
    for (int k = 0; k < 6; ++k) {
      const long double h = (k == 3 || k == 4) ? 1e-7L : 1e-7L * scale;
      Vec6L hi = th;
      Vec6L lo = th;
      hi(k) += h;
      lo(k) -= h;
      j.col(k) = (point(hi, t) - point(lo, t)) / (2.0L * h);
    }
    const long double ht = 1e-7L;
    g = (point(th, t + ht) - point(th, t - ht)) / (2.0L * ht);
  }

  // Fisher information with the phases eliminated (Schur complement), per unit
  // noise variance:  F = sum_i J_i^T (I - g_i g_i^T / |g_i|^2) J_i.
  template <std::size_t N>
  Mat6L reduced_information(const Vec6L& th, const std::array<long double, N>& t, std::size_t count) const {
    Mat6L f = Mat6L::Zero();
    for (std::size_t i = 0; i < count; ++i) {
      Mat36L j;
      Vec3L g;
      derivatives(th, t[i], j, g);
      const Mat3L p = Mat3L::Identity() - g * g.transpose() / g.squaredNorm();
      f += j.transpose() * p * j;
    }
    return f;
  }
};

// A true circle for generating samples: centre, unit normal, in-plane basis
// (u, v, n right-handed), radius; sample(t) = c + r (cos t u + sin t v).
struct TrueCircle {
  Vec3L c;
  Vec3L n;
  Vec3L u;
  Vec3L v;
  long double r;
  Vec3L sample(long double t) const { return c + r * (std::cos(t) * u + std::sin(t) * v); }
};

// Any orientation, centre uniform in a cube of half-side centre_span_mm.
inline TrueCircle random_circle(Rng& rng, long double radius_mm, double centre_span_mm) {
  TrueCircle tc;
  tc.n = rng.unit_vector().cast<long double>().normalized();
  tc.u = tc.n.cross(rng.unit_vector().cast<long double>()).normalized();
  tc.v = tc.n.cross(tc.u);
  tc.c = Vec3L(rng.uniform(-centre_span_mm, centre_span_mm), rng.uniform(-centre_span_mm, centre_span_mm),
               rng.uniform(-centre_span_mm, centre_span_mm));
  tc.r = radius_mm;
  return tc;
}

// Phases of `count` samples spread evenly over `arc_deg` from `start_rad` (a full
// circle: 360 / count apart).
template <std::size_t N>
void even_phases(std::array<long double, N>& t, std::size_t count, long double arc_deg, long double start_rad) {
  const bool full = arc_deg >= 360.0L;
  const long double step = deg_l(arc_deg) / static_cast<long double>(full ? count : count - 1);
  for (std::size_t i = 0; i < count; ++i) t[i] = start_rad + step * static_cast<long double>(i);
}

// Sum of squared 3-D distances of points from the circle (c, n, r), closed form.
template <typename Point>
long double circle_cost_l(const Point* p, std::size_t count, const Vec3L& c, const Vec3L& n_in, long double r) {
  const Vec3L n = n_in.normalized();
  long double sum = 0.0L;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3L d = p[i].template cast<long double>() - c;
    const long double h = n.dot(d);
    const long double rho = (d - h * n).norm();
    sum += h * h + (rho - r) * (rho - r);
  }
  return sum;
}

// Gauss-Newton on the point model over (theta, t_1..t_n), the phases eliminated
// at each step (variable projection), from theta0 and phases t0.
template <std::size_t N>
Vec6L reference_fit_l(const CircleModel& model, const Eigen::Vector3d* p, std::size_t count, Vec6L th,
                      std::array<long double, N> t, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    Mat6L a = Mat6L::Zero();
    Vec6L b = Vec6L::Zero();
    std::array<Mat36L, N> js;
    std::array<Vec3L, N> gs;
    std::array<Vec3L, N> es;
    for (std::size_t i = 0; i < count; ++i) {
      model.derivatives(th, t[i], js[i], gs[i]);
      es[i] = p[i].cast<long double>() - model.point(th, t[i]);
      const Mat3L proj = Mat3L::Identity() - gs[i] * gs[i].transpose() / gs[i].squaredNorm();
      a += js[i].transpose() * proj * js[i];
      b += js[i].transpose() * proj * es[i];
    }
    const Vec6L step = a.ldlt().solve(b);
    for (std::size_t i = 0; i < count; ++i) {
      t[i] += gs[i].dot(es[i] - js[i] * step) / gs[i].squaredNorm();
    }
    th += step;
  }
  return th;
}

}  // namespace trueaxis::test
