// SO(3): the exponential and logarithm maps between rotation vectors and
// rotation matrices, accurate over the whole range.
//
// Conventions
//  1. A rotation vector w = theta * n (unit axis n, angle theta in radians,
//     right-hand rule). exp(w) = I + sin(theta) [n]x + (1 - cos(theta)) [n]x^2
//     (Rodrigues).
//  2. log returns theta in [0, pi]. At exactly theta = pi the axis sign is not
//     determined by R; log returns one of the two, both map back to R.
//  3. Near theta = 0 exp switches to Taylor series: sin(theta) / theta =
//     1 - theta^2 / 6 and (1 - cos(theta)) / theta^2 = 1 / 2 - theta^2 / 24 below
//     so3_taylor_threshold(), where the first dropped terms (theta^4 / 120,
//     theta^4 / 720) stay below half an ulp of 1. The switch point derives from
//     numeric_limits<double>, not from a literal.
//  4. log follows Shepperd's method (the largest of 1 + trace and
//     1 + 2 r(i, i) - trace), so nothing divides by a small number anywhere:
//     a. trace branch (theta up to at least pi / 2): with h = vee(R) = sin(theta) n,
//        c = (1 + trace) / 4 = cos^2(theta / 2) and x = |h| / (2 c) = tan(theta / 2),
//        w = h atan(x) / (x c). Below x = so3_taylor_threshold() / 2 it is
//        w = h + delta h, delta = (1 - c - x^2 / 3 + x^4 / 5) / c (first dropped
//        term x^6 / 7 < 1e-22), with 1 - c taken from the exact 1 - r(i, i).
//     b. diagonal branches (theta near pi): the unnormalised quaternion q,
//        w = 2 atan2(|q_v|, q_w) q_v / |q_v| with q_w >= 0, accurate where the
//        trace-based formula loses half the digits.
//  5. The input of log is assumed to be a rotation (orthonormal, det +1) to
//     working precision; a general matrix gets the log of the rotation of its
//     Shepperd quaternion, never NaN.
//  6. Accuracy, eps = numeric_limits<double>::epsilon(), checked against long
//     double in tests/core/test_so3.cpp (measured values in brackets):
//     exp: off-diagonal entries within 3 eps min(theta, 1) of the exact rotation
//          [2.7], diagonal entries within 5 eps [4.2];
//     log: for R the rotation of w rounded to double, |log(R) - w| <= 1.25 eps
//          |w| in the series of 4a, theta < 2 atan(threshold / 2) (3e-12 rad
//          under the threshold) [1.0, about one ulp per component], and
//          <= 3 eps |w| up to pi [2.2]; at pi, one of +-w.
#pragma once

#include "trueaxis/core/types.hpp"

namespace trueaxis::core {

// The skew-symmetric matrix [w]x with [w]x v = w x v.
Mat3 hat(const Vec3& w);

// The vector of the skew-symmetric part of m: vee(hat(w)) = w.
Vec3 vee(const Mat3& m);

// exp: rotation vector (rad) -> rotation matrix.
Mat3 so3_exp(const Vec3& w_rad);

// log: rotation matrix -> rotation vector (rad) with |w| in [0, pi].
Vec3 so3_log(const Mat3& r);

// The Taylor-branch threshold (60 eps)^(1/4) = 3.4e-4 rad on theta for so3_exp
// and on 2 tan(theta / 2) for so3_log (conventions 3, 4a): below it, theta^4 / 120
// (the first dropped term of sin(theta) / theta) is below half an ulp of 1.
// Exposed so tests can probe it to the ulp.
double so3_taylor_threshold();

}  // namespace trueaxis::core
