// Bench and bound check of M4 on the Cortex-M7 (QEMU mps2-an500, -icount
// shift=6; bench_support.hpp): the identification (macro 9842, heap-free,
// stored through the keyed store) with its longest step against
// Module::kStepBoundInstructions, the sample macro 9841 at its worst (an angle
// inserted in front of 359 others), and the correction: macro 9843 and the
// direct call spindle::tool_tip_correction, which the issue bounds at 1,500
// instructions. It exits non-zero when a figure is over its bound or a value is
// wrong; ctest runs it as spindle_bounds_target.
//
// The session is the module's worst case: both balls at all 360 distinct
// angles the bins hold (1 deg steps), two revolutions, ball 2 streamed in
// decreasing angle so every new bin goes in front. The samples come from the
// model (core::spindle_ball_mm) at known parameters plus a uniform +-26 nm noise
// (15 nm RMS, fixed seed).
#include <cmath>
#include <cstdint>

#include "bench_module.hpp"
#include "split_mix64.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"

namespace {

namespace m = trueaxis::macros;
namespace sp = trueaxis::macros::spindle;
namespace core = trueaxis::core;
namespace mps2 = trueaxis::hal::mps2;
namespace var = trueaxis::macros::var;
using trueaxis::bench::print;
using trueaxis::bench::run;
using trueaxis::bench::ticks_to_instructions;
using trueaxis::bench::write_n;

constexpr std::uint64_t kCorrectionBound = 1500;
constexpr double kArcsec = core::kPi / (180.0 * 3600.0);
const core::SpindleGeometry kGeometry{350.0, {50.0, 150.0}};

core::SpindleParams truth() {
  core::SpindleParams p;
  p << 0.0123, -0.0087, 399.998, -20 * kArcsec, 35 * kArcsec, 0.0023, 0.0014, -19.9 * kArcsec, 11.2 * kArcsec;
  return p;
}

}  // namespace

int main() {
  trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  mps2::SysTickClock clock;
  static m::Module module(storage, clock);
  if (module.start() != core::Status::kOk) return 2;
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) return 3;

  std::uint64_t longest = 0, steps = 0, worst_add = 0;
  bool ok = run(module, clock, overhead, 9840, longest, steps);
  trueaxis::test::SplitMix64 rng(20261124);
  const core::SpindleParams p = truth();
  std::uint64_t count = 0;
  for (int rev = 0; rev < 2 && ok; ++rev) {
    for (int ball = 1; ball <= 2 && ok; ++ball) {
      for (int i = 0; i < 360 && ok; ++i) {
        const int deg = ball == 1 ? i : 359 - i;
        const core::Vec3 c = core::spindle_ball_mm(p, kGeometry, ball, core::deg_to_rad(deg));
        const double noise = 26e-6;
        const double args[5] = {static_cast<double>(deg + 360 * rev), static_cast<double>(ball),
                                c.x() + rng.uniform(-noise, noise), c.y() + rng.uniform(-noise, noise),
                                c.z() + rng.uniform(-noise, noise)};
        ok = write_n(module, var::kArgS, 1, &args[0]) && write_n(module, var::kArgT, 1, &args[1]) &&
             write_n(module, var::kArgX, 3, &args[2]) && run(module, clock, overhead, 9841, longest, steps);
        worst_add = longest > worst_add ? longest : worst_add;
        ++count;
      }
    }
  }
  print("session: ", count, " samples streamed by 9841, ");
  print("", static_cast<std::uint64_t>(module.value(var::kSpindleSessionAngles2)), " angles per ball; ");
  print("9841 at most ", worst_add, " instructions\n");

  const double args[5] = {m::kUnlockCode, 1.0, kGeometry.gauge_mm, kGeometry.ball_mm[0], kGeometry.ball_mm[1]};
  ok = ok && write_n(module, var::kUnlock, 1, &args[0]) && write_n(module, var::kArgR, 1, &args[1]) &&
       write_n(module, var::kArgD, 1, &args[2]) && write_n(module, var::kArgU, 1, &args[3]) &&
       write_n(module, var::kArgV, 1, &args[4]);
  const std::uint64_t c0 = clock.ticks();
  std::uint64_t longest_at = 0;
  ok = ok && run(module, clock, overhead, 9842, longest, steps, &longest_at);
  const std::uint64_t total = ticks_to_instructions(clock.ticks() - c0);
  if (!ok) {
    print("FAILED: the model could not be identified, error ",
          static_cast<std::uint64_t>(module.value(var::kError)), "\n");
    return 4;
  }
  print("macro 9842 (720 angles x 2 revolutions, stored): ", steps, " steps, ");
  print("", static_cast<std::uint64_t>(module.value(var::kSpindleEvaluations)), " evaluations, longest ");
  print("", longest, " instructions (step ");
  print("", longest_at, "), ");
  print("", total, " in all\n");
  bool within = longest <= m::Module::kStepBoundInstructions && worst_add <= m::Module::kStepBoundInstructions;

  // The run measured computed the right model (the bench's own sanity, at the
  // module's capacities; the contracts are tests/portable's): the tool tip at 250 mm, not a
  // ball depth, against the one the true parameters give.
  double worst_nm = 0.0;
  const core::SpindleAxes axes = core::spindle_axes(p);
  for (int deg = 0; deg < 360; deg += 30) {
    const auto r = sp::tool_tip_correction(module.state<m::spindle::Method>(), deg, 250.0);
    const auto t = core::spindle_correction(axes, kGeometry.gauge_mm, 250.0, core::deg_to_rad(deg));
    if (!r.ok() || !t.ok()) return 5;
    worst_nm = std::fmax(worst_nm, (r.value().tip_error_mm - t.value().tip_error_mm).norm() * 1e6);
  }
  print("tool tip at 250 mm against the truth: worst ", static_cast<std::uint64_t>(worst_nm + 0.5),
        " nm (limit 100)\n");
  within = within && worst_nm < 100.0;

  const double query[2] = {123.4, 100.0};
  ok = write_n(module, var::kArgS, 1, &query[0]) && write_n(module, var::kArgZ, 1, &query[1]) &&
       run(module, clock, overhead, 9843, longest, steps);
  print("macro 9843: ", steps, " step, ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;

  std::uint64_t worst = 0;
  for (int deg = -720; deg <= 720; deg += 45) {
    std::uint64_t samples[5];
    for (std::uint64_t& sample : samples) {
      const std::uint64_t t0 = clock.ticks();
      const auto r = sp::tool_tip_correction(module.state<m::spindle::Method>(), deg + 0.3, 100.0);
      const std::uint64_t t1 = clock.ticks();
      if (!r.ok()) return 6;
      sample = t1 - t0 - overhead;
    }
    const std::uint64_t n = ticks_to_instructions(trueaxis::bench::median(samples));
    worst = n > worst ? n : worst;
  }
  print("correction (direct call spindle::tool_tip_correction): ", worst,
        " instructions at most over -720..720 deg (bound 1500)\n");
  within = within && worst <= kCorrectionBound;
  mps2::console_write(within ? "all within their bounds\n" : "FAILED: a figure over its bound\n");
  return within ? 0 : 1;
}
