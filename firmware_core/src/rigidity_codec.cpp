#include "trueaxis/core/rigidity_codec.hpp"

#include "trueaxis/core/byte_order.hpp"

#include <cstring>
#include <limits>

namespace trueaxis::core {

namespace {

// The one list of fields, in layout order, for both directions: `Io` puts or
// gets a double at the cursor.
template <typename Io>
void header_fields(Io& io, Vec3& a_point, Vec3& a_dir, double& offset, double& offset_sigma, double& square,
                   double& square_sigma) {
  io(a_point);
  io(a_dir);
  io(offset);
  io(offset_sigma);
  io(square);
  io(square_sigma);
}

template <typename Io>
void pose_fields(Io& io, RigidityPose& p, double& count) {
  io(p.a_deg);
  io(p.rotvec_rad);
  io(p.rotvec_sigma_rad);
  io(p.rigidity_rad);
  io(p.rigidity_sigma_rad);
  io(p.theta_rad);
  io(p.a_error_rad);
  io(p.a_error_sigma_rad);
  io(p.origin_offset_mm);
  io(p.c_centre_mm);
  io(p.c_direction);
  io(p.c_x_axis);
  io(p.c_circle_rms_mm);
  io(p.c_arc_deg);
  io(count);
}

// Puts doubles into an array, in the layout's order.
struct RealWriter {
  double* p;
  void operator()(double v) { *p++ = v; }
  template <typename V>
  void operator()(const V& v) {
    for (int i = 0; i < static_cast<int>(v.size()); ++i) (*this)(static_cast<double>(v(i)));
  }
};

bool unit(const Vec3& v) { return std::abs(v.norm() - 1.0) <= kCodecUnitTolerance; }

bool nonnegative(const Vec3& v) { return v.minCoeff() >= 0.0; }

}  // namespace

std::size_t encode_rigidity_table(const RigidityTable& t, std::uint8_t* out, std::size_t capacity) {
  const std::size_t m = t.pose_count;
  if (m < kMinAPoses || m > kMaxAPoses || t.reference >= m) return 0;
  const std::size_t size = rigidity_table_bytes(m);
  if (out == nullptr || capacity < size) return 0;
  put_u16(out, kRigidityLayoutVersion);
  put_u16(out + 2, static_cast<std::uint16_t>(m));
  put_u16(out + 4, static_cast<std::uint16_t>(t.reference));
  put_u16(out + 6, t.home_identity);
  F64Writer w{out + 8};
  Vec3 a_point = t.a_axis_point_mm;
  Vec3 a_dir = t.a_axis_direction;
  double offset = t.c_to_a_offset_mm;
  double offset_sigma = t.c_to_a_offset_sigma_mm;
  double square = t.c_to_a_squareness_rad;
  double square_sigma = t.c_to_a_squareness_sigma_rad;
  header_fields(w, a_point, a_dir, offset, offset_sigma, square, square_sigma);
  for (std::size_t i = 0; i < m; ++i) {
    RigidityPose p = t.poses[i];
    double count = static_cast<double>(p.c_count);
    pose_fields(w, p, count);
  }
  return size;
}

void rigidity_header_reals(const RigidityTable& t, double out[kRigidityHeaderReals]) {
  RealWriter w{out};
  Vec3 a_point = t.a_axis_point_mm;
  Vec3 a_dir = t.a_axis_direction;
  double offset = t.c_to_a_offset_mm;
  double offset_sigma = t.c_to_a_offset_sigma_mm;
  double square = t.c_to_a_squareness_rad;
  double square_sigma = t.c_to_a_squareness_sigma_rad;
  header_fields(w, a_point, a_dir, offset, offset_sigma, square, square_sigma);
}

void rigidity_pose_reals(const RigidityTable& t, std::size_t pose, double out[kRigidityPoseReals]) {
  if (pose >= t.pose_count || pose >= kMaxAPoses) return;
  RealWriter w{out};
  RigidityPose p = t.poses[pose];
  double count = static_cast<double>(p.c_count);
  pose_fields(w, p, count);
}

std::size_t encode_rigidity_reals(std::size_t m, std::size_t reference, std::uint16_t home_identity,
                                  const double* header_reals, const double* pose_reals, std::uint8_t* out,
                                  std::size_t capacity) {
  if (m < kMinAPoses || m > kMaxAPoses || reference >= m) return 0;
  const std::size_t size = rigidity_table_bytes(m);
  if (out == nullptr || header_reals == nullptr || pose_reals == nullptr || capacity < size) return 0;
  put_u16(out, kRigidityLayoutVersion);
  put_u16(out + 2, static_cast<std::uint16_t>(m));
  put_u16(out + 4, static_cast<std::uint16_t>(reference));
  put_u16(out + 6, home_identity);
  F64Writer w{out + 8};
  for (std::size_t i = 0; i < kRigidityHeaderReals; ++i) w(header_reals[i]);
  for (std::size_t i = 0; i < m * kRigidityPoseReals; ++i) w(pose_reals[i]);
  return size;
}

Status decode_rigidity_table(const std::uint8_t* bytes, std::size_t size, RigidityTable& out) {
  if (bytes == nullptr || size < kRigidityHeaderBytes) return Status::kTableInvalid;
  const std::size_t m = get_u16(bytes + 2);
  const std::size_t reference = get_u16(bytes + 4);
  if (get_u16(bytes) != kRigidityLayoutVersion) return Status::kTableInvalid;
  const std::uint16_t home_identity = get_u16(bytes + 6);
  if (m < kMinAPoses || m > kMaxAPoses || reference >= m || size != rigidity_table_bytes(m)) {
    return Status::kTableInvalid;
  }
  for (std::size_t k = 8; k < size; k += 8) {
    if (!std::isfinite(get_f64(bytes + k))) return Status::kTableInvalid;
  }

  // Check every value before `out` is touched.
  F64Reader r{bytes + 8};
  Vec3 a_point;
  Vec3 a_dir;
  double offset = 0.0;
  double offset_sigma = 0.0;
  double square = 0.0;
  double square_sigma = 0.0;
  header_fields(r, a_point, a_dir, offset, offset_sigma, square, square_sigma);
  if (!unit(a_dir) || offset < 0.0 || offset_sigma < 0.0 || square_sigma < 0.0) return Status::kTableInvalid;
  double previous_a = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    RigidityPose p;
    double count = 0.0;
    pose_fields(r, p, count);
    if (i > 0 && !(p.a_deg > previous_a)) return Status::kTableInvalid;
    previous_a = p.a_deg;
    if (i == reference && !(std::abs(p.a_deg) <= kPoseAToleranceDeg)) return Status::kTableInvalid;
    if (!unit(p.c_direction) || !unit(p.c_x_axis) ||
        !(std::abs(p.c_direction.dot(p.c_x_axis)) <= kCodecUnitTolerance)) {
      return Status::kTableInvalid;
    }
    if (!(p.rotvec_rad.norm() <= kPi) || !nonnegative(p.rotvec_sigma_rad) || p.rigidity_rad < 0.0 ||
        p.rigidity_sigma_rad < 0.0 || p.a_error_sigma_rad < 0.0 || p.c_circle_rms_mm < 0.0 ||
        p.c_arc_deg < 0.0 || !(p.c_arc_deg < 360.0)) {
      return Status::kTableInvalid;
    }
    if (!(count == std::floor(count)) || count < static_cast<double>(kMinCPositions) ||
        count > static_cast<double>(kMaxCirclePoints)) {
      return Status::kTableInvalid;
    }
  }

  for (std::size_t i = m; i < kMaxAPoses; ++i) out.poses[i] = RigidityPose{};
  out.pose_count = m;
  out.reference = reference;
  out.home_identity = home_identity;
  F64Reader fill{bytes + 8};
  header_fields(fill, out.a_axis_point_mm, out.a_axis_direction, out.c_to_a_offset_mm, out.c_to_a_offset_sigma_mm,
                out.c_to_a_squareness_rad, out.c_to_a_squareness_sigma_rad);
  for (std::size_t i = 0; i < m; ++i) {
    double count = 0.0;
    pose_fields(fill, out.poses[i], count);
    out.poses[i].c_count = static_cast<std::size_t>(count);
  }
  prepare_rigidity_table(out);
  return Status::kOk;
}

}  // namespace trueaxis::core
