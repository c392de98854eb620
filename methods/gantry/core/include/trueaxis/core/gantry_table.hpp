// The stored gantry frames (M2): what a controller keeps of a computation, the
// point conversion its programs need, and the record's byte layout.
//
// Conventions
//  1. A GantryTable holds the global frame of the last computation stored and,
//     per sub-machine id 1..kMaxSubMachines, the frame of the computation that
//     stored it last (merge_frames: the sub-machines of a new computation
//     replace theirs, the others stay; docs/INTERFACE.md "With --store").
//  2. A stored sub-machine keeps every figure the report macros publish: the
//     frame, its uncertainty, the master axis, squareness, A-to-C offset and
//     angle with their sigmas, straightness per axis and the circles' RMS; the
//     global frame its flatness, straightness, noise floors and form errors. Sigmas of angles in
//     arc-seconds, as GantryFrames has them.
//  3. sub_T_global (the inverse of global_T_sub) is stored beside it, so the
//     point conversion is one rotation and one translation:
//         p_sub = R^T p_global + t,  R^T and t precomputed.
//
//  4. The figures issue 17 added (the noise floors, the form errors and their
//     sigmas; the squareness, A-to-C offset and A-to-C angle sigmas) read
//     kFigureNotStored (-1) where a table stored before them (layout 1) is
//     decoded: unknown, never a sigma of 0. A sub-machine of such a table kept
//     by a merge keeps -1 for them in the next record.
//
// Layout version 2 (integers little-endian unsigned, reals IEEE-754 binary64
// little-endian); its first 1880 bytes are layout 1's, field for field:
//   offset  size      field
//   0       2         layout version = 2 (1: the first 1880 bytes only)
//   2       2         present mask: bit N-1 set for sub-machine N, 1..0xFF
//   4       4         reserved, 0
//   8       18 x 8    global: tracker_T_global R (9, row-major), t (3),
//                     bed_flatness_mm, gantry_straightness_mm, origin_sigma_mm,
//                     angle_sigma_arcsec (3)
//   152     8 x 216   per sub-machine id 1..8 (zero when absent): master axis
//                     (u8, 0..2), 7 bytes reserved 0, then 26 x 8:
//                     global_T_sub R (9, row-major), t (3), origin_sigma_mm,
//                     angle_sigma_arcsec (3), squareness_arcsec (3),
//                     a_c_offset_mm, a_c_angle_deg, straightness_mm (3),
//                     c_circle_rms_mm, a_circle_rms_mm
//   1880    6 x 8     global (layout 2): bed_flatness_noise_floor_mm,
//                     gantry_straightness_noise_floor_mm, bed_form_error_mm,
//                     bed_form_error_sigma_mm, gantry_form_error_mm,
//                     gantry_form_error_sigma_mm
//   1928    8 x 40    per sub-machine id 1..8 (layout 2; zero when absent):
//                     squareness_sigma_arcsec (3), a_c_offset_sigma_mm,
//                     a_c_angle_sigma_deg
// Size: 2248 bytes (kGantryTableBytes; layout 1: kGantryTableBytesV1 = 1880).
// encode writes layout 2; decode reads both (the record's key-store layout
// version stays 1, so the frames a controller stored before keep loading:
// tests/macros/test_store_upgrade.cpp). sub_T_global is not stored: decode
// recomputes it with the same code, so a decoded table equals the encoded one
// bit for bit.
//
// Validation on decode (each failure kTableInvalid, `out` untouched): the size is
// exactly kGantryTableBytes with version 2 or kGantryTableBytesV1 with version
// 1; mask non-zero and below 0x100; reserved bytes 0; every real finite; each
// rotation orthonormal with determinant +1 within kGantryRotationTolerance;
// sigmas, flatness, straightness, RMS and the offset >= 0 (the layout-2
// figures >= 0 or exactly kFigureNotStored); the A-to-C angle in [0, 180];
// master axis 0..2; an absent sub-machine's bytes all zero.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/gantry_frames.hpp"
#include "trueaxis/core/status.hpp"

