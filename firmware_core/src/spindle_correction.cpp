#include "trueaxis/core/spindle_correction.hpp"

#include <cmath>

#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/screw.hpp"

namespace trueaxis::core {

double spindle_phi_rad(double phi_deg) {
  // n = trunc(phi_deg / 360) is fmod's quotient: for phi_deg below a multiple
  // 360 k the correctly rounded quotient never reaches k, since 360 k - phi_deg
  // is at least an ulp of phi_deg, which is at least 2^8 ulps of k, so the true
  // quotient is at least 2^8 / 360 = 0.71 of an ulp of k below k (rounding up
  // to k needs under a half; test_spindle_correction holds it at both sides of
  // every multiple to 360 x 2^17 and of every power of two of k). phi_deg -
  // 360 n is then exact below 2^44 deg (a multiple of phi_deg's ulp, at most
  // 2^-8, under 360 deg) and has phi_deg's sign or is 0, which copysign signs
  // as fmod's result is (-720 gives -0; issue 18).
  double reduced = phi_deg;
  if (!(std::abs(phi_deg) < 360.0)) {
    if (std::abs(phi_deg) < 0x1p44) {
      reduced = std::copysign(phi_deg - 360.0 * std::trunc(phi_deg / 360.0), phi_deg);
    } else {
      reduced = std::fmod(phi_deg, 360.0);
    }
  }
  return deg_to_rad(reduced);
}

namespace {

// R(phi) x for x normal to a (convention 2).
Vec3 turn(const Vec3& a, const Vec3& x, double c, double s) { return c * x + s * a.cross(x); }

template <typename Io, typename Model>
void model_fields(Io& io, Model& m) {
  io(m.fit.params);
  for (int r = 0; r < kSpindleParams; ++r) {
    for (int c = r; c < kSpindleParams; ++c) io(m.fit.covariance(r, c));
  }
  io(m.geometry.gauge_mm);
  io(m.geometry.ball_mm[0]);
  io(m.geometry.ball_mm[1]);
  io(m.fit.rms_mm);
  io(m.fit.synchronous_rms_mm);
  io(m.fit.noise_sigma_mm);
  io(m.fit.smallest_eigenvalue_ratio);
}

// theta_e and d_e (convention 2): the screw error (screw.hpp) from the ideal
// tool line (-Z through the origin) to the actual one through q along d, in
// closed form rather than through plucker_from_point and screw_error (the
// direct correction query's cost, issue 18). With k = (-Z) x d = (d_y, -d_x, 0)
// (exact: no cancellation, unlike a cross product of two unit vectors near 0),
// |k| = |d| sin(theta_e), -d_z = |d| cos(theta_e), so, d of any length:
//   theta_e = atan2(|k|, -d_z);
//   d_e = |q . k| / |k|, the component of q along the common perpendicular
//   k / |k| (screw_error's |w . axis|: w = q minus its part along d, normal to k).
// screw_error's parallel branch (screw.hpp convention 5), taken at its
// threshold |k| / |d| < kParallelSin (compared squared): d_e = |q x d| / |d|,
// the distance of the origin from the actual line (for k = 0 exactly, q's
// distance from the Z axis), theta_e still the atan2 (0 or pi when exactly
// parallel). Status codes as plucker_from_point's and screw_error's: kNotFinite
// for a non-finite q or d, kArgumentOutOfRange for a zero d and for
// coordinates so large that d_e overflows (screw_error: that a foot does; near
// 1e300 mm, no machine's). A d whose squared length leaves [2^-100, 2^100] is first scaled by
// its largest component, as plucker_from_point does (never here: |d| >= 1 for a
// unit a, d - a normal to it). Not inlined ([[gnu::noinline]]; ignored by
// compilers that do not know it): its temporaries stay out of
// spindle_correction's frame (docs/FIGURES.md "Stack").
[[gnu::noinline]] Status tool_line_error(const Vec3& q, const Vec3& d_in, SpindleCorrection& out) {
  if (!all_finite(q) || !all_finite(d_in)) return Status::kNotFinite;
  Vec3 d = d_in;
  double k2 = d.x() * d.x() + d.y() * d.y();  // |k|^2
  double dd = k2 + d.z() * d.z();             // |d|^2
  if (!(dd >= 0x1p-100 && dd <= 0x1p100)) {
    const double largest = d.cwiseAbs().maxCoeff();
    if (!(largest > 0.0)) return Status::kArgumentOutOfRange;
    d /= largest;
    k2 = d.x() * d.x() + d.y() * d.y();
    dd = k2 + d.z() * d.z();
  }
  const double k = std::sqrt(k2);
  out.theta_e_rad = std::atan2(k, -d.z());
  out.d_e_mm = k2 < kParallelSin * kParallelSin * dd ? std::sqrt(q.cross(d).squaredNorm() / dd)
                                                      : std::abs(q.x() * d.y() - q.y() * d.x()) / k;
  if (!std::isfinite(out.d_e_mm)) return Status::kArgumentOutOfRange;
  return Status::kOk;
}

constexpr std::size_t kHeaderBytes = 24;
constexpr std::size_t kRealCount = 9 + 45 + 3 + 4;
static_assert(kHeaderBytes + 8 * kRealCount == kSpindleModelBytes, "convention 5's layout");

}  // namespace

Result<SpindleCorrection> spindle_correction(const SpindleAxes& x, double gauge_mm, double tool_mm,
                                             double phi_rad) {
  if (!std::isfinite(gauge_mm) || !std::isfinite(tool_mm) || !std::isfinite(phi_rad)) return Status::kNotFinite;
  const double c = std::cos(phi_rad);
  const double s = std::sin(phi_rad);
  const Vec3 q = gauge_mm * x.a + turn(x.a, x.e, c, s);
  const Vec3 d = x.a + turn(x.a, x.w, c, s);
  SpindleCorrection out;
  const Status line = tool_line_error(q, d, out);
  if (line != Status::kOk) return line;
  out.tip_error_mm = (gauge_mm + tool_mm) * (x.a + Vec3::UnitZ()) + turn(x.a, x.e + tool_mm * x.w, c, s);
  return out;
}

Vec3 spindle_mean_tip_error_mm(const SpindleAxes& x, double gauge_mm, double tool_mm) {
  return (gauge_mm + tool_mm) * (x.a + Vec3::UnitZ());
}

Result<SpindleCorrectionSigma> spindle_correction_sigma(const SpindleParams& p, const SpindleCovariance& cov,
                                                        double gauge_mm, double tool_mm, double phi_rad) {
  // Outputs: theta_e, d_e, tip (3), mean tip (3).
  using Out = Eigen::Matrix<double, 8, 1>;
  auto outputs = [&](const SpindleParams& q, Out& o) -> Status {
    const SpindleAxes x = spindle_axes(q);
    const Result<SpindleCorrection> r = spindle_correction(x, gauge_mm, tool_mm, phi_rad);
    if (!r.ok()) return r.status();
    o(0) = r.value().theta_e_rad;
    o(1) = r.value().d_e_mm;
    o.segment<3>(2) = r.value().tip_error_mm;
    o.segment<3>(5) = spindle_mean_tip_error_mm(x, gauge_mm, tool_mm);
    return Status::kOk;
  };
  if (!p.allFinite() || !cov.allFinite()) return Status::kNotFinite;
  Eigen::Matrix<double, 8, kSpindleParams> j;
  for (int k = 0; k < kSpindleParams; ++k) {
    const double h = k < 3 ? 1e-7 : (k == 5 || k == 6) ? 1e-7 : 1e-9;
    SpindleParams plus = p;
    SpindleParams minus = p;
    plus(k) += h;
    minus(k) -= h;
    Out op;
    Out om;
    const Status a = outputs(plus, op);
    if (a != Status::kOk) return a;
    const Status b = outputs(minus, om);
    if (b != Status::kOk) return b;
    j.col(k) = (op - om) / (2.0 * h);
  }
  const Eigen::Matrix<double, 8, kSpindleParams> jc = j.lazyProduct(cov);  // no blocked product (heap on target)
  const Eigen::Matrix<double, 8, 8> c = jc.lazyProduct(j.transpose());
  SpindleCorrectionSigma out;
  out.theta_e_rad = std::sqrt(std::fmax(0.0, c(0, 0)));
  out.d_e_mm = std::sqrt(std::fmax(0.0, c(1, 1)));
  for (int k = 0; k < 3; ++k) {
    out.tip_error_mm(k) = std::sqrt(std::fmax(0.0, c(2 + k, 2 + k)));
    out.mean_tip_error_mm(k) = std::sqrt(std::fmax(0.0, c(5 + k, 5 + k)));
  }
  return out;
}

SpindleModel make_spindle_model(const SpindleFit& fit, const SpindleGeometry& geometry) {
  SpindleModel m;
  m.fit = fit;
  m.geometry = geometry;
  m.axes = spindle_axes(fit.params);
  return m;
}

std::size_t encode_spindle_model(const SpindleModel& model, std::uint8_t* out, std::size_t capacity) {
  if (out == nullptr || capacity < kSpindleModelBytes) return 0;
  for (std::size_t k = 0; k < kSpindleModelBytes; ++k) out[k] = 0;
  put_u16(out, kSpindleLayoutVersion);
  put_u16(out + 2, model.fit.noise_from_repeats ? 1 : 0);
  put_u32(out + 4, model.fit.samples);
  put_u32(out + 8, model.fit.angles[0]);
  put_u32(out + 12, model.fit.angles[1]);
  put_u32(out + 16, static_cast<std::uint32_t>(model.fit.evaluations));
  F64Writer w{out + kHeaderBytes};
  SpindleModel copy = model;
  model_fields(w, copy);
  return kSpindleModelBytes;
}

Status decode_spindle_model(const std::uint8_t* bytes, std::size_t size, SpindleModel& out) {
  if (bytes == nullptr || size != kSpindleModelBytes) return Status::kTableInvalid;
  const std::uint16_t flags = get_u16(bytes + 2);
  if (get_u16(bytes) != kSpindleLayoutVersion || flags > 1 || get_u32(bytes + 20) != 0 || get_u32(bytes + 4) == 0) {
    return Status::kTableInvalid;
  }
  SpindleModel m;
  m.fit.noise_from_repeats = flags == 1;
  m.fit.samples = get_u32(bytes + 4);
  m.fit.angles[0] = get_u32(bytes + 8);
  m.fit.angles[1] = get_u32(bytes + 12);
  m.fit.evaluations = static_cast<int>(get_u32(bytes + 16));
  F64Reader r{bytes + kHeaderBytes};
  model_fields(r, m);
  for (int row = 0; row < kSpindleParams; ++row) {
    for (int c = 0; c < row; ++c) m.fit.covariance(row, c) = m.fit.covariance(c, row);
  }
  const SpindleFit& f = m.fit;
  const bool finite = f.params.allFinite() && f.covariance.allFinite() && std::isfinite(m.geometry.gauge_mm) &&
                      std::isfinite(m.geometry.ball_mm[0]) && std::isfinite(m.geometry.ball_mm[1]) &&
                      std::isfinite(f.rms_mm) && std::isfinite(f.synchronous_rms_mm) &&
                      std::isfinite(f.noise_sigma_mm) && std::isfinite(f.smallest_eigenvalue_ratio);
  if (!finite) return Status::kTableInvalid;
  const double tilt = std::hypot(f.params(3), f.params(4));
  if (!(tilt <= kMaxSpindleTilt) || f.covariance.diagonal().minCoeff() < 0.0 || f.rms_mm < 0.0 ||
      f.synchronous_rms_mm < 0.0 || f.noise_sigma_mm < 0.0 || f.smallest_eigenvalue_ratio < 0.0 ||
      f.evaluations < 0 || !(m.geometry.ball_mm[1] > m.geometry.ball_mm[0])) {
    return Status::kTableInvalid;
  }
  m.axes = spindle_axes(f.params);
  out = m;
  return Status::kOk;
}

}  // namespace trueaxis::core
