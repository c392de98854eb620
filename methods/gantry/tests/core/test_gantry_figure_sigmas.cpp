// The figures issue 17 gave M2 a sigma or a noise floor: squareness, the
// A-to-C offset and angle (gantry_frames.hpp convention 7) against a
// first-order propagation written independently from the fits' covariances
// (closed-form gradients) and against a Monte Carlo on the independent ground
// truth (gantry_truth.hpp); the peak-to-valley noise floors and the
// noise-corrected form errors (form_noise.hpp) against tabulated and
// closed-form expectations and against Monte Carlos of the actual fits. Set
// TRUEAXIS_FIGURES=1 to print the measured ratios.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "gantry_truth.hpp"
#include "trueaxis/core/form_noise.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

bool print_figures() { return std::getenv("TRUEAXIS_FIGURES") != nullptr; }

// ---- noise floors -------------------------------------------------------------------

// E[max of n Rayleigh(1)] by inclusion-exclusion: sqrt(pi/2) sum_k (-1)^(k+1) C(n,k) / sqrt(k).
double max_rayleigh_closed(int n) {
  double sum = 0.0;
  double binom = 1.0;
  for (int k = 1; k <= n; ++k) {
    binom = binom * (n - k + 1) / k;
    sum += (k % 2 == 1 ? 1.0 : -1.0) * binom / std::sqrt(static_cast<double>(k));
  }
  return std::sqrt(core::kPi / 2.0) * sum;
}

// Points on four pads of a 6 x 3 m bed, `per_pad` each, heights `form` (RMS
// form_mm, orthogonal to every plane) plus isotropic noise s.
std::vector<Vec3> bed_points(t::Rng& rng, std::size_t per_pad, const std::vector<double>& form, double s) {
  std::vector<Vec3> p;
  const double pads[4][2] = {{60, 60}, {5860, 60}, {5860, 2860}, {60, 2860}};
  std::size_t i = 0;
  for (const auto& pad : pads) {
    for (std::size_t j = 0; j < per_pad; ++j, ++i) {
      const double x = pad[0] + 97.0 * static_cast<double>((j * 7) % 11) / 10.0;
      const double y = pad[1] + 97.0 * static_cast<double>((j * 3) % 5) / 4.0;
      p.emplace_back(x + s * rng.normal(), y + s * rng.normal(), form[i] + s * rng.normal());
    }
  }
  return p;
}

// A random height pattern with no plane in it (least squares on 1, x, y
// removed), RMS exactly rms_mm, for the points of bed_points (noise-free x, y).
std::vector<double> plane_free_form(t::Rng& rng, std::size_t per_pad, double rms_mm) {
  const std::vector<double> zero(4 * per_pad, 0.0);
  const std::vector<Vec3> xy = bed_points(rng, per_pad, zero, 0.0);
  const Eigen::Index m = static_cast<Eigen::Index>(xy.size());
  Eigen::MatrixXd a(m, 3);
  Eigen::VectorXd h(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Vec3& q = xy[static_cast<std::size_t>(i)];
    a.row(i) << 1.0, q.x(), q.y();
    h(i) = rng.normal();
  }
  h -= a * a.colPivHouseholderQr().solve(h);
  h *= rms_mm / std::sqrt(h.squaredNorm() / static_cast<double>(m));
  return std::vector<double>(h.data(), h.data() + h.size());
}

}  // namespace

TEST_CASE("the expected range of n normals matches the tabulated d2 and its limits", "[gantry][form]") {
  CHECK(core::expected_normal_range(0) == 0.0);
  CHECK(core::expected_normal_range(1) == 0.0);
  CHECK(core::expected_normal_range(2) == Approx(2.0 / std::sqrt(core::kPi)).epsilon(1e-9));
  // d2 of the SPC tables (Tippett 1925, Harter 1960).
  CHECK(core::expected_normal_range(3) == Approx(1.692569).epsilon(1e-6));
  CHECK(core::expected_normal_range(5) == Approx(2.325929).epsilon(1e-6));
  CHECK(core::expected_normal_range(10) == Approx(3.077505).epsilon(1e-6));
  CHECK(core::expected_normal_range(25) == Approx(3.931).epsilon(1e-3));
  CHECK(core::expected_normal_range(100) == Approx(5.015).epsilon(1e-3));
  CHECK(core::expected_normal_range(1000) == Approx(6.483).epsilon(1e-3));
}

