#include "trueaxis/macros/rigidity/rigidity_macros.hpp"

#include <cmath>

#include "trueaxis/core/residual_noise.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/macros/arguments.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/gates.hpp"

namespace trueaxis::macros::rigidity {

namespace {

using core::kArcsecPerRad;

// The C-circle RMS's noise floor and sigma under the ball noise #601.
core::ResidualNoise circle_noise(const core::RigidityPose& p, double ball_noise_mm) {
  return core::residual_rms_noise(p.c_circle_rms_mm, p.c_count, core::circle_residual_dof(p.c_count), ball_noise_mm);
}

MacroStep report_session(Context& ctx, std::size_t count) {
  ctx.out<var::kRigiditySessionCount>(static_cast<double>(count));
  ctx.out<var::kRigiditySessionCapacity>(static_cast<double>(kSessionCapacity));
  return done(core::Status::kOk);
}

// Q (#17) as a blend; false when it is not 0, 1, 2 or 3.
bool blend_of(double q, core::Blend& blend) {
  if (q == 0.0) blend = core::Blend::kLinear;
  else if (q == 1.0) blend = core::Blend::kGeodesic;
  else if (q == 2.0) blend = core::Blend::kCubic;
  else if (q == 3.0) blend = core::Blend::kCubicNotAKnot;
  else return false;
  return true;
}

// The reference pose's ball radius about C: the RMS distance of its samples
// from the C axis (the circle's centre and normal); 0 when none matches.
double reference_radius_mm(const core::RigidityTable& t, const RigiditySession& samples) {
  const core::RigidityPose& ref = t.poses[t.reference];
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const core::RigiditySample& s = samples.data()[k];
    if (!(std::abs(s.a_deg - ref.a_deg) <= core::kPoseAToleranceDeg)) continue;
    const core::Vec3 d = s.p_mm - ref.c_centre_mm;
    sum += (d - d.dot(ref.c_direction) * ref.c_direction).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

// The change gate's figure: the largest |rotvec_new - rotvec_stored(A)| over
// the new poses (rad), the stored table read at each new pose's A, clamped.
struct Change {
  double rad = 0.0;
  std::size_t pose = 0;  // 1-based; 0: no stored table
};
Change change_against(const State& state, const core::RigidityTable& t) {
  Change c;
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    // The stored table as it is, whatever home it was measured under (read_or, not use_or):
    // a new home is no reason to skip the gate.
    const core::Result<core::Vec3> stored = state.table.read_or([&](const core::RigidityTable& s) {
      return core::rigidity_rotvec_rad(s, t.poses[i].a_deg, core::Blend::kLinear, true);
    });
    if (!stored.ok()) return {};
    const double d = (t.poses[i].rotvec_rad - stored.value()).norm();
    if (c.pose == 0 || d > c.rad) c = {d, i + 1};
  }
  return c;
}

// The gates (rigidity_macros.hpp 9832, gates.hpp), then the outputs and the store.
MacroStep finish_build(Context& ctx, State& state, const core::RigidityTable& t, const RigiditySession& samples) {
  bool store = false;
  bool confirmed = false;
  if (!flag_of(ctx.in<var::kArgR>(), store) || !flag_of(ctx.in<var::kArgM>(), confirmed)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const double ball_noise = ctx.in<var::kRigidityBallNoise>();
  FitGate fit(ctx.in<var::kGateConfidence>());
  if (ball_noise > 0.0) {
    for (std::size_t i = 0; i < t.pose_count; ++i) {
      const core::RigidityPose& p = t.poses[i];
      const double ssr = p.c_circle_rms_mm * p.c_circle_rms_mm * static_cast<double>(p.c_count);
      fit.consider(i + 1, ssr / (ball_noise * ball_noise), core::circle_residual_dof(p.c_count));
    }
  }
  if (fit.refused()) return ctx.refuse(core::Status::kFitBeyondNoise, static_cast<double>(fit.item()), fit.ratio(), 1.0);
  const double max_a_error = ctx.in<var::kRigidityMaxAError>();
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    const double e = t.poses[i].a_error_rad * kArcsecPerRad;
    if (!(std::abs(e) <= max_a_error)) return ctx.refuse(kAErrorImplausible, static_cast<double>(i + 1), e, max_a_error);
  }
  const double min_radius = ctx.in<var::kRigidityMinCRadius>();
  const double radius = reference_radius_mm(t, samples);
  if (radius < min_radius) {
    return ctx.refuse(kCRadiusImplausible, static_cast<double>(t.reference + 1), radius, min_radius);
  }
  const Change change = change_against(state, t);
  const double change_arcsec = change.rad * kArcsecPerRad;
  const double max_change = ctx.in<var::kRigidityMaxChange>();
  if (store && change.pose != 0 && change_arcsec > max_change && !confirmed) {
    return ctx.refuse(core::Status::kChangeBeyondLimit, static_cast<double>(change.pose), change_arcsec, max_change);
  }

  std::size_t worst = 0;
  std::size_t worst_rms = 0;
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    if (t.poses[i].rigidity_rad > t.poses[worst].rigidity_rad) worst = i;
    if (t.poses[i].c_circle_rms_mm > t.poses[worst_rms].c_circle_rms_mm) worst_rms = i;
  }
  const core::ResidualNoise noise = circle_noise(t.poses[worst_rms], ball_noise);
  ctx.out<var::kRigidityPoses>(static_cast<double>(t.pose_count));
  ctx.out<var::kRigidityWorst>(t.poses[worst].rigidity_rad * kArcsecPerRad);
  ctx.out<var::kRigidityWorstSigma>(t.poses[worst].rigidity_sigma_rad * kArcsecPerRad);
  ctx.out3<var::kRigidityAPointX>(t.a_axis_point_mm);
  ctx.out3<var::kRigidityADirectionX>(t.a_axis_direction);
  ctx.out<var::kRigidityCToAOffset>(t.c_to_a_offset_mm);
  ctx.out<var::kRigidityCToASquareness>(t.c_to_a_squareness_rad * kArcsecPerRad);
  ctx.out<var::kRigidityWorstCircleRms>(t.poses[worst_rms].c_circle_rms_mm);
  ctx.out<var::kRigidityWorstCircleRmsFloor>(noise.floor_mm);
  ctx.out<var::kRigidityWorstCircleRmsSigma>(noise.sigma_mm);
  ctx.out<var::kRigidityChange>(change_arcsec);
  ctx.out<var::kRigidityChangePose>(static_cast<double>(change.pose));
  ctx.out<var::kRigidityFitRatio>(fit.ratio());
  ctx.out<var::kRigidityFitPose>(static_cast<double>(fit.item()));

