// Bench and bound check: the longest Module::step() of every macro on the
// Cortex-M7, in instructions (QEMU mps2-an500, -icount shift=6; see
// bench_support.hpp). The module header states the bound
// (Module::kStepBoundInstructions); this program prints each macro's steps and
// longest step and exits non-zero when one is over the bound or the emulator
// does not count instructions. ctest runs it as step_bound_target.
//
// The macros run on the inputs that make them work hardest: 9811 and 9814 on 32
// points (their capacity), 9810 on a random face, and a commit of the largest
// record (the rigidity table's 4096 bytes) through a macro that stages it, since
// a table commit is a step of its own.
#include <cstdint>

#include "bench_support.hpp"
#include "fixtures.hpp"
#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/record_codec.hpp"

namespace {

namespace m = trueaxis::macros;
namespace mps2 = trueaxis::hal::mps2;
namespace var = trueaxis::macros::var;
using trueaxis::bench::print;
using trueaxis::bench::ticks_to_instructions;
using trueaxis::macros::AccessFault;

// Stages the largest record there is, for the commit step.
m::MacroStep stage_largest(m::PlatformContext& ctx) {
  std::uint8_t* bytes = ctx.stage_record(m::RigidityTableRecord::kRecord.key, m::kMaxRecordPayloadBytes);
  if (bytes == nullptr) return m::done(trueaxis::core::Status::kStorageFailure);
  for (std::size_t i = 0; i + 8 <= m::kMaxRecordPayloadBytes; i += 8) m::put_f64(bytes + i, static_cast<double>(i));
  return m::done(trueaxis::core::Status::kOk);
}
constexpr m::OutputInfo kNoOutputs[] = {{100, "none", "", "Nothing."}};
constexpr m::MacroInfo kBenchMacros[] = {
    m::macro<&stage_largest>(9990, "stage_largest", "Stages the largest record.", kNoOutputs)};

struct Worst {
  std::uint64_t steps = 0;
  std::uint64_t longest = 0;
};

// Runs `macro` to the end, timing every step; false when it did not succeed.
bool run(m::Module& module, const mps2::SysTickClock& clock, std::uint64_t overhead, double macro, Worst& w) {
  if (module.write(var::kCmd, 1, &macro) != AccessFault::kNone) return false;
  w = Worst{};
  while (module.busy()) {
    const std::uint64_t t0 = clock.ticks();
    module.step();
    const std::uint64_t t1 = clock.ticks();
    const std::uint64_t n = ticks_to_instructions(t1 - t0 - overhead);
    if (n > w.longest) w.longest = n;
    ++w.steps;
  }
  return module.value(var::kStatus) == static_cast<double>(m::MacroState::kDone);
}

bool report(const char* name, const Worst& w) {
  print(name, w.steps, " step(s), longest ");
  print("", w.longest, " instructions\n");
  return w.longest <= m::Module::kStepBoundInstructions;
}

bool write3(m::Module& module, std::uint16_t first, const trueaxis::core::Vec3& p) {
  const double xyz[3] = {p.x(), p.y(), p.z()};
  return module.write(first, 3, xyz) == AccessFault::kNone;
}

}  // namespace

int main() {
  trueaxis::hal::RamNvStorage storage = mps2::board_nv_storage();
  mps2::SysTickClock clock;
  static m::Module module(storage, clock, kBenchMacros, 1);
  if (module.start() != trueaxis::core::Status::kOk) return 2;
  const std::uint64_t overhead = trueaxis::bench::clock_overhead(clock);
  if (!trueaxis::bench::calibrated(clock, overhead)) return 3;
  print("step bound (module.hpp): ", m::Module::kStepBoundInstructions, " instructions\n");

  trueaxis::test::SplitMix64 rng(0x5EED'0006);
  const trueaxis::test::Face face = trueaxis::test::random_face(rng);
  bool ok = true;
  Worst w;

  ok = ok && write3(module, var::kG57, face.points_machine[0]) && write3(module, var::kG58, face.points_machine[1]) &&
       write3(module, var::kG59, face.points_machine[2]);
  ok = ok && run(module, clock, overhead, 9810, w) && report("macro 9810: ", w);

  // 32 points of one tilted face, into the point list and into the session.
  ok = ok && run(module, clock, overhead, 9812, w) && report("macro 9812: ", w);
  trueaxis::core::Vec3 points[trueaxis::core::kMaxPlanePoints];
  for (std::size_t k = 0; k < trueaxis::core::kMaxPlanePoints; ++k) {
    const double x = 10.0 * static_cast<double>(k % 8);
    const double y = 10.0 * static_cast<double>(k / 8) + static_cast<double>(k % 3);
    points[k] = trueaxis::core::Vec3(x, y, 5.0 + 0.1 * y + 1e-4 * static_cast<double>(k % 5));
    ok = ok && write3(module, var::kArgX, points[k]);
    ok = ok && run(module, clock, overhead, 9813, w) && (k + 1 < trueaxis::core::kMaxPlanePoints || report("macro 9813: ", w));
  }
  ok = ok && run(module, clock, overhead, 9814, w) && report("macro 9814 (32 points): ", w);
  for (std::size_t k = 0; k < trueaxis::core::kMaxPlanePoints; ++k) {
    ok = ok && write3(module, static_cast<std::uint16_t>(var::kPointList + 3 * k), points[k]);
  }
  const double q = 32.0;
  ok = ok && module.write(var::kArgQ, 1, &q) == AccessFault::kNone;
  ok = ok && run(module, clock, overhead, 9811, w) && report("macro 9811 (32 points): ", w);

  const double unlock = m::kUnlockCode;
  ok = ok && module.write(var::kUnlock, 1, &unlock) == AccessFault::kNone;
  ok = ok && run(module, clock, overhead, 9990, w) && report("commit of a 4096-byte table: ", w);

  mps2::console_write(ok ? "all steps within the bound\n" : "FAILED: a step over the bound, or a macro failed\n");
  return ok ? 0 : 1;
}
