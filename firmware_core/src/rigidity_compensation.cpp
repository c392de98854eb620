#include "trueaxis/core/rigidity_compensation.hpp"

#include "trueaxis/core/so3.hpp"

namespace trueaxis::core {

namespace {

// Where a commanded A falls: the pose k with A_k <= A (and w in [0, 1) of the
// way to k + 1), or exactly on pose k (w = 0, `on_pose`).
struct Bracket {
  std::size_t k = 0;
  double w = 0.0;
  double a_deg = 0.0;  // A after clamping
  bool on_pose = false;
};

Status find_bracket(const RigidityTable& t, double a_deg, bool clamp, Bracket& b) {
  const std::size_t m = t.pose_count;
  if (m < 2 || m > kMaxAPoses) return Status::kNoTable;
  if (!std::isfinite(a_deg)) return Status::kNotFinite;
  const double first = t.poses[0].a_deg;
  const double last = t.poses[m - 1].a_deg;
  if (!(a_deg >= first && a_deg <= last)) {
    if (!clamp) return Status::kOutsideMeasuredRange;
    a_deg = a_deg < first ? first : last;
  }
  std::size_t k = 0;
  while (k + 1 < m && t.poses[k + 1].a_deg <= a_deg) ++k;
  b.k = k;
  b.a_deg = a_deg;
  b.on_pose = a_deg == t.poses[k].a_deg;
  b.w = b.on_pose ? 0.0 : (a_deg - t.poses[k].a_deg) / (t.poses[k + 1].a_deg - t.poses[k].a_deg);
  return Status::kOk;
}

// The natural cubic spline between poses k and k + 1 (convention 3), for the
// rotation vector, the A positioning error or the origin offset.
template <typename T>
T cubic(const RigidityTable& t, const Bracket& b, const T& y0, const T& y1, const T& m0, const T& m1) {
  const double h = t.poses[b.k + 1].a_deg - t.poses[b.k].a_deg;
  const double x = b.a_deg - t.poses[b.k].a_deg;
  const T slope = (y1 - y0) / h - (h / 6.0) * (2.0 * m0 + m1);
  return y0 + x * (slope + x * (0.5 * m0 + x * ((m1 - m0) / (6.0 * h))));
}

Vec3 blend_rotvec(const RigidityTable& t, const Bracket& b, Blend blend) {
  const RigidityPose& p0 = t.poses[b.k];
  if (b.on_pose) return p0.rotvec_rad;
  const RigidityPose& p1 = t.poses[b.k + 1];
  switch (blend) {
    case Blend::kLinear:
      return (1.0 - b.w) * p0.rotvec_rad + b.w * p1.rotvec_rad;
    case Blend::kGeodesic:
      return so3_log(t.rotation[b.k] * so3_exp(b.w * t.geodesic_step_rad[b.k]));
    case Blend::kCubic:
      return cubic(t, b, p0.rotvec_rad, p1.rotvec_rad, t.spline_m[b.k], t.spline_m[b.k + 1]);
    default:
      return cubic(t, b, p0.rotvec_rad, p1.rotvec_rad, t.spline_k[b.k], t.spline_k[b.k + 1]);
  }
}

// R(nA, theta(A)) and the theory axes R(nA, theta(A)) E_ref Rz(C) (convention 5).
void theory_axes(const RigidityTable& t, const RigidityState& st, double c_deg, Mat3& turn, Mat3& axes) {
  turn = so3_exp(st.theta_rad * t.a_axis_direction);
  axes = turn * t.reference_axes * rot_z(deg_to_rad(c_deg));
}

bool valid_blend(Blend blend) {
  return blend == Blend::kLinear || blend == Blend::kGeodesic || blend == Blend::kCubic ||
         blend == Blend::kCubicNotAKnot;
}

}  // namespace

Result<Vec3> rigidity_rotvec_rad(const RigidityTable& table, double a_deg, Blend blend, bool clamp) {
  if (!valid_blend(blend)) return Status::kArgumentOutOfRange;
  Bracket b;
  const Status s = find_bracket(table, a_deg, clamp, b);
  if (s != Status::kOk) return s;
  return blend_rotvec(table, b, blend);
}

Result<RigidityState> rigidity_state(const RigidityTable& table, double a_deg, Blend blend, bool clamp) {
  if (!valid_blend(blend)) return Status::kArgumentOutOfRange;
  Bracket b;
  const Status s = find_bracket(table, a_deg, clamp, b);
  if (s != Status::kOk) return s;
  RigidityState out;
  out.rotvec_rad = blend_rotvec(table, b, blend);
  const RigidityPose& p0 = table.poses[b.k];
  if (b.on_pose) {
    out.a_error_rad = p0.a_error_rad;
    out.origin_offset_mm = p0.origin_offset_mm;
  } else {
    const RigidityPose& p1 = table.poses[b.k + 1];
    if (blend == Blend::kCubic || blend == Blend::kCubicNotAKnot) {
      out.a_error_rad = cubic(table, b, p0.a_error_rad, p1.a_error_rad, table.spline_e[b.k], table.spline_e[b.k + 1]);
      out.origin_offset_mm =
          cubic(table, b, p0.origin_offset_mm, p1.origin_offset_mm, table.spline_d[b.k], table.spline_d[b.k + 1]);
    } else {
      out.a_error_rad = (1.0 - b.w) * p0.a_error_rad + b.w * p1.a_error_rad;
      out.origin_offset_mm = (1.0 - b.w) * p0.origin_offset_mm + b.w * p1.origin_offset_mm;
    }
  }
  // The commanded A, not the clamped one, turns the frames (convention 4).
  out.theta_rad = deg_to_rad(a_deg - table.poses[table.reference].a_deg) + out.a_error_rad;
  return out;
}

Result<RigidityFrames> rigidity_frames(const RigidityTable& table, double a_deg, double c_deg, Blend blend,
                                       bool clamp) {
  if (!std::isfinite(c_deg)) return Status::kNotFinite;
  const Result<RigidityState> state = rigidity_state(table, a_deg, blend, clamp);
  if (!state.ok()) return state.status();
  const RigidityState& st = state.value();
  const Vec3& a0 = table.a_axis_point_mm;
  Mat3 turn;
  Mat3 table_axes;
  theory_axes(table, st, c_deg, turn, table_axes);
  RigidityFrames f;
  f.machine_T_table_theory.rotation = table_axes;
  f.machine_T_table_theory.translation_mm = a0 + turn * (table.poses[table.reference].c_centre_mm - a0);
  f.machine_T_table_actual.rotation = so3_exp(st.rotvec_rad) * table_axes;
  f.machine_T_table_actual.translation_mm = f.machine_T_table_theory.translation_mm + st.origin_offset_mm;
  return f;
}

Status rigidity_actual_axes(const RigidityTable& table, double a_deg, double c_deg, Blend blend, bool clamp,
                            Mat3& axes) {
  if (!std::isfinite(c_deg)) return Status::kNotFinite;
  const Result<RigidityState> state = rigidity_state(table, a_deg, blend, clamp);
  if (!state.ok()) return state.status();
  Mat3 turn;
  Mat3 table_axes;
  theory_axes(table, state.value(), c_deg, turn, table_axes);
  axes = so3_exp(state.value().rotvec_rad) * table_axes;
  return Status::kOk;
}

Result<RigidTransform> rigidity_correction(const RigidityTable& table, double a_deg, double c_deg, Blend blend,
                                           bool clamp) {
  const Result<RigidityFrames> frames = rigidity_frames(table, a_deg, c_deg, blend, clamp);
  if (!frames.ok()) return frames.status();
  return frames.value().machine_T_table_actual * frames.value().machine_T_table_theory.inverse();
}

}  // namespace trueaxis::core
