#include "trueaxis/core/rigidity_leveling.hpp"

#include <limits>

namespace trueaxis::core {

namespace {

constexpr double kRadPerDeg = kPi / 180.0;

// Signed angle about the unit `axis` from `from` to `to`, both projected on its plane.
double signed_angle(const Vec3& from, const Vec3& to, const Vec3& axis) {
  const Vec3 f = from - from.dot(axis) * axis;
  const Vec3 g = to - to.dot(axis) * axis;
  return std::atan2(axis.dot(f.cross(g)), f.dot(g));
}

struct Attitude {
  double a_deg = 0.0;
  double c_deg = 0.0;
};

// Convention 4's closed-form guesses on the rigid measured axes. Returns 2, or
// 1 with the cones' nearest point when they do not meet (convention 5), or 0
// when the A and C axes are parallel.
int rigid_guesses(const RigidityTable& t, const Vec3& q, Attitude guesses[2]) {
  const Mat3& e_ref = t.reference_axes;
  const Vec3 a = e_ref.transpose() * t.a_axis_direction;
  const Vec3 z = e_ref.transpose() * Vec3::UnitZ();
  const Vec3 ez = Vec3::UnitZ();
  const double s = a.z();
  const double det = 1.0 - s * s;
  if (!(det > 1e-12)) return 0;
  const double k1 = z.dot(a);
  const double k2 = q.z();
  const double alpha = (k1 - s * k2) / det;
  const double beta = (k2 - s * k1) / det;
  const double gamma_sq = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * s) / det;
  const int count = gamma_sq > 0.0 ? 2 : 1;
  const double gamma = gamma_sq > 0.0 ? std::sqrt(gamma_sq) : 0.0;
  const double a_ref = t.poses[t.reference].a_deg;
  for (int k = 0; k < count; ++k) {
    const Vec3 p = alpha * a + beta * ez + (k == 0 ? gamma : -gamma) * a.cross(ez);
    guesses[k].c_deg = rad_to_deg(signed_angle(q, p, ez));
    guesses[k].a_deg = a_ref + rad_to_deg(signed_angle(p, z, a));
  }
  return count;
}

// Newton on (v_x, v_y) (convention 4).
Status solve_both_axes(const RigidityTable& t, const Vec3& q, Blend blend, Attitude& x) {
  const Vec3& na = t.a_axis_direction;
  for (int it = 0; it < kCalibratedLevelMaxIterations; ++it) {
    Mat3 axes;
    // E_act(A) Rz(C) from the table, clamped (convention 6).
    const Status s = rigidity_actual_axes(t, x.a_deg, x.c_deg, blend, true, axes);
    if (s != Status::kOk) return s;
    const Vec3 v = axes * q;
    if (v.z() > 0.0 && std::atan2(std::hypot(v.x(), v.y()), v.z()) <= kCalibratedLevelTolerance_rad) {
      return Status::kOk;
    }
    const Vec3 dv_da = kRadPerDeg * na.cross(v);
    const Vec3 dv_dc = kRadPerDeg * (axes * Vec3::UnitZ().cross(q));
    const double j_det = dv_da.x() * dv_dc.y() - dv_dc.x() * dv_da.y();
    if (!(std::abs(j_det) > 0.0)) return Status::kNoConvergence;
    x.a_deg += -(dv_dc.y() * v.x() - dv_dc.x() * v.y()) / j_det;
    x.c_deg += -(-dv_da.y() * v.x() + dv_da.x() * v.y()) / j_det;
    if (!std::isfinite(x.a_deg) || !std::isfinite(x.c_deg)) return Status::kNoConvergence;
  }
  return Status::kNoConvergence;
}

// C kept, A bringing v nearest +Z (convention 5): the rigid turn about nA that
// maximises v.Z is atan2((nA x v).Z, v_perp.Z), applied until it vanishes.
Status solve_a_only(const RigidityTable& t, const Vec3& q, Blend blend, Attitude& x) {
  const Vec3& na = t.a_axis_direction;
  for (int it = 0; it < kCalibratedLevelMaxIterations; ++it) {
    Mat3 axes;
    // E_act(A) Rz(C) from the table, clamped (convention 6).
    const Status s = rigidity_actual_axes(t, x.a_deg, x.c_deg, blend, true, axes);
    if (s != Status::kOk) return s;
    const Vec3 v = axes * q;
    const double turn = std::atan2(na.cross(v).z(), (v - na.dot(v) * na).z());
    if (std::abs(turn) <= kCalibratedLevelTolerance_rad) return Status::kOk;
    x.a_deg += rad_to_deg(turn);
  }
  return Status::kNoConvergence;
}

LevelSolution make(const Attitude& x, const RigidityTable& t, const LevelInput& in, const LevelConfig& cfg,
                   bool clamp) {
  LevelSolution s = level_solution(wrap_deg_180(x.c_deg), x.a_deg, in.current_pose, cfg);
  const bool in_range = x.a_deg >= t.poses[0].a_deg && x.a_deg <= t.poses[t.pose_count - 1].a_deg;
  s.reachable = s.reachable && (clamp || in_range);
  return s;
}

}  // namespace

Result<LevelResult> level_on_table(const LevelInput& in, const LevelConfig& cfg, const RigidityTable& table,
                                   Blend blend, bool clamp) {
  const Status config_status = validate(cfg);
  if (config_status != Status::kOk) return config_status;
  LevelConfig open = cfg;
  open.a_min_deg = -std::numeric_limits<double>::max();
  open.a_max_deg = std::numeric_limits<double>::max();
  open.c_min_deg = -std::numeric_limits<double>::max();
  open.c_max_deg = std::numeric_limits<double>::max();
  const Result<LevelResult> ideal = level_face(in, open);
  if (!ideal.ok()) return ideal.status();
  LevelResult out = ideal.value();

  Mat3 probe_axes;
  const Status probe =
      rigidity_actual_axes(table, in.probe_pose.a_deg, in.probe_pose.c_deg, blend, clamp, probe_axes);
  if (probe != Status::kOk) return probe;
  const Vec3 n_machine = table_rotation(in.probe_pose, cfg) * ideal.value().normal_table;
  const Vec3 q = (probe_axes.transpose() * n_machine).normalized();
  out.normal_table = q;
  const double rho = std::hypot(q.x(), q.y());
  const double tilt_rad = std::atan2(rho, q.z());
  out.tilt_deg = rad_to_deg(tilt_rad);

  const double direction_sigma_rad = out.direction_sigma_arcsec / kArcsecPerRad;
  const bool level = q.z() > 0.0 && (rho == 0.0 || tilt_rad <= direction_sigma_rad);
  Attitude guesses[2];
  const int count = level ? 0 : rigid_guesses(table, q, guesses);
  if (count == 2) {
    LevelSolution s[2];
    for (int k = 0; k < 2; ++k) {
      const Status st = solve_both_axes(table, q, blend, guesses[k]);
      if (st != Status::kOk) return st;
      s[k] = make(guesses[k], table, in, cfg, clamp);
    }
    order_level_solutions(s[0], s[1], in.current_pose, out.chosen, out.other);
  } else {
    Attitude x;
    x.c_deg = count == 1 ? guesses[0].c_deg : in.current_pose.c_deg;
    x.a_deg = table.poses[table.reference].a_deg;
    const Status st = solve_a_only(table, q, blend, x);
    if (st != Status::kOk) return st;
    out.chosen = make(x, table, in, cfg, clamp);
    out.other = out.chosen;
  }
  if (!out.chosen.reachable) return Status::kUnreachable;
  return out;
}

}  // namespace trueaxis::core
