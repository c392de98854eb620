// The smallest complete firmware: the module over the board's storage and clock,
// every macro of its method set linked in (tests/target/CMakeLists.txt builds
// one image per set). Built to measure the footprint (flash, RAM; the size
// report reads the static `module`'s size) and run as a boot test: it starts,
// runs macro 9810 once on a fixed face when levelling is built (else macro 9812's
// absence: unknown_macro) and checks #9001 and #9002. The objects main owns are
// static, so the image's .bss shows all the RAM the module needs besides the
// stack.
#include <cstdint>

#include "trueaxis/hal/mps2/board_nv_storage.hpp"
#include "trueaxis/hal/mps2/semihosting.hpp"
#include "trueaxis/hal/mps2/systick_clock.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

static_assert(trueaxis::hal::mps2::kBoardNvBytes >= trueaxis::macros::kRequiredStorageBytes,
              "the board's storage must hold every persistent record (macros/records.hpp)");

extern "C" std::uint32_t __stack_bottom__[];  // toolchain/mps2-an500.ld
extern "C" std::uint32_t __stack_top__[];

namespace {

constexpr std::uint32_t kStackPaint = 0x5AC4'5AC4;

// Fills the unused stack below the caller's frame with kStackPaint.
__attribute__((noinline)) void paint_stack() {
  std::uintptr_t sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  const std::uintptr_t limit = sp - 256;  // keep clear of this frame
  for (std::uint32_t* p = __stack_bottom__; reinterpret_cast<std::uintptr_t>(p) < limit; ++p) *p = kStackPaint;
}

// Bytes of stack ever used: from the top down to the lowest overwritten paint.
std::uint64_t stack_used_bytes() {
  const std::uint32_t* p = __stack_bottom__;
  while (p < __stack_top__ && *p == kStackPaint) ++p;
  return static_cast<std::uint64_t>(__stack_top__ - p) * sizeof(std::uint32_t);
}

namespace var = trueaxis::macros::var;

// Levelling is built into this image's module.
constexpr bool kLevelBuilt = trueaxis::macros::is_macro(9810);

bool load_face(trueaxis::macros::Module& module) {
  const double g57[3] = {0.0, 0.0, 0.0};
  const double g58[3] = {100.0, 0.0, 0.0};
  const double g59[3] = {0.0, 86.602540378443865, 50.0};
  const double cmd = kLevelBuilt ? 9810.0 : 9812.0;
  using trueaxis::macros::AccessFault;
  return module.write(var::kG57, 3, g57) == AccessFault::kNone &&
         module.write(var::kG58, 3, g58) == AccessFault::kNone &&
         module.write(var::kG59, 3, g59) == AccessFault::kNone &&
         module.write(var::kCmd, 1, &cmd) == AccessFault::kNone;
}

}  // namespace

int main() {
  paint_stack();
  static trueaxis::hal::RamNvStorage storage = trueaxis::hal::mps2::board_nv_storage();
  static trueaxis::hal::mps2::SysTickClock clock;
  static trueaxis::macros::Module module(storage, clock);
  static_cast<void>(module.start());
  if (!load_face(module)) return 2;
  while (module.busy()) module.step();
  using trueaxis::macros::MacroState;
  const double error = module.value(var::kError);
  const bool done = kLevelBuilt ? module.value(var::kStatus) == static_cast<double>(MacroState::kDone)
                                : module.value(var::kStatus) == static_cast<double>(MacroState::kError) &&
                                      error == static_cast<double>(trueaxis::core::Status::kUnknownMacro);
  if (kLevelBuilt) {
    trueaxis::hal::mps2::console_write(done ? "firmware: macro 9810 done" : "firmware: macro 9810 failed");
  } else {
    trueaxis::hal::mps2::console_write(done ? "firmware: macro 9812 (not built) is unknown_macro"
                                            : "firmware: macro 9812 did not answer unknown_macro");
  }
  trueaxis::hal::mps2::console_write(", stack used ");
  trueaxis::hal::mps2::console_write_uint(stack_used_bytes());
  trueaxis::hal::mps2::console_write(" bytes\n");
  return done ? 0 : 1;
}
