#include "trueaxis/sim/machines/gantry_machine.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::sim {

namespace {

using core::Mat3;
using core::Vec3;

// A rotation vector given in arc-seconds; exactly I for zero.
Mat3 turn_by(const Vec3& rotation_arcsec) {
  const double t = rotation_arcsec.norm();
  if (t == 0.0) return Mat3::Identity();
  return turn(rotation_arcsec / t, arcsec_to_rad(t));
}

double bow_shape(double q, double q_min, double q_max) {
  if (!(q_max > q_min)) return 0.0;
  return std::sin(core::kPi * (q - q_min) / (q_max - q_min));
}

double arcsec_from_square(const Vec3& u, const Vec3& w) {
  return (core::angle_between(u, w) - 0.5 * core::kPi) * kArcsecPerRad;
}

SubMachineConfig sub(int id, const char* name, const Vec3& wrist, const Vec3& tool, const Vec3& a_nominal,
                     double swing, const Vec3& stroke_min, const Vec3& stroke_max) {
  SubMachineConfig s;
  s.id = id;
  s.name = name;
  s.wrist_mm = wrist;
  s.tool_nominal = tool;
  s.a_nominal = a_nominal;
  s.swing_mm = swing;
  s.stroke_min_mm = stroke_min;
  s.stroke_max_mm = stroke_max;
  return s;
}

}  // namespace

GantryConfig ideal_gantry() {
  GantryConfig g;
  g.sub_machines = {
      sub(1, "cross beam", Vec3(250.0, 1200.0, 1100.0), -Vec3::UnitZ(), Vec3::UnitX(), 300.0,
          Vec3(-300.0, -1100.0, -600.0), Vec3(300.0, 1100.0, 0.0)),
      sub(2, "left column", Vec3(250.0, -50.0, 400.0), Vec3::UnitY(), Vec3::UnitX(), 250.0,
          Vec3(-250.0, 0.0, -200.0), Vec3(250.0, 500.0, 1100.0)),
      sub(3, "right column", Vec3(250.0, 2450.0, 400.0), -Vec3::UnitY(), Vec3::UnitZ(), 350.0,
          Vec3(-250.0, -500.0, -200.0), Vec3(250.0, 0.0, 1100.0)),
      sub(4, "floor bridge", Vec3(250.0, 1200.0, 300.0), Vec3::UnitZ(), Vec3::UnitY(), 200.0,
          Vec3(-300.0, -1000.0, 0.0), Vec3(300.0, 1000.0, 300.0)),
  };
  return g;
}

GantryConfig realistic_gantry() {
  GantryConfig g = ideal_gantry();
  g.side_1_yaw_arcsec = 25.0;
  g.side_1_tilt_arcsec = -15.0;
  g.side_2_yaw_arcsec = -20.0;
  g.side_2_tilt_arcsec = 10.0;
  g.gantry_yaw_arcsec = 6.0;
  g.gantry_pitch_arcsec = -4.0;
  g.gantry_bow_h_mm = 0.003;
  g.gantry_bow_v_mm = 0.002;
  struct Errors {
    Vec3 mount, head;
    double xy, yz, zx, offset, angle;
    Vec3 bow;
  };
  const Errors e[4] = {
      {Vec3(12.0, -8.0, 20.0), Vec3(10.0, -14.0, 0.0), 15.0, -22.0, 18.0, 0.022, 25.0, Vec3(0.0015, 0.002, 0.001)},
      {Vec3(-15.0, 10.0, 8.0), Vec3(-9.0, 0.0, 11.0), -12.0, 30.0, -20.0, -0.031, -18.0, Vec3(0.001, 0.0015, 0.002)},
      {Vec3(7.0, 18.0, -25.0), Vec3(5.0, 0.0, -13.0), 20.0, 14.0, 27.0, 0.015, 32.0, Vec3(0.001, 0.0015, 0.002)},
      {Vec3(-10.0, -12.0, 15.0), Vec3(8.0, 15.0, 0.0), -25.0, -10.0, 12.0, -0.040, -28.0, Vec3(0.0015, 0.002, 0.001)},
  };
  for (std::size_t i = 0; i < g.sub_machines.size(); ++i) {
    SubMachineConfig& s = g.sub_machines[i];
    s.mount_rotation_arcsec = e[i].mount;
    s.head_rotation_arcsec = e[i].head;
    s.squareness_xy_arcsec = e[i].xy;
    s.squareness_yz_arcsec = e[i].yz;
    s.squareness_zx_arcsec = e[i].zx;
    s.a_c_offset_mm = e[i].offset;
    s.a_c_angle_error_arcsec = e[i].angle;
    s.bow_mm = e[i].bow;
  }
  return g;
}