TEST_CASE("the expected largest 2-D distance matches inclusion-exclusion and a Monte Carlo", "[gantry][form]") {
  CHECK(core::expected_max_rayleigh(0) == 0.0);
  for (int n = 1; n <= 20; ++n) {
    INFO("n = " << n);
    CHECK(core::expected_max_rayleigh(static_cast<std::size_t>(n)) == Approx(max_rayleigh_closed(n)).epsilon(1e-8));
  }
  t::Rng rng(1701);
  for (int n : {100, 2048}) {
    double sum = 0.0;
    const int runs = 2000;
    for (int r = 0; r < runs; ++r) {
      double m = 0.0;
      for (int i = 0; i < n; ++i) m = std::max(m, std::hypot(rng.normal(), rng.normal()));
      sum += m;
    }
    INFO("n = " << n);
    CHECK(core::expected_max_rayleigh(static_cast<std::size_t>(n)) == Approx(sum / runs).epsilon(0.01));
  }
}

TEST_CASE("the flatness floor is the mean peak-to-valley of plane fits to pure noise", "[gantry][form]") {
  t::Rng rng(1702);
  const double s = 0.01;
  for (std::size_t per_pad : {2u, 9u, 32u}) {
    const std::size_t n = 4 * per_pad;
    const std::vector<double> flat(n, 0.0);
    double sum = 0.0;
    const int runs = 1500;
    for (int r = 0; r < runs; ++r) {
      const std::vector<Vec3> p = bed_points(rng, per_pad, flat, s);
      const auto fit = core::fit_plane_group({p.data(), p.size()}, core::PointNoise{});
      REQUIRE(fit.ok());
      sum += fit.value().flatness_mm;
    }
    const double floor = core::flatness_noise_floor_mm(n, core::plane_residual_dof(n), s);
    if (print_figures()) std::printf("flatness floor n=%zu: predicted %.5f, observed %.5f\n", n, floor, sum / runs);
    INFO("points " << n);
    CHECK(floor == Approx(sum / runs).epsilon(0.03));
  }
}

TEST_CASE("the straightness floor is the mean worst-pass straightness of line fits to pure noise",
          "[gantry][form]") {
  t::Rng rng(1703);
  const double s = 0.01;
  for (std::size_t per_pass : {8u, 30u}) {
    for (std::size_t passes : {1u, 3u}) {
      std::vector<std::vector<Vec3>> pts(passes);
      core::PointSpan spans[core::kMaxPasses];
      double sum = 0.0;
      const int runs = 1500;
      for (int r = 0; r < runs; ++r) {
        for (std::size_t k = 0; k < passes; ++k) {
          pts[k].clear();
          for (std::size_t i = 0; i < per_pass; ++i) {
            pts[k].emplace_back(100.0 * static_cast<double>(i) + s * rng.normal(), 1500.0 + s * rng.normal(), 2300.0 + s * rng.normal());
          }
          spans[k] = {pts[k].data(), pts[k].size()};
        }
        const auto axis = core::fit_axis_passes(spans, passes, core::PointNoise{});
        REQUIRE(axis.ok());
        sum += axis.value().straightness_mm;
      }
      const std::size_t count = passes * per_pass;
      const double floor =
          core::straightness_noise_floor_mm(count, passes * core::line_residual_dof(per_pass), s);
      if (print_figures()) {
        std::printf("straightness floor %zu x %zu: predicted %.5f, observed %.5f\n", passes, per_pass, floor, sum / runs);
      }
      INFO(passes << " passes of " << per_pass);
      CHECK(floor == Approx(sum / runs).epsilon(0.03));
    }
  }
}

