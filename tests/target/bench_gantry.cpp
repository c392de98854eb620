// Bench and bound check of M2 on the Cortex-M7 (QEMU mps2-an500, -icount
// shift=6; bench_support.hpp): the frame computation (macro 9823, heap-free,
// stored through the keyed store) with its longest step against
// Module::kStepBoundInstructions, and the point conversion: macro 9825 and the
// direct call gantry::sub_point_mm, which the issue bounds at 200 instructions.
// It exits non-zero when a figure is over its bound or a value is wrong; ctest
// runs it as gantry_bounds_target.
//
// The machine is built so that its frames are known: the bed is z = 0, the side
// faces x = 0 and y = 0, the gantry runs along +X, so the global frame is the
// tracker's; sub-machine N has ideal axes, its wrist centre at W_N, its C axis
// vertical and its A axis along X through W_N, the tool pointing down and a
// swing of 300 mm, so O_N = W_N - (0, 0, 300) and a global point p is p - O_N in
// its frame. The points carry a uniform +-10 um noise (fixed seed), so every fit
// has residuals to take its sigma from. Sub-machine 1 and the machine's own
// groups are at the module's capacities (gantry_map.hpp), the step bound's worst
// case; sub-machines 2..4 are of the simulator's plan (3 passes of 15, circles
// of 24): 2,029 of the session's 2,048 points.
//
// Last, the stack: 9823 once more (not stored), every step() called with the
// stack below it painted, and the direct call sub_point_mm the same way; it
// prints the most either wrote ("stack measured: ROOT N bytes", the roots of
// tools/stack_report.py), which ctest's stack_measured_gantry holds against the
// analysis (tests/target/stack_cross_check.py: analysed >= measured).
#include <cmath>
#include <cstdint>

#include "bench_module.hpp"
#include "split_mix64.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"

extern "C" std::uint32_t __stack_bottom__[];  // toolchain/mps2-an500.ld

namespace {

namespace m = trueaxis::macros;
namespace g = trueaxis::macros::gantry;
namespace core = trueaxis::core;
namespace mps2 = trueaxis::hal::mps2;
namespace var = trueaxis::macros::var;
using trueaxis::bench::print;
using trueaxis::bench::run;
using trueaxis::bench::ticks_to_instructions;
using trueaxis::bench::write_n;

constexpr std::uint64_t kConvertBound = 200;
constexpr double kSwingMm = 300.0;
constexpr int kSubMachines = 4;

core::Vec3 wrist(int id) { return core::Vec3(1000.0 * id, 1500.0, 1800.0); }

class Streamer {
 public:
  Streamer(m::Module& mod, const mps2::SysTickClock& clock, std::uint64_t overhead)
      : mod_(mod), clock_(clock), overhead_(overhead) {}

  // Adds p (plus noise) to group (T, Q, D) through 9821.
  void add(int t, g::GroupKind q, int d, const core::Vec3& p) {
    const double tqd[3] = {static_cast<double>(t), static_cast<double>(q), static_cast<double>(d)};
    const core::Vec3 n(noise(), noise(), noise());
    const double xyz[3] = {p.x() + n.x(), p.y() + n.y(), p.z() + n.z()};
    std::uint64_t longest = 0, steps = 0;
    ok_ = ok_ && write_n(mod_, var::kArgD, 1, &tqd[2]) && write_n(mod_, var::kArgQ, 1, &tqd[1]) &&
          write_n(mod_, var::kArgT, 1, &tqd[0]) && write_n(mod_, var::kArgX, 3, xyz) &&
          run(mod_, clock_, overhead_, 9821, longest, steps);
    worst_ = longest > worst_ ? longest : worst_;
    ++count_;
  }
  // The longest 9821 (it compares a point with its group's, duplicate_sample).
  std::uint64_t worst() const { return worst_; }
  bool ok() const { return ok_; }
  std::uint64_t count() const { return count_; }

 private:
  double noise() { return rng_.uniform(-0.01, 0.01); }

