#include "trueaxis/macros/canary/canary_macros.hpp"

#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/canary_sum.hpp"

namespace trueaxis::macros::canary {

core::Status SumRecord::decode(const std::uint8_t* bytes, std::size_t length, Type& out) {
  if (length != 8) return core::Status::kTableInvalid;
  out.value = core::get_f64(bytes);
  return core::Status::kOk;
}

std::size_t SumRecord::encode(const Type& t, std::uint8_t* out, std::size_t capacity) {
  if (capacity < 8) return 0;
  core::put_f64(out, t.value);
  return 8;
}

MacroStep run_scale(Context& ctx, State&) {
  ctx.out<100>(ctx.in<var::kArgA>() * ctx.in<kGain>());
  return done(core::Status::kOk);
}

MacroStep run_clear(Context& ctx, State&) {
  ctx.out<100>(static_cast<double>(ctx.open_session().size()));
  return done(core::Status::kOk);
}

MacroStep run_add(Context& ctx, State&) {
  CanarySession* s = ctx.session();
  if (s == nullptr) return done(core::Status::kSessionClosed);
  const core::Status status = s->add(ctx.in<var::kArgA>());
  if (status != core::Status::kOk) return done(status);
  ctx.out<100>(static_cast<double>(s->size()));
  return done(core::Status::kOk);
}

MacroStep run_sum(Context& ctx, State& state) {
  const CanarySession* s = ctx.session();
  if (s == nullptr) return done(core::Status::kSessionClosed);
  if (s->empty()) return done(kCanaryEmpty);
  Work& work = ctx.open_work();
  double values[4] = {};
  for (std::size_t i = 0; i < s->size(); ++i) values[i] = (*s)[i];
  work.sum.value = core::canary_sum(values, s->size());
  ctx.out<100>(work.sum.value * ctx.in<kGain>());
  if (ctx.in<var::kArgR>() != 1.0) return done(core::Status::kOk);
  return done(ctx.stage_table(state.table, work.sum));
}

MacroStep run_stored(Context& ctx, State& state) {
  return state.table.read_or([&](const Sum& sum) {
    ctx.out<100>(sum.value);
    return done(core::Status::kOk);
  });
}

}  // namespace trueaxis::macros::canary
