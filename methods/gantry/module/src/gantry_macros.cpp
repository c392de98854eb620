#include "trueaxis/macros/gantry/gantry_macros.hpp"

#include <cmath>

#include "trueaxis/core/residual_noise.hpp"
#include "trueaxis/macros/arguments.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/gates.hpp"

namespace trueaxis::macros::gantry {

namespace {

bool finite(const core::Vec3& v) { return v.allFinite(); }

MacroStep report_session(Context& ctx, const PointSession& s) {
  ctx.out<var::kGantrySessionCount>(static_cast<double>(s.size()));
  ctx.out<var::kGantrySessionCapacity>(static_cast<double>(kSessionCapacity));
  ctx.out<var::kGantryGroupCount>(static_cast<double>(s.groups()));
  return done(core::Status::kOk);
}

std::size_t capacity_of(std::size_t group) {
  if (group < 3) return kMaxPlanePoints;
  if (group < kGlobalGroups) return kMaxPassPoints;
  return (group - kGlobalGroups) % kSubGroups < 3 * kMaxPasses ? kMaxPassPoints : kMaxCirclePoints;
}

// Spans of the session's groups for the sub-machines it mentions (id order),
// into an `in` as constructed (the work just opened: a GantryInput() here
// would be a 2 kB temporary on the stack of step()).
void gather(const PointSession& s, core::GantryInput& in) {
  in.bed = s.span(0);
  in.side_1 = s.span(1);
  in.side_2 = s.span(2);
  for (std::size_t k = 0; k < kMaxPasses; ++k) {
    in.gantry_passes[k] = s.span(3 + k);
    if (in.gantry_passes[k].count > 0) in.gantry_pass_count = k + 1;
  }
  for (std::size_t id = 1; id <= core::kMaxSubMachines; ++id) {
    if (!s.mentions(id)) continue;
    core::SubMachineInput& sub = in.sub_machines[in.sub_machine_count++];
    sub.id = static_cast<int>(id);
    const std::size_t base = kGlobalGroups + (id - 1) * kSubGroups;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      for (std::size_t k = 0; k < kMaxPasses; ++k) {
        sub.passes[axis][k] = s.span(base + axis * kMaxPasses + k);
        if (sub.passes[axis][k].count > 0) sub.pass_count[axis] = k + 1;
      }
    }
    sub.c_circle = s.span(base + 3 * kMaxPasses);
    sub.a_circle = s.span(base + 3 * kMaxPasses + 1);
    sub.swing_mm = s.parameters(id).swing_mm;
    sub.tool_direction = s.parameters(id).tool_direction;
  }
}

MacroStep report_global(Context& ctx, const core::StoredGlobal& g, std::size_t count, std::uint16_t mask) {
  ctx.out3<var::kGlobalOriginX>(g.tracker_T_global.t);
  ctx.out3<var::kGlobalXX>(g.tracker_T_global.R.col(0));
  ctx.out3<var::kGlobalYX>(g.tracker_T_global.R.col(1));
  ctx.out3<var::kGlobalZX>(g.tracker_T_global.R.col(2));
  ctx.out<var::kGlobalBedFlatness>(g.bed_flatness_mm);
  ctx.out<var::kGlobalGantryStraightness>(g.gantry_straightness_mm);
  ctx.out<var::kGlobalOriginSigma>(g.origin_sigma_mm);
  ctx.out3<var::kGlobalAngleSigmaX>(g.angle_sigma_arcsec);
  ctx.out<var::kGlobalSubMachines>(static_cast<double>(count));
  ctx.out<var::kGlobalIdMask>(static_cast<double>(mask));
  ctx.out<var::kGlobalBedFlatnessFloor>(g.bed_flatness_noise_floor_mm);
  ctx.out<var::kGlobalGantryStraightnessFloor>(g.gantry_straightness_noise_floor_mm);
  ctx.out<var::kGlobalBedFormError>(g.bed_form_error_mm);
  ctx.out<var::kGlobalBedFormErrorSigma>(g.bed_form_error_sigma_mm);
  ctx.out<var::kGlobalGantryFormError>(g.gantry_form_error_mm);
  ctx.out<var::kGlobalGantryFormErrorSigma>(g.gantry_form_error_sigma_mm);
  return done(core::Status::kOk);
}

MacroStep report_sub(Context& ctx, const core::StoredSubMachine& s) {
  ctx.out3<var::kSubOriginX>(s.global_T_sub.t);
  ctx.out<var::kSubOriginSigma>(s.origin_sigma_mm);
  ctx.out3<var::kSubXX>(s.global_T_sub.R.col(0));
  ctx.out3<var::kSubYX>(s.global_T_sub.R.col(1));
  ctx.out3<var::kSubZX>(s.global_T_sub.R.col(2));
  ctx.out<var::kSubMasterAxis>(static_cast<double>(s.master_axis));
  ctx.out3<var::kSubSquarenessXY>(s.squareness_arcsec);
  ctx.out<var::kSubACOffset>(s.a_c_offset_mm);
  ctx.out<var::kSubACAngle>(s.a_c_angle_deg);
  ctx.out3<var::kSubAngleSigmaX>(s.angle_sigma_arcsec);
  ctx.out3<var::kSubStraightnessX>(s.straightness_mm);
  ctx.out<var::kSubCCircleRms>(s.c_circle_rms_mm);
  ctx.out<var::kSubACircleRms>(s.a_circle_rms_mm);
  ctx.out3<var::kSubSquarenessSigmaXY>(s.squareness_sigma_arcsec);
  ctx.out<var::kSubACOffsetSigma>(s.a_c_offset_sigma_mm);
  ctx.out<var::kSubACAngleSigma>(s.a_c_angle_sigma_deg);
  return done(core::Status::kOk);
}

// No sub-machine present (merge_frames replaces the global frame whole).
void reset(core::GantryTable& t) {
  for (core::StoredSubMachine& sub : t.sub_machines) sub.present = false;
}

// The frames a report reads: R = 1 the stored ones, R = 0 the last computation
// (as a table of its own, in the work's `merged`: one report for both).
template <typename Report>
MacroStep with_frames(Context& ctx, const State& state, bool stored, Report report) {
  if (stored) return state.table.read_or(report);
  if (!state.built) return done(core::Status::kNoTable);
  Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);
  reset(work->merged);
  core::merge_frames(work->merged, work->frames);
  return report(static_cast<const core::GantryTable&>(work->merged));
}