  m::Module& mod_;
  const mps2::SysTickClock& clock_;
  std::uint64_t overhead_;
  trueaxis::test::SplitMix64 rng_{20261123};
  bool ok_ = true;
  std::uint64_t count_ = 0;
  std::uint64_t worst_ = 0;
};

// Stack painting: a window below the caller's stack pointer is filled with a
// pattern before the call and searched for the lowest overwritten word after
// it. Both run in the caller's frame, so the figure is the call's alone; a
// figure of kStackWindow means the window was too small (or an exception came
// at the deepest point: its frame is in the figure).
constexpr std::uint32_t kStackPaint = 0x5AC4'5AC4;
constexpr std::uintptr_t kStackWindow = 16 * 1024;

__attribute__((always_inline)) inline void paint_below(std::uintptr_t sp) {
  for (auto* p = reinterpret_cast<volatile std::uint32_t*>(sp - kStackWindow);
       p < reinterpret_cast<volatile std::uint32_t*>(sp); ++p) {
    *p = kStackPaint;
  }
}

__attribute__((always_inline)) inline std::uint64_t written_below(std::uintptr_t sp) {
  auto* p = reinterpret_cast<volatile std::uint32_t*>(sp - kStackWindow);
  while (p < reinterpret_cast<volatile std::uint32_t*>(sp) && *p == kStackPaint) ++p;
  return sp - reinterpret_cast<std::uintptr_t>(p);
}

// The stack one Module::step() used.
__attribute__((noinline)) std::uint64_t stack_of_step(m::Module& module) {
  std::uintptr_t sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  if (sp - kStackWindow < reinterpret_cast<std::uintptr_t>(__stack_bottom__)) return kStackWindow;
  paint_below(sp);
  module.step();
  return written_below(sp);
}

// The stack one gantry::sub_point_mm used.
__attribute__((noinline)) std::uint64_t stack_of_convert(const m::Module& module, int id, const core::Vec3& p) {
  std::uintptr_t sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  if (sp - kStackWindow < reinterpret_cast<std::uintptr_t>(__stack_bottom__)) return kStackWindow;
  paint_below(sp);
  const auto r = g::sub_point_mm(module.state<m::gantry::Method>(), id, p);
  const std::uint64_t used = written_below(sp);
  return r.ok() ? used : kStackWindow;
}

void machine_groups(Streamer& s) {
  const double pads[4][2] = {{60, 60}, {5860, 60}, {5860, 2860}, {60, 2860}};
  for (const auto& pad : pads) {  // 4 x 32 = 128 points
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 4; ++j) s.add(0, g::GroupKind::kBed, 0, core::Vec3(pad[0] + 10 * i, pad[1] + 20 * j, 0));
    }
  }
  for (int i = 0; i < 16; ++i) {  // 16 x 8 = 128 each
    for (int j = 0; j < 8; ++j) s.add(0, g::GroupKind::kSide1, 0, core::Vec3(0, 10 + 5 * i, -10 - 6 * j));
  }
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 8; ++j) s.add(0, g::GroupKind::kSide2, 0, core::Vec3(10 + 5 * i, 0, -10 - 6 * j));
  }
  for (int k = 1; k <= g::kMaxPasses; ++k) {
    for (int i = 0; i < g::kMaxPassPoints; ++i) {
      s.add(0, g::GroupKind::kGantryPass, k, core::Vec3(100 + 90.0 * i, 1500, 2300));
    }
  }
}

void sub_groups(Streamer& s, int id, int passes, int pass_points, int circle_points) {
  const core::Vec3 w = wrist(id);
  const double strokes[3] = {800, 600, 300};  // x longest: the master axis
  const g::GroupKind kinds[3] = {g::GroupKind::kXPass, g::GroupKind::kYPass, g::GroupKind::kZPass};
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 1; k <= passes; ++k) {
      for (int i = 0; i < pass_points; ++i) {
        const double t = -0.5 * strokes[axis] + strokes[axis] * i / (pass_points - 1);
        s.add(id, kinds[axis], k, w + t * core::Vec3::Unit(axis));
      }
    }
  }
  for (int i = 0; i < circle_points; ++i) {  // C: 0..345 deg about the vertical through W
    const double th = core::deg_to_rad(345.0 * i / (circle_points - 1));
    s.add(id, g::GroupKind::kCCircle, 0, w + core::Vec3(120 * std::cos(th), 120 * std::sin(th), -200));
  }
  for (int i = 0; i < circle_points; ++i) {  // A: -90..90 deg about X through W
    const double th = core::deg_to_rad(-90.0 + 180.0 * i / (circle_points - 1));
    s.add(id, g::GroupKind::kACircle, 0, w + core::Vec3(50, 200 * std::sin(th), -200 * std::cos(th)));
  }
}

}  // namespace

