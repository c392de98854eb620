#include "trueaxis/sim/machines/cradle_machine.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::sim {

namespace {

using core::Mat3;
using core::Vec3;

Mat3 rot_x(double angle_rad) {
  Mat3 r;
  r << 1.0, 0.0, 0.0,
       0.0, std::cos(angle_rad), -std::sin(angle_rad),
       0.0, std::sin(angle_rad), std::cos(angle_rad);
  return r;
}

Mat3 rot_y(double angle_rad) {
  Mat3 r;
  r << std::cos(angle_rad), 0.0, std::sin(angle_rad),
       0.0, 1.0, 0.0,
       -std::sin(angle_rad), 0.0, std::cos(angle_rad);
  return r;
}

Mat3 rot_z(double angle_rad) {
  Mat3 r;
  r << std::cos(angle_rad), -std::sin(angle_rad), 0.0,
       std::sin(angle_rad), std::cos(angle_rad), 0.0,
       0.0, 0.0, 1.0;
  return r;
}

Mat3 skew(const Vec3& w) {
  Mat3 k;
  k << 0.0, -w.z(), w.y(),
       w.z(), 0.0, -w.x(),
       -w.y(), w.x(), 0.0;
  return k;
}

// Rodrigues, with 1 - cos t written as 2 sin^2(t/2) so arc-second angles keep
// their digits; exactly I for the zero vector (the ideal machine stays exact).
Mat3 rotation_from_vector(const Vec3& w_rad) {
  const double t = w_rad.norm();
  if (t == 0.0) return Mat3::Identity();
  const Mat3 k = skew(w_rad / t);
  const double s_half = std::sin(0.5 * t);
  return Mat3::Identity() + std::sin(t) * k + (2.0 * s_half * s_half) * (k * k);
}

// The rotation vector of a rotation well away from 180 deg (every rotation the
// truth takes the log of is below a few hundred arc-seconds): the axis from the
// skew part, the angle from atan2 of its norm and the trace.
Vec3 vector_from_rotation(const Mat3& r) {
  const Vec3 s(0.5 * (r(2, 1) - r(1, 2)), 0.5 * (r(0, 2) - r(2, 0)), 0.5 * (r(1, 0) - r(0, 1)));
  const double sin_t = s.norm();
  if (sin_t == 0.0) return Vec3::Zero();
  const double t = std::atan2(sin_t, 0.5 * (r.trace() - 1.0));
  return s * (t / sin_t);
}

}  // namespace

CradleMachine::CradleMachine(const FaceConfig& face, const CradleErrors& errors, const CradlePivot& pivot)
    : face_(face), errors_(errors), pivot_(pivot) {
  const double t = core::deg_to_rad(face.tilt_deg);
  const double az = core::deg_to_rad(face.azimuth_deg);
  normal_table_ = core::Vec3(std::sin(t) * std::cos(az), std::sin(t) * std::sin(az), std::cos(t));
  q_ = rot_z(arcsec_to_rad(errors.a_dir_y_arcsec)) * rot_y(-arcsec_to_rad(errors.a_dir_z_arcsec));
  a_dir_ = q_.col(0);
  b_ = q_ * rot_y(-arcsec_to_rad(errors.c_squareness_arcsec));
  a_point_ = pivot.c_point_mm + Vec3(0.0, pivot.a_offset_y_mm, pivot.a_offset_z_mm) + errors.a_point_mm;
  origin_k_ = a_point_ + (errors.c_offset_mm - pivot.a_offset_y_mm) * q_.col(1) - pivot.a_offset_z_mm * b_.col(2);
  pivot_k_ = origin_k_ + errors.pivot_z_mm * b_.col(2);
}

core::Mat3 CradleMachine::table_rotation(double a_deg, double c_deg) {
  return rot_x(core::deg_to_rad(a_deg)) * rot_z(core::deg_to_rad(c_deg));
}

core::Vec3 CradleMachine::nominal_machine_point(const core::Vec3& p_table_mm, double a_deg, double c_deg) const {
  const Vec3 d(0.0, pivot_.a_offset_y_mm, pivot_.a_offset_z_mm);
  return rot_x(core::deg_to_rad(a_deg)) * (rot_z(core::deg_to_rad(c_deg)) * p_table_mm - d) + pivot_.c_point_mm + d;
}

double CradleMachine::actual_a_deg(double a_deg) const {
  return a_deg + a_drive_error_arcsec(a_deg) / 3600.0;
}

double CradleMachine::a_drive_error_arcsec(double a_deg) const {
  return errors_.a_error_0_arcsec + errors_.a_error_1_arcsec * std::sin(core::deg_to_rad(a_deg));
}

