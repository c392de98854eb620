// Bench and bound check of M3 on the Cortex-M7 (QEMU mps2-an500, -icount
// shift=6; bench_support.hpp): the instructions of the real-time compensation
// query (rigidity::compensation_rad, the direct call) for each blend, which the
// issue bounds at 1,500, and the longest step of the table build (9832) and of
// the query macro (9833) and of leveling on the calibrated axes (9810 and 9811
// with #508 = 1, Newton on the table), against Module::kStepBoundInstructions.
// It exits non-zero when a figure is over its bound; ctest runs it as
// rigidity_bounds_target.
//
// The samples come from a cradle whose C table tilts with A (a rotation of up
// to 30" that grows as sin A about X), ball 200 mm out. The query is timed on
// the largest table there is (16 poses, core::kMaxAPoses, 12 C each): its
// bracket search is linear, so the figure is the largest over an A in every
// bracket, at the first and the last pose, and just inside the last.
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "bench_module.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace core = trueaxis::core;
namespace mps2 = trueaxis::hal::mps2;
namespace var = trueaxis::macros::var;
using trueaxis::bench::print;
using trueaxis::bench::run;
using trueaxis::bench::ticks_to_instructions;
using trueaxis::bench::write_n;

constexpr std::uint32_t kQueryBound = 1500;
constexpr int kMaxPoses = static_cast<int>(core::kMaxAPoses);

core::Vec3 ball(double a_deg, double c_deg) {
  const double a = core::deg_to_rad(a_deg);
  const double droop = core::deg_to_rad(30.0 / 3600.0) * std::sin(a);
  const Eigen::AngleAxisd ra(a, core::Vec3::UnitX());
  const Eigen::AngleAxisd rd(droop, core::Vec3::UnitX());
  const Eigen::AngleAxisd rc(core::deg_to_rad(c_deg), core::Vec3::UnitZ());
  return ra * (rd * (rc * core::Vec3(200.0, 0.0, 50.0)));
}

}  // namespace

