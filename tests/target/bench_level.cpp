// Bench: Cortex-M7 instructions of one run of macro 9810 (three-point level),
// and of 9816 (the re-probe after leveling, judged as a check) on a session of
// the same three points, measured with SysTick under QEMU's instruction counting.
//
// Run (the custom target run_bench_level does exactly this):
//   qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none
//       -semihosting -no-reboot -icount shift=6 -kernel bench_level_target
// Under -icount shift=6 every instruction takes 64 ns of virtual time and SysTick
// runs at the 25 MHz CPU clock: 1.6 ticks per instruction (systick_clock.hpp).
// Without -icount the numbers are host-speed noise; the bench says so by
// checking a calibration loop of known length first.
//
// What is timed: Module::step() running the pending 9810 (reading G57..G59 and
// the arguments, level_face, staging and publishing the results, clearing the
// arguments), the median of kRuns runs, minus the median cost of an empty
// measurement; and, for comparison, core::level_face alone on the same face.
#include <cstdint>

#include "bench_module.hpp"
#include "bench_support.hpp"
#include "fixtures.hpp"
#include "trueaxis/core/leveling.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/hal/mps2/semihosting.hpp"
#include "trueaxis/hal/mps2/systick_clock.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace mps2 = trueaxis::hal::mps2;
namespace var = trueaxis::macros::var;
using trueaxis::bench::median;
using trueaxis::bench::print;
using trueaxis::bench::ticks_to_instructions;
using trueaxis::macros::AccessFault;

constexpr int kRuns = 9;

bool prepare_run(trueaxis::macros::Module& module, const trueaxis::test::Face& f) {
  const double ijk[3] = {f.hint_machine.x(), f.hint_machine.y(), f.hint_machine.z()};
  const double cmd = 9810.0;
  return module.write(var::kArgA, 1, &f.probe_a_deg) == AccessFault::kNone &&
         module.write(var::kArgC, 1, &f.probe_c_deg) == AccessFault::kNone &&
         module.write(var::kArgI, 3, ijk) == AccessFault::kNone &&
         module.write(var::kCmd, 1, &cmd) == AccessFault::kNone;
}

bool load_points(trueaxis::macros::Module& module, const trueaxis::test::Face& f) {
  const std::uint16_t first[3] = {var::kG57, var::kG58, var::kG59};
  for (int k = 0; k < 3; ++k) {
    const double xyz[3] = {f.points_machine[k].x(), f.points_machine[k].y(), f.points_machine[k].z()};
    if (module.write(first[k], 3, xyz) != AccessFault::kNone) return false;
  }
  return true;
}

}  // namespace

int main() {
  trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  mps2::SysTickClock clock;
  // Static, as in the firmware image: the module with all four methods (108.8
  // KiB) is larger than the image's 64 KiB stack reservation.
  static trueaxis::macros::Module module(storage, clock);
  static_cast<void>(module.start());

  std::uint64_t samples[kRuns];
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) return 6;

  trueaxis::test::SplitMix64 rng(0x5EED'0005);
  const trueaxis::test::Face face = trueaxis::test::random_face(rng);
  if (!load_points(module, face)) return 2;
  for (std::uint64_t& s : samples) {
    if (!prepare_run(module, face)) return 3;
    const std::uint64_t t0 = clock.ticks();
    module.step();
    const std::uint64_t t1 = clock.ticks();
    if (module.value(var::kStatus) != static_cast<double>(trueaxis::macros::MacroState::kDone)) return 4;
    s = t1 - t0 - overhead;
  }
  const std::uint64_t ticks = median(samples);
  print("macro 9810: ", ticks_to_instructions(ticks), " instructions");
  print(" (median of 9 runs, ", ticks, " SysTick ticks at 1.6 per instruction)\n");

  trueaxis::core::LevelInput in;
  in.points_mm = face.points_machine;
  in.count = 3;
  in.probe_pose = {face.probe_a_deg, face.probe_c_deg};
  in.current_pose = in.probe_pose;
  in.outward_hint_machine = face.hint_machine;
  trueaxis::core::LevelConfig cfg;
  cfg.a_sign = module.value(var::kASign);
  cfg.c_sign = module.value(var::kCSign);
  for (std::uint64_t& s : samples) {
    const std::uint64_t t0 = clock.ticks();
    const auto r = trueaxis::core::level_face(in, cfg);
    const std::uint64_t t1 = clock.ticks();
    if (!r.ok()) return 5;
    s = t1 - t0 - overhead;
  }
  print("core::level_face alone: ", ticks_to_instructions(median(samples)), " instructions\n");

  // 9816: the session (9812, then 9813 a point) holds the face's three
  // points; the check levels through them and judges the tilt against #509.
  std::uint64_t longest = 0, steps = 0;
  bool ok = trueaxis::bench::run(module, clock, overhead, 9812, longest, steps);
  for (int k = 0; k < 3 && ok; ++k) {
    const double xyz[3] = {face.points_machine[k].x(), face.points_machine[k].y(), face.points_machine[k].z()};
    ok = trueaxis::bench::write_n(module, var::kArgX, 3, xyz) && trueaxis::bench::run(module, clock, overhead, 9813, longest, steps);
  }
  const double ijk[3] = {face.hint_machine.x(), face.hint_machine.y(), face.hint_machine.z()};
  ok = ok && trueaxis::bench::write_n(module, var::kArgA, 1, &face.probe_a_deg) &&
       trueaxis::bench::write_n(module, var::kArgC, 1, &face.probe_c_deg) &&
       trueaxis::bench::write_n(module, var::kArgI, 3, ijk) &&
       trueaxis::bench::run(module, clock, overhead, 9816, longest, steps);
  if (!ok) return 7;
  print("macro 9816 (3 points): ", steps, " step, ");
  print("", longest, " instructions\n");
  return 0;
}
