// The kinematics of an XYZAC cradle (trunnion) machine on its calibrated axes:
// what trueaxis_kins.so (trueaxis_kins.cpp beside this file) runs in
// LinuxCNC's servo thread. No heap, no exceptions, no I/O: the module reads the
// table file at its start and hands the bytes over.
//
// Conventions (mm, commanded degrees)
//  1. World coordinates (a program's X, Y, Z, "table coordinates"): where a
//     point fixed to the table is in the machine frame with the table at A = 0,
//     C = 0. Joints: the machine's X, Y, Z of the tool tip, and A, C as
//     commanded (world A, C = joint A, C).
//  2. Ideal (no table loaded): joints = Rx(A) Rz(C) world, both turns
//     right-handed (core::table_rotation with signs +1), C about the vertical
//     line through the nominal pivot r and A about the X line through r + d,
//     d = (0, dy, dz): xyzac-trt-kins' x/y/z-rot-point and y/z-offset, so
//         joints = Rx(A) (Rz(C) (world - r) + r - (r + d)) + r + d;
//     r = d = 0 (the start): both about the machine origin, the cradle of
//     host_sim's cradle_machine.hpp. A table's measured axes replace them.
//  3. Calibrated (a stored M3 table, rigidity_compensation.hpp): with
//     F(A, C) the table's theory frame and K(A, C) = actual_T_theory (exactly
//     what macro 9835 computes, core::rigidity_correction's arithmetic on
//     core::rigidity_frames), and T0 = the actual frame at A = 0, C = 0,
//         theory point  p = F(A, C) T0^-1 world   (where the ideal machine on
//                        the measured axes puts it),
//         joints        = K(A, C) p               (9835 of p, R = 0).
//     forward is the same backwards: world = T0 F^-1 K^-1 joints. Outside the
//     table's measured A range the end pose's correction applies (9833's
//     R = 1), so the servo thread never meets a refusal; inside it the joints
//     are 9835's answer bit for bit. Blend: the not-a-knot cubic (Q = 3), as
//     leveling on the calibrated axes.
//  4. Identity (switchkins type 0, as xyzac-trt-kins' identityfirst): joints =
//     world, for probing programs in machine coordinates.
//  5. The tool tip (M4): with a stored spindle model loaded, tip_error gives
//     the tool tip's error at an oriented spindle angle (M19's) and a tool
//     length below the gauge line, in the machine's axes: exactly what macro
//     9843 answers (core::spindle_phi_rad, core::spindle_correction). The
//     module subtracts it from the joints' X, Y, Z (the real tip lands where
//     the program says) and adds it back in the forward kinematics.
//  6. The tool length (as xyzac-trt-kins' tool-offset): t is the active tool's
//     length offset, LinuxCNC's motion.tooloffset.z (G43 H.. from the tool
//     table; 0 under G49), measured from the gauge line down the tool, which
//     points along the machine's -Z at every A and C (the spindle does not
//     tilt on a cradle machine). LinuxCNC adds t to the world's Z, the
//     table's, where the tool's direction is the table's turn of the
//     machine's Z, not Z itself; so the tip is W - t z in world coordinates
//     and the joints hold the gauge line t above where the tip must be:
//         joints = map(W - t z, A, C) + t z - tip_error(phi, t)
//     (map the identity or conventions 2, 3; tip_error 0 with the correction
//     off), and forward the same backwards. With G43 the controlled point is
//     the tool's tip, with G49 (t = 0) the gauge line; type 0 leaves W as it
//     is but for M4's tip error, as LinuxCNC does with its own offset.
//  8. The home: a table holds the axes as they were homed when it was
//     measured (the module's #904 then, in the table: its home identity);
//     the kinematics load it only under that identity (the module parameter
//     home=, the machine's #904 now), so a moved home switch or home offset,
//     said so by a new identity, stops the start rather than turn the table
//     about axes that are no longer where it says.
//  7. In the servo thread (trueaxis_kins.c): the correction the kinematics
//     apply is not the pins' at once but a ramp towards it, at most `ramp`
//     mm a servo period (by length; tip_ramp_step), so that switching it on
//     or turning the oriented spindle moves the joints smoothly (the tool
//     offset itself applies at once, as in xyzac-trt-kins: change tools in
//     machine coordinates or at A = 0). Its target is the tip error at the spindle's angle, or, for a
//     rotating tool, its mean over a revolution (the error a tool that cuts
//     all round leaves on the part), or 0 with the correction off.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/rigid_transform.hpp"
#include "trueaxis/core/rigidity_compensation.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::linuxcnc {

// Why a table file was refused, one line (record_file.hpp's or the codec's).
struct LoadResult {
  bool ok = false;
  const char* why = "";
};

class CradleKinematics {
 public:
  // Convention 2 (the state after construction).
  void make_ideal();
  // Convention 2's nominal pivot (mm); false (unchanged) for a non-finite one.
  bool set_nominal_pivot(const core::Vec3& rot_point_mm, double y_offset_mm, double z_offset_mm);

