#include "kins_api.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

#include "cradle_kinematics.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/macros/record_file.hpp"

namespace {

using trueaxis::core::Vec3;

trueaxis::linuxcnc::CradleKinematics g_kins;
// The file, one byte beyond the largest table file so that a longer file is seen.
std::uint8_t g_file[trueaxis::core::kRigidityTableMaxBytes + trueaxis::macros::kRecordFileOverhead + 1];

static_assert(trueaxis::core::kSpindleModelBytes <= trueaxis::core::kRigidityTableMaxBytes,
              "the spindle model's file fits the buffer sized for the rigidity table's");

// The machine's linear unit in mm (trueaxis_kins_set_linear_units).
double g_mm_per_unit = 1.0;

}  // namespace

namespace {

// Reads the file at `path` into g_file and hands it to `load` (a
// CradleKinematics loader); 0, or -1 with *why.
template <typename Load>
int load_file(const char* path, const char** why, Load load) {
  std::FILE* f = std::fopen(path, "rb");
  if (f == nullptr) {
    *why = std::strerror(errno);
    return -1;
  }
  const std::size_t n = std::fread(g_file, 1, sizeof g_file, f);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) {
    *why = "it could not be read to its end";
    return -1;
  }
  if (n == sizeof g_file) {
    *why = "it is larger than any trueaxis record file: not one";
    return -1;
  }
  const trueaxis::linuxcnc::LoadResult r = load(n);
  if (!r.ok) {
    *why = r.why;
    return -1;
  }
  return 0;
}

}  // namespace

extern "C" int trueaxis_kins_load(const char* path, const char** why) {
  return load_file(path, why, [](std::size_t n) { return g_kins.load_table(g_file, n); });
}

extern "C" int trueaxis_kins_load_spindle(const char* path, const char** why) {
  return load_file(path, why, [](std::size_t n) { return g_kins.load_spindle(g_file, n); });
}

extern "C" int trueaxis_kins_spindle_loaded(void) { return g_kins.spindle_loaded() ? 1 : 0; }

extern "C" int trueaxis_kins_tip_error(double phi_deg, double tool_mm, double error_mm[3]) {
  Vec3 e;
  if (!g_kins.tip_error(phi_deg, tool_mm, e)) return -1;
  error_mm[0] = e.x();
  error_mm[1] = e.y();
  error_mm[2] = e.z();
  return 0;
}

extern "C" size_t trueaxis_kins_poses(void) { return g_kins.poses(); }
extern "C" double trueaxis_kins_a_min_deg(void) { return g_kins.a_min_deg(); }
extern "C" double trueaxis_kins_a_max_deg(void) { return g_kins.a_max_deg(); }

extern "C" int trueaxis_kins_set_linear_units(const char* units, const char** why) {
  // The names LinuxCNC's [TRAJ] LINEAR_UNITS takes.
  for (const char* mm : {"mm", "metric"}) {
    if (std::strcmp(units, mm) == 0) {
      g_mm_per_unit = 1.0;
      return 0;
    }
  }
  for (const char* inch : {"inch", "in", "imperial"}) {
    if (std::strcmp(units, inch) == 0) {
      g_mm_per_unit = 25.4;
      return 0;
    }
  }
  *why = "linear_units takes what [TRAJ] LINEAR_UNITS does: mm (metric) or inch (in, imperial)";
  return -1;
}

namespace {

// "A,B[,C]" into exactly `count` finite numbers; NULL or "" all 0.
bool numbers(const char* text, int count, double* out) {
  for (int i = 0; i < count; ++i) out[i] = 0.0;
  if (text == nullptr || text[0] == '\0') return true;
  const char* at = text;
  for (int i = 0; i < count; ++i) {
    char* end = nullptr;
    out[i] = std::strtod(at, &end);
    if (end == at || !std::isfinite(out[i])) return false;
    at = end;
    if (i + 1 < count && *at++ != ',') return false;
  }
  return *at == '\0';
}

}  // namespace

extern "C" int trueaxis_kins_set_home(const char* home, const char** why) {
  double h = 0.0;
  if (!numbers(home, 1, &h) || !(h >= 0.0 && h <= 65535.0 && h == std::floor(h))) {
    *why = "home takes a whole number 0..65535: the machine's home identity, the module's #904";
    return -1;
  }
  g_kins.set_home(static_cast<std::uint16_t>(h));
  return 0;
}

extern "C" unsigned trueaxis_kins_file_home(void) { return g_kins.file_home(); }
extern "C" unsigned trueaxis_kins_home(void) { return g_kins.home(); }

