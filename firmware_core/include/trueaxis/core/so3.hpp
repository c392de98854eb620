// SO(3): the exponential and logarithm maps between rotation vectors and
// rotation matrices, accurate over the whole range.
//
// Conventions
//  1. A rotation vector w = theta * n (unit axis n, angle theta in radians,
//     right-hand rule). exp(w) = I + sin(theta) [n]x + (1 - cos(theta)) [n]x^2
//     (Rodrigues).
//  2. log returns theta in [0, pi]. At exactly theta = pi the axis sign is not
//     determined by R; log returns one of the two, both map back to R.
//  3. Near theta = 0 both maps switch to Taylor series; the switch points derive
//     from numeric_limits<double>, not from literals, so the truncation error of
//     the series stays below one ulp.
//  4. log goes through a unit quaternion built with Shepperd's method, so it
//     stays accurate near pi where the trace-based formula loses half the digits.
//  5. The input of log is assumed to be a rotation (orthonormal, det +1) to
//     working precision; a general matrix gets the log of its nearest-by-
//     quaternion rotation, never NaN.
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

// The Taylor-branch threshold on theta used by so3_exp and so3_log:
// below it, theta^4 / 120 (the first dropped term of sin(theta)/theta) is below
// half an ulp of 1. Exposed so tests can probe it to the ulp.
double so3_taylor_threshold();

}  // namespace trueaxis::core
