#include "trueaxis/macros/spindle/spindle_macros.hpp"

#include <algorithm>
#include <cmath>

#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/macros/arguments.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/gates.hpp"

namespace trueaxis::macros::spindle {

namespace {

MacroStep report_session(Context& ctx, const core::SpindleBins& b) {
  ctx.out<var::kSpindleSessionSamples>(static_cast<double>(b.samples()));
  ctx.out<var::kSpindleSessionAngles1>(static_cast<double>(b.angles(1)));
  ctx.out<var::kSpindleSessionAngles2>(static_cast<double>(b.angles(2)));
  ctx.out<var::kSpindleSessionCapacity>(static_cast<double>(core::kSpindleBins));
  return done(core::Status::kOk);
}

// 9843's outputs (#100..#104), which 9844 shares.
void out_correction(Context& ctx, const core::SpindleCorrection& c) {
  ctx.out<var::kSpindleThetaE>(c.theta_e_rad * core::kArcsecPerRad);
  ctx.out<var::kSpindleDE>(c.d_e_mm);
  ctx.out3<var::kSpindleTipX>(c.tip_error_mm);
}

// The spindle angle in radians, reduced first so that many revolutions lose nothing.
double radians(double phi_deg) { return core::deg_to_rad(std::fmod(phi_deg, 360.0)); }

bool tool_in_range(double tool_mm) { return tool_mm >= 0.0 && tool_mm <= rows::kBig; }

// The model a report reads: R = 1 the stored one, R = 0 the last identification.
template <typename Report>
MacroStep with_model(Context& ctx, const State& state, bool stored, Report report) {
  if (stored) return state.table.read_or(report);
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);
  return report(work->computed);
}

// The change gate's figure: the largest |tip_new - tip_stored| at V over the
// angles 0, 10, .. 350 deg; pose 0 (no angle) without a stored model. The
// measuring log keeps the angle's step, 1 .. 36 (angle 10 (step - 1) deg): a
// byte does not hold 350 (measuring_log.hpp convention 1).
struct Change {
  double mm = 0.0;
  double angle_deg = 0.0;
  bool stored = false;
  std::uint8_t step = 0;
};
Change change_against(const State& state, const core::SpindleModel& m) {
  Change c;
  const double tool = m.geometry.ball_mm[1];
  for (int k = 0; k < kChangeAngles; ++k) {
    const double phi_deg = kChangeStepDeg * k;
    const core::Result<core::SpindleCorrection> stored = tool_tip_correction(state, phi_deg, tool);
    if (!stored.ok()) return {};
    const core::Result<core::SpindleCorrection> now =
        core::spindle_correction(m.axes, m.geometry.gauge_mm, tool, core::deg_to_rad(phi_deg));
    if (!now.ok()) return {};
    const double d = (now.value().tip_error_mm - stored.value().tip_error_mm).norm();
    if (!c.stored || d > c.mm) c = {d, phi_deg, true, change_log_step(k)};
  }
  return c;
}

// The gates (spindle_macros.hpp 9842), then the outputs and the store.
MacroStep finish_build(Context& ctx, State& state, Work& work, const core::SpindleBins& bins) {
  bool store = false;
  bool confirmed = false;
  if (!flag_of(ctx.in<var::kArgR>(), store) || !flag_of(ctx.in<var::kArgM>(), confirmed)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const double noise = ctx.in<var::kSpindleProbeNoise>();
  const double form = ctx.in<var::kSpindleFormAllowance>();
  const double variance = noise * noise + form * form / 3.0;  // per axis
  FitGate fit(ctx.in<var::kGateConfidence>());
  if (variance > 0.0) {
    for (int ball = 1; ball <= 2; ++ball) {
      const std::size_t n = bins.samples(ball);
      fit.consider(static_cast<std::size_t>(ball), work.computed.fit.ball_ssr_mm2[ball - 1] / variance, n > 2 ? 3 * n - 4 : 0);
    }
  }
  if (fit.refused()) return ctx.refuse(core::Status::kFitBeyondNoise, static_cast<double>(fit.item()), fit.ratio(), 1.0);
  const Change change = change_against(state, work.computed);
  const double max_change = ctx.in<var::kSpindleMaxChange>();
  if (store && change.stored && change.mm > max_change && !confirmed) {
    return ctx.refuse(core::Status::kChangeBeyondLimit, change.angle_deg, change.mm, max_change, change.step);
  }

  const core::SpindleFit& f = work.computed.fit;
  ctx.out<var::kSpindleEvaluations>(static_cast<double>(f.evaluations));
  ctx.out<var::kSpindleNoiseSigma>(f.noise_sigma_mm);
  ctx.out<var::kSpindleSynchronousRms>(f.synchronous_rms_mm);
  ctx.out<var::kSpindleNoiseFromRepeats>(f.noise_from_repeats ? 1.0 : 0.0);
  ctx.out<var::kSpindleSamplesUsed>(static_cast<double>(f.samples));
  ctx.out<var::kSpindleFitRatio>(fit.ratio());
  ctx.out<var::kSpindleFitBall>(static_cast<double>(fit.item()));
  ctx.out<var::kSpindleChange>(change.mm);
  ctx.out<var::kSpindleChangeAngle>(change.angle_deg);
  ctx.out<var::kSpindleBallSpacing>(work.spacing_mm);
  // The measuring log: the screw's parameters a_x .. w_y with their sigmas (kLogFigures, as the check's).
  LogEntry entry;
  for (std::uint16_t k = 0; k < 6; ++k) {
    const Eigen::Index p = static_cast<Eigen::Index>(k) + 3;
    const double scale = k == 2 || k == 3 ? 1.0 : core::kArcsecPerRad;
    const double v = f.covariance(p, p);
    entry.add(static_cast<std::uint16_t>(k + 1), 0, f.params(p) * scale, std::sqrt(v > 0.0 ? v : 0.0) * scale);
  }
  ctx.log(entry);
  ctx.set_on_success(state.built);
  if (!store) return done(core::Status::kOk);
  return done(ctx.stage_table(state.table, work.computed));  // the module commits it, then makes it live
}

}  // namespace

core::Result<core::SpindleCorrection> tool_tip_correction(const State& state, double phi_deg, double tool_mm) {
  if (!std::isfinite(phi_deg) || !std::isfinite(tool_mm)) return core::Status::kNotFinite;
  if (!tool_in_range(tool_mm)) return core::Status::kArgumentOutOfRange;
  // radians(phi_deg) bit for bit (9844 gives the same outputs) without fmod's cost.
  const double phi = core::spindle_phi_rad(phi_deg);
  return state.table.read_or([&](const core::SpindleModel& m) {
    return core::spindle_correction(m.axes, m.geometry.gauge_mm, tool_mm, phi);
  });
}

MacroStep run_session_clear(Context& ctx, State&) { return report_session(ctx, ctx.open_session()); }

MacroStep run_session_add(Context& ctx, State&) {
  const double t = ctx.in<var::kArgT>();
  if (!whole_in(t, 1.0, 2.0)) return done(core::Status::kArgumentOutOfRange);
  const core::SpindleSample s{ctx.in<var::kArgS>(), static_cast<int>(t),
                              core::Vec3(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>())};
  core::SpindleBins* bins = ctx.session();
  if (bins == nullptr) return done(core::Status::kSessionClosed);
  const core::Status status = bins->add(s);
  if (status != core::Status::kOk) return done(status);
  return report_session(ctx, *bins);
}

MacroStep run_build(Context& ctx, State& state) {
  bool flag = false;
  if (!flag_of(ctx.in<var::kArgR>(), flag) || !flag_of(ctx.in<var::kArgM>(), flag)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  if (ctx.first_step()) {
    const core::SpindleBins* bins = ctx.session();
    if (bins == nullptr) return done(core::Status::kSessionClosed);
    core::SpindleGeometry g;
    g.gauge_mm = ctx.in<var::kArgD>();
    g.ball_mm[0] = ctx.in<var::kArgU>();
    g.ball_mm[1] = ctx.in<var::kArgV>();
    if (!(g.gauge_mm > 0.0) || !(g.ball_mm[0] >= 0.0) || !(g.ball_mm[1] > g.ball_mm[0])) {
      return done(core::Status::kArgumentOutOfRange);
    }
    // The spacing gate (one file in other units than the other), then the
    // ball-distance gate (both in metres): before the fit, which on such data
    // would only fail to converge.
    const double given = g.ball_mm[1] - g.ball_mm[0];
    const double spacing = (bins->sums(2).mean_mm() - bins->sums(1).mean_mm()).norm();
    const double max_error = ctx.in<var::kSpindleMaxSpacingError>();
    if (bins->samples(1) > 0 && bins->samples(2) > 0 && !(std::abs(spacing - given) <= max_error)) {
      return ctx.refuse(kBallSpacingImplausible, 0.0, spacing - given, max_error);
    }
    const double min_distance = ctx.in<var::kSpindleMinBallSpacing>();
    if (given < min_distance) return ctx.refuse(kBallsTooClose, 0.0, given, min_distance);
    state.built = false;
    Work& work = ctx.open_work();
    work.computed.geometry = g;
    work.phase = Work::Phase::kFit;
    work.spacing_mm = spacing;
    work.builder.start(*bins, g, ctx.in<var::kSpindleMaxGap>());
    return more();
  }
  Work* work = ctx.work();
  const core::SpindleBins* bins = ctx.session();
  if (work == nullptr || bins == nullptr) return done(core::Status::kResultReplaced);  // cannot happen: one macro at a time
  switch (work->phase) {
    case Work::Phase::kFit: {
      const core::SpindleStep step = work->builder.step();
      if (step.status != core::Status::kOk) return done(step.status);
      if (step.more) return more();
      // In place (core::make_spindle_model's fields): a SpindleModel temporary
      // would be 0.9 kB on the stack of step().
      work->computed.fit = work->builder.fit();
      work->computed.axes = core::spindle_axes(work->computed.fit.params);
      work->phase = Work::Phase::kGates;
      return more();
    }
    case Work::Phase::kGates:
      break;
  }
  return finish_build(ctx, state, *work, *bins);
}

MacroStep run_correction(Context& ctx, State& state) {
  const core::Result<core::SpindleCorrection> c =
      tool_tip_correction(state, ctx.in<var::kArgS>(), ctx.in<var::kArgZ>());
  if (!c.ok()) return done(c.status());
  out_correction(ctx, c.value());
  return done(core::Status::kOk);
}

MacroStep run_report(Context& ctx, State& state) {
  bool stored = false;
  if (!flag_of(ctx.in<var::kArgR>(), stored)) return done(core::Status::kArgumentOutOfRange);
  const double phi_deg = ctx.in<var::kArgS>();
  const double tool_mm = ctx.in<var::kArgZ>();
  if (!tool_in_range(tool_mm)) return done(core::Status::kArgumentOutOfRange);
  const double phi = radians(phi_deg);
  return with_model(ctx, state, stored, [&](const core::SpindleModel& m) -> MacroStep {
    const core::Result<core::SpindleCorrection> c = core::spindle_correction(m.axes, m.geometry.gauge_mm, tool_mm, phi);
    if (!c.ok()) return done(c.status());
    const core::Result<core::SpindleCorrectionSigma> s =
        core::spindle_correction_sigma(m.fit.params, m.fit.covariance, m.geometry.gauge_mm, tool_mm, phi);
    if (!s.ok()) return done(s.status());
    out_correction(ctx, c.value());
    ctx.out<var::kSpindleThetaESigma>(s.value().theta_e_rad * core::kArcsecPerRad);
    ctx.out<var::kSpindleDESigma>(s.value().d_e_mm);
    ctx.out3<var::kSpindleTipSigmaX>(s.value().tip_error_mm);
    ctx.out3<var::kSpindleMeanTipX>(core::spindle_mean_tip_error_mm(m.axes, m.geometry.gauge_mm, tool_mm));
    ctx.out3<var::kSpindleMeanTipSigmaX>(s.value().mean_tip_error_mm);
    return done(core::Status::kOk);
  });
}

MacroStep run_words(Context& ctx, State& state) {
  bool stored = false;
  const double q = ctx.in<var::kArgQ>();
  if (!flag_of(ctx.in<var::kArgR>(), stored) || !whole_in(q, 0.0, 1.0)) return done(core::Status::kArgumentOutOfRange);
  return with_model(ctx, state, stored, [&](const core::SpindleModel& m) -> MacroStep {
    std::uint8_t bytes[core::kSpindleModelBytes];
    if (core::encode_spindle_model(m, bytes, sizeof bytes) != sizeof bytes) return done(core::Status::kTableInvalid);
    const std::size_t first = static_cast<std::size_t>(q) * kWordsPerPart;
    const std::size_t words = std::min(kWordsPerPart, core::kSpindleModelBytes / 4 - first);
    ctx.out<var::kSpindleWordsBytes>(static_cast<double>(core::kSpindleModelBytes));
    ctx.out<var::kSpindleWordsCount>(static_cast<double>(words));
    for (std::size_t k = 0; k < kWordsPerPart; ++k) {
      const std::uint32_t w = k < words ? core::get_u32(bytes + 4 * (first + k)) : 0u;
      ctx.out_at<var::kSpindleWordsFirst, kWordsPerPart>(k, static_cast<double>(w));
    }
    return done(core::Status::kOk);
  });
}

MacroStep run_model(Context& ctx, State& state) {
  bool stored = false;
  const double q = ctx.in<var::kArgQ>();
  if (!flag_of(ctx.in<var::kArgR>(), stored) || !whole_in(q, 1.0, core::kSpindleParams)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const int k = static_cast<int>(q) - 1;
  return with_model(ctx, state, stored, [&](const core::SpindleModel& m) -> MacroStep {
    const core::SpindleFit& f = m.fit;
    ctx.out<var::kSpindleParamValue>(f.params(k));
    ctx.out<var::kSpindleParamSigma>(std::sqrt(f.covariance(k, k)));
    ctx.out<var::kSpindleRms>(f.rms_mm);
    ctx.out<var::kSpindleModelSynchronousRms>(f.synchronous_rms_mm);
    ctx.out<var::kSpindleModelNoiseSigma>(f.noise_sigma_mm);
    ctx.out<var::kSpindleModelNoiseFromRepeats>(f.noise_from_repeats ? 1.0 : 0.0);
    ctx.out<var::kSpindleModelSamples>(static_cast<double>(f.samples));
    ctx.out<var::kSpindleModelEvaluations>(static_cast<double>(f.evaluations));
    ctx.out<var::kSpindleModelGauge>(m.geometry.gauge_mm);
    ctx.out<var::kSpindleModelBall1>(m.geometry.ball_mm[0]);
    ctx.out<var::kSpindleModelBall2>(m.geometry.ball_mm[1]);
    ctx.out<var::kSpindleModelEigenRatio>(f.smallest_eigenvalue_ratio);
    return done(core::Status::kOk);
  });
}

}  // namespace trueaxis::macros::spindle

namespace trueaxis::macros::spindle {

MacroStep run_check(Context& ctx, State& state) {
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);
  const core::SpindleFit& built = work->computed.fit;
  const double tilt_tolerance = ctx.in<var::kSpindleCheckTilt>();
  const double offset_tolerance = ctx.in<var::kSpindleCheckOffset>();
  return state.table.read_or([&](const core::SpindleModel& stored) {
    // Figure k: parameter 4 + k (a_x .. w_y, spindle_model.hpp convention 1).
    return publish_check(ctx, 6, [&](std::size_t k) {
      const Eigen::Index p = static_cast<Eigen::Index>(k) + 3;
      const bool offset = k == 2 || k == 3;
      const double scale = offset ? 1.0 : core::kArcsecPerRad;
      CheckFigure f;
      f.kind = static_cast<std::uint16_t>(k + 1);
      f.stored = stored.fit.params(p) * scale;
      f.measured = built.params(p) * scale;
      f.deviation = f.measured - f.stored;
      // A variance rounded below 0 counts as 0; a NaN stays NaN (and fails, check.hpp).
      const auto variance = [](double v) { return v < 0.0 ? 0.0 : v; };
      f.sigma = std::sqrt(variance(stored.fit.covariance(p, p)) + variance(built.covariance(p, p))) * scale;
      f.tolerance = offset ? offset_tolerance : tilt_tolerance;
      return f;
    });
  });
}

}  // namespace trueaxis::macros::spindle
