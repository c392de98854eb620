#include "trueaxis/core/gantry_frames.hpp"

#include <Eigen/Eigenvalues>

#include "trueaxis/core/form_noise.hpp"
#include "trueaxis/core/so3.hpp"

namespace trueaxis::core {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// (t, phi) of `moved` relative to `nominal`: moved.R = nominal.R exp([phi]x).
Vec6 frame_delta(const Rigid3& nominal, const Rigid3& moved) {
  Vec6 d;
  d.head<3>() = moved.t - nominal.t;
  d.tail<3>() = so3_log(nominal.R.transpose() * moved.R);
  return d;
}

// Stack (docs/FIGURES.md "Stack"): the solvers and the covariances are the builder's
// (GantryBuilder's scratch members, passed in), and the functions marked
// noinline keep their temporaries out of their callers' frames, so that
// step()'s deepest call (a perturbed sub-machine frame) does not carry them.
// [[gnu::noinline]] is ignored by compilers that do not know it.

void summarise(const Mat6& cov, FrameUncertainty& u) {
  u.covariance = cov;
  u.origin_sigma_mm = std::sqrt(std::max(0.0, cov.topLeftCorner<3, 3>().trace()));
  for (int k = 0; k < 3; ++k) u.angle_sigma_arcsec(k) = kArcsecPerRad * std::sqrt(std::max(0.0, cov(3 + k, 3 + k)));
}

template <int N>
using Eigensolver = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>>;

// A sub-machine's frame with its diagnostics (convention 7).
struct SubSample {
  Rigid3 frame;
  Vec5 figures = Vec5::Zero();
};

const Rigid3& frame_of(const Rigid3& f) { return f; }
const Rigid3& frame_of(const SubSample& s) { return s.frame; }
void add_figures(const Rigid3&, const Rigid3&, Vec5&) {}
void add_figures(const SubSample& plus, const SubSample& minus, Vec5& var) {
  const Vec5 g = 0.5 * (plus.figures - minus.figures);
  var += g.cwiseProduct(g);
}

// Adds sum_k g_k g_k^T over the eigenvectors of a fit's covariance (convention 5),
// and for a SubSample its figures' g_k^2 to `figure_var` (convention 7);
// eval(delta, sample) recomputes the frame with the fit's parameters moved by
// delta. `es`: scratch.
template <int N, typename Sample, typename Eval>
[[gnu::noinline]] Status add_sensitivity(const Eigen::Matrix<double, N, N>& cov, const Rigid3& nominal, Eval eval,
                                         Mat6& acc, Vec5& figure_var, Eigensolver<N>& es) {
  es.compute(cov);
  if (es.info() != Eigen::Success) return Status::kNotFinite;
  for (int k = 0; k < N; ++k) {
    const double lambda = es.eigenvalues()(k);
    if (!(lambda > 0.0)) continue;
    const Eigen::Matrix<double, N, 1> step = std::sqrt(lambda) * es.eigenvectors().col(k);
    Sample plus;
    Sample minus;
    Status status = eval(step, plus);
    if (status != Status::kOk) return status;
    status = eval(Eigen::Matrix<double, N, 1>(-step), minus);
    if (status != Status::kOk) return status;
    const Vec6 g = 0.5 * (frame_delta(nominal, frame_of(plus)) - frame_delta(nominal, frame_of(minus)));
    acc += g * g.transpose();
    add_figures(plus, minus, figure_var);
  }
  return Status::kOk;
}

// Convention 7, cheap enough for every perturbed build (no inverse
// trigonometry: docs/GUIDE.md "Macros that take several steps"): the cosines of
// the three squareness angles and of the A-to-C angle, and the signed A-to-C
// offset along unit(a x c). d(angle) = -d(cos) / sin: sub_into_global divides
// the cosines' variances by sin^2 of the nominal angles.
Vec5 figures_of(const Vec3 dirs[3], const Line3& c, const Line3& a) {
  const Vec3 m = a.direction.cross(c.direction);
  Vec5 f;
  f << dirs[0].dot(dirs[1]), dirs[1].dot(dirs[2]), dirs[2].dot(dirs[0]),
      (a.point_mm - c.point_mm).dot(m) / m.norm(), a.direction.dot(c.direction);
  return f;
}

// The RMS of the stated sigma_i over groups of points and (mean sigma_i^4)^(1/4)
// (convention 8, form_noise.hpp item 5).
struct NoiseMoments {
  double rms_mm = 0.0;
  double quartic_mm = 0.0;
};

NoiseMoments noise_moments(const PointNoise& noise, const PointSpan* groups, std::size_t group_count) {
  NoiseMoments m;
  if (!noise.modelled()) return m;
  double sum2 = 0.0;
  double sum4 = 0.0;
  std::size_t n = 0;
  for (std::size_t g = 0; g < group_count; ++g) {
    for (std::size_t i = 0; i < groups[g].count; ++i) {
      const double s = noise.sigma_mm(groups[g].points_mm[i]);
      sum2 += s * s;
      sum4 += s * s * s * s;
    }
    n += groups[g].count;
  }
  if (n == 0) return m;
  m.rms_mm = std::sqrt(sum2 / static_cast<double>(n));
  m.quartic_mm = std::sqrt(std::sqrt(sum4 / static_cast<double>(n)));
  return m;
}

// Convention 8, into `out`.
[[gnu::noinline]] void form_figures(const GantryInput& in, const GantryOptions& opt, const PlaneEstimate& bed,
                                    const AxisEstimate& gantry, GlobalFrame& out) {
  const PointNoise& noise = opt.instrument.modelled() ? opt.instrument : opt.noise;
  const NoiseMoments bed_noise = noise_moments(noise, &in.bed, 1);
  const NoiseMoments gantry_noise = noise_moments(noise, in.gantry_passes, in.gantry_pass_count);
  const double s_bed = bed_noise.rms_mm;
  const double s_gantry = gantry_noise.rms_mm;
  const std::size_t bed_dof = plane_residual_dof(bed.count);
  std::size_t gantry_dof = 0;
  for (std::size_t k = 0; k < in.gantry_pass_count; ++k) gantry_dof += line_residual_dof(in.gantry_passes[k].count);
  const std::size_t gantry_count = gantry.point_count;
  out.bed_flatness_noise_floor_mm = flatness_noise_floor_mm(bed.count, bed_dof, s_bed);
  out.gantry_straightness_noise_floor_mm = straightness_noise_floor_mm(gantry_count, gantry_dof, s_gantry);
  const FormError bed_form = form_error(bed.rms_residual_mm, bed.count, bed_dof, s_bed, bed_noise.quartic_mm);
  const double gantry_rms =
      gantry_count > 0 ? std::sqrt(gantry.residual_ssr_mm2 / static_cast<double>(gantry_count)) : 0.0;
  const FormError gantry_form = form_error(gantry_rms, gantry_count, gantry_dof, s_gantry, gantry_noise.quartic_mm);
  out.bed_form_error_mm = bed_form.form_mm;
  out.bed_form_error_sigma_mm = bed_form.sigma_mm;
  out.gantry_form_error_mm = gantry_form.form_mm;
  out.gantry_form_error_sigma_mm = gantry_form.sigma_mm;
}

template <typename T>
Status take(const Result<T>& r, T& out) {
  if (r.ok()) out = r.value();
  return r.status();
}

Status check_options(const GantryOptions& o) {
  Status status = check_noise(o.noise);
  if (status != Status::kOk) return status;
  if ((status = check_noise(o.instrument)) != Status::kOk) return status;
  if (std::isnan(o.min_arc_deg) || std::isnan(o.min_ac_sin)) return Status::kNotFinite;
  if (!(o.min_arc_deg >= 0.0 && o.min_arc_deg < 360.0) || !(o.min_ac_sin > 0.0 && o.min_ac_sin <= 1.0)) {
    return Status::kArgumentOutOfRange;
  }
  return Status::kOk;
}

Status check_ids(const GantryInput& in) {
  if (in.sub_machine_count == 0) return Status::kMissingGroup;
  if (in.sub_machine_count > kMaxSubMachines) return Status::kTooManyPoints;
  for (std::size_t i = 0; i < in.sub_machine_count; ++i) {
    const int id = in.sub_machines[i].id;
    if (id < 1 || id > static_cast<int>(kMaxSubMachines)) return Status::kArgumentOutOfRange;
    for (std::size_t j = 0; j < i; ++j) {
      if (in.sub_machines[j].id == id) return Status::kArgumentOutOfRange;
    }
  }
  return Status::kOk;
}

// S1 from the four fits, with its uncertainty (convention 5); `cov` and `es`: scratch.
[[gnu::noinline]] Status global_from_fits(const PlaneEstimate& bed, const PlaneEstimate& side_1,
                                          const PlaneEstimate& side_2, const AxisEstimate& gantry, GlobalFrame& out,
                                          Mat6& cov, Eigensolver<3>& es) {
  Status status = Status::kOk;
  const Vec3 zero = Vec3::Zero();
  const Plane3 p_bed = perturbed_plane(bed, zero);
  const Plane3 p_1 = perturbed_plane(side_1, zero);
  const Plane3 p_2 = perturbed_plane(side_2, zero);
  Rigid3 nominal;
  if ((status = take(global_frame_from(p_bed, p_1, p_2, gantry.direction), nominal)) != Status::kOk) return status;

  cov.setZero();
  const auto bed_eval = [&](const Vec3& d, Rigid3& f) {
    return take(global_frame_from(perturbed_plane(bed, d), p_1, p_2, gantry.direction), f);
  };
  const auto side_1_eval = [&](const Vec3& d, Rigid3& f) {
    return take(global_frame_from(p_bed, perturbed_plane(side_1, d), p_2, gantry.direction), f);
  };
  const auto side_2_eval = [&](const Vec3& d, Rigid3& f) {
    return take(global_frame_from(p_bed, p_1, perturbed_plane(side_2, d), gantry.direction), f);
  };
  const auto gantry_eval = [&](const Vec3& d, Rigid3& f) {
    return take(global_frame_from(p_bed, p_1, p_2, (gantry.direction + d).normalized()), f);
  };
  Vec5 unused = Vec5::Zero();
  if ((status = add_sensitivity<3, Rigid3>(bed.covariance, nominal, bed_eval, cov, unused, es)) != Status::kOk) {
    return status;
  }
  if ((status = add_sensitivity<3, Rigid3>(side_1.covariance, nominal, side_1_eval, cov, unused, es)) !=
      Status::kOk) {
    return status;
  }
  if ((status = add_sensitivity<3, Rigid3>(side_2.covariance, nominal, side_2_eval, cov, unused, es)) !=
      Status::kOk) {
    return status;
  }
  if ((status = add_sensitivity<3, Rigid3>(gantry.covariance, nominal, gantry_eval, cov, unused, es)) !=
      Status::kOk) {
    return status;
  }

  out.tracker_T_global = nominal;
  out.bed_flatness_mm = bed.flatness_mm;
  out.gantry_straightness_mm = gantry.straightness_mm;
  out.side_1_flatness_mm = side_1.flatness_mm;
  out.side_2_flatness_mm = side_2.flatness_mm;
  summarise(cov, out.uncertainty);
  return Status::kOk;
}

Axis longest_stroke(const AxisEstimate axes[3]) {
  int best = 0;
  for (int k = 1; k < 3; ++k) {
    if (axes[k].stroke_mm > axes[best].stroke_mm) best = k;
  }
  return static_cast<Axis>(best);
}

CircleSummary summarise_circle(const CircleFit& fit, const Vec3& oriented_normal, const Rigid3& global_T_tracker) {
  CircleSummary s;
  s.centre_mm = apply_point(global_T_tracker, fit.centre_mm);
  s.normal = apply_direction(global_T_tracker, oriented_normal);
  s.radius_mm = fit.radius_mm;
  s.rms_distance_mm = fit.rms_distance_mm;
  s.max_distance_mm = fit.max_distance_mm;
  s.arc_deg = fit.arc_deg;
  return s;
}

// Into the global frame, with the global frame's own covariance (convention
// 5): `own` is the sub-machine's in the tracker frame.
[[gnu::noinline]] void sub_into_global(const SubMachineInput& in, const GlobalFrame& global,
                                       const AxisEstimate axes[3], const Vec3 dirs[3], Axis master,
                                       const SubGeometry& nominal, const CircleFit& c_fit, const CircleFit& a_fit,
                                       const Mat6& own, const Vec5& figure_var, SubMachineFrame& out) {
  const Rigid3 global_T_tracker = inverse(global.tracker_T_global);
  const Rigid3 global_T_sub = compose(global_T_tracker, nominal.tracker_T_sub);
  const Mat3 r_g_t = global_T_tracker.R;
  Mat6 j_own = Mat6::Identity();
  j_own.topLeftCorner<3, 3>() = r_g_t;
  Mat6 j_global = Mat6::Zero();
  j_global.topLeftCorner<3, 3>() = -r_g_t;
  j_global.topRightCorner<3, 3>() = hat(global_T_sub.t);
  j_global.bottomRightCorner<3, 3>() = -global_T_sub.R.transpose();
  const Mat6 cov = j_own * own * j_own.transpose() +
                   j_global * global.uncertainty.covariance * j_global.transpose();

  out.id = in.id;
  out.global_T_sub = global_T_sub;
  out.master_axis = master;
  for (int k = 0; k < 3; ++k) {
    out.measured_axes[k] = r_g_t * dirs[k];
    out.stroke_mm[k] = axes[k].stroke_mm;
    out.straightness_mm[k] = axes[k].straightness_mm;
  }
  for (int k = 0; k < 3; ++k) {
    out.squareness_arcsec(k) = kArcsecPerRad * (angle_between(dirs[k], dirs[(k + 1) % 3]) - 0.5 * kPi);
  }
  out.a_c_offset_mm = nominal.a_c_offset_mm;
  out.a_c_angle_deg = nominal.a_c_angle_deg;
  // figure_var holds the cosines' variances (figures_of).
  for (int k = 0; k < 3; ++k) {
    const double sin = dirs[k].cross(dirs[(k + 1) % 3]).norm();
    out.squareness_sigma_arcsec(k) = kArcsecPerRad * std::sqrt(figure_var(k)) / sin;
  }
  out.a_c_offset_sigma_mm = std::sqrt(figure_var(3));
  out.a_c_angle_sigma_deg = std::sqrt(figure_var(4)) / nominal.a.cross(nominal.c).norm() * 180.0 / kPi;
  out.wrist_centre_mm = apply_point(global_T_tracker, nominal.wrist_centre_mm);
  out.c_circle = summarise_circle(c_fit, nominal.c, global_T_tracker);
  out.a_circle = summarise_circle(a_fit, nominal.a, global_T_tracker);
  summarise(cov, out.uncertainty);
}

// The builder's scratch for sub_from_fits.
struct SubScratch {
  Mat6& own;
  Vec5& figure_var;
  Eigensolver<3>& es3;
  Eigensolver<6>& es6;
};

// S2-S4 of one sub-machine from its five fits, with its uncertainty
// (convention 5) and diagnostics.
[[gnu::noinline]] Status sub_from_fits(const SubMachineInput& in, const GantryOptions& opt,
                                       const GlobalFrame& global, const AxisEstimate axes[3], const CircleFit& c_fit,
                                       const CircleFit& a_fit, SubMachineFrame& out, const SubScratch& scratch) {
  Status status = Status::kOk;
  const Axis master = longest_stroke(axes);
  const Vec3 gantry_x = global.tracker_T_global.R.col(0);
  Vec3 dirs[3] = {axes[0].direction, axes[1].direction, axes[2].direction};
  const Line3 c_line{c_fit.centre_mm, c_fit.normal};
  const Line3 a_line{a_fit.centre_mm, a_fit.normal};
  const auto build = [&](const Vec3 d[3], const Line3& c, const Line3& a, SubGeometry& g) {
    return take(sub_frame_from(d, master, c, in.tool_direction, a, in.swing_mm, gantry_x, opt.min_ac_sin), g);
  };
  SubGeometry nominal;
  if ((status = build(dirs, c_line, a_line, nominal)) != Status::kOk) return status;

  Mat6& own = scratch.own;  // tracker-frame origin, rotation about the sub-machine's axes
  own.setZero();
  Vec5& figure_var = scratch.figure_var;
  figure_var.setZero();
  for (int k = 0; k < 3; ++k) {
    const auto eval = [&](const Vec3& d, SubSample& f) {
      Vec3 moved[3] = {dirs[0], dirs[1], dirs[2]};
      moved[k] = (dirs[k] + d).normalized();
      SubGeometry g;
      const Status s = build(moved, c_line, a_line, g);
      f.frame = g.tracker_T_sub;
      f.figures = figures_of(moved, c_line, a_line);
      return s;
    };
    status = add_sensitivity<3, SubSample>(axes[k].covariance, nominal.tracker_T_sub, eval, own, figure_var,
                                           scratch.es3);
    if (status != Status::kOk) return status;
  }
  const auto c_eval = [&](const Vec6& d, SubSample& f) {
    SubGeometry g;
    const Line3 c = perturbed_circle_axis(c_fit, d);
    const Status s = build(dirs, c, a_line, g);
    f.frame = g.tracker_T_sub;
    f.figures = figures_of(dirs, c, a_line);
    return s;
  };
  const auto a_eval = [&](const Vec6& d, SubSample& f) {
    SubGeometry g;
    const Line3 a = perturbed_circle_axis(a_fit, d);
    const Status s = build(dirs, c_line, a, g);
    f.frame = g.tracker_T_sub;
    f.figures = figures_of(dirs, c_line, a);
    return s;
  };
  status = add_sensitivity<6, SubSample>(c_fit.covariance, nominal.tracker_T_sub, c_eval, own, figure_var,
                                         scratch.es6);
  if (status != Status::kOk) return status;
  status = add_sensitivity<6, SubSample>(a_fit.covariance, nominal.tracker_T_sub, a_eval, own, figure_var,
                                         scratch.es6);
  if (status != Status::kOk) return status;
  sub_into_global(in, global, axes, dirs, master, nominal, c_fit, a_fit, own, figure_var, out);
  return Status::kOk;
}

// A fit into the builder's member: the Result is this function's temporary,
// not one in the frame of step().
template <typename T, typename Fit>
[[gnu::noinline]] Status fit_into(Fit fit, T& out) {
  return take(fit(), out);
}

}  // namespace

