// Must NOT compile: a handler that names a variable the map does not define
// (TRUEAXIS_CANARY_IN: #10, letter G, has no variable) or stages a result
// outside #100..#199 (TRUEAXIS_CANARY_OUT: #500). The tests
// typed_accessor_rejects_* build it and expect the compiler's refusal.
#include "trueaxis/macros/macro_context.hpp"

namespace trueaxis::macros {

MacroStep canary(MacroContext& ctx);

MacroStep canary(MacroContext& ctx) {
#if defined(TRUEAXIS_CANARY_IN)
  ctx.out<100>(ctx.in<10>());
#elif defined(TRUEAXIS_CANARY_OUT)
  ctx.out<500>(ctx.in<1>());
#else
  ctx.out<100>(ctx.in<1>());  // the control: this one compiles
#endif
  return done(core::Status::kOk);
}

}  // namespace trueaxis::macros