TEST_CASE("no stated noise, no points or no degrees of freedom give zeros, never NaN", "[gantry][form]") {
  CHECK(core::flatness_noise_floor_mm(36, 33, 0.0) == 0.0);
  CHECK(core::straightness_noise_floor_mm(0, 0, 0.01) == 0.0);
  const core::FormError none = core::form_error(0.02, 36, 33, 0.0);
  CHECK(none.form_mm == 0.02);
  CHECK(none.sigma_mm == 0.0);
  const core::FormError empty = core::form_error(0.02, 0, 0, 0.01);
  CHECK(empty.form_mm == 0.0);
  CHECK(empty.sigma_mm == 0.0);
  // At the floor: form 0 (to rounding), sigma the no-form limit (V / 2 pi)^(1/4).
  const double s = 0.01;
  const core::FormError at = core::form_error(s * std::sqrt(33.0 / 36.0), 36, 33, s);
  CHECK(at.form_mm < 1e-6 * s);
  const double v0 = 2.0 * 33.0 * s * s * s * s / (36.0 * 36.0);
  CHECK(at.sigma_mm == Approx(std::pow(v0 / (2.0 * core::kPi), 0.25)).epsilon(1e-12));
  // Far above: the first-order s / sqrt(n) (form dominates).
  const core::FormError far = core::form_error(100.0 * s, 36, 33, s);
  CHECK(far.sigma_mm == Approx(s / 6.0).epsilon(0.01));
}

TEST_CASE("the form error's sigma is honest within 1.5 from no form to 30 times the noise", "[gantry][form]") {
  t::Rng rng(1704);
  const double s = 0.01;
  const std::size_t per_pad = 9;
  const std::size_t n = 4 * per_pad;
  for (double ratio : {0.0, 0.1, 0.2, 0.4, 1.0, 3.0, 30.0}) {
    const double form = ratio * s;
    const std::vector<double> pattern = plane_free_form(rng, per_pad, form);
    double e2 = 0.0;
    double s2 = 0.0;
    int within = 0;
    const int runs = 2000;
    for (int r = 0; r < runs; ++r) {
      const std::vector<Vec3> p = bed_points(rng, per_pad, pattern, s);
      const auto fit = core::fit_plane_group({p.data(), p.size()}, core::PointNoise{});
      REQUIRE(fit.ok());
      const core::FormError f = core::form_error(fit.value().rms_residual_mm, n, core::plane_residual_dof(n), s);
      e2 += (f.form_mm - form) * (f.form_mm - form);
      s2 += f.sigma_mm * f.sigma_mm;
      within += std::abs(f.form_mm - form) <= 3.0 * f.sigma_mm ? 1 : 0;
    }
    const double honest = std::sqrt(s2 / e2);
    if (print_figures()) {
      std::printf("form %.1f x noise: sigma predicted/observed %.3f, within 3 sigma %.4f\n", ratio, honest,
                  static_cast<double>(within) / runs);
    }
    INFO("form " << ratio << " x the noise");
    CHECK(honest > 1.0 / 1.5);
    CHECK(honest < 1.5);
    if (ratio == 0.0) CHECK(within >= 0.99 * runs);
  }
}

// ---- squareness, A-to-C offset and angle ------------------------------------------------

namespace {

// Convention 7 restated with closed-form gradients from the fits' covariances:
// angle(p, q) has gradient -(q_perp / sin) on p; the signed offset f = w . m /
// |m|, w = R_A - R_C, m = a x c, has gradients m^ on R_A, -m^ on R_C,
// (c x w) / |m| - f (c x m^) / |m| on a and (w x a) / |m| - f (m^ x a) / |m| on c.
struct Independent {
  Vec3 squareness_rad = Vec3::Zero();
  double offset_mm = 0.0;
  double angle_rad = 0.0;
};

double angle_var(const Vec3& p, const core::Mat3& cp, const Vec3& q, const core::Mat3& cq) {
  const double sin2 = p.cross(q).squaredNorm();
  return (q.dot(cp * q) + p.dot(cq * p)) / sin2;
}

// A circle's normal covariance (3x3) from its (centre, a, b, r) covariance.
core::Mat3 normal_cov(const core::CircleFit& f) {
  Eigen::Matrix<double, 3, 2> uv;
  uv << f.axis_u, f.axis_v;
  return uv * f.covariance.block<2, 2>(3, 3) * uv.transpose();
}

Independent independent_sigmas(const core::SubMachineInput& in, const core::PointNoise& noise = {}) {
  Independent out;
  core::AxisEstimate axes[3];
  for (int k = 0; k < 3; ++k) {
    const auto a = core::fit_axis_passes(in.passes[k], in.pass_count[k], noise);
    REQUIRE(a.ok());
    axes[k] = a.value();
  }
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    out.squareness_rad(k) =
        std::sqrt(angle_var(axes[k].direction, axes[k].covariance, axes[j].direction, axes[j].covariance));
  }
  auto work = std::make_unique<core::CircleFitWork>();
  core::CircleFit c, a;
  REQUIRE(core::fit_circle_group(in.c_circle, noise, 30.0, *work, c) == core::Status::kOk);
  REQUIRE(core::fit_circle_group(in.a_circle, noise, 30.0, *work, a) == core::Status::kOk);
  const core::Mat3 cc = normal_cov(c);
  const core::Mat3 ca = normal_cov(a);
  out.angle_rad = std::sqrt(angle_var(a.normal, ca, c.normal, cc));
  const Vec3 w = a.centre_mm - c.centre_mm;
  const Vec3 m = a.normal.cross(c.normal);
  const double len = m.norm();
  const Vec3 mh = m / len;
  const double f = w.dot(mh);
  const Vec3 g_a = (c.normal.cross(w) - f * c.normal.cross(mh)) / len;
  const Vec3 g_c = (w.cross(a.normal) - f * mh.cross(a.normal)) / len;
  // Full 6-parameter gradients (centre, a, b, r) of each circle.
  Eigen::Matrix<double, 6, 1> j_c, j_a;
  j_c << -mh, g_c.dot(c.axis_u), g_c.dot(c.axis_v), 0.0;
  j_a << mh, g_a.dot(a.axis_u), g_a.dot(a.axis_v), 0.0;
  out.offset_mm = std::sqrt(j_c.dot(c.covariance * j_c) + j_a.dot(a.covariance * j_a));
  return out;
}

}  // namespace

