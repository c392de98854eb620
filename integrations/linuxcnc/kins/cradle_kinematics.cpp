#include "cradle_kinematics.hpp"

#include <cmath>

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/macros/applied_records.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/record_file.hpp"

namespace trueaxis::linuxcnc {

namespace {

constexpr core::Blend kBlend = core::Blend::kCubicNotAKnot;

bool finite(const core::Vec3& v, double a, double c) { return v.allFinite() && std::isfinite(a) && std::isfinite(c); }

// Convention 2's turn.
core::Mat3 ideal_rotation(double a_deg, double c_deg) {
  return core::table_rotation(core::TablePose{a_deg, c_deg}, core::LevelConfig{});
}

}  // namespace

void CradleKinematics::make_ideal() { calibrated_ = false; }

bool CradleKinematics::set_nominal_pivot(const core::Vec3& rot_point_mm, double y_offset_mm, double z_offset_mm) {
  const core::Vec3 a_point = rot_point_mm + core::Vec3(0.0, y_offset_mm, z_offset_mm);
  if (!rot_point_mm.allFinite() || !a_point.allFinite()) return false;
  c_point_ = rot_point_mm;
  a_point_ = a_point;
  return true;
}

LoadResult CradleKinematics::load_table(const std::uint8_t* file, std::size_t size) {
  const std::uint8_t* payload = nullptr;
  std::size_t length = 0;
  const macros::RecordFileError e =
      macros::decode_record_file(macros::RigidityTableRecord::kRecord.key, file, size, payload, length);
  if (e != macros::RecordFileError::kNone) return {false, macros::record_file_text(e)};
  core::RigidityTable table;
  if (core::decode_rigidity_table(payload, length, table) != core::Status::kOk) {
    return {false, "the rigidity table in it does not decode (a file of another build, or written by hand?)"};
  }
  file_home_ = table.home_identity;
  if (table.home_identity != home_) {
    return {false, "it was measured under another home of the axes than this machine's (home=, the module's #904): "
                   "home them as then, or measure M3 again and write the file again"};
  }
  const core::Result<core::RigidityFrames> zero = core::rigidity_frames(table, 0.0, 0.0, kBlend, true);
  if (!zero.ok()) return {false, "the rigidity table in it gives no frame at A = 0, C = 0"};
  table_ = table;
  world_T_table_ = zero.value().machine_T_table_actual;
  table_T_world_ = world_T_table_.inverse();
  calibrated_ = true;
  return {true, ""};
}

LoadResult CradleKinematics::load_spindle(const std::uint8_t* file, std::size_t size) {
  const std::uint8_t* payload = nullptr;
  std::size_t length = 0;
  const macros::RecordFileError e =
      macros::decode_record_file(macros::SpindleModelRecord::kRecord.key, file, size, payload, length);
  if (e != macros::RecordFileError::kNone) return {false, macros::record_file_text(e)};
  core::SpindleModel model;
  if (core::decode_spindle_model(payload, length, model) != core::Status::kOk) {
    return {false, "the spindle model in it does not decode (a file of another build, or written by hand?)"};
  }
  spindle_ = model;
  spindle_loaded_ = true;
  return {true, ""};
}

bool CradleKinematics::tip_error(double phi_deg, double tool_mm, core::Vec3& error_mm) const {
  // 9843's refusals: a length below 0 or beyond the map's bound (macros::rows::kBig).
  if (!spindle_loaded_ || !std::isfinite(phi_deg) || !(tool_mm >= 0.0 && tool_mm <= macros::rows::kBig)) return false;
  const core::Result<core::SpindleCorrection> c = core::spindle_correction(
      spindle_.axes, spindle_.geometry.gauge_mm, tool_mm, core::spindle_phi_rad(phi_deg));
  if (!c.ok()) return false;
  error_mm = c.value().tip_error_mm;
  return true;
}

// Convention 2 both ways; about the origin exactly as before the pivot existed.
core::Vec3 CradleKinematics::ideal_joints(const core::Vec3& world_mm, double a_deg, double c_deg) const {
  if (c_point_ == core::Vec3::Zero() && a_point_ == core::Vec3::Zero()) return ideal_rotation(a_deg, c_deg) * world_mm;
  const core::Mat3 rc = ideal_rotation(0.0, c_deg);
  const core::Mat3 ra = ideal_rotation(a_deg, 0.0);
  return ra * (rc * (world_mm - c_point_) + c_point_ - a_point_) + a_point_;
}

core::Vec3 CradleKinematics::ideal_world(const core::Vec3& joint_mm, double a_deg, double c_deg) const {
  if (c_point_ == core::Vec3::Zero() && a_point_ == core::Vec3::Zero()) {
    return ideal_rotation(a_deg, c_deg).transpose() * joint_mm;
  }
  const core::Mat3 rc = ideal_rotation(0.0, c_deg);
  const core::Mat3 ra = ideal_rotation(a_deg, 0.0);
  return rc.transpose() * (ra.transpose() * (joint_mm - a_point_) + a_point_ - c_point_) + c_point_;
}

bool CradleKinematics::theory_point(const core::Vec3& world_mm, double a_deg, double c_deg, core::Vec3& p_mm) const {
  if (!finite(world_mm, a_deg, c_deg)) return false;
  if (!calibrated_) {
    p_mm = ideal_joints(world_mm, a_deg, c_deg);
    return true;
  }
  const core::Result<core::RigidityFrames> f = core::rigidity_frames(table_, a_deg, c_deg, kBlend, true);
  if (!f.ok()) return false;
  p_mm = f.value().machine_T_table_theory.point(table_T_world_.point(world_mm));
  return true;
}

bool CradleKinematics::inverse(const core::Vec3& world_mm, double a_deg, double c_deg, core::Vec3& joint_mm) const {
  if (!finite(world_mm, a_deg, c_deg)) return false;
  if (!calibrated_) {
    joint_mm = ideal_joints(world_mm, a_deg, c_deg);
    return true;
  }
  const core::Result<core::RigidityFrames> f = core::rigidity_frames(table_, a_deg, c_deg, kBlend, true);
  if (!f.ok()) return false;
  const core::Vec3 p = f.value().machine_T_table_theory.point(table_T_world_.point(world_mm));
  // core::rigidity_correction's arithmetic on the same frames: 9835's K.
  const core::RigidTransform k = f.value().machine_T_table_actual * f.value().machine_T_table_theory.inverse();
  joint_mm = k.point(p);
  return true;
}

bool CradleKinematics::forward(const core::Vec3& joint_mm, double a_deg, double c_deg, core::Vec3& world_mm) const {
  if (!finite(joint_mm, a_deg, c_deg)) return false;
  if (!calibrated_) {
    world_mm = ideal_world(joint_mm, a_deg, c_deg);
    return true;
  }
  const core::Result<core::RigidityFrames> f = core::rigidity_frames(table_, a_deg, c_deg, kBlend, true);
  if (!f.ok()) return false;
  const core::RigidTransform k = f.value().machine_T_table_actual * f.value().machine_T_table_theory.inverse();
  const core::Vec3 p = k.inverse().point(joint_mm);
  world_mm = world_T_table_.point(f.value().machine_T_table_theory.inverse().point(p));
  return true;
}

bool CradleKinematics::mean_tip_error(double tool_mm, core::Vec3& error_mm) const {
  if (!spindle_loaded_ || !(tool_mm >= 0.0 && tool_mm <= macros::rows::kBig)) return false;
  error_mm = core::spindle_mean_tip_error_mm(spindle_.axes, spindle_.geometry.gauge_mm, tool_mm);
  return error_mm.allFinite();
}

bool CradleKinematics::to_joints(bool cradle, const core::Vec3& world_mm, double a_deg, double c_deg, double tool_mm,
                                 bool tip, double phi_deg, core::Vec3& joint_mm) const {
  core::Vec3 e = core::Vec3::Zero();
  if (tip && !tip_error(phi_deg, tool_mm, e)) return false;  // never an uncorrected move
  return to_joints(cradle, world_mm, a_deg, c_deg, tool_mm, e, joint_mm);
}

bool CradleKinematics::to_world(bool cradle, const core::Vec3& joint_mm, double a_deg, double c_deg, double tool_mm,
                                bool tip, double phi_deg, core::Vec3& world_mm) const {
  core::Vec3 e = core::Vec3::Zero();
  if (tip && !tip_error(phi_deg, tool_mm, e)) return false;
  return to_world(cradle, joint_mm, a_deg, c_deg, tool_mm, e, world_mm);
}

bool CradleKinematics::to_joints(bool cradle, const core::Vec3& world_mm, double a_deg, double c_deg, double tool_mm,
                                 const core::Vec3& e, core::Vec3& joint_mm) const {
  if (!finite(world_mm, a_deg, c_deg) || !std::isfinite(tool_mm) || !e.allFinite()) return false;
  if (!cradle) {  // the identity: the tool offset is LinuxCNC's own, in the world's Z already
    joint_mm = world_mm - e;
    return true;
  }
  const core::Vec3 along = tool_mm * core::Vec3::UnitZ();  // the gauge line above the tip
  core::Vec3 tip_at;
  if (!inverse(world_mm - along, a_deg, c_deg, tip_at)) return false;
  joint_mm = tip_at + along - e;
  return true;
}

bool CradleKinematics::to_world(bool cradle, const core::Vec3& joint_mm, double a_deg, double c_deg, double tool_mm,
                                const core::Vec3& e, core::Vec3& world_mm) const {
  if (!finite(joint_mm, a_deg, c_deg) || !std::isfinite(tool_mm) || !e.allFinite()) return false;
  if (!cradle) {
    world_mm = joint_mm + e;
    return true;
  }
  const core::Vec3 along = tool_mm * core::Vec3::UnitZ();
  core::Vec3 w;
  if (!forward(joint_mm + e - along, a_deg, c_deg, w)) return false;  // the real tip, machine frame
  world_mm = w + along;
  return true;
}

bool tip_ramp_step(const core::Vec3& target, double ramp_mm, core::Vec3& applied) {
  const core::Vec3 step = target - applied;
  const double length = step.norm();
  if (!(ramp_mm > 0.0) || !std::isfinite(ramp_mm)) ramp_mm = kDefaultTipRampMm;
  if (length <= ramp_mm) {
    applied = target;
    return true;
  }
  applied += (ramp_mm / length) * step;
  return false;
}

}  // namespace trueaxis::linuxcnc
