#include "trueaxis/sim/machines/virtual_spindle.hpp"

#include <cmath>

namespace trueaxis::sim {

namespace {

using core::Mat3;
using core::Vec3;

Vec3 polar(double r, double deg, const Vec3& x, const Vec3& y) {
  const double t = core::deg_to_rad(deg);
  return r * (std::cos(t) * x + std::sin(t) * y);
}

}  // namespace

SpindleConfig realistic_spindle() {
  SpindleConfig c;
  c.o1_mm = Vec3(0.0123, -0.0087, 400.005);
  c.upper_runout_mm = 0.002;
  c.upper_runout_deg = 40.0;
  c.lower_runout_mm = 0.004;
  c.lower_runout_deg = 160.0;
  c.tilt_x_arcsec = 22.0;
  c.tilt_y_arcsec = -31.0;
  c.bearing_spacing_error_mm = 0.003;
  c.bearing_to_holder_error_mm = -0.002;
  c.holder_length_error_mm = 0.003;
  c.collet_lower_offset_mm = 0.002;
  c.collet_lower_deg = 100.0;
  c.collet_upper_offset_mm = 0.0015;
  c.collet_upper_deg = 250.0;
  c.collet_depth_error_mm = 0.002;
  c.collet_length_error_mm = -0.004;
  return c;
}

VirtualSpindle::VirtualSpindle(const SpindleConfig& config) : config_(config) {
  const SpindleConfig& c = config;
  const Mat3 r_s = (Eigen::AngleAxisd(arcsec_to_rad(c.tilt_y_arcsec), Vec3::UnitX()) *
                    Eigen::AngleAxisd(arcsec_to_rad(c.tilt_x_arcsec), -Vec3::UnitY()))
                       .toRotationMatrix();
  a_ = -r_s.col(2);
  e1_ = r_s.col(0);
  e2_ = r_s.col(1);

  const double h = c.bearing_spacing_mm + c.bearing_spacing_error_mm;
  const double to_gauge = h + c.bearing_to_holder_mm + c.bearing_to_holder_error_mm + c.holder_length_mm +
                          c.holder_length_error_mm;
  const double h1 = c.collet_depth_mm + c.collet_depth_error_mm;
  const double l_chuck = c.collet_length_mm + c.collet_length_error_mm;

  a1_ = polar(c.upper_runout_mm, c.upper_runout_deg, e1_, e2_);
  a2_ = polar(c.lower_runout_mm, c.lower_runout_deg, e1_, e2_) + h * a_;
  const Vec3 n = (a2_ - a1_).normalized();
  o3_ = a1_ + to_gauge * n;
  const Vec3 z3 = -n;
  const Vec3 x3 = (e1_ - e1_.dot(n) * n).normalized();
  const Vec3 y3 = z3.cross(x3);
  o4_ = o3_ + polar(c.collet_lower_offset_mm, c.collet_lower_deg, x3, y3) - h1 * z3;
  o4s_ = o3_ + polar(c.collet_upper_offset_mm, c.collet_upper_deg, x3, y3) + (l_chuck - h1) * z3;
  d_ = (o4_ - o4s_).normalized();
}

double VirtualSpindle::gauge_mm() const {
  return config_.bearing_spacing_mm + config_.bearing_to_holder_mm + config_.holder_length_mm;
}

core::SpindleGeometry VirtualSpindle::geometry() const {
  core::SpindleGeometry g;
  g.gauge_mm = gauge_mm();
  g.ball_mm[0] = config_.ball_mm[0];
  g.ball_mm[1] = config_.ball_mm[1];
  return g;
}

Vec3 VirtualSpindle::turn(const Vec3& p_body, double phi_deg) const {
  return config_.o1_mm + Eigen::AngleAxisd(core::deg_to_rad(phi_deg), a_) * p_body;
}

Vec3 VirtualSpindle::tool_point_mm(double depth_mm, double phi_deg) const {
  return turn(o4_ + (depth_mm - config_.collet_depth_mm) * d_, phi_deg);
}

Vec3 VirtualSpindle::ball_mm(int ball, double phi_deg) const {
  return tool_point_mm(config_.ball_mm[ball == 2 ? 1 : 0], phi_deg);
}

Line VirtualSpindle::tool_axis(double phi_deg) const {
  Line l;
  l.point_mm = tool_point_mm(0.0, phi_deg);
  l.direction = Eigen::AngleAxisd(core::deg_to_rad(phi_deg), a_) * d_;
  return l;
}

double VirtualSpindle::axial_error_mm() const {
  const double b_ref = 0.5 * (config_.ball_mm[0] + config_.ball_mm[1]);
  const Vec3 q0 = o4_ + (b_ref - config_.collet_depth_mm) * d_;
  return q0.dot(a_) - gauge_mm() - b_ref;
}

core::SpindleParams VirtualSpindle::identifiable_truth() const {
  const double b_ref = 0.5 * (config_.ball_mm[0] + config_.ball_mm[1]);
  const Vec3 q0 = o4_ + (b_ref - config_.collet_depth_mm) * d_;
  const Vec3 w = d_ / d_.dot(a_) - a_;
  const Vec3 o = config_.o1_mm + axial_error_mm() * a_;
  const Vec3 e = q0 - q0.dot(a_) * a_ - b_ref * w;
  core::SpindleParams p;
  p << o.x(), o.y(), o.z(), a_.x(), a_.y(), e.x(), e.y(), w.x(), w.y();
  return p;
}

double VirtualSpindle::mapping_error_mm(double depth_mm) const {
  const double b_ref = 0.5 * (config_.ball_mm[0] + config_.ball_mm[1]);
  const double one_minus_c = 0.5 * (d_ - a_).squaredNorm();  // 1 - d . a for unit d, a, without cancellation
  const Vec3 w = d_ / d_.dot(a_) - a_;
  return std::abs(depth_mm - b_ref) * one_minus_c * std::sqrt(1.0 + w.squaredNorm());
}

ScrewError VirtualSpindle::screw_error(double phi_deg) const {
  const Line actual = tool_axis(phi_deg);
  const Vec3 ideal = -Vec3::UnitZ();
  const Vec3 k = ideal.cross(actual.direction);
  const Vec3 p = actual.point_mm - config_.o1_mm;
  ScrewError s;
  s.theta_e_rad = std::atan2(k.norm(), ideal.dot(actual.direction));
  if (k.norm() > 0.0) {
    s.d_e_mm = std::abs(p.dot(k)) / k.norm();
  } else {
    s.d_e_mm = (p - p.dot(ideal) * ideal).norm();
  }
  return s;
}

Vec3 VirtualSpindle::tool_tip_error_mm(double tool_length_mm, double phi_deg) const {
  const Vec3 ideal_tip = config_.o1_mm - (gauge_mm() + tool_length_mm) * Vec3::UnitZ();
  return tool_tip_mm(tool_length_mm, phi_deg) - ideal_tip;
}

}  // namespace trueaxis::sim