void GantryBuilder::start(const GantryInput& input, const GantryOptions& options, GantryFrames& out) {
  in_ = &input;
  options_ = options;
  out_ = &out;
  out.sub_machine_count = 0;
  phase_ = Phase::kCheck;
  sub_ = 0;
  steps_ = 0;
  failed_id_ = 0;
}

GantryStep GantryBuilder::fail(Status status) {
  phase_ = Phase::kFailed;
  out_->sub_machine_count = 0;
  return {status, false};
}

GantryStep GantryBuilder::step() {
  if (phase_ == Phase::kIdle || phase_ == Phase::kDone || phase_ == Phase::kFailed) {
    return {phase_ == Phase::kDone ? Status::kOk : Status::kArgumentOutOfRange, false};
  }
  ++steps_;
  const GantryInput& in = *in_;
  const SubMachineInput& sub = in.sub_machines[sub_];
  Status status = Status::kOk;
  switch (phase_) {
    case Phase::kCheck:
      if ((status = check_options(options_)) != Status::kOk) return fail(status);
      if ((status = check_ids(in)) != Status::kOk) return fail(status);
      if (in.gantry_pass_count > kMaxPasses) return fail(Status::kTooManyPoints);
      phase_ = Phase::kBed;
      return {Status::kOk, true};
    case Phase::kBed:
      status = fit_into(
          [&]() -> Result<PlaneEstimate> {
            const Result<PlaneEstimate> bed = fit_plane_group(in.bed, options_.noise);
            if (!bed.ok()) return bed;
            return orient_plane(bed.value(), Vec3::UnitZ());
          },
          bed_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kSide1;
      return {Status::kOk, true};
    case Phase::kSide1:
      status = fit_into([&] { return fit_plane_group(in.side_1, options_.noise); }, side_1_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kSide2;
      return {Status::kOk, true};
    case Phase::kSide2:
      status = fit_into([&] { return fit_plane_group(in.side_2, options_.noise); }, side_2_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kGantry;
      return {Status::kOk, true};
    case Phase::kGantry:
      status = fit_into([&] { return fit_axis_passes(in.gantry_passes, in.gantry_pass_count, options_.noise); },
                        gantry_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kGlobal;
      return {Status::kOk, true};
    case Phase::kGlobal:
      status = global_from_fits(bed_, side_1_, side_2_, gantry_, out_->global, own_, eigen3_);
      if (status != Status::kOk) return fail(status);
      form_figures(in, options_, bed_, gantry_, out_->global);
      phase_ = Phase::kAxisX;
      return {Status::kOk, true};
    case Phase::kAxisX:
    case Phase::kAxisY:
    case Phase::kAxisZ: {
      const int k = static_cast<int>(phase_) - static_cast<int>(Phase::kAxisX);
      failed_id_ = sub.id;
      if (sub.pass_count[k] > kMaxPasses) return fail(Status::kTooManyPoints);
      status = fit_into([&] { return fit_axis_passes(sub.passes[k], sub.pass_count[k], options_.noise); }, axes_[k]);
      if (status != Status::kOk) return fail(status);
      phase_ = static_cast<Phase>(static_cast<int>(phase_) + 1);
      return {Status::kOk, true};
    }
    case Phase::kCircleC:
      failed_id_ = sub.id;
      status = fit_circle_group(sub.c_circle, options_.noise, options_.min_arc_deg, circle_work_, c_fit_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kCircleA;
      return {Status::kOk, true};
    case Phase::kCircleA:
      failed_id_ = sub.id;
      status = fit_circle_group(sub.a_circle, options_.noise, options_.min_arc_deg, circle_work_, a_fit_);
      if (status != Status::kOk) return fail(status);
      phase_ = Phase::kSub;
      return {Status::kOk, true};
    case Phase::kSub:
      failed_id_ = sub.id;
      status = sub_from_fits(sub, options_, out_->global, axes_, c_fit_, a_fit_, out_->sub_machines[sub_],
                             {own_, figure_var_, eigen3_, eigen6_});
      if (status != Status::kOk) return fail(status);
      failed_id_ = 0;
      if (++sub_ < in.sub_machine_count) {
        phase_ = Phase::kAxisX;
        return {Status::kOk, true};
      }
      out_->sub_machine_count = in.sub_machine_count;
      phase_ = Phase::kDone;
      return {Status::kOk, false};
    default:
      return fail(Status::kArgumentOutOfRange);
  }
}

Status compute_gantry_frames(const GantryInput& input, const GantryOptions& options, GantryFrames& out) {
  GantryBuilder builder;
  builder.start(input, options, out);
  GantryStep s;
  do {
    s = builder.step();
  } while (s.more);
  if (s.status != Status::kOk) out = GantryFrames();
  return s.status;
}

}  // namespace trueaxis::core
