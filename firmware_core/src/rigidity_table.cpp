#include "trueaxis/core/rigidity_table.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "rigidity_pipeline.hpp"

namespace trueaxis::core {

namespace {

constexpr std::size_t kDirectionsPerPose = 6;  // 5 of the centre-normal block, 1 of the phase

bool valid_arc_option(double deg) { return deg >= 0.0 && deg < 360.0; }

double mod_360(double deg) {
  const double m = std::fmod(deg, 360.0);
  return m < 0.0 ? m + 360.0 : m;  // fmod's result is exact; m + 360 may round to 360
}

// Distinct values of `sorted` (ascending, in [0, 360)) taken circularly: values
// closer than kPoseAToleranceDeg count once.
std::size_t distinct_on_circle(const double* sorted, std::size_t n) {
  if (n == 0) return 0;
  std::size_t distinct = 1;
  for (std::size_t k = 1; k < n; ++k) {
    if (sorted[k] - sorted[k - 1] > kPoseAToleranceDeg) ++distinct;
  }
  if (distinct > 1 && sorted[0] + 360.0 - sorted[n - 1] <= kPoseAToleranceDeg) --distinct;
  return distinct;
}

}  // namespace

void RigidityBuilder::start(const RigiditySample* samples, std::size_t count, const RigidityOptions& options) {
  samples_ = samples;
  count_ = count;
  options_ = options;
  phase_ = Phase::kGroup;
  cursor_ = 0;
  steps_ = 0;
  failed_pose_ = 0;
  final_status_ = Status::kOk;
  first_seen_count_ = 0;
  eigen_pose_ = kMaxAPoses;
  plus_done_ = false;
  table_.pose_count = 0;  // no 5.5 kB temporary on a firmware stack
}

RigidityStep RigidityBuilder::fail(Status s, std::size_t pose_index_plus_one) {
  phase_ = Phase::kFailed;
  final_status_ = s;
  failed_pose_ = pose_index_plus_one;
  return {s, false};
}

RigidityStep RigidityBuilder::step() {
  if (phase_ == Phase::kIdle) return {Status::kArgumentOutOfRange, false};
  if (phase_ == Phase::kDone || phase_ == Phase::kFailed) return {final_status_, false};
  ++steps_;
  switch (phase_) {
    case Phase::kGroup: return step_group();
    case Phase::kSort: return step_sort();
    case Phase::kFit: return step_fit();
    case Phase::kNominal: return step_nominal();
    case Phase::kJacobian: return step_jacobian();
    default: return step_finish();
  }
}

RigidityStep RigidityBuilder::step_group() {
  if (cursor_ == 0) {
    if (!std::isfinite(options_.min_c_arc_deg) || !std::isfinite(options_.min_a_arc_deg)) {
      return fail(Status::kNotFinite);
    }
    if (!valid_arc_option(options_.min_c_arc_deg) || !valid_arc_option(options_.min_a_arc_deg)) {
      return fail(Status::kArgumentOutOfRange);
    }
    if (samples_ == nullptr && count_ > 0) return fail(Status::kArgumentOutOfRange);
    if (count_ > kMaxRigiditySamples) return fail(Status::kTooManyPoints);
  }
  const std::size_t end = std::min(cursor_ + kGroupChunk, count_);
  for (std::size_t k = cursor_; k < end; ++k) {
    const RigiditySample& s = samples_[k];
    if (!std::isfinite(s.a_deg) || !std::isfinite(s.c_deg) || !all_finite(s.p_mm)) return fail(Status::kNotFinite);
    std::size_t pose = 0;
    while (pose < first_seen_count_ && !(std::abs(s.a_deg - first_seen_a_deg_[pose]) <= kPoseAToleranceDeg)) ++pose;
    if (pose == first_seen_count_) {
      if (first_seen_count_ == kMaxAPoses) return fail(Status::kTooManyPoses);
      first_seen_a_deg_[first_seen_count_++] = s.a_deg;
    }
    pose_of_sample_[k] = static_cast<std::uint8_t>(pose);
    c_mod_360_[k] = mod_360(s.c_deg);
  }
  cursor_ = end;
  if (cursor_ == count_) phase_ = Phase::kSort;
  return {Status::kOk, true};
}

RigidityStep RigidityBuilder::step_sort() {
  const std::size_t m = first_seen_count_;
  if (m < kMinAPoses) return fail(Status::kTooFewPoses);
  // Rank of each first-seen pose by A (the A values are distinct: a pose is new
  // only when its A is farther than the tolerance from every earlier one).
  for (std::size_t i = 0; i < m; ++i) {
    std::size_t rank = 0;
    for (std::size_t j = 0; j < m; ++j) rank += first_seen_a_deg_[j] < first_seen_a_deg_[i] ? 1 : 0;
    sorted_of_first_seen_[i] = static_cast<std::uint8_t>(rank);
    fits_[rank] = PoseFit{};
    fits_[rank].a_deg = first_seen_a_deg_[i];
  }
  std::size_t reference = m;
  for (std::size_t r = 0; r < m; ++r) {
    if (std::abs(fits_[r].a_deg) <= kPoseAToleranceDeg &&
        (reference == m || std::abs(fits_[r].a_deg) < std::abs(fits_[reference].a_deg))) {
      reference = r;
    }
  }
  if (reference == m) return fail(Status::kNoReferencePose);
  for (std::size_t k = 0; k < count_; ++k) ++fits_[sorted_of_first_seen_[pose_of_sample_[k]]].count;
  table_.pose_count = m;
  table_.reference = reference;
  table_.home_identity = options_.home_identity;
  phase_ = Phase::kFit;
  cursor_ = 0;
  return {Status::kOk, true};
}

RigidityStep RigidityBuilder::step_fit() {
  const std::size_t r = cursor_;
  PoseFit& pf = fits_[r];
  if (pf.count > kMaxCirclePoints || pf.count > options_.max_pose_samples) {
    return fail(Status::kTooManyPoints, r + 1);
  }
  std::size_t n = 0;
  for (std::size_t k = 0; k < count_; ++k) {
    if (sorted_of_first_seen_[pose_of_sample_[k]] == r) pose_samples_[n++] = static_cast<std::uint16_t>(k);
  }
  // By C: the distinct count needs the order, and the fit's orientation evidence
  // (consecutive samples) is strongest along it.
  std::sort(pose_samples_, pose_samples_ + n,
            [this](std::uint16_t a, std::uint16_t b) { return c_mod_360_[a] < c_mod_360_[b]; });
  for (std::size_t k = 0; k < n; ++k) angles_deg_[k] = c_mod_360_[pose_samples_[k]];
  if (distinct_on_circle(angles_deg_, n) < kMinCPositions) return fail(Status::kTooFewCPositions, r + 1);
  for (std::size_t k = 0; k < n; ++k) {
    points_[k] = samples_[pose_samples_[k]].p_mm;
    angles_deg_[k] = samples_[pose_samples_[k]].c_deg;
  }

  CircleFitOptions options;
  options.angles_deg = angles_deg_;
  options.min_arc_deg = options_.min_c_arc_deg;
  const Status fitted = fit_circle(points_, n, options, work_.circle_work, work_.circle);
  if (fitted != Status::kOk) return fail(fitted, r + 1);
  const CircleFit& fit = work_.circle;
  const Result<CircularMean> phase = circle_phase_offset_rad(fit, points_, angles_deg_, n);
  if (!phase.ok()) return fail(phase.status(), r + 1);
  if (!(phase.value().resultant_length >= kMinPhaseResultant)) return fail(Status::kCPhaseInconsistent, r + 1);

  pf.centre = fit.centre_mm;
  pf.normal = fit.normal;
  pf.x_axis = circle_direction(fit, phase.value().mean_rad);
  pf.axis_u = fit.axis_u;
  pf.axis_v = fit.axis_v;
  pf.covariance = fit.covariance.topLeftCorner<5, 5>();
  pf.phase_sigma_rad = phase.value().standard_error_rad;
  pf.rms_mm = fit.rms_distance_mm;
  pf.arc_deg = fit.arc_deg;

  if (++cursor_ == table_.pose_count) phase_ = Phase::kNominal;
  return {Status::kOk, true};
}

RigidityStep RigidityBuilder::step_nominal() {
  const std::size_t m = table_.pose_count;
  detail::RigidityPoseFrame* frames = work_.frames;
  for (std::size_t i = 0; i < m; ++i) frames[i] = {fits_[i].a_deg, fits_[i].centre, fits_[i].normal, fits_[i].x_axis};
  const Status s = detail::evaluate_rigidity(frames, m, table_.reference, options_.min_a_arc_deg, scratch_, work_);
  if (s != Status::kOk) return fail(s);

  table_.a_axis_point_mm = scratch_.a_point;
  table_.a_axis_direction = scratch_.a_direction;
  table_.c_to_a_offset_mm = scratch_.offset_mm;
  table_.c_to_a_squareness_rad = scratch_.squareness_rad;
  for (std::size_t i = 0; i < m; ++i) {
    RigidityPose& p = table_.poses[i];
    const PoseFit& f = fits_[i];
    p.a_deg = f.a_deg;
    p.rotvec_rad = scratch_.rotvec[i];
    p.rigidity_rad = scratch_.rotvec[i].norm();
    p.theta_rad = scratch_.theta[i];
    p.a_error_rad = scratch_.a_error[i];
    p.origin_offset_mm = scratch_.origin_offset[i];
    p.c_centre_mm = f.centre;
    p.c_direction = f.normal;
    p.c_x_axis = f.x_axis;
    p.c_circle_rms_mm = f.rms_mm;
    p.c_arc_deg = f.arc_deg;
    p.c_count = f.count;
    // step_finish sets them for every pose but the reference, whose 0 is
    // exact: none may survive from the builder's last table.
    p.rotvec_sigma_rad = Vec3::Zero();
    p.rigidity_sigma_rad = 0.0;
    p.a_error_sigma_rad = 0.0;
    rotvec_cov_[i] = Mat3::Zero();
    a_error_var_[i] = 0.0;
  }
  offset_var_ = 0.0;
  squareness_var_ = 0.0;
  phase_ = Phase::kJacobian;
  cursor_ = 0;
  plus_done_ = false;
  eigen_pose_ = kMaxAPoses;
  return {Status::kOk, true};
}

// The central difference of one column, one side per step: an evaluation is an
// A-axis circle fit plus m frames, the step's unit of work.
RigidityStep RigidityBuilder::step_jacobian() {
  const std::size_t columns = kDirectionsPerPose * table_.pose_count;
  while (cursor_ < columns) {
    const std::size_t pose = cursor_ / kDirectionsPerPose;
    const std::size_t direction = cursor_ % kDirectionsPerPose;
    if (eigen_pose_ != pose) {
      eigen_.compute(fits_[pose].covariance);
      eigen_pose_ = pose;
    }
    const double sigma = direction < 5 ? std::sqrt(std::max(0.0, eigen_.eigenvalues()(static_cast<Eigen::Index>(direction))))
                                       : fits_[pose].phase_sigma_rad;
    if (!(sigma > 0.0)) {
      ++cursor_;
      continue;
    }
    const double h = std::max(sigma, kJacobianMinStep);
    if (!plus_done_) {
      const Status s = evaluate_perturbed(h, plus_);
      if (s != Status::kOk) return fail(s);
      plus_done_ = true;
      return {Status::kOk, true};
    }
    const Status s = evaluate_perturbed(-h, scratch_);
    if (s != Status::kOk) return fail(s);
    const double scale = sigma / (2.0 * h);
    for (std::size_t i = 0; i < table_.pose_count; ++i) {
      const Vec3 d = (plus_.rotvec[i] - scratch_.rotvec[i]) * scale;
      rotvec_cov_[i] += d * d.transpose();
      const double e = (plus_.a_error[i] - scratch_.a_error[i]) * scale;
      a_error_var_[i] += e * e;
    }
    const double d_offset = (plus_.offset_mm - scratch_.offset_mm) * scale;
    const double d_square = (plus_.squareness_rad - scratch_.squareness_rad) * scale;
    offset_var_ += d_offset * d_offset;
    squareness_var_ += d_square * d_square;
    plus_done_ = false;
    ++cursor_;
    return {Status::kOk, true};
  }
  phase_ = Phase::kFinish;
  return {Status::kOk, true};
}

Status RigidityBuilder::evaluate_perturbed(double signed_step, detail::RigidityEvaluation& out) {
  const std::size_t m = table_.pose_count;
  const std::size_t pose = cursor_ / kDirectionsPerPose;
  const std::size_t direction = cursor_ % kDirectionsPerPose;
  detail::RigidityPoseFrame* frames = work_.frames;
  for (std::size_t i = 0; i < m; ++i) frames[i] = {fits_[i].a_deg, fits_[i].centre, fits_[i].normal, fits_[i].x_axis};

  const PoseFit& f = fits_[pose];
  detail::RigidityPoseFrame& p = frames[pose];
  Vec3 x = f.x_axis;
  if (direction < 5) {
    const Eigen::Matrix<double, 5, 1> dx = signed_step * eigen_.eigenvectors().col(static_cast<Eigen::Index>(direction));
    p.centre = f.centre + dx.head<3>();
    p.normal = (f.normal + dx(3) * f.axis_u + dx(4) * f.axis_v).normalized();
  } else {
    x = std::cos(signed_step) * f.x_axis + std::sin(signed_step) * f.normal.cross(f.x_axis);
  }
  // X follows its plane by the smallest rotation (convention 7).
  p.x_axis = (x - x.dot(p.normal) * p.normal).normalized();
  // The arc was judged on the nominal data; a perturbation must not flip it.
  return detail::evaluate_rigidity(frames, m, table_.reference, 0.0, out, work_);
}

RigidityStep RigidityBuilder::step_finish() {
  for (std::size_t i = 0; i < table_.pose_count; ++i) {
    RigidityPose& p = table_.poses[i];
    if (i == table_.reference) continue;  // exactly 0 (convention 5)
    const Mat3& cov = rotvec_cov_[i];
    p.rotvec_sigma_rad = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
    const double isotropic = std::sqrt(std::max(0.0, cov.trace() / 3.0));
    double along = isotropic;
    if (p.rigidity_rad > 0.0) {
      const Vec3 u = p.rotvec_rad / p.rigidity_rad;
      along = std::sqrt(std::max(0.0, u.dot(cov * u)));
    }
    p.rigidity_sigma_rad = p.rigidity_rad < along ? isotropic : along;
    p.a_error_sigma_rad = std::sqrt(a_error_var_[i]);
  }
  table_.c_to_a_offset_sigma_mm = std::sqrt(offset_var_);
  table_.c_to_a_squareness_sigma_rad = std::sqrt(squareness_var_);
  prepare_rigidity_table(table_, spline_work_);
  phase_ = Phase::kDone;
  final_status_ = Status::kOk;
  return {Status::kOk, false};
}

Status build_rigidity_table(const RigiditySample* samples, std::size_t count, const RigidityOptions& options,
                            RigidityBuilder& builder) {
  builder.start(samples, count, options);
  for (;;) {
    const RigidityStep s = builder.step();
    if (!s.more) return s.status;
  }
}

}  // namespace trueaxis::core
