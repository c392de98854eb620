#include "trueaxis/macros/level/level_macros.hpp"

#include <cmath>

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/rigidity_leveling.hpp"
#include "trueaxis/core/sphere_fit.hpp"
#include "trueaxis/macros/check.hpp"

namespace trueaxis::macros::level {

namespace {

core::LevelConfig read_config(const Context& ctx) {
  core::LevelConfig c;
  c.a_min_deg = ctx.in<var::kAMin>();
  c.a_max_deg = ctx.in<var::kAMax>();
  c.c_min_deg = ctx.in<var::kCMin>();
  c.c_max_deg = ctx.in<var::kCMax>();
  c.a_sign = ctx.in<var::kASign>();
  c.c_sign = ctx.in<var::kCSign>();
  c.probe_sigma_mm = ctx.in<var::kProbeSigma>();
  c.max_direction_sigma_deg = ctx.in<var::kMaxDirectionSigma>();
  return c;
}

template <std::uint16_t X>
core::Vec3 read_point(const Context& ctx) {
  return core::Vec3(ctx.in<X>(), ctx.in<X + 1>(), ctx.in<X + 2>());
}

// 9816's outputs: the face's tilt where it was probed again (deg, and its
// sigma in arcsec) judged against #509 (check.hpp). A function of its own, so
// that 9811's deepest path through level_and_report keeps its frame.
[[gnu::noinline]] MacroStep judge_tilt(Context& ctx, double tilt_deg, double sigma_arcsec) {
  CheckFigure f;
  f.kind = 1;
  f.measured = f.deviation = tilt_deg * 3600.0;
  f.sigma = sigma_arcsec;
  f.tolerance = ctx.in<var::kLevelCheckTolerance>();
  return publish_check(ctx, 1, [&f](std::size_t) { return f; });
}

// Shared by 9810, 9811, 9814 and 9816 (`check`): everything but where the
// points come from.
MacroStep level_and_report(Context& ctx, const core::Vec3* points, std::size_t count, bool check = false) {
  core::LevelInput input;
  input.points_mm = points;
  input.count = count;
  input.probe_pose = {ctx.in<var::kArgA>(), ctx.in<var::kArgC>()};
  input.current_pose = input.probe_pose;  // the table has not moved since probing
  input.outward_hint_machine = read_point<var::kArgI>(ctx);

  const bool calibrated = ctx.in<var::kLevelAxes>() == 1.0;
  const StoredTable<RigidityTableRecord>* axes = ctx.services().calibrated_axes;
  if (calibrated && axes == nullptr) return done(core::Status::kMethodNotBuilt);
  const core::Result<core::LevelResult> r =
      !calibrated ? core::level_face(input, read_config(ctx))
                  : axes->use_or([&](const core::RigidityTable& t) {
                      return core::level_on_table(input, read_config(ctx), t, core::Blend::kCubicNotAKnot, false);
                    });
  if (!r.ok()) return done(r.status());
  const core::LevelResult& out = r.value();
  if (check) return judge_tilt(ctx, out.machine_tilt_deg, out.machine_tilt_sigma_arcsec);
  ctx.out<var::kLevelC>(out.chosen.c_deg);
  ctx.out<var::kLevelA>(out.chosen.a_deg);
  ctx.out<var::kLevelOtherC>(out.other.c_deg);
  ctx.out<var::kLevelOtherA>(out.other.a_deg);
  ctx.out<var::kLevelNormalX>(out.normal_table.x());
  ctx.out<var::kLevelNormalY>(out.normal_table.y());
  ctx.out<var::kLevelNormalZ>(out.normal_table.z());
  ctx.out<var::kLevelTilt>(out.tilt_deg);
  ctx.out<var::kLevelTiltSigma>(out.tilt_sigma_arcsec);
  ctx.out<var::kLevelCSigma>(out.c_sigma_arcsec);
  ctx.out<var::kLevelDirectionSigma>(out.direction_sigma_arcsec);
  ctx.out<var::kLevelFlatness>(out.flatness_mm);
  ctx.out<var::kLevelPointCount>(static_cast<double>(out.count));
  ctx.out<var::kLevelOutlierPoint>(static_cast<double>(out.outlier_point));
  ctx.out<var::kLevelMaxResidual>(out.max_standardized_residual);
  ctx.out<var::kLevelOtherReachable>(out.other.reachable ? 1.0 : 0.0);
  ctx.out<var::kLevelAxesUsed>(calibrated ? 1.0 : 0.0);
  ctx.out<var::kLevelMachineTilt>(out.machine_tilt_deg);
  ctx.out<var::kLevelMachineTiltSigma>(out.machine_tilt_sigma_arcsec);
  return done(core::Status::kOk);
}

MacroStep report_session(Context& ctx, std::size_t count) {
  ctx.out<var::kLevelSessionCount>(static_cast<double>(count));
  ctx.out<var::kLevelSessionCapacity>(static_cast<double>(kSessionCapacity));
  return done(core::Status::kOk);
}

}  // namespace

MacroStep run_level_3pt(Context& ctx, State&) {
  const core::Vec3 points[3] = {read_point<var::kG57>(ctx), read_point<var::kG58>(ctx), read_point<var::kG59>(ctx)};
  return level_and_report(ctx, points, 3);
}

MacroStep run_level_points(Context& ctx, State&) {
  const double q = ctx.in<var::kArgQ>();
  if (!(q >= 3.0 && q <= static_cast<double>(core::kMaxPlanePoints)) || q != std::floor(q)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const auto count = static_cast<std::size_t>(q);
  core::Vec3 points[core::kMaxPlanePoints];
  for (std::size_t k = 0; k < count; ++k) {
    points[k] = core::Vec3(ctx.in_block<var::kPointList>(3 * k), ctx.in_block<var::kPointList>(3 * k + 1),
                           ctx.in_block<var::kPointList>(3 * k + 2));
  }
  return level_and_report(ctx, points, count);
}

MacroStep run_session_clear(Context& ctx, State& state) {
  state.points.clear();
  return report_session(ctx, 0);
}

MacroStep run_session_add(Context& ctx, State& state) {
  const core::Vec3 p = read_point<var::kArgX>(ctx);
  Session<core::Vec3, kSessionCapacity>& session = state.points;
  const core::Status s = session.add(p);
  if (s != core::Status::kOk) return done(s);
  return report_session(ctx, session.size());
}

MacroStep run_session_compute(Context& ctx, State& state) {
  const Session<core::Vec3, kSessionCapacity>& session = state.points;
  if (session.size() < 3) return done(core::Status::kTooFewSamples);
  return level_and_report(ctx, session.data(), session.size());
}

MacroStep run_session_ball(Context& ctx, State& state) {
  const Session<core::Vec3, kSessionCapacity>& session = state.points;
  if (session.size() < 4) return done(core::Status::kTooFewSamples);
  const core::Result<core::SphereFit> r =
      core::fit_sphere(session.data(), session.size(), ctx.in<var::kArgR>(), ctx.in<var::kProbeSigma>());
  if (r.status() == core::Status::kNotIdentifiable) return done(kTouchesCoplanar);
  if (!r.ok()) return done(r.status());
  const core::SphereFit& fit = r.value();
  ctx.out<var::kBallCentreX>(fit.centre_mm.x());
  ctx.out<var::kBallCentreY>(fit.centre_mm.y());
  ctx.out<var::kBallCentreZ>(fit.centre_mm.z());
  ctx.out<var::kBallRadius>(fit.radius_mm);
  ctx.out<var::kBallCentreSigmaX>(fit.centre_sigma_mm.x());
  ctx.out<var::kBallCentreSigmaY>(fit.centre_sigma_mm.y());
  ctx.out<var::kBallCentreSigmaZ>(fit.centre_sigma_mm.z());
  ctx.out<var::kBallRadiusSigma>(fit.radius_sigma_mm);
  ctx.out<var::kBallRmsResidual>(fit.rms_residual_mm);
  ctx.out<var::kBallMaxResidual>(fit.max_residual_mm);
  ctx.out<var::kBallPointCount>(static_cast<double>(fit.count));
  return done(core::Status::kOk);
}

MacroStep run_session_check(Context& ctx, State& state) {
  const Session<core::Vec3, kSessionCapacity>& session = state.points;
  if (session.size() < 3) return done(core::Status::kTooFewSamples);
  return level_and_report(ctx, session.data(), session.size(), true);
}

}  // namespace trueaxis::macros::level