TEST_CASE("squareness, A-to-C offset and angle sigmas equal an independent propagation", "[gantry][sigma]") {
  auto out = std::make_unique<core::GantryFrames>();
  for (std::uint64_t seed : {1801u, 1802u, 1803u}) {
    t::Rng rng(seed);
    t::TrueGantry truth = t::make_truth(rng);
    // Next to the offset's singularity: sub-machine 1 with its A and C axes
    // crossing exactly (a length of 0 has no derivative; the signed offset has).
    truth.subs[0].offset = 0;
    t::Sampler sampler(truth, rng, t::kTracker);
    const t::Samples s = sampler.sample();
    const core::GantryInput in = t::make_input(truth, s);
    REQUIRE(core::compute_gantry_frames(in, core::GantryOptions{}, *out) == core::Status::kOk);
    for (std::size_t i = 0; i < 4; ++i) {
      INFO("seed " << seed << ", sub-machine " << i + 1);
      const core::SubMachineFrame& f = out->sub_machines[i];
      const Independent ind = independent_sigmas(in.sub_machines[i]);
      for (int k = 0; k < 3; ++k) {
        CHECK(f.squareness_sigma_arcsec(k) == Approx(core::kArcsecPerRad * ind.squareness_rad(k)).epsilon(1e-4));
      }
      CHECK(f.a_c_offset_sigma_mm == Approx(ind.offset_mm).epsilon(1e-4));
      CHECK(f.a_c_angle_sigma_deg == Approx(ind.angle_rad * 180.0 / core::kPi).epsilon(1e-4));
      CHECK(f.a_c_offset_sigma_mm > 0.0);
    }
  }
}

TEST_CASE("at an A-to-C offset of exactly 0 its sigma is the signed offset's, not 0", "[gantry][sigma]") {
  // Noise-free points with the tracker model's covariances: the fitted offset
  // is 0 to rounding, where the length |f| has no derivative.
  t::Rng rng(1820);
  t::TrueGantry truth = t::make_truth(rng);
  for (t::TrueSub& sub : truth.subs) sub.offset = 0;
  t::Sampler sampler(truth, rng, t::NoiseSpec{});
  const t::Samples s = sampler.sample();
  const core::GantryInput in = t::make_input(truth, s);
  core::GantryOptions options;
  options.noise = {t::kTracker.a_mm, t::kTracker.b_per_mm, Vec3::Zero()};
  auto out = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(in, options, *out) == core::Status::kOk);
  for (std::size_t i = 0; i < 4; ++i) {
    INFO("sub-machine " << i + 1);
    const core::SubMachineFrame& f = out->sub_machines[i];
    CHECK(f.a_c_offset_mm < 1e-9);
    const Independent ind = independent_sigmas(in.sub_machines[i], options.noise);
    CHECK(f.a_c_offset_sigma_mm == Approx(ind.offset_mm).epsilon(1e-4));
    CHECK(f.a_c_offset_sigma_mm > 1e-3);
  }
}