// The fit gate on one circle (gates.hpp): n rms^2 over the mean of the
// tracker's variance (a + b r)^2 at its points (r their distance from the
// tracker, the origin of the points' frame), 2 n - 6 degrees of freedom.
void consider_circle(FitGate& fit, int id, const core::CircleSummary& circle, const core::PointSpan& points, double a,
                     double b_per_mm) {
  if (points.count < 4) return;
  double variance = 0.0;
  for (std::size_t i = 0; i < points.count; ++i) {
    const double s = a + b_per_mm * points.points_mm[i].norm();
    variance += s * s;
  }
  variance /= static_cast<double>(points.count);
  if (!(variance > 0.0)) return;
  const double n = static_cast<double>(points.count);
  fit.consider(static_cast<std::size_t>(id), n * circle.rms_distance_mm * circle.rms_distance_mm / variance,
               core::circle_residual_dof(points.count));
}

// The bed-span gate's figure: the largest distance of a bed point from the first.
double bed_span_mm(const core::PointSpan& bed) {
  double span = 0.0;
  for (std::size_t i = 1; i < bed.count; ++i) span = std::fmax(span, (bed.points_mm[i] - bed.points_mm[0]).norm());
  return span;
}

// The change gate's figures: the largest move of a sub-machine's origin and
// turn of its axes from the stored frames of the same id (global frame); the
// turn from |R - R_stored|_F = 2 sqrt(2) sin(angle / 2).
// The angle (arcsec) that turns rotation `from` into `to`.
double turn_arcsec(const core::Mat3& to, const core::Mat3& from) {
  const double chord = (to - from).norm() / (2.0 * std::sqrt(2.0));
  const double half = std::fmin(1.0, chord);  // sin(angle / 2); atan2 keeps to the firmware's libm
  return 2.0 * std::atan2(half, std::sqrt(1.0 - half * half)) * core::kArcsecPerRad;
}