int main() {
  trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  mps2::SysTickClock clock;
  static m::Module module(storage, clock);
  if (module.start() != core::Status::kOk) return 2;
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) return 3;

  // The densest poses first (36 C each, rigidity_map.hpp kMaxPoseSamples: the
  // step bound must hold for them; 14 x 36 = 504 of the 512 samples), then the production shape that stays stored.
  struct Shape {
    const char* name;
    int poses, c_positions;
    double a_first, a_step;
  };
  const Shape shapes[2] = {{"macro 9832 (14 poses x 36 C): ", 14, 36, -84.0, 12.0},
                           {"macro 9832 (16 poses x 12 C): ", 16, 12, -84.0, 12.0}};
  std::uint64_t longest = 0, steps = 0;
  bool within = true;
  for (const Shape& shape : shapes) {
    bool ok = run(module, clock, overhead, 9830, longest, steps);
    std::uint64_t worst_add = 0;  // 9831 compares a sample with every one before it (duplicate_sample)
    for (int i = 0; i < shape.poses && ok; ++i) {
      for (int k = 0; k < shape.c_positions && ok; ++k) {
        const double a = shape.a_first + shape.a_step * i;
        const double c = 360.0 / shape.c_positions * k;
        const core::Vec3 p = ball(a, c);
        const double ac[3] = {a, 0.0, c};
        const double xyz[3] = {p.x(), p.y(), p.z()};
        ok = write_n(module, var::kArgA, 3, ac) && write_n(module, var::kArgX, 3, xyz) &&
             run(module, clock, overhead, 9831, longest, steps);
        worst_add = longest > worst_add ? longest : worst_add;
      }
    }
    print("macro 9831: at most ", worst_add, " instructions");
    print(" (the last of ", static_cast<std::uint64_t>(shape.poses * shape.c_positions), " samples)\n");
    within = within && worst_add <= m::Module::kStepBoundInstructions;
    const double unlock = m::kUnlockCode;
    const double store = 1.0;
    ok = ok && write_n(module, var::kUnlock, 1, &unlock) && write_n(module, var::kArgR, 1, &store) &&
         run(module, clock, overhead, 9832, longest, steps);
    if (!ok) {
      mps2::console_write("FAILED: the table could not be built\n");
      return 4;
    }
    print(shape.name, steps, " steps, longest ");
    print("", longest, " instructions\n");
    within = within && longest <= m::Module::kStepBoundInstructions;
  }

  // The run measured computed the right table (the bench's own sanity; the
  // contracts are tests/portable's): the droop is a turn
  // about the A axis, which M3's definitions count as A positioning error, so
  // pose 16 (A = 96) must read a_error = 30" sin 96 deg and a zero rotation vector.
  const double pose_args[2] = {16.0, 1.0};  // Q = pose 16, R = 1: the stored table
  bool ok = write_n(module, var::kArgQ, 2, pose_args) && run(module, clock, overhead, 9834, longest, steps);
  const double a_error = module.value(var::kPoseAError);
  const double rigidity = module.value(var::kPoseRigidity);
  const double expected = 30.0 * std::sin(core::deg_to_rad(96.0));
  print("pose A = 96: A positioning error (micro-arcsec) ", static_cast<std::uint64_t>(a_error * 1e6 + 0.5),
        ", rigidity (micro-arcsec) ");
  print("", static_cast<std::uint64_t>(rigidity * 1e6 + 0.5), ", expected ");
  print("", static_cast<std::uint64_t>(expected * 1e6 + 0.5), " and 0\n");
  within = within && ok && std::fabs(a_error - expected) < 1e-6 && rigidity < 1e-6;
  const double a = 47.5;
  const double query[3] = {a, 0.0, 0.0};  // A, then Q (#17) and R (#18) below
  ok = write_n(module, var::kArgA, 1, query) && run(module, clock, overhead, 9833, longest, steps);
  print("macro 9833 (linear): ", steps, " step, ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;
  // The check (9836) of the 16-pose build against the same table stored: 30
  // figures, each found among the poses, in one step.
  ok = run(module, clock, overhead, 9836, longest, steps) && module.value(var::kCheckFigures) == 30.0 &&
       module.value(var::kCheckVerdict) == 0.0;
  print("macro 9836 (16 poses, 30 figures): ", steps, " step, ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;
  // The measuring log's append is a step of its own (module.hpp contract 9):
  // its worst case is the full ring, 32 entries read, shifted and saved again.
  for (int k = 0; k < 40 && ok; ++k) ok = run(module, clock, overhead, 9836, longest, steps);
  std::uint64_t append_at = 0;
  ok = ok && module.value(var::kLogCount) == 32.0 && run(module, clock, overhead, 9836, longest, steps, &append_at);
  print("macro 9836 with the log full (32 entries): ", steps, " steps, the append (step ");
  print("", append_at, ") ");
  print("", longest, " instructions\n");
  within = within && ok && append_at == 2 && longest <= m::Module::kStepBoundInstructions;

  // A in the middle of every bracket, on the first and the last pose, and one
  // ulp inside the last: the largest of each A's median.
  double as[kMaxPoses + 3];
  std::size_t n_as = 0;
  for (int k = 0; k + 1 < kMaxPoses; ++k) as[n_as++] = -78.0 + 12.0 * k;
  as[n_as++] = -84.0;
  as[n_as++] = 96.0;
  as[n_as++] = std::nextafter(96.0, 0.0);
  const char* names[4] = {"linear", "geodesic", "cubic", "cubic not-a-knot"};
  for (int b = 0; b < 4; ++b) {
    std::uint64_t worst = 0;
    for (std::size_t i = 0; i < n_as; ++i) {
      std::uint64_t samples[5];
      for (std::uint64_t& s : samples) {
        const std::uint64_t t0 = clock.ticks();
        const auto r = m::rigidity::compensation_rad(module.state<m::rigidity::Method>(), as[i], static_cast<core::Blend>(b), false);
        const std::uint64_t t1 = clock.ticks();
        if (!r.ok()) return 5;
        s = t1 - t0 - overhead;
      }
      const std::uint64_t n = ticks_to_instructions(trueaxis::bench::median(samples));
      worst = n > worst ? n : worst;
    }
    print("compensation query, ", static_cast<std::uint64_t>(b), " ");
    mps2::console_write(names[b]);
    print(": ", worst, " instructions at most over A (bound 1500)\n");
    within = within && worst <= kQueryBound;
  }

  // Leveling on the calibrated axes: a face tilted 40 deg, probed at A = C = 0.
  const double on = 1.0;
  ok = write_n(module, var::kLevelAxes, 1, &on);
  const core::Vec3 n(std::sin(0.7) * std::cos(0.5), std::sin(0.7) * std::sin(0.5), std::cos(0.7));
  const core::Vec3 u = n.unitOrthogonal();
  const core::Vec3 w = n.cross(u);
  core::Vec3 points[core::kMaxPlanePoints];
  for (std::size_t k = 0; k < core::kMaxPlanePoints; ++k) {
    const double t = 2.0 * core::kPi * static_cast<double>(k) / core::kMaxPlanePoints;
    const double r = k < 3 ? 60.0 : 20.0 + static_cast<double>(k);
    points[k] = core::Vec3(0.0, 0.0, 80.0) + r * (std::cos(t) * u + std::sin(t) * w);
  }
  const std::uint16_t targets[3] = {var::kG57, var::kG58, var::kG59};
  for (int k = 0; k < 3 && ok; ++k) {
    const double xyz[3] = {points[k].x(), points[k].y(), points[k].z()};
    ok = write_n(module, targets[k], 3, xyz);
  }
  ok = ok && run(module, clock, overhead, 9810, longest, steps) && module.value(var::kLevelAxesUsed) == 1.0;
  print("macro 9810 on the calibrated axes: ", steps, " step(s), longest ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;
  for (std::size_t k = 0; k < core::kMaxPlanePoints && ok; ++k) {
    const double xyz[3] = {points[k].x(), points[k].y(), points[k].z()};
    ok = write_n(module, static_cast<std::uint16_t>(var::kPointList + 3 * k), 3, xyz);
  }
  const double q = static_cast<double>(core::kMaxPlanePoints);
  ok = ok && write_n(module, var::kArgQ, 1, &q) && run(module, clock, overhead, 9811, longest, steps) &&
       module.value(var::kLevelAxesUsed) == 1.0;
  print("macro 9811 (32 points) on the calibrated axes: ", steps, " step(s), longest ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;
  mps2::console_write(within ? "all within their bounds\n" : "FAILED: a figure over its bound\n");
  return within ? 0 : 1;
}