namespace trueaxis::core {

inline constexpr std::uint16_t kGantryLayoutVersion = 2;
inline constexpr std::size_t kGantryHeaderBytes = 8;
inline constexpr std::size_t kGantryGlobalBytes = 18 * 8;
inline constexpr std::size_t kGantrySubBytes = 8 + 26 * 8;
inline constexpr std::size_t kGantryTableBytesV1 =
    kGantryHeaderBytes + kGantryGlobalBytes + kMaxSubMachines * kGantrySubBytes;
inline constexpr std::size_t kGantryGlobalFigureBytes = 6 * 8;  // layout 2
inline constexpr std::size_t kGantrySubFigureBytes = 5 * 8;
inline constexpr std::size_t kGantryTableBytes =
    kGantryTableBytesV1 + kGantryGlobalFigureBytes + kMaxSubMachines * kGantrySubFigureBytes;
// Convention 4.
inline constexpr double kFigureNotStored = -1.0;
inline constexpr double kGantryRotationTolerance = 1e-9;

struct StoredGlobal {
  Rigid3 tracker_T_global;
  double bed_flatness_mm = 0.0;
  double gantry_straightness_mm = 0.0;
  double origin_sigma_mm = 0.0;
  Vec3 angle_sigma_arcsec = Vec3::Zero();
  double bed_flatness_noise_floor_mm = 0.0;  // layout 2 (convention 4)
  double gantry_straightness_noise_floor_mm = 0.0;
  double bed_form_error_mm = 0.0;
  double bed_form_error_sigma_mm = 0.0;
  double gantry_form_error_mm = 0.0;
  double gantry_form_error_sigma_mm = 0.0;
};

struct StoredSubMachine {
  bool present = false;
  Rigid3 global_T_sub;
  Rigid3 sub_T_global;  // convention 3
  Axis master_axis = Axis::kX;
  double origin_sigma_mm = 0.0;
  Vec3 angle_sigma_arcsec = Vec3::Zero();
  Vec3 squareness_arcsec = Vec3::Zero();
  double a_c_offset_mm = 0.0;
  double a_c_angle_deg = 0.0;
  Vec3 straightness_mm = Vec3::Zero();
  double c_circle_rms_mm = 0.0;
  double a_circle_rms_mm = 0.0;
  Vec3 squareness_sigma_arcsec = Vec3::Zero();  // layout 2 (convention 4)
  double a_c_offset_sigma_mm = 0.0;
  double a_c_angle_sigma_deg = 0.0;
};

struct GantryTable {
  StoredGlobal global;
  StoredSubMachine sub_machines[kMaxSubMachines];  // [id - 1]

  // Bit N-1 set for each present sub-machine N.
  std::uint16_t id_mask() const;
  std::size_t count() const;
};

// What a GantryTable keeps of a computation's global frame and sub-machine.
StoredGlobal stored_global(const GlobalFrame& global);
StoredSubMachine stored_sub_machine(const SubMachineFrame& frame);

// Convention 1: the computation's global frame and its sub-machines replace
// those in `table`; the other sub-machines stay.
void merge_frames(GantryTable& table, const GantryFrames& frames);

// Convention 3: a point in the global frame in sub-machine `sub`'s coordinates.
inline Vec3 global_to_sub_mm(const StoredSubMachine& sub, const Vec3& p_global_mm) {
  return sub.sub_T_global.R * p_global_mm + sub.sub_T_global.t;
}

// Writes the table into out[0..capacity) in layout 2; the bytes written (kGantryTableBytes),
// or 0 when the capacity is too small or no sub-machine is present.
std::size_t encode_gantry_table(const GantryTable& table, std::uint8_t* out, std::size_t capacity);

// Reads a table written by encode_gantry_table (layout 2) or by its layout-1
// predecessor (the new figures kFigureNotStored). kTableInvalid on
// any failed check; `out` is untouched then.
[[nodiscard]] Status decode_gantry_table(const std::uint8_t* bytes, std::size_t size, GantryTable& out);

}  // namespace trueaxis::core
