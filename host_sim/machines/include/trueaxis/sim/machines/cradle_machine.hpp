// A virtual cradle (trunnion) table carrying a workpiece with one inclined flat
// face: the ground truth the host simulator measures. The instruments that
// measure it (the touch probe, the calibration ball) are in instruments/; this
// machine gives them the face and the table's pose.
//
// Conventions
//  1. Machine: A tilts the cradle about machine X, C turns the table about its own
//     Z. Nominally, a point fixed to the table, written p_table with the table at
//     zero (its origin on the C axis), is at
//         p_machine = Rx(A) (Rz(C) p_table - d) + r + d
//     with C about the vertical line through the nominal pivot r (CradlePivot's
//     c_point_mm: the table's origin at A = 0) and A about the X line through
//     r + d, d = (0, a_offset_y_mm, a_offset_z_mm): xyzac-trt-kins' x/y/z-rot-point
//     and y/z-offset (trueaxis_kins' pivot= and a_offset=). Both signs +1
//     (commanded = physical, right-handed), i.e. the module's configuration
//     a_sign = c_sign = +1. CradlePivot{} (the default): r = d = 0, both about
//     the machine origin, Rx(A) Rz(C) p_table.
//     The true machine is that plus the geometric errors of cradle_errors.hpp:
//         p_machine = machine_T_table(A, C) p_table;
//     with CradleErrors{} (all zero) the two are the same, bit for bit. The face,
//     and whatever an instrument measures on the table, follow the true machine.
//  2. Face: a plane through (0, 0, height_mm) with the table at zero; its outward
//     (spindle-side) unit normal there is
//         n_table = (sin t cos az, sin t sin az, cos t),  t = tilt_deg, az = azimuth_deg,
//     so the face falls towards azimuth az (measured from +X towards +Y) and
//     rises towards az + 180 deg. 0 <= tilt_deg < 90. face_at(A, C) is that plane
//     in the machine frame: the image of (0, 0, height_mm) and R n_table.
//  3. M3 ground truth (docs/INTERFACE.md "M3 rigidity", docs/METHODS.md M3), from
//     this model alone. A pose is a commanded A; the reference pose is A = 0. For a
//     ball at table height h, a pose's C centre is the point of the true C axis at
//     table Z = h (the centre of the ball's C circle), its C direction the true C
//     axis direction, and its actual frame E(A) = the table's axes at C = 0 (the
//     ball's phase on the table only multiplies E on the right and cancels). Its
//     theory frame is E(0) turned about the true A axis by theta(A), the signed
//     angle about a_dir from (c(0) - a_point) to (c(A) - a_point) (both projected
//     on the plane normal to a_dir). rotation vector = log(E(A) E_theory(A)^T),
//     A positioning error = theta(A) - A. Both are exactly zero at A = 0.
#pragma once

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

// Convention 1's nominal pivot (mm). The geometric errors are taken from it:
// the true A axis passes through r + d + a_point_mm, the table's origin lies
// c_offset_mm - a_offset_y_mm across it (cradle_errors.hpp model 3).
struct CradlePivot {
  core::Vec3 c_point_mm = core::Vec3::Zero();  // r
  double a_offset_y_mm = 0.0;                  // d
  double a_offset_z_mm = 0.0;
};

struct FaceConfig {
  double tilt_deg = 12.5;
  double azimuth_deg = 30.0;
  double height_mm = 40.0;
};

class CradleMachine {
 public:
  explicit CradleMachine(const FaceConfig& face, const CradleErrors& errors = CradleErrors{},
                         const CradlePivot& pivot = CradlePivot{});

  const FaceConfig& face() const { return face_; }
  const CradleErrors& errors() const { return errors_; }
  const CradlePivot& pivot() const { return pivot_; }

  // The NOMINAL R_machine_table Rx(A) Rz(C) (convention 1), whatever the errors.
  static core::Mat3 table_rotation(double a_deg, double c_deg);
  // The NOMINAL machine point of a table point (convention 1), whatever the errors.
  core::Vec3 nominal_machine_point(const core::Vec3& p_table_mm, double a_deg, double c_deg) const;

  // The TRUE machine_T_table at commanded (a_deg, c_deg): cradle_errors.hpp model 5.
  RigidTransform machine_T_table(double a_deg, double c_deg) const;

  // The cradle's actual angle alpha for commanded A, and e(A) = alpha - A in
  // arcsec (cradle_errors.hpp model 2).
  double actual_a_deg(double a_deg) const;
  double a_drive_error_arcsec(double a_deg) const;

  // The true A axis (model 1), and the true C axis line at commanded A (point:
  // the table origin; direction: +Z of the table), machine frame.
  Line a_axis() const { return Line{a_point_, a_dir_}; }
  Line c_axis_at(double a_deg) const;

  // Convention 3, for a ball at table height height_mm.
  core::Vec3 c_centre_at(double a_deg, double height_mm) const;
  double theory_angle_rad(double a_deg, double height_mm) const;
  core::Vec3 rotation_vector_rad(double a_deg, double height_mm) const;
  double a_positioning_error_arcsec(double a_deg, double height_mm) const;

  // C-to-A location errors at the reference pose (A = 0), ISO 230-1 style as M3
  // reports them: the length of the common perpendicular of the C and A axis
  // lines (mm), and angle(C direction, A direction) - 90 deg (arcsec, signed).
  double c_to_a_offset_mm() const;
  double c_to_a_squareness_arcsec() const;

  // The face's outward unit normal, table at zero (convention 2).
  const core::Vec3& normal_table() const { return normal_table_; }

  // The face's tilt from horizontal, degrees, with the table at (a_deg, c_deg).
  double tilt_deg_at(double a_deg, double c_deg) const;

  // The face's plane in the machine frame with the table at (a_deg, c_deg),
  // its normal outward (convention 2).
  Plane face_at(double a_deg, double c_deg) const;

 private:
  FaceConfig face_;
  CradleErrors errors_;
  CradlePivot pivot_;
  core::Vec3 normal_table_;
  core::Vec3 a_point_;     // model 1's point, with convention 1's r + d
  core::Mat3 q_;           // model 1: X, Y, Z -> a_dir, v, w
  core::Mat3 b_;           // model 3: the table's axes at C = 0, cradle frame
  core::Vec3 a_dir_;       // model 1
  core::Vec3 origin_k_;    // model 3: table origin, cradle frame
  core::Vec3 pivot_k_;     // model 4
};

}  // namespace trueaxis::sim
