#include "kins_api.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "cradle_kinematics.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/macros/record_file.hpp"

namespace {

using trueaxis::core::Vec3;

trueaxis::linuxcnc::CradleKinematics g_kins;
// The file, one byte beyond the largest table file so that a longer file is seen.
std::uint8_t g_file[trueaxis::core::kRigidityTableMaxBytes + trueaxis::macros::kRecordFileOverhead + 1];

}  // namespace

extern "C" int trueaxis_kins_load(const char* path, const char** why) {
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
    *why = "it is larger than any rigidity table file: not a table file";
    return -1;
  }
  const trueaxis::linuxcnc::LoadResult r = g_kins.load_table(g_file, n);
  if (!r.ok) {
    *why = r.why;
    return -1;
  }
  return 0;
}

extern "C" size_t trueaxis_kins_poses(void) { return g_kins.poses(); }
extern "C" double trueaxis_kins_a_min_deg(void) { return g_kins.a_min_deg(); }
extern "C" double trueaxis_kins_a_max_deg(void) { return g_kins.a_max_deg(); }

extern "C" int trueaxis_kins_inverse(const double world_mm[3], double a_deg, double c_deg, double joint_mm[3]) {
  Vec3 j;
  if (!g_kins.inverse(Vec3(world_mm[0], world_mm[1], world_mm[2]), a_deg, c_deg, j)) return -1;
  joint_mm[0] = j.x();
  joint_mm[1] = j.y();
  joint_mm[2] = j.z();
  return 0;
}

extern "C" int trueaxis_kins_forward(const double joint_mm[3], double a_deg, double c_deg, double world_mm[3]) {
  Vec3 w;
  if (!g_kins.forward(Vec3(joint_mm[0], joint_mm[1], joint_mm[2]), a_deg, c_deg, w)) return -1;
  world_mm[0] = w.x();
  world_mm[1] = w.y();
  world_mm[2] = w.z();
  return 0;
}
