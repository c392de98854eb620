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

// Unit quaternion (w, x, y, z) of a rotation matrix by Shepperd's method: the
// largest of the four diagonal combinations is taken under the square root, so
// no branch divides by a small number.
void quaternion_from_matrix(const Mat3& r, double& qw, Vec3& qv) {
  const double t = r.trace();
  if (t >= r(0, 0) && t >= r(1, 1) && t >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + t);  // 4 qw
    qw = 0.25 * s;
    qv = Vec3(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1)) / s;
  } else if (r(0, 0) >= r(1, 1) && r(0, 0) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));  // 4 qx
    qw = (r(2, 1) - r(1, 2)) / s;
    qv = Vec3(0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s);
  } else if (r(1, 1) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));  // 4 qy
    qw = (r(0, 2) - r(2, 0)) / s;
    qv = Vec3((r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s);
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));  // 4 qz
    qw = (r(1, 0) - r(0, 1)) / s;
    qv = Vec3((r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s);
  }
  const double norm = std::sqrt(qw * qw + qv.squaredNorm());
  qw /= norm;
  qv /= norm;
  if (qw < 0.0) {  // q and -q are the same rotation; qw >= 0 gives theta <= pi
    qw = -qw;
    qv = -qv;
  }
}

}  // namespace

Vec3 so3_log(const Mat3& r) {
  double qw = 1.0;
  Vec3 qv = Vec3::Zero();
  quaternion_from_matrix(r, qw, qv);
  const double vn = qv.norm();  // sin(theta / 2)
  // theta = 2 atan2(|v|, w); w = theta / |v| * v.
  if (2.0 * vn < so3_taylor_threshold()) {
    // 2 atan(x) / x with x = |v| / w, Taylor: 2 (1 - x^2 / 3) / w.
    const double x2 = (vn * vn) / (qw * qw);
    return (2.0 / qw) * (1.0 - x2 / 3.0) * qv;
  }
  return (2.0 * std::atan2(vn, qw) / vn) * qv;
}

}  // namespace trueaxis::core
