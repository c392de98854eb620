#include "trueaxis/sim/tools/trt_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/services.hpp"

namespace trueaxis::sim {

namespace {

constexpr double kArcsecPerRad = 180.0 * 3600.0 / 3.14159265358979323846;
constexpr double kMaxTiltRad = 3.14159265358979323846 / 180.0;  // convention 4: 1 deg

[[gnu::format(printf, 1, 2)]] std::string line(const char* format, ...) {
  char text[200];
  std::va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  return text;
}

}  // namespace

double TrtParameters::not_held_arcsec() const {
  return std::hypot(a_direction_y_arcsec, a_direction_z_arcsec) + c_tilt_arcsec + rigidity_arcsec + a_error_arcsec;
}

bool trt_parameters(const core::RigidityTable& table, TrtParameters& out, std::string& why) {
  if (table.pose_count == 0 || table.reference >= table.pose_count) {
    why = "the table has no reference pose";
    return false;
  }
  const core::Vec3& n_a = table.a_axis_direction;
  const core::RigidityPose& ref = table.poses[table.reference];
  const core::Vec3& n_c = ref.c_direction;
  const double a_tilt = std::atan2(std::hypot(n_a.y(), n_a.z()), n_a.x());
  const double c_tilt = std::atan2(std::hypot(n_c.x(), n_c.y()), n_c.z());
  if (!(a_tilt <= kMaxTiltRad)) {
    why = "the table's A axis is not within 1 deg of +X: xyzac-trt-kins turns A about +X";
    return false;
  }
  if (!(c_tilt <= kMaxTiltRad)) {
    why = "the table's C axis at A = 0 is not within 1 deg of +Z: xyzac-trt-kins turns C about +Z";
    return false;
  }
  TrtParameters p;
  p.rot_point_mm = ref.c_centre_mm;
  const double t = (p.rot_point_mm.x() - table.a_axis_point_mm.x()) / n_a.x();
  const core::Vec3 on_a = table.a_axis_point_mm + t * n_a;
  p.y_offset_mm = on_a.y() - p.rot_point_mm.y();
  p.z_offset_mm = on_a.z() - p.rot_point_mm.z();
  p.a_direction_y_arcsec = std::atan2(n_a.y(), n_a.x()) * kArcsecPerRad;
  p.a_direction_z_arcsec = std::asin(std::clamp(n_a.z(), -1.0, 1.0)) * kArcsecPerRad;
  p.c_tilt_arcsec = c_tilt * kArcsecPerRad;
  for (std::size_t i = 0; i < table.pose_count; ++i) {
    p.rigidity_arcsec = std::max(p.rigidity_arcsec, table.poses[i].rigidity_rad * kArcsecPerRad);
    p.a_error_arcsec = std::max(p.a_error_arcsec, std::fabs(table.poses[i].a_error_rad) * kArcsecPerRad);
  }
  const bool finite = std::isfinite(p.rot_point_mm.x()) && std::isfinite(p.rot_point_mm.y()) &&
                      std::isfinite(p.rot_point_mm.z()) && std::isfinite(p.y_offset_mm) && std::isfinite(p.z_offset_mm);
  if (!finite) {
    why = "the table gives no finite pivot";
    return false;
  }
  out = p;
  return true;
}

std::string trt_hal_text(const TrtParameters& p, const std::string& component) {
  std::string text =
      "# xyzac-trt-kins' pivot from the controller's stored M3 table (trueaxis-calibrate linuxcnc-trt rigidity):\n"
      "# the C axis with the table at A = 0 through the ball's C centre, the A axis' offset from it (mm).\n"
      "# What these parameters cannot hold (trueaxis_kins table= holds all of it):\n";
  text += line("#   the A axis' direction: %.2f\" towards +Y, %.2f\" towards +Z from +X\n", p.a_direction_y_arcsec,
               p.a_direction_z_arcsec);
  text += line("#   the C axis at A = 0: %.2f\" from +Z\n", p.c_tilt_arcsec);
  text += line("#   the rigidity: up to %.2f\" (the table's largest rotation vector)\n", p.rigidity_arcsec);
  text += line("#   the A positioning error: up to %.2f\" (--linuxcnc-comp writes it as the A joint's compensation)\n",
               p.a_error_arcsec);
  text += line("#   together %.2f\": %.2f um at 100 mm from the axes\n", p.not_held_arcsec(),
               p.not_held_arcsec() / kArcsecPerRad * 100.0 * 1000.0);
  const char* names[5] = {"x-rot-point", "y-rot-point", "z-rot-point", "y-offset", "z-offset"};
  const double values[5] = {p.rot_point_mm.x(), p.rot_point_mm.y(), p.rot_point_mm.z(), p.y_offset_mm, p.z_offset_mm};
  for (int k = 0; k < 5; ++k) text += line("setp %s.%s %.6f\n", component.c_str(), names[k], values[k]);
  return text;
}

bool decode_rigidity_file(const std::string& file, core::RigidityTable& table, std::string& why) {
  const std::uint8_t* payload = nullptr;
  std::size_t length = 0;
  const macros::RecordFileError e =
      macros::decode_record_file(macros::RigidityTableRecord::kRecord.key,
                                 reinterpret_cast<const std::uint8_t*>(file.data()), file.size(), payload, length);
  if (e != macros::RecordFileError::kNone) {
    why = macros::record_file_text(e);
    return false;
  }
  if (core::decode_rigidity_table(payload, length, table) != core::Status::kOk) {
    why = "the rigidity table in it does not decode";
    return false;
  }
  return true;
}

}  // namespace trueaxis::sim