struct Change {
  double origin_mm = 0.0;
  double origin_id = 0.0;
  double angle_arcsec = 0.0;
  double angle_id = 0.0;
};
Change change_against(const State& state, const core::GantryFrames& f) {
  Change c;
  state.table.read([&](const core::GantryTable& t) {
    for (std::size_t i = 0; i < f.sub_machine_count; ++i) {
      const core::SubMachineFrame& now = f.sub_machines[i];
      if (now.id < 1 || now.id > static_cast<int>(core::kMaxSubMachines)) continue;
      const core::StoredSubMachine& was = t.sub_machines[now.id - 1];
      if (!was.present) continue;
      const double moved = (now.global_T_sub.t - was.global_T_sub.t).norm();
      const double turned = turn_arcsec(now.global_T_sub.R, was.global_T_sub.R);
      if (c.origin_id == 0.0 || moved > c.origin_mm) {
        c.origin_mm = moved;
        c.origin_id = now.id;
      }
      if (c.angle_id == 0.0 || turned > c.angle_arcsec) {
        c.angle_arcsec = turned;
        c.angle_id = now.id;
      }
    }
  });
  return c;
}

}  // namespace

void PointSession::clear() {
  count_ = 0;
  last_group_ = kGroupCount;
  for (std::size_t g = 0; g < kGroupCount; ++g) first_[g] = count_in_[g] = 0;
  for (SubMachineParameters& p : parameters_) p = SubMachineParameters();
}

core::Result<std::size_t> PointSession::group_of(double t, double q, double d) {
  if (!whole_in(t, 0.0, core::kMaxSubMachines) || !whole_in(q, 1.0, 9.0)) return core::Status::kArgumentOutOfRange;
  const auto kind = static_cast<GroupKind>(static_cast<int>(q));
  const bool global_kind = kind <= GroupKind::kGantryPass;
  if (global_kind != (t == 0.0)) return core::Status::kArgumentOutOfRange;
  const bool pass = kind == GroupKind::kGantryPass || kind == GroupKind::kXPass || kind == GroupKind::kYPass ||
                    kind == GroupKind::kZPass;
  if (pass && !whole_in(d, 1.0, kMaxPasses)) return core::Status::kArgumentOutOfRange;
  const std::size_t k = pass ? static_cast<std::size_t>(d) - 1 : 0;
  switch (kind) {
    case GroupKind::kBed: return std::size_t{0};
    case GroupKind::kSide1: return std::size_t{1};
    case GroupKind::kSide2: return std::size_t{2};
    case GroupKind::kGantryPass: return 3 + k;
    default: break;
  }
  const std::size_t base = kGlobalGroups + (static_cast<std::size_t>(t) - 1) * kSubGroups;
  switch (kind) {
    case GroupKind::kXPass: return base + k;
    case GroupKind::kYPass: return base + kMaxPasses + k;
    case GroupKind::kZPass: return base + 2 * kMaxPasses + k;
    case GroupKind::kCCircle: return base + 3 * kMaxPasses;
    default: return base + 3 * kMaxPasses + 1;  // kACircle
  }
}

core::Status PointSession::add(std::size_t group, const core::Vec3& p_mm) {
  const core::Vec3* first = points_ + first_[group];
  for (std::size_t i = 0; i < count_in_[group]; ++i) {
    if (core::same_bits(first[i], p_mm)) return core::Status::kDuplicateSample;
  }
  if (group != last_group_ && count_in_[group] > 0) return core::Status::kGroupNotContiguous;
  if (count_in_[group] == capacity_of(group)) return core::Status::kTooManyPoints;
  if (count_ == kSessionCapacity) return core::Status::kSessionFull;
  if (count_in_[group] == 0) first_[group] = static_cast<std::uint16_t>(count_);
  points_[count_++] = p_mm;
  ++count_in_[group];
  last_group_ = group;
  return core::Status::kOk;
}

core::Status PointSession::set_parameters(double t, double swing_mm, const core::Vec3& tool, double nominal_flag,
                                          const core::Vec3& nominal_origin_mm) {
  if (!whole_in(t, 1.0, core::kMaxSubMachines)) return core::Status::kArgumentOutOfRange;
  if (!std::isfinite(swing_mm) || !finite(tool) || !finite(nominal_origin_mm)) return core::Status::kNotFinite;
  if (!(swing_mm >= 0.0 && swing_mm <= rows::kBig) || tool.norm() == 0.0) return core::Status::kArgumentOutOfRange;
  bool nominal = false;
  if (!flag_of(nominal_flag, nominal)) return core::Status::kArgumentOutOfRange;
  parameters_[static_cast<std::size_t>(t) - 1] = {true, swing_mm, tool, nominal,
                                                 nominal ? nominal_origin_mm : core::Vec3::Zero()};
  return core::Status::kOk;
}