TEST_CASE("squareness, A-to-C offset and angle sigmas match the Monte-Carlo spread within 1.5",
          "[gantry][sigma][mc]") {
  t::Rng rng(1810);
  t::TrueGantry truth = t::make_truth(rng);
  truth.subs[1].offset = 0;  // one sub-machine at the offset's singularity
  t::Sampler sampler(truth, rng, t::kTracker);
  auto out = std::make_unique<core::GantryFrames>();
  core::GantryOptions options;  // the module's: sigmas from the fits' residuals
  options.instrument = {t::kTracker.a_mm, t::kTracker.b_per_mm, Vec3::Zero()};
  const int runs = 1000;
  double e2[4][5] = {};
  double s2[4][5] = {};
  int form_within[2] = {0, 0};
  double pv[2] = {0, 0};
  double floor[2] = {0, 0};
  for (int r = 0; r < runs; ++r) {
    const t::Samples s = sampler.sample();
    const core::GantryInput in = t::make_input(truth, s);
    REQUIRE(core::compute_gantry_frames(in, options, *out) == core::Status::kOk);
    for (std::size_t i = 0; i < 4; ++i) {
      const core::SubMachineFrame& f = out->sub_machines[i];
      const t::TrueSub& ts = truth.subs[i];
      const double e[5] = {f.squareness_arcsec(0) - static_cast<double>(ts.squareness_arcsec(0)),
                           f.squareness_arcsec(1) - static_cast<double>(ts.squareness_arcsec(1)),
                           f.squareness_arcsec(2) - static_cast<double>(ts.squareness_arcsec(2)),
                           f.a_c_offset_mm - static_cast<double>(ts.offset),
                           f.a_c_angle_deg - static_cast<double>(ts.ac_angle_deg)};
      const double sg[5] = {f.squareness_sigma_arcsec(0), f.squareness_sigma_arcsec(1), f.squareness_sigma_arcsec(2),
                            f.a_c_offset_sigma_mm, f.a_c_angle_sigma_deg};
      for (int k = 0; k < 5; ++k) {
        e2[i][k] += e[k] * e[k];
        s2[i][k] += sg[k] * sg[k];
      }
    }
    // The truth's bed is flat and its gantry straight: both form errors 0.
    const core::GlobalFrame& g = out->global;
    form_within[0] += g.bed_form_error_mm <= 3.0 * g.bed_form_error_sigma_mm ? 1 : 0;
    form_within[1] += g.gantry_form_error_mm <= 3.0 * g.gantry_form_error_sigma_mm ? 1 : 0;
    pv[0] += g.bed_flatness_mm;
    pv[1] += g.gantry_straightness_mm;
    floor[0] += g.bed_flatness_noise_floor_mm;
    floor[1] += g.gantry_straightness_noise_floor_mm;
  }
  const char* names[5] = {"squareness xy", "squareness yz", "squareness zx", "A-to-C offset", "A-to-C angle"};
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 5; ++k) {
      const double ratio = std::sqrt(s2[i][k] / e2[i][k]);
      if (print_figures()) {
        std::printf("sub %d %-14s sigma %.5g, observed %.5g, predicted/observed %.3f\n", i + 1, names[k],
                    std::sqrt(s2[i][k] / runs), std::sqrt(e2[i][k] / runs), ratio);
      }
      INFO("sub-machine " << i + 1 << " " << names[k]);
      CHECK(ratio > 1.0 / 1.5);
      CHECK(ratio < 1.5);
    }
  }
  if (print_figures()) {
    std::printf("perfect bed: form within 3 sigma %d/%d, flatness mean %.5f floor %.5f\n", form_within[0], runs,
                pv[0] / runs, floor[0] / runs);
    std::printf("straight gantry: form within 3 sigma %d/%d, straightness mean %.5f floor %.5f\n", form_within[1],
                runs, pv[1] / runs, floor[1] / runs);
  }
  CHECK(form_within[0] >= 0.99 * runs);
  CHECK(form_within[1] >= 0.99 * runs);
  // The floor from the RMS of the points' sigmas against the mean peak-to-valley
  // of points whose sigmas differ with their range.
  CHECK(floor[0] == Approx(pv[0]).epsilon(0.1));
  CHECK(floor[1] == Approx(pv[1]).epsilon(0.1));
}