int main() {
  trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  mps2::SysTickClock clock;
  static m::Module module(storage, clock);
  if (module.start() != core::Status::kOk) return 2;
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) return 3;

  std::uint64_t longest = 0, steps = 0;
  bool ok = run(module, clock, overhead, 9820, longest, steps);
  Streamer s(module, clock, overhead);
  machine_groups(s);
  sub_groups(s, 1, g::kMaxPasses, g::kMaxPassPoints, g::kMaxCirclePoints);
  for (int id = 2; id <= kSubMachines; ++id) sub_groups(s, id, 3, 15, 24);
  for (int id = 1; id <= kSubMachines && ok; ++id) {
    const double tool[3] = {0.0, 0.0, -1.0};
    const double d = kSwingMm;
    const double t = id;
    ok = write_n(module, var::kArgI, 3, tool) && write_n(module, var::kArgD, 1, &d) &&
         write_n(module, var::kArgT, 1, &t) && run(module, clock, overhead, 9822, longest, steps);
  }
  ok = ok && s.ok();
  print("session: ", s.count(), " points streamed by 9821, ");
  print("at most ", s.worst(), " instructions each\n");
  ok = ok && s.worst() <= m::Module::kStepBoundInstructions;

  const double unlock = m::kUnlockCode;
  const double store = 1.0;
  ok = ok && write_n(module, var::kUnlock, 1, &unlock) && write_n(module, var::kArgR, 1, &store);
  std::uint64_t c0 = clock.ticks();
  std::uint64_t longest_at = 0;
  ok = ok && run(module, clock, overhead, 9823, longest, steps, &longest_at);
  const std::uint64_t total = ticks_to_instructions(clock.ticks() - c0);
  if (!ok || module.value(var::kGantryBuilt) != kSubMachines) {
    print("FAILED: the frames could not be computed, error ", static_cast<std::uint64_t>(module.value(var::kError)),
          "\n");
    return 4;
  }
  print("macro 9823 (4 sub-machines, stored): ", steps, " steps, longest ");
  print("", longest, " instructions (step ");
  print("", longest_at, "), ");
  print("", total, " in all\n");
  bool within = longest <= m::Module::kStepBoundInstructions;

  // The run measured computed the right frames (the bench's own sanity, at the
  // module's capacities; the contracts are tests/portable's): p in sub-machine N's frame is
  // p - O_N to within the noise's effect.
  double worst_mm = 0.0;
  const core::Vec3 p(2500.0, 1200.0, 400.0);
  for (int id = 1; id <= kSubMachines; ++id) {
    const core::Vec3 expected = p - (wrist(id) - core::Vec3(0, 0, kSwingMm));
    const auto r = g::sub_point_mm(module.state<m::gantry::Method>(), id, p);
    if (!r.ok()) return 5;
    worst_mm = std::fmax(worst_mm, (r.value() - expected).norm());
  }
  print("conversion against the construction: worst ", static_cast<std::uint64_t>(worst_mm * 1e6 + 0.5),
        " nm (limit 100000)\n");
  within = within && worst_mm < 0.1;

  const double args[4] = {3.0, p.x(), p.y(), p.z()};
  ok = write_n(module, var::kArgT, 1, &args[0]) && write_n(module, var::kArgX, 3, &args[1]) &&
       run(module, clock, overhead, 9825, longest, steps);
  print("macro 9825: ", steps, " step, ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;
  // The check (9827) of the build against the same frames stored: 8 figures, one step.
  ok = run(module, clock, overhead, 9827, longest, steps) && module.value(var::kCheckFigures) == 2.0 * kSubMachines &&
       module.value(var::kCheckVerdict) == 0.0;
  print("macro 9827 (4 sub-machines, 8 figures): ", steps, " step, ");
  print("", longest, " instructions\n");
  within = within && ok && longest <= m::Module::kStepBoundInstructions;

  std::uint64_t worst = 0;
  for (int id = 1; id <= kSubMachines; ++id) {
    std::uint64_t samples[5];
    for (std::uint64_t& sample : samples) {
      const std::uint64_t t0 = clock.ticks();
      const auto r = g::sub_point_mm(module.state<m::gantry::Method>(), id, p);
      const std::uint64_t t1 = clock.ticks();
      if (!r.ok()) return 6;
      sample = t1 - t0 - overhead;
    }
    const std::uint64_t n = ticks_to_instructions(trueaxis::bench::median(samples));
    worst = n > worst ? n : worst;
  }
  print("point conversion (direct call gantry::sub_point_mm): ", worst, " instructions at most (bound 200)\n");
  within = within && worst <= kConvertBound;

  std::uint64_t step_stack = 0, convert_stack = 0, stack_steps = 0;
  const double compute = 9823.0;
  if (write_n(module, var::kCmd, 1, &compute)) {
    while (module.busy()) {
      const std::uint64_t used = stack_of_step(module);
      step_stack = used > step_stack ? used : step_stack;
      ++stack_steps;
    }
  }
  for (int id = 1; id <= kSubMachines; ++id) {
    const std::uint64_t used = stack_of_convert(module, id, p);
    convert_stack = used > convert_stack ? used : convert_stack;
  }
  const bool measured = module.value(var::kStatus) == static_cast<double>(m::MacroState::kDone) &&
                        step_stack < kStackWindow && convert_stack < kStackWindow;
  print("stack measured: step ", step_stack, " bytes (the most of 9823's ");
  print("", stack_steps, " steps, painted)\n");
  print("stack measured: query:sub_point_mm ", convert_stack, " bytes (painted)\n");
  if (!measured) mps2::console_write("FAILED: the stack could not be measured\n");
  within = within && measured;
  mps2::console_write(within ? "all within their bounds\n" : "FAILED: a figure over its bound\n");
  return within ? 0 : 1;
}