std::size_t PointSession::groups() const {
  std::size_t n = 0;
  for (std::size_t g = 0; g < kGroupCount; ++g) n += count_in_[g] > 0 ? 1 : 0;
  return n;
}

bool PointSession::mentions(std::size_t id) const {
  if (parameters_[id - 1].given) return true;
  const std::size_t base = kGlobalGroups + (id - 1) * kSubGroups;
  for (std::size_t g = base; g < base + kSubGroups; ++g) {
    if (count_in_[g] > 0) return true;
  }
  return false;
}

core::Result<core::Vec3> sub_point_mm(const State& state, int id, const core::Vec3& p_global_mm) {
  if (id < 1 || id > static_cast<int>(core::kMaxSubMachines)) return core::Status::kArgumentOutOfRange;
  return state.table.read_or([&](const core::GantryTable& t) {
    const core::StoredSubMachine& s = t.sub_machines[id - 1];
    return s.present ? core::Result<core::Vec3>(core::global_to_sub_mm(s, p_global_mm))
                     : core::Result<core::Vec3>(core::Status::kNoTable);
  });
}

MacroStep run_session_clear(Context& ctx, State&) {
  return report_session(ctx, ctx.open_session());
}

MacroStep run_session_add(Context& ctx, State&) {
  const core::Result<std::size_t> group =
      PointSession::group_of(ctx.in<var::kArgT>(), ctx.in<var::kArgQ>(), ctx.in<var::kArgD>());
  if (!group.ok()) return done(group.status());
  const core::Vec3 p(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>());
  if (!finite(p)) return done(core::Status::kNotFinite);
  if (p.cwiseAbs().maxCoeff() > rows::kBig) return done(core::Status::kArgumentOutOfRange);
  PointSession* s = ctx.session();
  if (s == nullptr) return done(core::Status::kSessionClosed);
  const core::Status status = s->add(group.value(), p);
  if (status != core::Status::kOk) return done(status);
  return report_session(ctx, *s);
}

MacroStep run_parameters(Context& ctx, State&) {
  const core::Vec3 tool(ctx.in<var::kArgI>(), ctx.in<var::kArgJ>(), ctx.in<var::kArgK>());
  PointSession* s = ctx.session();
  if (s == nullptr) return done(core::Status::kSessionClosed);
  const core::Vec3 nominal(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>());
  const core::Status status =
      s->set_parameters(ctx.in<var::kArgT>(), ctx.in<var::kArgD>(), tool, ctx.in<var::kArgQ>(), nominal);
  if (status != core::Status::kOk) return done(status);
  return report_session(ctx, *s);
}

