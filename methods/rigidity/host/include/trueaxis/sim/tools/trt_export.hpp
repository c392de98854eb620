// M3's calibration as LinuxCNC's own xyzac-trt-kins parameters, for a machine
// that keeps those kinematics (`trueaxis-calibrate linuxcnc-trt rigidity`).
//
// Conventions
//  1. xyzac-trt-kins (LinuxCNC 2.9, trtfuncs.c): C turns the table about the
//     vertical line through (x, y, z)-rot-point r, A about the X line through
//     r + (0, y-offset, z-offset), world = the machine's coordinates at
//     A = 0, C = 0 (trueaxis_kins' convention 2 with pivot= and a_offset=).
//  2. From a stored M3 table: r = the reference pose's C centre (the C axis at
//     A = 0 at the ball's height, where the table was measured); the offsets
//     are the table's A axis line at X = r.x, less r. On the measured axes'
//     locations the two kinematics agree at the ball.
//  3. What the parameters cannot hold, stated beside them (trueaxis_kins
//     table= holds all of it): the A axis' direction off +X, the C axis' off
//     +Z, the poses' rigidity (rotation vectors) and the A positioning error
//     (the last one the A joint's compensation file can: --linuxcnc-comp).
//     A point L mm from the axes is off by up to about L times their sum.
//  4. A table whose A axis is not within 1 deg of +X, or whose C axis at A = 0
//     is not within 1 deg of +Z, is refused: xyzac-trt-kins turns about those
//     (a machine configured with a_sign or c_sign -1 is not that cradle).
#pragma once

#include <string>

#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/types.hpp"

namespace trueaxis::sim {

struct TrtParameters {
  core::Vec3 rot_point_mm = core::Vec3::Zero();
  double y_offset_mm = 0.0;
  double z_offset_mm = 0.0;
  // Convention 3 (arcsec).
  double a_direction_y_arcsec = 0.0;  // A axis from +X towards +Y
  double a_direction_z_arcsec = 0.0;  // ... and towards +Z
  double c_tilt_arcsec = 0.0;         // the C axis at A = 0 from +Z
  double rigidity_arcsec = 0.0;       // the largest rotation vector's length
  double a_error_arcsec = 0.0;        // the largest |A positioning error|
  double not_held_arcsec() const;     // their sum
};

// Conventions 2-4; false with the sentence why (convention 4).
bool trt_parameters(const core::RigidityTable& table, TrtParameters& out, std::string& why);

// The HAL file: a comment block with convention 3's figures, then one setp a
// pin of component `component` (xyzac-trt-kins by default).
std::string trt_hal_text(const TrtParameters& p, const std::string& component = "xyzac-trt-kins");

// A rigidity record file (record_file.hpp, as rigidity_kins_file makes it)
// decoded; false with the sentence why.
bool decode_rigidity_file(const std::string& file, core::RigidityTable& table, std::string& why);

}  // namespace trueaxis::sim