  // Convention 3 from a table file's bytes (record_file.hpp of the rigidity
  // record, as `trueaxis-calibrate rigidity --store --linuxcnc-kins` writes
  // it); on refusal the kinematics stay as they were. A table measured under
  // another home identity than set_home()'s (0 at the start) is refused
  // (convention 8); file_home() is the last file's, refused or not.
  LoadResult load_table(const std::uint8_t* file, std::size_t size);
  void set_home(std::uint16_t home) { home_ = home; }
  std::uint16_t home() const { return home_; }
  std::uint16_t file_home() const { return file_home_; }

  bool calibrated() const { return calibrated_; }
  std::size_t poses() const { return calibrated_ ? table_.pose_count : 0; }
  double a_min_deg() const { return calibrated_ ? table_.poses[0].a_deg : 0.0; }
  double a_max_deg() const { return calibrated_ ? table_.poses[table_.pose_count - 1].a_deg : 0.0; }

  // Conventions 2, 3: false only for a non-finite input (joints untouched).
  bool inverse(const core::Vec3& world_mm, double a_deg, double c_deg, core::Vec3& joint_mm) const;
  bool forward(const core::Vec3& joint_mm, double a_deg, double c_deg, core::Vec3& world_mm) const;

  // Convention 5: a spindle model file (record_file.hpp of the spindle record,
  // as `trueaxis-calibrate spindle --store --linuxcnc-kins` writes it); on
  // refusal the model stays as it was.
  LoadResult load_spindle(const std::uint8_t* file, std::size_t size);
  bool spindle_loaded() const { return spindle_loaded_; }
  // The tip error (mm) at phi_deg and tool_mm; false (error untouched) without
  // a model, for a non-finite input, or a tool length 9843 refuses (below 0 or
  // beyond 1e5 mm).
  bool tip_error(double phi_deg, double tool_mm, core::Vec3& error_mm) const;

  // Convention 7: the tip error averaged over a revolution at tool_mm (9844's
  // mean), for a rotating tool; false as tip_error.
  bool mean_tip_error(double tool_mm, core::Vec3& error_mm) const;

  // The whole of LinuxCNC's inverse and forward (conventions 4-6): `cradle`
  // false the identity, true the cradle; tool_mm the tool offset t; with
  // `tip` the M4 tip error at phi_deg and t taken off the joints (added back
  // going forward). False (output untouched) for a non-finite input, the tip
  // asked for without a model or at a length it refuses (t below 0: a tool
  // offset measured upwards).
  bool to_joints(bool cradle, const core::Vec3& world_mm, double a_deg, double c_deg, double tool_mm, bool tip,
                 double phi_deg, core::Vec3& joint_mm) const;
  bool to_world(bool cradle, const core::Vec3& joint_mm, double a_deg, double c_deg, double tool_mm, bool tip,
                double phi_deg, core::Vec3& world_mm) const;
  // The same with the tip's error given (convention 7: the one the servo
  // thread has ramped to); false only for a non-finite input.
  bool to_joints(bool cradle, const core::Vec3& world_mm, double a_deg, double c_deg, double tool_mm,
                 const core::Vec3& tip_error_mm, core::Vec3& joint_mm) const;
  bool to_world(bool cradle, const core::Vec3& joint_mm, double a_deg, double c_deg, double tool_mm,
                const core::Vec3& tip_error_mm, core::Vec3& world_mm) const;

  // Convention 3's theory point p of a world point (the ideal machine's where
  // no table is loaded): the point 9835 converts into the joints.
  bool theory_point(const core::Vec3& world_mm, double a_deg, double c_deg, core::Vec3& p_mm) const;

 private:
  core::Vec3 ideal_joints(const core::Vec3& world_mm, double a_deg, double c_deg) const;
  core::Vec3 ideal_world(const core::Vec3& joint_mm, double a_deg, double c_deg) const;

  core::RigidityTable table_;
  core::SpindleModel spindle_;
  bool spindle_loaded_ = false;
  core::Vec3 c_point_ = core::Vec3::Zero();  // r: the nominal C axis' point (convention 2)
  core::Vec3 a_point_ = core::Vec3::Zero();  // r + d: the nominal A axis' point
  core::RigidTransform table_T_world_;  // T0^-1
  core::RigidTransform world_T_table_;  // T0
  bool calibrated_ = false;
  std::uint16_t home_ = 0;
  std::uint16_t file_home_ = 0;
};

// Convention 7: one servo period's step of `applied` towards `target`, at most
// ramp_mm long (a ramp not above 0, or not finite: a pin netted to a signal
// nobody sets, kDefaultTipRampMm); true when it has arrived.
inline constexpr double kDefaultTipRampMm = 0.0005;
bool tip_ramp_step(const core::Vec3& target, double ramp_mm, core::Vec3& applied);

}  // namespace trueaxis::linuxcnc