  // The measuring log: the worst rigidity and the largest A positioning error (kLogFigureKinds).
  std::size_t worst_a = 0;
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    if (std::abs(t.poses[i].a_error_rad) > std::abs(t.poses[worst_a].a_error_rad)) worst_a = i;
  }
  LogEntry entry;
  entry.add(kLogRigidity, worst + 1, t.poses[worst].rigidity_rad * kArcsecPerRad,
            t.poses[worst].rigidity_sigma_rad * kArcsecPerRad);
  entry.add(kLogAError, worst_a + 1, t.poses[worst_a].a_error_rad * kArcsecPerRad,
            t.poses[worst_a].a_error_sigma_rad * kArcsecPerRad);
  ctx.log(entry);

  ctx.set_on_success(state.built);
  if (!store) return done(core::Status::kOk);
  return done(ctx.stage_table(state.table, t));  // the module commits the record, then makes t live
}

}  // namespace

core::Result<core::Vec3> compensation_rad(const State& state, double a_deg, core::Blend blend, bool clamp) {
  return state.table.use_or(
      [&](const core::RigidityTable& t) { return core::rigidity_rotvec_rad(t, a_deg, blend, clamp); });
}

MacroStep run_session_clear(Context& ctx, State&) {
  ctx.open_session();
  return report_session(ctx, 0);
}