core::Mat3 orthonormalise(const core::Vec3& d_x, const core::Vec3& d_y, const core::Vec3& d_z, MasterAxis master) {
  Vec3 x = d_x.normalized();
  Vec3 y = d_y.normalized();
  Vec3 z = d_z.normalized();
  switch (master) {
    case MasterAxis::kX:
      y = z.cross(x).normalized();
      z = x.cross(y);
      break;
    case MasterAxis::kY:
      x = y.cross(z).normalized();
      z = x.cross(y);
      break;
    case MasterAxis::kZ:
      x = y.cross(z).normalized();
      y = z.cross(x);
      break;
  }
  Mat3 axes;
  axes << x, y, z;
  return axes;
}

const char* master_axis_name(MasterAxis master) {
  switch (master) {
    case MasterAxis::kX: return "x";
    case MasterAxis::kY: return "y";
    case MasterAxis::kZ: return "z";
  }
  return "?";
}

GantryMachine::GantryMachine(const GantryConfig& config) : config_(config) {
  side_1_.point_mm = Vec3(config.side_1_offset_mm, 0.0, 0.0);
  side_1_.normal = turn(Vec3::UnitZ(), arcsec_to_rad(config.side_1_yaw_arcsec)) *
                   turn(Vec3::UnitY(), arcsec_to_rad(config.side_1_tilt_arcsec)) * (-Vec3::UnitX());
  side_2_.point_mm = Vec3(0.0, config.side_2_offset_mm, 0.0);
  side_2_.normal = turn(Vec3::UnitZ(), arcsec_to_rad(config.side_2_yaw_arcsec)) *
                   turn(Vec3::UnitX(), arcsec_to_rad(config.side_2_tilt_arcsec)) * (-Vec3::UnitY());

  g_ = turn(Vec3::UnitZ(), arcsec_to_rad(config.gantry_yaw_arcsec)) *
       turn(Vec3::UnitY(), -arcsec_to_rad(config.gantry_pitch_arcsec)) * Vec3::UnitX();
  const Vec3 n_h = Vec3::UnitZ().cross(g_).normalized();
  bow_dir_ = config.gantry_bow_h_mm * n_h + config.gantry_bow_v_mm * g_.cross(n_h);

  // Convention 4: the three planes' common point from their 3x3 system.
  const Plane bed = bed_plane();
  Mat3 normals;
  normals.row(0) = bed.normal.transpose();
  normals.row(1) = side_1_.normal.transpose();
  normals.row(2) = side_2_.normal.transpose();
  const Vec3 offsets(bed.normal.dot(bed.point_mm), side_1_.normal.dot(side_1_.point_mm),
                     side_2_.normal.dot(side_2_.point_mm));
  const Vec3 x = g_;
  const Vec3 y = bed.normal.cross(x).normalized();
  machine_T_global_.rotation << x, y, x.cross(y);
  machine_T_global_.translation_mm = normals.inverse() * offsets;
  const RigidTransform global_T = global_T_machine();

  for (const SubMachineConfig& s : config.sub_machines) {
    SubMachineTruth t;
    t.id = s.id;
    const Mat3 r_m = turn_by(s.mount_rotation_arcsec);
    const double s_xy = arcsec_to_rad(s.squareness_xy_arcsec);
    const double s_yz = arcsec_to_rad(s.squareness_yz_arcsec);
    const double s_zx = arcsec_to_rad(s.squareness_zx_arcsec);
    const double alpha = -std::sin(s_zx);
    const double beta = (-std::sin(s_yz) + std::sin(s_xy) * alpha) / std::cos(s_xy);
    const double gamma = std::sqrt(1.0 - alpha * alpha - beta * beta);
    t.d_x = r_m.col(0);
    t.d_y = std::cos(s_xy) * r_m.col(1) - std::sin(s_xy) * r_m.col(0);
    t.d_z = alpha * r_m.col(0) + beta * r_m.col(1) + gamma * r_m.col(2);

    const Mat3 r_h = r_m * turn_by(s.head_rotation_arcsec);
    const double delta = arcsec_to_rad(s.a_c_angle_error_arcsec);
    t.c_dir = r_h * s.tool_nominal;
    t.a_dir = std::cos(delta) * (r_h * s.a_nominal) - std::sin(delta) * t.c_dir;
    t.wrist_mm = s.wrist_mm;
    t.a_point_mm = s.wrist_mm + s.a_c_offset_mm * t.c_dir.cross(t.a_dir).normalized();
    t.smr_home_mm = s.wrist_mm + r_h * (s.smr_head_mm.x() * s.a_nominal +
                                        s.smr_head_mm.y() * s.tool_nominal.cross(s.a_nominal) +
                                        s.smr_head_mm.z() * s.tool_nominal);
    t.origin_mm = s.wrist_mm + s.swing_mm * t.c_dir;

    const Vec3 stroke = s.stroke_max_mm - s.stroke_min_mm;
    t.master = MasterAxis::kX;
    if (stroke.y() > stroke.x()) t.master = MasterAxis::kY;
    if (stroke.z() > std::max(stroke.x(), stroke.y())) t.master = MasterAxis::kZ;
    t.axes = orthonormalise(t.d_x, t.d_y, t.d_z, t.master);
    t.squareness_xy_arcsec = arcsec_from_square(t.d_x, t.d_y);
    t.squareness_yz_arcsec = arcsec_from_square(t.d_y, t.d_z);
    t.squareness_zx_arcsec = arcsec_from_square(t.d_z, t.d_x);
    t.a_c_offset_mm = std::abs(s.a_c_offset_mm);
    t.a_c_angle_deg = core::rad_to_deg(core::angle_between(t.a_dir, t.c_dir));

    t.origin_global_mm = global_T.apply(t.origin_mm);
    t.axes_global = global_T.rotation * t.axes;
    t.global_T_sub.setIdentity();
    t.global_T_sub.topLeftCorner<3, 3>() = t.axes_global;
    t.global_T_sub.topRightCorner<3, 1>() = t.origin_global_mm;

    Mat3 bows;
    const Vec3 d[3] = {t.d_x, t.d_y, t.d_z};
    for (int k = 0; k < 3; ++k) {
      const Vec3& next = d[(k + 1) % 3];
      bows.col(k) = s.bow_mm[k] * (next - next.dot(d[k]) * d[k]).normalized();
    }
    bow_dirs_.push_back(bows);
    subs_.push_back(t);
  }
}

