#include "trueaxis/core/so3.hpp"

#include <limits>

namespace trueaxis::core {

double so3_taylor_threshold() {
  // theta^4 / 120 < eps / 2  <=>  theta < (60 eps)^(1/4).
  return std::sqrt(std::sqrt(60.0 * std::numeric_limits<double>::epsilon()));
}

Mat3 hat(const Vec3& w) {
  Mat3 m;
  m <<  0.0,  -w.z(),  w.y(),
        w.z(),  0.0,  -w.x(),
       -w.y(),  w.x(),  0.0;
  return m;
}

Vec3 vee(const Mat3& m) {
  return Vec3(0.5 * (m(2, 1) - m(1, 2)), 0.5 * (m(0, 2) - m(2, 0)), 0.5 * (m(1, 0) - m(0, 1)));
}

Mat3 so3_exp(const Vec3& w_rad) {
  const double theta2 = w_rad.squaredNorm();
  const double theta = std::sqrt(theta2);
  double a;  // sin(theta) / theta
  double b;  // (1 - cos(theta)) / theta^2
  if (theta < so3_taylor_threshold()) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    // 1 - cos(theta) = 2 sin^2(theta / 2) avoids the cancellation of 1 - cos.
    const double s_half = std::sin(0.5 * theta);
    a = std::sin(theta) / theta;
    b = 2.0 * s_half * s_half / theta2;
  }
  const Mat3 k = hat(w_rad);
  return Mat3::Identity() + a * k + b * (k * k);
}

namespace {

// Convention 4a: w = h atan(x) / (x c), written as h + delta h below the
// threshold so that each component is rounded about once. 1 - r(i, i) is exact
// for a rotation (Sterbenz), so d, c and x keep their relative precision.
Vec3 log_trace_branch(const Mat3& r) {
  const Vec3 h = vee(r);                                                   // sin(theta) n
  const double d = (1.0 - r(0, 0)) + (1.0 - r(1, 1)) + (1.0 - r(2, 2));  // 3 - trace
  const double c = 1.0 - 0.25 * d;                                        // (1 + trace) / 4
  const double x2 = h.squaredNorm() / (4.0 * c * c);                     // tan^2(theta / 2)
  const double half_threshold = 0.5 * so3_taylor_threshold();
  if (x2 < half_threshold * half_threshold) {
    const double delta = (0.25 * d - x2 / 3.0 + 0.2 * x2 * x2) / c;
    return h + delta * h;
  }
  const double x = std::sqrt(x2);
  return (std::atan(x) / (x * c)) * h;
}

// Convention 4b: Shepperd's three diagonal branches, the largest diagonal
// combination under the square root so that nothing divides by a small number.
// The quaternion is left unnormalised: theta and the axis depend on its direction only.
Vec3 log_diagonal_branch(const Mat3& r) {
  int i = 0;
  if (r(1, 1) > r(i, i)) i = 1;
  if (r(2, 2) > r(i, i)) i = 2;
  const int j = (i + 1) % 3;
  const int k = (i + 2) % 3;
  const double s = 2.0 * std::sqrt(1.0 + r(i, i) - r(j, j) - r(k, k));  // 4 |q_i| >= 2
  double qw = (r(k, j) - r(j, k)) / s;
  Vec3 qv;
  qv(i) = 0.25 * s;
  qv(j) = (r(j, i) + r(i, j)) / s;
  qv(k) = (r(k, i) + r(i, k)) / s;
  if (qw < 0.0) {  // q and -q are the same rotation; qw >= 0 gives theta <= pi
    qw = -qw;
    qv = -qv;
  }
  const double vn = qv.norm();  // >= 0.5
  return (2.0 * std::atan2(vn, qw) / vn) * qv;
}

}  // namespace

Vec3 so3_log(const Mat3& r) {
  const double t = r.trace();
  if (t >= r(0, 0) && t >= r(1, 1) && t >= r(2, 2)) return log_trace_branch(r);
  return log_diagonal_branch(r);
}

}  // namespace trueaxis::core