MacroStep run_session_add(Context& ctx, State&) {
  core::RigiditySample s;
  s.a_deg = ctx.in<var::kArgA>();
  s.c_deg = ctx.in<var::kArgC>();
  s.p_mm = core::Vec3(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>());
  RigiditySession* samples = ctx.session();
  if (samples == nullptr) return done(core::Status::kSessionClosed);
  // X first: it differs between nearly any two samples, so most comparisons stop there.
  const auto same = [&s](const core::RigiditySample& o) {
    return core::same_bits(s.p_mm, o.p_mm) && core::same_bits(s.c_deg, o.c_deg) && core::same_bits(s.a_deg, o.a_deg);
  };
  if (samples->find_if(same) != nullptr) return done(core::Status::kDuplicateSample);
  const core::Status status = samples->add(s);
  if (status != core::Status::kOk) return done(status);
  return report_session(ctx, samples->size());
}

MacroStep run_build(Context& ctx, State& state) {
  bool flag = false;
  if (ctx.first_step()) {
    if (!flag_of(ctx.in<var::kArgR>(), flag) || !flag_of(ctx.in<var::kArgM>(), flag)) {
      return done(core::Status::kArgumentOutOfRange);
    }
    const RigiditySession* samples = ctx.session();
    if (samples == nullptr) return done(core::Status::kSessionClosed);
    core::RigidityOptions options;
    options.min_c_arc_deg = ctx.in<var::kRigidityMinCArc>();
    options.max_pose_samples = kMaxPoseSamples;
    options.home_identity = static_cast<std::uint16_t>(ctx.in<var::kHomeIdentity>());  // a whole number 0..65535
    state.built = false;
    Work& work = ctx.open_work();
    work.built = false;
    work.builder.start(samples->data(), samples->size(), options);
    return more();  // the first step only checks and starts: the builder's steps follow
  }
  Work* work = ctx.work();
  const RigiditySession* samples = ctx.session();
  if (work == nullptr || samples == nullptr) return done(core::Status::kResultReplaced);  // cannot happen: one macro at a time
  if (work->built) return finish_build(ctx, state, work->builder.table(), *samples);
  const core::RigidityStep step = work->builder.step();
  if (step.status != core::Status::kOk) return done(step.status);
  work->built = !step.more;
  return more();  // the gates run in a step of their own
}