RigidTransform GantryMachine::global_T_machine() const {
  RigidTransform t;
  t.rotation = machine_T_global_.rotation.transpose();
  t.translation_mm = -(t.rotation * machine_T_global_.translation_mm);
  return t;
}

core::Vec3 GantryMachine::side_point(int k, double along_mm, double z_mm) const {
  const Plane& p = side_plane(k);
  // Solve n . (x - p0) = 0 for the coordinate the face is normal to.
  if (k == 1) {
    const double x = p.point_mm.x() - (p.normal.y() * (along_mm - p.point_mm.y()) +
                                       p.normal.z() * (z_mm - p.point_mm.z())) / p.normal.x();
    return Vec3(x, along_mm, z_mm);
  }
  const double y = p.point_mm.y() - (p.normal.x() * (along_mm - p.point_mm.x()) +
                                     p.normal.z() * (z_mm - p.point_mm.z())) / p.normal.y();
  return Vec3(along_mm, y, z_mm);
}

core::Vec3 GantryMachine::gantry_target(double u_mm) const {
  const double lo = config_.gantry_travel_min_mm;
  const double hi = config_.gantry_travel_max_mm;
  return config_.gantry_target_home_mm + u_mm * g_ + (bow_shape(u_mm, lo, hi) - bow_shape(0.0, lo, hi)) * bow_dir_;
}

double GantryMachine::gantry_straightness_mm(const std::vector<double>& u_mm) const {
  if (u_mm.empty()) return 0.0;
  const double lo = config_.gantry_travel_min_mm;
  const double hi = config_.gantry_travel_max_mm;
  double mean = 0.0;
  for (double u : u_mm) mean += bow_shape(u, lo, hi);
  mean /= static_cast<double>(u_mm.size());
  double worst = 0.0;
  for (double u : u_mm) worst = std::max(worst, std::abs(bow_shape(u, lo, hi) - mean));
  return 2.0 * bow_dir_.norm() * worst;
}

core::Vec3 GantryMachine::axis_shift(std::size_t index, const core::Vec3& q_mm) const {
  const SubMachineConfig& s = config_.sub_machines[index];
  const SubMachineTruth& t = subs_[index];
  const Vec3 d[3] = {t.d_x, t.d_y, t.d_z};
  Vec3 shift = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const double lo = s.stroke_min_mm[k];
    const double hi = s.stroke_max_mm[k];
    shift += q_mm[k] * d[k] + (bow_shape(q_mm[k], lo, hi) - bow_shape(0.0, lo, hi)) * bow_dirs_[index].col(k);
  }
  return shift;
}

core::Vec3 GantryMachine::head_point(std::size_t index, const core::Vec3& q_mm, double a_deg, double c_deg,
                                     const core::Vec3& p_home_mm) const {
  const SubMachineTruth& t = subs_[index];
  const Mat3 r_a = turn(t.a_dir, core::deg_to_rad(a_deg));
  const Mat3 r_c = turn(t.c_dir, core::deg_to_rad(c_deg));
  return axis_shift(index, q_mm) + t.wrist_mm +
         r_c * (t.a_point_mm - t.wrist_mm + r_a * (p_home_mm - t.a_point_mm));
}

core::Vec3 GantryMachine::smr(std::size_t index, const core::Vec3& q_mm, double a_deg, double c_deg) const {
  return head_point(index, q_mm, a_deg, c_deg, subs_[index].smr_home_mm);
}

}  // namespace trueaxis::sim
