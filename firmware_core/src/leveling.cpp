#include "trueaxis/core/leveling.hpp"

#include <algorithm>
#include <limits>

#include "trueaxis/core/plane_fit.hpp"

namespace trueaxis::core {

namespace {


bool is_sign(double s) { return s == 1.0 || s == -1.0; }

// The representative c + k 360 inside [lo, hi] nearest to `current`; false when
// the range holds none.
bool nearest_representative(double c_deg, double current_deg, double lo, double hi, double& out) {
  // Whole turns k are chosen first and added once, so the result is rounded once,
  // at its own magnitude (stepping from a far limit would lose digits of c).
  const double k_min = std::ceil((lo - c_deg) / 360.0);
  const double k_max = std::floor((hi - c_deg) / 360.0);
  if (k_min > k_max) return false;
  const double k = std::min(std::max(std::round((current_deg - c_deg) / 360.0), k_min), k_max);
  out = c_deg + 360.0 * k;
  return out >= lo && out <= hi;
}

// The commanded solution for physical angles (rad), convention 2 of the header.
LevelSolution make_physical_solution(double c_phys_rad, double a_phys_rad, const TablePose& current,
                                     const LevelConfig& cfg) {
  return level_solution(wrap_deg_180(cfg.c_sign * rad_to_deg(c_phys_rad)), cfg.a_sign * rad_to_deg(a_phys_rad),
                       current, cfg);
}

double move_cost_deg(const LevelSolution& s, const TablePose& current) {
  return std::abs(s.a_deg - current.a_deg) + std::abs(s.c_deg - current.c_deg);
}

}  // namespace

LevelSolution level_solution(double c_cmd_deg, double a_cmd_deg, const TablePose& current, const LevelConfig& cfg) {
  LevelSolution s;
  s.a_deg = a_cmd_deg + 0.0;  // + 0.0 turns -0 into 0
  s.c_deg = c_cmd_deg;
  const bool c_ok = nearest_representative(c_cmd_deg, current.c_deg, cfg.c_min_deg, cfg.c_max_deg, s.c_deg);
  s.reachable = c_ok && s.a_deg >= cfg.a_min_deg && s.a_deg <= cfg.a_max_deg;
  return s;
}

void order_level_solutions(const LevelSolution& s1, const LevelSolution& s2, const TablePose& current,
                           LevelSolution& chosen, LevelSolution& other) {
  const bool take_second =
      s2.reachable && (!s1.reachable || move_cost_deg(s2, current) < move_cost_deg(s1, current) - kLevelTieDeg);
  chosen = take_second ? s2 : s1;
  other = take_second ? s1 : s2;
}

Status validate(const LevelConfig& c) {
  const double values[] = {c.a_min_deg, c.a_max_deg, c.c_min_deg, c.c_max_deg,
                           c.probe_sigma_mm, c.max_direction_sigma_deg};
  for (double v : values) {
    if (!std::isfinite(v)) return Status::kConfigInvalid;
  }
  if (!(c.a_min_deg <= c.a_max_deg) || !(c.c_min_deg <= c.c_max_deg)) return Status::kConfigInvalid;
  if (!is_sign(c.a_sign) || !is_sign(c.c_sign)) return Status::kConfigInvalid;
  if (c.probe_sigma_mm < 0.0 || !(c.max_direction_sigma_deg > 0.0)) return Status::kConfigInvalid;
  return Status::kOk;
}

Mat3 table_rotation(const TablePose& pose, const LevelConfig& config) {
  return rot_x(config.a_sign * deg_to_rad(pose.a_deg)) * rot_z(config.c_sign * deg_to_rad(pose.c_deg));
}

Result<LevelResult> level_face(const LevelInput& in, const LevelConfig& cfg) {
  const Status config_status = validate(cfg);
  if (config_status != Status::kOk) return config_status;
  if (in.points_mm == nullptr) return Status::kTooFewPoints;
  const double pose_values[] = {in.probe_pose.a_deg, in.probe_pose.c_deg, in.current_pose.a_deg,
                                in.current_pose.c_deg};
  for (double v : pose_values) {
    if (!std::isfinite(v)) return Status::kNotFinite;
  }
  if (!all_finite(in.outward_hint_machine)) return Status::kNotFinite;

  const Result<PlaneFit> fitted = fit_plane(in.points_mm, in.count);
  if (!fitted.ok()) return fitted.status();
  const PlaneFit& fit = fitted.value();

  const double sigma = cfg.probe_sigma_mm;
  const double direction_sigma_rad = sigma / fit.spread_v_mm;
  if (direction_sigma_rad > deg_to_rad(cfg.max_direction_sigma_deg)) return Status::kPointsTooClose;

  const Vec3 hint = in.outward_hint_machine.squaredNorm() > 0.0 ? in.outward_hint_machine.normalized()
                                                                 : Vec3::UnitZ();
  const double hint_cos = fit.normal.dot(hint);
  // Refuse when the face is so close to perpendicular to the hint that the probe
  // noise could flip which side is outward (3 sigma of the normal's direction).
  if (std::abs(hint_cos) < std::max(kOrientationMinCos, 3.0 * direction_sigma_rad)) {
    return Status::kOrientationAmbiguous;
  }
  const double orient = hint_cos > 0.0 ? 1.0 : -1.0;

  // The probe saw the face with the table at probe_pose: n_machine = R n_table.
  const Mat3 R_table_machine = table_rotation(in.probe_pose, cfg).transpose();
  const Vec3 n = R_table_machine * (orient * fit.normal);
  const Vec3 u = R_table_machine * fit.axis_u;
  const Vec3 v = R_table_machine * fit.axis_v;

  LevelResult out;
  out.normal_table = n;
  out.count = fit.count;
  out.flatness_mm = fit.flatness_mm;
  out.direction_sigma_arcsec = direction_sigma_rad * kArcsecPerRad;

  const double rho = std::hypot(n.x(), n.y());
  const double tilt_rad = std::atan2(rho, n.z());
  out.tilt_deg = rad_to_deg(tilt_rad);

  // Level as far as the measurement can tell: the tilt is not larger than the
  // normal's 1-sigma direction error, so C would be set by noise. Keep C, A = 0.
  // A face facing down (n.z < 0) is never level: it needs A near 180 deg.
  const bool level = n.z() > 0.0 && (rho == 0.0 || tilt_rad <= direction_sigma_rad);
  if (level) {
    out.chosen = level_solution(in.current_pose.c_deg, 0.0, in.current_pose, cfg);
    out.other = out.chosen;
  } else {
    const double c1 = std::atan2(n.x(), n.y());
    const LevelSolution s1 = make_physical_solution(c1, tilt_rad, in.current_pose, cfg);
    const LevelSolution s2 = make_physical_solution(c1 + kPi, -tilt_rad, in.current_pose, cfg);
    order_level_solutions(s1, s2, in.current_pose, out.chosen, out.other);
  }
  if (!out.chosen.reachable) return Status::kUnreachable;

  // Propagate the fit's direction covariance sigma^2 diag(1/s_u^2, 1/s_v^2),
  // its in-plane axes written in the normal's frame.
  const auto propagate = [&](const Vec3& dir, const Vec3& axis_u, const Vec3& axis_v) {
    const double du = dir.dot(axis_u) / fit.spread_u_mm;
    const double dv = dir.dot(axis_v) / fit.spread_v_mm;
    return sigma * std::sqrt(du * du + dv * dv);
  };
  const Vec3 z_tangent = Vec3::UnitZ() - n.z() * n;
  if (z_tangent.norm() > 0.0 && tilt_rad > 0.0) {
    const Vec3 d = z_tangent.normalized();
    out.tilt_sigma_arcsec = propagate(d, u, v) * kArcsecPerRad;
    const double c_sigma_rad = propagate(n.cross(d), u, v) / std::sin(tilt_rad);
    out.c_sigma_arcsec = std::min(c_sigma_rad, kPi) * kArcsecPerRad;
  } else {
    out.tilt_sigma_arcsec = direction_sigma_rad * kArcsecPerRad;
    out.c_sigma_arcsec = (sigma > 0.0 ? kPi : 0.0) * kArcsecPerRad;
  }

  // The same tilt and its sigma in the machine frame, as probed (convention 8).
  const Vec3 n_machine = orient * fit.normal;
  const double machine_tilt_rad = std::atan2(std::hypot(n_machine.x(), n_machine.y()), n_machine.z());
  out.machine_tilt_deg = rad_to_deg(machine_tilt_rad);
  const Vec3 z_machine_tangent = Vec3::UnitZ() - n_machine.z() * n_machine;
  out.machine_tilt_sigma_arcsec =
      (z_machine_tangent.norm() > 0.0 && machine_tilt_rad > 0.0
           ? propagate(z_machine_tangent.normalized(), fit.axis_u, fit.axis_v)
           : direction_sigma_rad) *
      kArcsecPerRad;

  if (fit.count >= 5 && sigma > 0.0) {
    const double n_pts = static_cast<double>(fit.count);
    for (std::size_t i = 0; i < fit.count; ++i) {
      const Vec3 q = in.points_mm[i] - fit.centroid_mm;
      const double qu = q.dot(fit.axis_u) / fit.spread_u_mm;
      const double qv = q.dot(fit.axis_v) / fit.spread_v_mm;
      const double leverage = 1.0 / n_pts + qu * qu + qv * qv;
      const double room = std::max(1.0 - leverage, std::numeric_limits<double>::epsilon());
      const double t = std::abs(fit.normal.dot(q)) / (sigma * std::sqrt(room));
      if (t > out.max_standardized_residual) {
        out.max_standardized_residual = t;
        out.outlier_point = i + 1;
      }
    }
    if (out.max_standardized_residual <= kOutlierLimit) out.outlier_point = 0;
  }
  return out;
}

}  // namespace trueaxis::core
