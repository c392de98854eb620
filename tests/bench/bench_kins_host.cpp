// The real-time cost of the LinuxCNC cradle kinematics (integrations/linuxcnc/kins):
// ns per kinematicsInverse and kinematicsForward on a 7-pose table (the
// realistic virtual cradle's, noise-free), calibrated and ideal, best of
// several runs over 200,000 calls at A, C spread over the range. LinuxCNC
// calls the inverse once per servo period in coordinated motion.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "cradle_kinematics.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/macros/record_file.hpp"
#include "trueaxis/macros/services.hpp"
#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/machines/cradle_errors.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/program.hpp"

namespace {

constexpr const char* kHelp =
    "usage: bench_kins_host\n"
    "  ns per inverse and forward call of the LinuxCNC cradle kinematics, calibrated (a 7-pose M3 table)\n"
    "  and ideal, best of 7 runs of 200,000 calls.\n"
    "  --help, --version  this text; the version line\n";

using trueaxis::core::Vec3;

double best_ns(const std::vector<double>& a, const std::vector<double>& c, bool inverse,
               const trueaxis::linuxcnc::CradleKinematics& kins, double& sink) {
  double best = 1e30;
  for (int run = 0; run < 7; ++run) {
    Vec3 out = Vec3::Zero();
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < a.size(); ++i) {
      const Vec3 in(100.0 + out.x() * 1e-9, 20.0, 30.0);
      const bool ok = inverse ? kins.inverse(in, a[i], c[i], out) : kins.forward(in, a[i], c[i], out);
      sink += ok ? 1.0 : 0.0;
    }
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(a.size()));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_kins_host", kHelp)) return 0;
  namespace core = trueaxis::core;
  namespace sim = trueaxis::sim;
  const sim::CradleMachine machine(sim::FaceConfig{}, sim::realistic_errors());
  const sim::CalibrationBall ball;
  std::vector<core::RigiditySample> samples;
  for (int a = -90; a <= 90; a += 30) {
    for (int c = 0; c < 360; c += 10) samples.push_back({double(a), double(c), ball.centre_mm(machine.machine_T_table(a, c))});
  }
  static core::RigidityBuilder builder;
  if (core::build_rigidity_table(samples.data(), samples.size(), core::RigidityOptions{}, builder) != core::Status::kOk) {
    std::fprintf(stderr, "bench_kins_host: the table did not build\n");
    return 1;
  }
  std::vector<std::uint8_t> record(core::kRigidityTableMaxBytes), file(record.size() + trueaxis::macros::kRecordFileOverhead);
  const std::size_t n = core::encode_rigidity_table(builder.table(), record.data(), record.size());
  file.resize(trueaxis::macros::encode_record_file(trueaxis::macros::RigidityTableRecord::kRecord.key, record.data(), n,
                                                   file.data(), file.size()));
  trueaxis::linuxcnc::CradleKinematics calibrated, ideal;
  if (!calibrated.load_table(file.data(), file.size()).ok) {
    std::fprintf(stderr, "bench_kins_host: the table file did not load\n");
    return 1;
  }
  std::vector<double> a(200000), c(200000);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = -95.0 + 190.0 * static_cast<double>(i % 997) / 996.0;
    c[i] = 0.37 * static_cast<double>(i % 1973);
  }
  double sink = 0.0;
  const double inverse_ns = best_ns(a, c, true, calibrated, sink);
  const double forward_ns = best_ns(a, c, false, calibrated, sink);
  const double ideal_inverse_ns = best_ns(a, c, true, ideal, sink);
  const double ideal_forward_ns = best_ns(a, c, false, ideal, sink);
  std::printf("calibrated (7 poses, not-a-knot cubic): inverse %.0f ns, forward %.0f ns; ideal: inverse %.0f ns, "
              "forward %.0f ns (%.0f calls, every one succeeded: %s)\n",
              inverse_ns, forward_ns, ideal_inverse_ns, ideal_forward_ns, sink,
              sink == 4.0 * 7.0 * static_cast<double>(a.size()) ? "yes" : "NO");
  return 0;
}
