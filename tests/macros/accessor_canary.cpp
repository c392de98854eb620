// Must NOT compile: a handler that names a variable the map does not define
// (TRUEAXIS_CANARY_IN: #10, letter G, has no variable), stages a result
// outside #100..#199 (TRUEAXIS_CANARY_OUT: #500), or reads another method's
// variable (TRUEAXIS_CANARY_OTHER: M1's context and M3's #600). The tests
// typed_accessor_rejects_* build it and expect the compiler's refusal.
#include "trueaxis/macros/level/level_macros.hpp"
#include "trueaxis/macros/method_context.hpp"

namespace trueaxis::macros {

MacroStep canary(PlatformContext& ctx);
MacroStep canary_level(level::Context& ctx);

MacroStep canary(PlatformContext& ctx) {
#if defined(TRUEAXIS_CANARY_IN)
  ctx.out<100>(ctx.in<10>());
#elif defined(TRUEAXIS_CANARY_OUT)
  ctx.out<500>(ctx.in<1>());
#else
  ctx.out<100>(ctx.in<1>());  // the control: this one compiles
#endif
  return done(core::Status::kOk);
}

MacroStep canary_level(level::Context& ctx) {
#if defined(TRUEAXIS_CANARY_OTHER)
  ctx.out<100>(ctx.in<600>());  // rigidity_min_c_arc: M3's, not M1's
#else
  ctx.out<100>(ctx.in<var::kAMin>());  // the control: M1's own configuration
#endif
  return done(core::Status::kOk);
}

}  // namespace trueaxis::macros