MacroStep run_query(Context& ctx, State& state) {
  core::Blend blend = core::Blend::kLinear;
  bool clamp = false;
  if (!blend_of(ctx.in<var::kArgQ>(), blend) || !flag_of(ctx.in<var::kArgR>(), clamp)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const core::Result<core::Vec3> r = compensation_rad(state, ctx.in<var::kArgA>(), blend, clamp);
  if (!r.ok()) return done(r.status());
  ctx.out3<var::kRigidityRotvecX>(r.value(), kArcsecPerRad);
  ctx.out<var::kRigidityRotvecNorm>(r.value().norm() * kArcsecPerRad);
  return done(core::Status::kOk);
}

namespace {

MacroStep report_pose(Context& ctx, const core::RigidityTable& t) {
  const double q = ctx.in<var::kArgQ>();
  if (!whole_in(q, 1.0, static_cast<double>(t.pose_count))) return done(core::Status::kArgumentOutOfRange);
  const core::RigidityPose& p = t.poses[static_cast<std::size_t>(q) - 1];
  ctx.out<var::kPoseA>(p.a_deg);
  ctx.out3<var::kPoseRotvecX>(p.rotvec_rad, kArcsecPerRad);
  ctx.out3<var::kPoseRotvecSigmaX>(p.rotvec_sigma_rad, kArcsecPerRad);
  ctx.out<var::kPoseRigidity>(p.rigidity_rad * kArcsecPerRad);
  ctx.out<var::kPoseRigiditySigma>(p.rigidity_sigma_rad * kArcsecPerRad);
  ctx.out<var::kPoseAError>(p.a_error_rad * kArcsecPerRad);
  ctx.out3<var::kPoseCCentreX>(p.c_centre_mm);
  ctx.out3<var::kPoseCDirectionX>(p.c_direction);
  ctx.out<var::kPoseCCircleRms>(p.c_circle_rms_mm);
  ctx.out<var::kPoseCount>(static_cast<double>(t.pose_count));
  ctx.out<var::kPoseAErrorSigma>(p.a_error_sigma_rad * kArcsecPerRad);
  const core::ResidualNoise noise = circle_noise(p, ctx.in<var::kRigidityBallNoise>());
  ctx.out<var::kPoseCCircleRmsSigma>(noise.sigma_mm);
  ctx.out<var::kPoseCCircleRmsFloor>(noise.floor_mm);
  return done(core::Status::kOk);
}

}  // namespace

MacroStep run_pose(Context& ctx, State& state) {
  bool stored = false;
  if (!flag_of(ctx.in<var::kArgR>(), stored)) return done(core::Status::kArgumentOutOfRange);
  if (stored) return state.table.read_or([&](const core::RigidityTable& t) { return report_pose(ctx, t); });
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  return work != nullptr ? report_pose(ctx, work->builder.table()) : done(core::Status::kResultReplaced);
}

namespace {

MacroStep report_reals(Context& ctx, const core::RigidityTable& t) {
  const double q = ctx.in<var::kArgQ>();
  if (!whole_in(q, 0.0, static_cast<double>(t.pose_count))) return done(core::Status::kArgumentOutOfRange);
  ctx.out<var::kRealsPoseCount>(static_cast<double>(t.pose_count));
  ctx.out<var::kRealsReference>(static_cast<double>(t.reference + 1));
  ctx.out<var::kRealsHomeIdentity>(static_cast<double>(t.home_identity));
  double reals[core::kRigidityPoseReals] = {};
  std::size_t count = core::kRigidityHeaderReals;
  if (q == 0.0) {
    core::rigidity_header_reals(t, reals);
  } else {
    core::rigidity_pose_reals(t, static_cast<std::size_t>(q) - 1, reals);
    count = core::kRigidityPoseReals;
  }
  for (std::size_t k = 0; k < core::kRigidityPoseReals; ++k) {
    ctx.out_at<var::kRealsFirst, core::kRigidityPoseReals>(k, k < count ? reals[k] : 0.0);
  }
  return done(core::Status::kOk);
}

}  // namespace

MacroStep run_reals(Context& ctx, State& state) {
  bool stored = false;
  if (!flag_of(ctx.in<var::kArgR>(), stored)) return done(core::Status::kArgumentOutOfRange);
  if (stored) return state.table.read_or([&](const core::RigidityTable& t) { return report_reals(ctx, t); });
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  return work != nullptr ? report_reals(ctx, work->builder.table()) : done(core::Status::kResultReplaced);
}

MacroStep run_convert(Context& ctx, State& state) {
  core::Blend blend = core::Blend::kLinear;
  bool inverse = false;
  if (!blend_of(ctx.in<var::kArgQ>(), blend) || !flag_of(ctx.in<var::kArgR>(), inverse)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const core::Vec3 direction(ctx.in<var::kArgI>(), ctx.in<var::kArgJ>(), ctx.in<var::kArgK>());
  const core::Vec3 point(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>());
  const core::Result<core::RigidTransform> r = state.table.use_or([&](const core::RigidityTable& t) {
    return core::rigidity_correction(t, ctx.in<var::kArgA>(), ctx.in<var::kArgC>(), blend, false);
  });
  if (!r.ok()) return done(r.status());
  const core::RigidTransform actual_T_theory = inverse ? r.value().inverse() : r.value();
  ctx.out3<var::kConvertPointX>(actual_T_theory.point(point));
  ctx.out3<var::kConvertDirectionX>(actual_T_theory.direction(direction));
  return done(core::Status::kOk);
}

}  // namespace trueaxis::macros::rigidity

namespace trueaxis::macros::rigidity {

namespace {

// The stored table's pose at a commanded A (within kPoseAToleranceDeg), or
// nullptr: a check judges only the poses the calibration measured (between
// them the table is an interpolation, whose own error is not a machine's
// change).
const core::RigidityPose* stored_at(const core::RigidityTable& t, double a_deg) {
  for (std::size_t i = 0; i < t.pose_count; ++i) {
    if (std::abs(t.poses[i].a_deg - a_deg) <= core::kPoseAToleranceDeg) return &t.poses[i];
  }
  return nullptr;
}

// The poses of `built` that are judged (check.hpp): not the reference, at a stored pose's A.
bool judged(const core::RigidityTable& built, std::size_t i, const core::RigidityTable& stored) {
  return i != built.reference && stored_at(stored, built.poses[i].a_deg) != nullptr;
}

// Figure k (0-based) of the check: two per judged pose, in A order.
CheckFigure check_figure(const core::RigidityTable& built, const core::RigidityTable& stored, std::size_t k,
                         double rotation_tolerance, double a_error_tolerance) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < built.pose_count; ++i) {
    if (!judged(built, i, stored)) continue;
    if (k / 2 != n++) continue;
    const core::RigidityPose& p = built.poses[i];
    const core::RigidityPose& s = *stored_at(stored, p.a_deg);
    CheckFigure f;
    f.item = static_cast<std::uint16_t>(i + 1);
    // The log names the stored table's pose at that A: the table the entry
    // carries the sequence of, whose poses a reader can ask for (9834, R = 1).
    f.log_item = static_cast<std::uint16_t>(&s - &stored.poses[0] + 1);
    if (k % 2 == 0) {
      const core::Vec3 d = p.rotvec_rad - s.rotvec_rad;
      const core::Vec3 var = p.rotvec_sigma_rad.cwiseAbs2() + s.rotvec_sigma_rad.cwiseAbs2();
      const double length = d.norm();
      f.kind = kCheckRotation;
      f.stored = s.rotvec_rad.norm() * kArcsecPerRad;
      f.measured = p.rotvec_rad.norm() * kArcsecPerRad;
      f.deviation = length * kArcsecPerRad;
      // Along the difference's direction; the largest axis' while there is none.
      f.sigma = (length > 0.0 ? std::sqrt(d.cwiseAbs2().dot(var)) / length : std::sqrt(var.maxCoeff())) * kArcsecPerRad;
      f.tolerance = rotation_tolerance;
    } else {
      f.kind = kCheckAError;
      f.stored = s.a_error_rad * kArcsecPerRad;
      f.measured = p.a_error_rad * kArcsecPerRad;
      f.deviation = f.measured - f.stored;
      f.sigma = std::hypot(p.a_error_sigma_rad, s.a_error_sigma_rad) * kArcsecPerRad;
      f.tolerance = a_error_tolerance;
    }
    return f;
  }
  return {};
}

}  // namespace

MacroStep run_check(Context& ctx, State& state) {
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);
  const core::RigidityTable& built = work->builder.table();
  const double rotation_tolerance = ctx.in<var::kRigidityCheckRotation>();
  const double a_error_tolerance = ctx.in<var::kRigidityCheckAError>();
  return state.table.use_or([&](const core::RigidityTable& stored) {
    std::size_t poses = 0;
    for (std::size_t i = 0; i < built.pose_count; ++i) poses += judged(built, i, stored) ? 1U : 0U;
    return publish_check(ctx, 2 * poses, [&](std::size_t k) {
      return check_figure(built, stored, k, rotation_tolerance, a_error_tolerance);
    });
  });
}

}  // namespace trueaxis::macros::rigidity