MacroStep run_build(Context& ctx, State& state) {
  bool store = false;
  bool confirmed = false;
  if (!flag_of(ctx.in<var::kArgR>(), store) || !flag_of(ctx.in<var::kArgM>(), confirmed)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  if (ctx.first_step()) {
    const PointSession* session = ctx.session();
    if (session == nullptr) return done(core::Status::kSessionClosed);
    state.built = false;
    Work& work = ctx.open_work();
    gather(*session, work.input);
    // The bed-span gate, before the computation (gates.hpp).
    const double span = bed_span_mm(work.input.bed);
    const double min_span = ctx.in<var::kGantryMinBedSpan>();
    if (work.input.bed.count > 0 && span < min_span) return ctx.refuse(kBedSpanImplausible, 0.0, span, min_span);
    work.bed_span_mm = span;
    for (std::size_t i = 0; i < work.input.sub_machine_count; ++i) {
      if (!session->parameters(static_cast<std::size_t>(work.input.sub_machines[i].id)).given) {
        return done(core::Status::kMissingGroup);
      }
    }
    // The swing gate: a length in metres reads 1000 times short (gates.hpp).
    const double min_swing = ctx.in<var::kGantryMinSwing>();
    for (std::size_t i = 0; i < work.input.sub_machine_count; ++i) {
      const core::SubMachineInput& sub = work.input.sub_machines[i];
      if (sub.swing_mm < min_swing) return ctx.refuse(kSwingImplausible, sub.id, sub.swing_mm, min_swing);
    }
    core::GantryOptions options;
    options.min_arc_deg = ctx.in<var::kGantryMinArc>();
    // The tracker's stated noise (#701, #702) in its data sheet's form a + b r,
    // the tracker at the points' origin.
    options.instrument = {ctx.in<var::kGantryTrackerNoise>(), ctx.in<var::kGantryTrackerNoisePerM>() / 1000.0,
                          core::Vec3::Zero(), true};
    work.builder.start(work.input, options, work.frames);
    return more();
  }
  Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);  // cannot happen: one macro at a time
  if (!work->computed) {
    const core::GantryStep step = work->builder.step();
    if (step.status != core::Status::kOk) return done(step.status);
    // The outputs, the merge and the record take a step of their own, so the
    // last sub-machine's frame and the record's encoding never share one.
    work->computed = !step.more;
    return more();
  }

  const core::GantryFrames& f = work->frames;
  double worst = 0.0;
  for (std::size_t i = 0; i < f.sub_machine_count; ++i) {
    worst = std::fmax(worst, f.sub_machines[i].uncertainty.origin_sigma_mm);
  }
  ctx.out<var::kGantryBuilt>(static_cast<double>(f.sub_machine_count));
  ctx.out<var::kGantryWorstOriginSigma>(worst);
  ctx.out<var::kGantryBuildFlatness>(f.global.bed_flatness_mm);
  ctx.out<var::kGantryBuildStraightness>(f.global.gantry_straightness_mm);
  // The fit gate on every sub-machine's C and A circles (gates.hpp).
  FitGate fit(ctx.in<var::kGateConfidence>());
  const double noise_a = ctx.in<var::kGantryTrackerNoise>();
  const double noise_b = ctx.in<var::kGantryTrackerNoisePerM>() / 1000.0;
  for (std::size_t i = 0; i < f.sub_machine_count; ++i) {
    const core::SubMachineInput& in = work->input.sub_machines[i];
    consider_circle(fit, f.sub_machines[i].id, f.sub_machines[i].c_circle, in.c_circle, noise_a, noise_b);
    consider_circle(fit, f.sub_machines[i].id, f.sub_machines[i].a_circle, in.a_circle, noise_a, noise_b);
  }
  if (fit.refused()) return ctx.refuse(core::Status::kFitBeyondNoise, static_cast<double>(fit.item()), fit.ratio(), 1.0);
  // The nominal-origin gate: the measured origin where the drawing puts it (gates.hpp).
  const PointSession* session = ctx.session();
  const double max_offset = ctx.in<var::kGantryMaxNominalOffset>();
  for (std::size_t i = 0; session != nullptr && i < f.sub_machine_count; ++i) {
    const SubMachineParameters& p = session->parameters(static_cast<std::size_t>(f.sub_machines[i].id));
    const double offset = (f.sub_machines[i].global_T_sub.t - p.nominal_origin_mm).norm();
    if (p.nominal_given && !(offset <= max_offset)) {
      return ctx.refuse(kOriginOffNominal, static_cast<double>(f.sub_machines[i].id), offset, max_offset);
    }
  }
  // The change gate against the stored frames (gates.hpp).
  const Change change = change_against(state, f);
  const double max_origin = ctx.in<var::kGantryMaxOriginChange>();
  const double max_angle = ctx.in<var::kGantryMaxAngleChange>();
  if (store && !confirmed) {
    if (change.origin_mm > max_origin) {
      return ctx.refuse(core::Status::kChangeBeyondLimit, change.origin_id, change.origin_mm, max_origin);
    }
    if (change.angle_arcsec > max_angle) {
      return ctx.refuse(core::Status::kChangeBeyondLimit, change.angle_id, change.angle_arcsec, max_angle);
    }
  }
  ctx.out<var::kGantryOriginChange>(change.origin_mm);
  ctx.out<var::kGantryOriginChangeId>(change.origin_id);
  ctx.out<var::kGantryAngleChange>(change.angle_arcsec);
  ctx.out<var::kGantryAngleChangeId>(change.angle_id);
  ctx.out<var::kGantryBedSpan>(work->bed_span_mm);
  ctx.out<var::kGantryFitRatio>(fit.ratio());
  ctx.out<var::kGantryFitSubMachine>(static_cast<double>(fit.item()));
  // The measuring log: the bed's and the gantry's form errors (kLogFigureKinds).
  LogEntry entry;
  entry.add(kLogBedForm, 0, f.global.bed_form_error_mm, f.global.bed_form_error_sigma_mm);
  entry.add(kLogGantryForm, 0, f.global.gantry_form_error_mm, f.global.gantry_form_error_sigma_mm);
  ctx.log(entry);
  ctx.set_on_success(state.built);
  if (!store) return done(core::Status::kOk);
  // The stored frames (if any) with this computation merged in (gantry_table.hpp).
  reset(work->merged);
  state.table.read([&](const core::GantryTable& t) { work->merged = t; });
  core::merge_frames(work->merged, f);
  return done(ctx.stage_table(state.table, work->merged));  // the module commits it, then makes it live
}

