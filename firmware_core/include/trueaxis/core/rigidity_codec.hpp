// The rigidity table's stored form: a byte layout independent of the
// platform's endianness and struct padding, for the persistent record.
//
// Layout version 1 (all integers little-endian unsigned, all reals IEEE-754
// binary64 little-endian; m = pose count):
//   offset  size      field
//   0       2         layout version = 1
//   2       2         m, kMinAPoses..kMaxAPoses
//   4       2         reference pose index, < m
//   6       2         home_identity (0: none recorded; before it, a reserved 0)
//   8       10 x 8    a_axis_point_mm (3), a_axis_direction (3), c_to_a_offset_mm,
//                     c_to_a_offset_sigma_mm, c_to_a_squareness_rad,
//                     c_to_a_squareness_sigma_rad
//   88      m x 27 x 8  per pose, in A order: a_deg, rotvec_rad (3),
//                     rotvec_sigma_rad (3), rigidity_rad, rigidity_sigma_rad,
//                     theta_rad, a_error_rad, a_error_sigma_rad,
//                     origin_offset_mm (3), c_centre_mm (3), c_direction (3),
//                     c_x_axis (3), c_circle_rms_mm, c_arc_deg, c_count
// Size: 88 + 216 m bytes; 3544 for 16 poses (kRigidityTableMaxBytes).
// The derived data (rigidity_table.hpp convention 8) is not stored: decode
// recomputes it with the same code, so a decoded table equals the encoded one
// bit for bit.
//
// Validation on decode (each failure kTableInvalid, `out` untouched): the size is
// exactly 88 + 216 m; version 1; m in range; reference < m; every
// real finite; A strictly increasing; |A_ref| <= kPoseAToleranceDeg; the A
// direction, each c_direction and c_x_axis unit within kCodecUnitTolerance and
// c_x_axis normal to c_direction within it; |rotvec| <= pi; sigmas, rms, arc
// and the C-to-A offset >= 0; arc < 360; c_count a whole number in
// kMinCPositions..kMaxCirclePoints.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::core {

inline constexpr std::uint16_t kRigidityLayoutVersion = 1;
inline constexpr std::size_t kRigidityHeaderBytes = 88;
inline constexpr std::size_t kRigidityPoseBytes = 27 * 8;
inline constexpr std::size_t kRigidityTableMaxBytes = kRigidityHeaderBytes + kMaxAPoses * kRigidityPoseBytes;
inline constexpr double kCodecUnitTolerance = 1e-9;
static_assert(kRigidityTableMaxBytes <= 4096, "a full table must fit its 4096-byte record");

// Bytes a table of `pose_count` poses takes.
constexpr std::size_t rigidity_table_bytes(std::size_t pose_count) {
  return kRigidityHeaderBytes + pose_count * kRigidityPoseBytes;
}

// Writes the table into out[0..capacity); returns the bytes written, or 0 when
// the capacity is too small or the table's pose count or reference is out of
// range (nothing is written then).
std::size_t encode_rigidity_table(const RigidityTable& table, std::uint8_t* out, std::size_t capacity);

// Reads a table written by encode_rigidity_table (layout above), derived data
// included. kTableInvalid on any failed check; `out` is untouched then.
[[nodiscard]] Status decode_rigidity_table(const std::uint8_t* bytes, std::size_t size, RigidityTable& out);

// The layout's reals apart from its bytes, for a transport that carries
// doubles exactly (the registers: macro 9837): the header's ten (offset 8 on)
// and each pose's 27 (its c_count as a real), in layout order, as stored.
inline constexpr std::size_t kRigidityHeaderReals = 10;
inline constexpr std::size_t kRigidityPoseReals = 27;
static_assert(kRigidityHeaderBytes == 8 + 8 * kRigidityHeaderReals && kRigidityPoseBytes == 8 * kRigidityPoseReals,
              "the reals are the layout's");
void rigidity_header_reals(const RigidityTable& table, double out[kRigidityHeaderReals]);
// Pose `pose` (< table.pose_count, 0-based in A order); nothing written beyond it.
void rigidity_pose_reals(const RigidityTable& table, std::size_t pose, double out[kRigidityPoseReals]);

// The layout's bytes from its reals (rigidity_header_reals, then
// pose_count x rigidity_pose_reals) and the home identity:
// encode_rigidity_table's bytes bit for bit. Returns the bytes written, or 0
// as encode_rigidity_table; it checks nothing else (decode_rigidity_table does).
std::size_t encode_rigidity_reals(std::size_t pose_count, std::size_t reference, std::uint16_t home_identity,
                                  const double* header_reals, const double* pose_reals, std::uint8_t* out,
                                  std::size_t capacity);

}  // namespace trueaxis::core