RigidTransform CradleMachine::machine_T_table(double a_deg, double c_deg) const {
  // alpha built as A + e rather than from actual_a_deg so that e = 0 leaves A's
  // radians untouched (bit-exact ideal machine).
  const double alpha = core::deg_to_rad(a_deg) + arcsec_to_rad(a_drive_error_arcsec(a_deg));
  const Mat3 r_a = q_ * rot_x(alpha) * q_.transpose();
  const Vec3 d_rad = arcsec_to_rad(errors_.k_gravity_arcsec * std::sin(alpha)) * b_.col(0) +
                     arcsec_to_rad(errors_.k_stiffness_arcsec * std::sin(2.0 * alpha) +
                                   (a_deg == errors_.local_a_deg ? errors_.local_arcsec : 0.0)) * b_.col(1);
  const Mat3 r_def = rotation_from_vector(d_rad);
  RigidTransform machine_T;
  machine_T.rotation = r_a * r_def * b_ * rot_z(core::deg_to_rad(c_deg));
  const Vec3 origin_k = origin_k_ + (r_def - Mat3::Identity()) * (origin_k_ - pivot_k_);
  machine_T.translation_mm = a_point_ + r_a * (origin_k - a_point_);
  return machine_T;
}

Line CradleMachine::c_axis_at(double a_deg) const {
  const RigidTransform machine_T = machine_T_table(a_deg, 0.0);
  return Line{machine_T.translation_mm, machine_T.rotation.col(2)};
}

core::Vec3 CradleMachine::c_centre_at(double a_deg, double height_mm) const {
  return machine_T_table(a_deg, 0.0).apply(Vec3(0.0, 0.0, height_mm));
}

double CradleMachine::theory_angle_rad(double a_deg, double height_mm) const {
  const Vec3 a_point = a_point_;
  const auto across_a = [&](const Vec3& p) {
    const Vec3 u = p - a_point;
    return Vec3(u - u.dot(a_dir_) * a_dir_);
  };
  const Vec3 from = across_a(c_centre_at(0.0, height_mm));
  const Vec3 to = across_a(c_centre_at(a_deg, height_mm));
  return std::atan2(a_dir_.dot(from.cross(to)), from.dot(to));
}

core::Vec3 CradleMachine::rotation_vector_rad(double a_deg, double height_mm) const {
  // At the reference the theory frame is the actual frame by definition: zero,
  // not a rounding residue.
  if (a_deg == 0.0) return Vec3::Zero();
  const Mat3 e_pose = machine_T_table(a_deg, 0.0).rotation;
  const Mat3 e_ref = machine_T_table(0.0, 0.0).rotation;
  const Mat3 turn_about_a = q_ * rot_x(theory_angle_rad(a_deg, height_mm)) * q_.transpose();
  const Mat3 e_theory = turn_about_a * e_ref;
  return vector_from_rotation(e_pose * e_theory.transpose());
}

double CradleMachine::a_positioning_error_arcsec(double a_deg, double height_mm) const {
  if (a_deg == 0.0) return 0.0;
  return (theory_angle_rad(a_deg, height_mm) - core::deg_to_rad(a_deg)) * kArcsecPerRad;
}

double CradleMachine::c_to_a_offset_mm() const {
  const Line c = c_axis_at(0.0);
  const Vec3 between = c.point_mm - a_point_;
  const Vec3 normal = c.direction.cross(a_dir_);
  const double sin_angle = normal.norm();
  // Parallel lines (never for a cradle, but defined): the distance between them.
  if (sin_angle < 1e-12) return (between - between.dot(a_dir_) * a_dir_).norm();
  return std::abs(between.dot(normal)) / sin_angle;
}

double CradleMachine::c_to_a_squareness_arcsec() const {
  const Vec3 c = c_axis_at(0.0).direction;
  const double angle = std::atan2(c.cross(a_dir_).norm(), c.dot(a_dir_));
  return (angle - 0.5 * core::kPi) * kArcsecPerRad;
}

double CradleMachine::tilt_deg_at(double a_deg, double c_deg) const {
  const core::Vec3 n_machine = machine_T_table(a_deg, c_deg).rotation * normal_table_;
  // atan2 of the horizontal and vertical parts stays accurate near 0, where acos does not.
  const double horizontal = std::hypot(n_machine.x(), n_machine.y());
  return core::rad_to_deg(std::atan2(horizontal, n_machine.z()));
}

Plane CradleMachine::face_at(double a_deg, double c_deg) const {
  const RigidTransform machine_T = machine_T_table(a_deg, c_deg);
  return Plane{machine_T.apply(core::Vec3(0.0, 0.0, face_.height_mm)), machine_T.rotation * normal_table_};
}

}  // namespace trueaxis::sim