MacroStep run_global(Context& ctx, State& state) {
  bool stored = false;
  if (!flag_of(ctx.in<var::kArgR>(), stored)) return done(core::Status::kArgumentOutOfRange);
  return with_frames(ctx, state, stored, [&](const core::GantryTable& t) {
    return report_global(ctx, t.global, t.count(), t.id_mask());
  });
}

MacroStep run_convert(Context& ctx, State& state) {
  const double t = ctx.in<var::kArgT>();
  if (!whole_in(t, 1.0, core::kMaxSubMachines)) return done(core::Status::kArgumentOutOfRange);
  const core::Vec3 p(ctx.in<var::kArgX>(), ctx.in<var::kArgY>(), ctx.in<var::kArgZ>());
  if (!finite(p)) return done(core::Status::kNotFinite);
  const core::Result<core::Vec3> r = sub_point_mm(state, static_cast<int>(t), p);
  if (!r.ok()) return done(r.status());
  ctx.out3<var::kGantryPointX>(r.value());
  return done(core::Status::kOk);
}

MacroStep run_sub(Context& ctx, State& state) {
  bool stored = false;
  const double t = ctx.in<var::kArgT>();
  if (!flag_of(ctx.in<var::kArgR>(), stored) || !whole_in(t, 1.0, core::kMaxSubMachines)) {
    return done(core::Status::kArgumentOutOfRange);
  }
  const auto id = static_cast<std::size_t>(t);
  return with_frames(ctx, state, stored, [&](const core::GantryTable& table) {
    const core::StoredSubMachine& s = table.sub_machines[id - 1];
    return s.present ? report_sub(ctx, s) : done(core::Status::kNoTable);
  });
}

}  // namespace trueaxis::macros::gantry

namespace trueaxis::macros::gantry {

MacroStep run_check(Context& ctx, State& state) {
  if (!state.built) return done(core::Status::kNoTable);
  const Work* work = ctx.work();
  if (work == nullptr) return done(core::Status::kResultReplaced);
  const core::GantryFrames& built = work->frames;
  const double origin_tolerance = ctx.in<var::kGantryCheckOrigin>();
  const double angle_tolerance = ctx.in<var::kGantryCheckAngle>();
  return state.table.read_or([&](const core::GantryTable& stored) {
    // The computation's sub-machines the stored frames hold, in id order.
    const auto in_both = [&](std::size_t i) {
      const int id = built.sub_machines[i].id;
      return id >= 1 && id <= static_cast<int>(core::kMaxSubMachines) && stored.sub_machines[id - 1].present;
    };
    std::size_t subs = 0;
    for (std::size_t i = 0; i < built.sub_machine_count; ++i) subs += in_both(i) ? 1U : 0U;
    return publish_check(ctx, 2 * subs, [&](std::size_t k) {
      CheckFigure f;
      std::size_t n = 0;
      for (std::size_t i = 0; i < built.sub_machine_count; ++i) {
        if (!in_both(i) || k / 2 != n++) continue;
        const core::StoredSubMachine now = core::stored_sub_machine(built.sub_machines[i]);
        const core::StoredSubMachine& was = stored.sub_machines[built.sub_machines[i].id - 1];
        f.item = static_cast<std::uint16_t>(built.sub_machines[i].id);
        if (k % 2 == 0) {
          f.kind = kCheckOrigin;
          f.stored = was.global_T_sub.t.norm();
          f.measured = now.global_T_sub.t.norm();
          f.deviation = (now.global_T_sub.t - was.global_T_sub.t).norm();
          f.sigma = std::sqrt((now.origin_sigma_mm * now.origin_sigma_mm + was.origin_sigma_mm * was.origin_sigma_mm) / 3.0);
          f.tolerance = origin_tolerance;
        } else {
          f.kind = kCheckAngle;
          f.measured = f.deviation = turn_arcsec(now.global_T_sub.R, was.global_T_sub.R);
          f.sigma = std::sqrt((now.angle_sigma_arcsec.squaredNorm() + was.angle_sigma_arcsec.squaredNorm()) / 3.0);
          f.tolerance = angle_tolerance;
        }
        break;
      }
      return f;
    });
  });
}

}  // namespace trueaxis::macros::gantry