extern "C" int trueaxis_kins_set_pivot(const char* rot_point, const char* a_offset, const char** why) {
  double r[3];
  double d[2];
  if (!numbers(rot_point, 3, r)) {
    *why = "pivot takes X,Y,Z: the C axis' point at A = 0 (xyzac-trt-kins' x/y/z-rot-point), the machine's units";
    return -1;
  }
  if (!numbers(a_offset, 2, d)) {
    *why = "a_offset takes DY,DZ: the A axis' offset from the pivot (xyzac-trt-kins' y-offset, z-offset)";
    return -1;
  }
  const double k = g_mm_per_unit;
  if (!g_kins.set_nominal_pivot(k * Vec3(r[0], r[1], r[2]), k * d[0], k * d[1])) {
    *why = "the pivot is not finite in mm";
    return -1;
  }
  return 0;
}

extern "C" int trueaxis_kins_to_joints(int type, const double world[3], double a_deg, double c_deg, double tool,
                                       int tip, double phi_deg, double joint[3]) {
  double e[3] = {0.0, 0.0, 0.0};  // on without a model, or with pins it refuses: an error, never an uncorrected move
  if (trueaxis_kins_tip_target(tip != 0 ? 1 : 0, phi_deg, tool, e) != 0) return -1;
  return trueaxis_kins_to_joints_with(type, world, a_deg, c_deg, tool, e, joint);
}

extern "C" int trueaxis_kins_to_world(int type, const double joint[3], double a_deg, double c_deg, double tool,
                                      int tip, double phi_deg, double world[3]) {
  double e[3] = {0.0, 0.0, 0.0};
  if (trueaxis_kins_tip_target(tip != 0 ? 1 : 0, phi_deg, tool, e) != 0) return -1;
  return trueaxis_kins_to_world_with(type, joint, a_deg, c_deg, tool, e, world);
}

extern "C" int trueaxis_kins_tip_target(int mode, double phi_deg, double tool, double target_mm[3]) {
  Vec3 e = Vec3::Zero();
  const double tool_mm = g_mm_per_unit * tool;
  if ((mode == 1 && !g_kins.tip_error(phi_deg, tool_mm, e)) || (mode == 2 && !g_kins.mean_tip_error(tool_mm, e)) ||
      mode < 0 || mode > 2) {
    return -1;
  }
  for (int i = 0; i < 3; ++i) target_mm[i] = e[i];
  return 0;
}

extern "C" int trueaxis_kins_tip_ramp(const double target_mm[3], double ramp_mm, double applied_mm[3]) {
  Vec3 applied(applied_mm[0], applied_mm[1], applied_mm[2]);
  const bool arrived =
      trueaxis::linuxcnc::tip_ramp_step(Vec3(target_mm[0], target_mm[1], target_mm[2]), ramp_mm, applied);
  for (int i = 0; i < 3; ++i) applied_mm[i] = applied[i];
  return arrived ? 1 : 0;
}

extern "C" int trueaxis_kins_to_joints_with(int type, const double world[3], double a_deg, double c_deg, double tool,
                                            const double tip_error_mm[3], double joint[3]) {
  const double k = g_mm_per_unit;
  const Vec3 e(tip_error_mm[0], tip_error_mm[1], tip_error_mm[2]);
  if (type != 1 && e == Vec3::Zero()) {  // the identity: the world as LinuxCNC has it, bit for bit in any unit
    if (!Vec3(world[0], world[1], world[2]).allFinite()) return -1;
    for (int i = 0; i < 3; ++i) joint[i] = world[i];
    return 0;
  }
  Vec3 j;
  if (!g_kins.to_joints(type == 1, k * Vec3(world[0], world[1], world[2]), a_deg, c_deg, k * tool, e, j)) return -1;
  j /= k;
  for (int i = 0; i < 3; ++i) joint[i] = j[i];
  return 0;
}

extern "C" int trueaxis_kins_to_world_with(int type, const double joint[3], double a_deg, double c_deg, double tool,
                                           const double tip_error_mm[3], double world[3]) {
  const double k = g_mm_per_unit;
  const Vec3 e(tip_error_mm[0], tip_error_mm[1], tip_error_mm[2]);
  if (type != 1 && e == Vec3::Zero()) {
    if (!Vec3(joint[0], joint[1], joint[2]).allFinite()) return -1;
    for (int i = 0; i < 3; ++i) world[i] = joint[i];
    return 0;
  }
  Vec3 w;
  if (!g_kins.to_world(type == 1, k * Vec3(joint[0], joint[1], joint[2]), a_deg, c_deg, k * tool, e, w)) return -1;
  w /= k;
  for (int i = 0; i < 3; ++i) world[i] = w[i];
  return 0;
}
