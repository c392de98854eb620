// M4's outputs (spindle_correction.hpp): the screw error and the tool-tip error
// against a computation written here a different way (the phi = 0 line turned
// by Rodrigues' formula, the angle from a chord, the distance from the triple
// product), at the parallel and the intersecting case exactly, the mean over a
// revolution against a numerical average, the propagated sigmas against a
// Monte Carlo of the parameters, and the stored model's codec.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "reference.hpp"
#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/screw.hpp"
#include "trueaxis/core/spindle_correction.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

constexpr double kArcsec = core::kPi / (180.0 * 3600.0);

core::SpindleParams random_params(t::Rng& rng, double tilt) {
  core::SpindleParams p;
  p << rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(300, 500), tilt * rng.uniform(-1, 1),
      tilt * rng.uniform(-1, 1), rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), tilt * rng.uniform(-1, 1),
      tilt * rng.uniform(-1, 1);
  return p;
}

Vec3 rodrigues(const Vec3& axis, double phi, const Vec3& v) {
  return v * std::cos(phi) + axis.cross(v) * std::sin(phi) + axis * axis.dot(v) * (1 - std::cos(phi));
}

struct Reference {
  double theta = 0, distance = 0;
  Vec3 tip = Vec3::Zero();
};

// Everything from O1 (the parameters' o does not enter).
Reference reference(const core::SpindleParams& p, double g, double l, double phi) {
  const double ax = p(3), ay = p(4), az = -std::sqrt(1 - ax * ax - ay * ay);
  const Vec3 a(ax, ay, az);
  const Vec3 e(p(5), p(6), -(ax * p(5) + ay * p(6)) / az);
  const Vec3 w(p(7), p(8), -(ax * p(7) + ay * p(8)) / az);
  const Vec3 q = rodrigues(a, phi, g * a + e);
  const Vec3 d = rodrigues(a, phi, a + w).normalized();
  const Vec3 ideal(0, 0, -1);
  Reference r;
  r.theta = 2 * std::asin((d - ideal).norm() / 2);
  const Vec3 n = ideal.cross(d);
  r.distance = std::fabs(q.dot(n)) / n.norm();
  r.tip = rodrigues(a, phi, g * a + e + l * (a + w)) - (g + l) * ideal;
  return r;
}

}  // namespace

TEST_CASE("screw and tip error against an independent computation", "[spindle]") {
  t::Rng rng(81);
  for (int trial = 0; trial < 2000; ++trial) {
    const double tilt = trial < 1000 ? 100 * kArcsec : 0.2;
    const core::SpindleParams p = random_params(rng, tilt);
    const double g = rng.uniform(100, 500), l = rng.uniform(0, 300), phi = rng.uniform(-10, 10);
    const auto c = core::spindle_correction(core::spindle_axes(p), g, l, phi);
    REQUIRE(c.ok());
    const Reference r = reference(p, g, l, phi);
    INFO("trial " << trial);
    CHECK(c.value().theta_e_rad == Approx(r.theta).epsilon(1e-9));
    CHECK(c.value().d_e_mm == Approx(r.distance).epsilon(1e-6).margin(1e-12));
    CHECK((c.value().tip_error_mm - r.tip).norm() < 1e-12);
  }
}

TEST_CASE("the parallel and the intersecting case", "[spindle]") {
  core::SpindleParams p = core::SpindleParams::Zero();
  p(2) = 400;
  SECTION("a on -Z, tool parallel to it: theta 0, d_e the offset, tip error the offset turned") {
    p(5) = 0.003;
    p(6) = -0.004;
    for (double phi : {0.0, 0.7, 3.0}) {
      const auto c = core::spindle_correction(core::spindle_axes(p), 350, 100, phi);
      REQUIRE(c.ok());
      CHECK(c.value().theta_e_rad == 0.0);
      CHECK(c.value().d_e_mm == Approx(0.005).epsilon(1e-12));
      // turning about -Z by phi: right-handed about the tool direction
      const Vec3 turned = rodrigues(-Vec3::UnitZ(), phi, Vec3(0.003, -0.004, 0));
      CHECK((c.value().tip_error_mm - turned).norm() < 1e-15);
    }
  }
  SECTION("the tool line through the axis at the gauge plane: the lines meet, d_e 0") {
    p(7) = 20 * kArcsec;
    const auto c = core::spindle_correction(core::spindle_axes(p), 350, 100, 1.1);
    REQUIRE(c.ok());
    CHECK(c.value().theta_e_rad == Approx(std::atan(20 * kArcsec)).epsilon(1e-12));  // d = a + w, |w| = tan theta
    CHECK(c.value().d_e_mm < 1e-12);
  }
  SECTION("non-finite input") {
    CHECK(core::spindle_correction(core::spindle_axes(p), 350, NAN, 0).status() == Status::kNotFinite);
    CHECK(core::spindle_correction(core::spindle_axes(p), 350, 0, INFINITY).status() == Status::kNotFinite);
  }
}

TEST_CASE("the mean tip error is the average over a revolution", "[spindle]") {
  t::Rng rng(82);
  for (int trial = 0; trial < 20; ++trial) {
    const core::SpindleParams p = random_params(rng, 100 * kArcsec);
    const core::SpindleAxes x = core::spindle_axes(p);
    Vec3 sum = Vec3::Zero();
    constexpr int kSteps = 360;
    for (int i = 0; i < kSteps; ++i) {
      sum += core::spindle_correction(x, 350, 120, 2 * core::kPi * i / kSteps).value().tip_error_mm;
    }
    CHECK((sum / kSteps - core::spindle_mean_tip_error_mm(x, 350, 120)).norm() < 1e-13);
  }
}

TEST_CASE("propagated sigmas against a Monte Carlo of the parameters", "[spindle][mc]") {
  t::Rng rng(83);
  core::SpindleParams p;
  p << 0.01, -0.01, 400, 30 * kArcsec, -40 * kArcsec, 0.003, 0.002, 15 * kArcsec, 10 * kArcsec;
  // A covariance of the fit's shape: 15 nm noise, 144 samples (scaled identity
  // in parameter units plus a correlation between e and w).
  core::SpindleCovariance c = core::SpindleCovariance::Zero();
  const double s_mm = 2e-6, s_rad = 2e-8;
  for (int k = 0; k < 3; ++k) c(k, k) = s_mm * s_mm;
  c(3, 3) = c(4, 4) = c(7, 7) = c(8, 8) = s_rad * s_rad;
  c(5, 5) = c(6, 6) = s_mm * s_mm;
  c(5, 7) = c(7, 5) = -0.8 * s_mm * s_rad;
  c(6, 8) = c(8, 6) = -0.8 * s_mm * s_rad;
  const double g = 350, l = 250, phi = 0.9;
  const auto sigma = core::spindle_correction_sigma(p, c, g, l, phi);
  REQUIRE(sigma.ok());
  const Eigen::Matrix<double, 9, 9> chol = c.llt().matrixL();
  constexpr int kDraws = 4000;
  double sq_theta = 0, sq_d = 0;
  Vec3 sq_tip = Vec3::Zero(), sq_mean = Vec3::Zero();
  const core::SpindleAxes x0 = core::spindle_axes(p);
  const auto c0 = core::spindle_correction(x0, g, l, phi).value();
  const Vec3 m0 = core::spindle_mean_tip_error_mm(x0, g, l);
  for (int i = 0; i < kDraws; ++i) {
    Eigen::Matrix<double, 9, 1> z;
    for (int k = 0; k < 9; ++k) z(k) = rng.normal();
    const core::SpindleParams q = p + chol * z;
    const core::SpindleAxes x = core::spindle_axes(q);
    const auto cq = core::spindle_correction(x, g, l, phi).value();
    sq_theta += std::pow(cq.theta_e_rad - c0.theta_e_rad, 2) / kDraws;
    sq_d += std::pow(cq.d_e_mm - c0.d_e_mm, 2) / kDraws;
    sq_tip += (cq.tip_error_mm - c0.tip_error_mm).cwiseAbs2() / kDraws;
    sq_mean += (core::spindle_mean_tip_error_mm(x, g, l) - m0).cwiseAbs2() / kDraws;
  }
  CHECK(sigma.value().theta_e_rad == Approx(std::sqrt(sq_theta)).epsilon(0.06));
  CHECK(sigma.value().d_e_mm == Approx(std::sqrt(sq_d)).epsilon(0.06));
  for (int k = 0; k < 3; ++k) {
    CHECK(sigma.value().tip_error_mm(k) == Approx(std::sqrt(sq_tip(k))).epsilon(0.06));
    CHECK(sigma.value().mean_tip_error_mm(k) == Approx(std::sqrt(sq_mean(k))).epsilon(0.06));
  }
}

namespace {

core::SpindleModel sample_model() {
  core::SpindleFit f;
  f.params << 0.01, -0.01, 400, 30 * kArcsec, -40 * kArcsec, 0.003, 0.002, 15 * kArcsec, 10 * kArcsec;
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 9; ++c) f.covariance(r, c) = (r == c ? 4e-12 : 1e-13) * (1 + r + c);
  }
  f.rms_mm = 5e-5;
  f.synchronous_rms_mm = 4.8e-5;
  f.noise_sigma_mm = 1.5e-5;
  f.noise_from_repeats = true;
  f.samples = 576;
  f.angles[0] = f.angles[1] = 72;
  f.smallest_eigenvalue_ratio = 1e-3;
  f.evaluations = 5;
  return core::make_spindle_model(f, core::SpindleGeometry{350.0, {50.0, 150.0}});
}

}  // namespace

TEST_CASE("the stored model: round trip bit for bit, every refusal leaves the output untouched", "[spindle]") {
  const core::SpindleModel m = sample_model();
  std::uint8_t bytes[core::kSpindleModelBytes];
  REQUIRE(core::encode_spindle_model(m, bytes, sizeof bytes) == core::kSpindleModelBytes);
  CHECK(core::encode_spindle_model(m, bytes, sizeof bytes - 1) == 0);
  core::SpindleModel back;
  REQUIRE(core::decode_spindle_model(bytes, sizeof bytes, back) == Status::kOk);
  CHECK(bool(back.fit.params == m.fit.params));
  CHECK(bool(back.fit.covariance == m.fit.covariance));
  CHECK(back.fit.noise_sigma_mm == m.fit.noise_sigma_mm);
  CHECK(back.fit.samples == 576);
  CHECK(back.fit.evaluations == 5);
  CHECK(back.fit.noise_from_repeats);
  CHECK(back.geometry.ball_mm[1] == 150.0);
  CHECK(bool(back.axes.a == m.axes.a));
  CHECK(bool(back.axes.w == m.axes.w));

  auto refused = [&](auto change) {
    std::uint8_t copy[core::kSpindleModelBytes];
    std::memcpy(copy, bytes, sizeof copy);
    change(copy);
    core::SpindleModel out = sample_model();
    out.fit.samples = 12345;
    const Status s = core::decode_spindle_model(copy, sizeof copy, out);
    return s == Status::kTableInvalid && out.fit.samples == 12345;
  };
  auto put = [](std::uint8_t* b, std::size_t offset, double v) { trueaxis::core::put_f64(b + offset, v); };
  CHECK(core::decode_spindle_model(bytes, sizeof bytes - 1, back) == Status::kTableInvalid);
  CHECK(refused([](std::uint8_t* b) { b[0] = 2; }));                       // version
  CHECK(refused([](std::uint8_t* b) { b[2] = 2; }));                       // flags
  CHECK(refused([](std::uint8_t* b) { b[23] = 1; }));                      // reserved
  CHECK(refused([](std::uint8_t* b) { std::memset(b + 4, 0, 4); }));       // no samples
  CHECK(refused([&](std::uint8_t* b) { put(b, 24 + 8 * 3, 0.6); }));       // a_x beyond sin 30 deg
  CHECK(refused([&](std::uint8_t* b) { put(b, 24 + 8 * 8, NAN); }));       // a parameter
  CHECK(refused([&](std::uint8_t* b) { put(b, 96, -1e-12); }));            // a negative variance
  CHECK(refused([&](std::uint8_t* b) { put(b, 456 + 16, 50.0); }));        // b_2 = b_1
  CHECK(refused([&](std::uint8_t* b) { put(b, 480 + 16, -1e-9); }));       // noise sigma < 0
  CHECK(refused([&](std::uint8_t* b) { put(b, 480 + 24, INFINITY); }));    // the last real
  CHECK(refused([&](std::uint8_t* b) { put(b, 480, -1e-9); }));           // rms < 0
  CHECK(refused([&](std::uint8_t* b) { put(b, 488, -1e-9); }));           // synchronous RMS < 0
  CHECK(refused([&](std::uint8_t* b) { put(b, 504, -1e-9); }));           // eigenvalue ratio < 0
  CHECK(refused([](std::uint8_t* b) { b[19] = 0x80; }));                  // evaluations beyond INT_MAX
  CHECK_FALSE(refused([&](std::uint8_t* b) { put(b, 24 + 8 * 3, 0.4); })); // a tilt inside the limit is a model
}

// --- proposed (review of M4) ---

TEST_CASE("the stored model's bytes are convention 5's layout, field by field", "[spindle]") {
  core::SpindleModel m = sample_model();
  m.fit.angles[0] = 71;  // distinct, so a swap shows
  m.fit.angles[1] = 73;
  std::uint8_t b[core::kSpindleModelBytes];
  REQUIRE(core::encode_spindle_model(m, b, sizeof b) == core::kSpindleModelBytes);
  using core::get_f64;
  CHECK(core::get_u16(b) == 1);
  CHECK(core::get_u16(b + 2) == 1);
  CHECK(core::get_u32(b + 4) == 576);
  CHECK(core::get_u32(b + 8) == 71);
  CHECK(core::get_u32(b + 12) == 73);
  CHECK(core::get_u32(b + 16) == 5);
  CHECK(core::get_u32(b + 20) == 0);
  for (int k = 0; k < 9; ++k) CHECK(get_f64(b + 24 + 8 * k) == m.fit.params(k));
  std::size_t at = 96;
  for (int r = 0; r < 9; ++r) {
    for (int c = r; c < 9; ++c, at += 8) CHECK(get_f64(b + at) == m.fit.covariance(r, c));
  }
  CHECK(at == 456);
  CHECK(get_f64(b + 456) == 350.0);
  CHECK(get_f64(b + 464) == 50.0);
  CHECK(get_f64(b + 472) == 150.0);
  CHECK(get_f64(b + 480) == m.fit.rms_mm);
  CHECK(get_f64(b + 488) == m.fit.synchronous_rms_mm);
  CHECK(get_f64(b + 496) == m.fit.noise_sigma_mm);
  CHECK(get_f64(b + 504) == m.fit.smallest_eigenvalue_ratio);
  core::SpindleModel back;
  REQUIRE(core::decode_spindle_model(b, sizeof b, back) == Status::kOk);
  CHECK(back.fit.angles[0] == 71);
  CHECK(back.fit.angles[1] == 73);
  CHECK(back.fit.rms_mm == m.fit.rms_mm);
  CHECK(back.fit.synchronous_rms_mm == m.fit.synchronous_rms_mm);
  CHECK(back.fit.smallest_eigenvalue_ratio == m.fit.smallest_eigenvalue_ratio);
  CHECK(back.geometry.gauge_mm == 350.0);
  CHECK(back.geometry.ball_mm[0] == 50.0);
}

// --- the screw error in closed form (issue 18 item 3) ---

namespace {

// Convention 2's q and d, formed as spindle_correction forms them, so the two
// computations below see the same line.
void tool_line(const core::SpindleAxes& x, double g, double phi, Vec3& q, Vec3& d) {
  const double c = std::cos(phi), s = std::sin(phi);
  q = g * x.a + (c * x.e + s * x.a.cross(x.e));
  d = x.a + (c * x.w + s * x.a.cross(x.w));
}

// The general path spindle_correction no longer takes: plucker_from_point and
// screw_error from the ideal line (-Z through the origin).
struct General {
  Status status = Status::kOk;
  core::ScrewError screw;
};
General general(const Vec3& q, const Vec3& d) {
  General r;
  const auto actual = core::plucker_from_point(q, d);
  if (!actual.ok()) {
    r.status = actual.status();
    return r;
  }
  core::PluckerLine ideal;
  ideal.direction = -Vec3::UnitZ();
  const auto e = core::screw_error(ideal, actual.value());
  r.status = e.status();
  r.screw = e.value();
  return r;
}

// Worst differences of spindle_correction against general() and how often
// each of screw_error's branches was met.
struct Agreement {
  double theta = 0, distance = 0;
  int cases = 0, parallel = 0, status_mismatch = 0;
  void add(const core::SpindleAxes& x, double g, double phi) {
    Vec3 q, d;
    tool_line(x, g, phi, q, d);
    const General ref = general(q, d);
    const auto c = core::spindle_correction(x, g, 100.0, phi);
    ++cases;
    if (c.status() != ref.status) ++status_mismatch;
    if (!c.ok() || ref.status != Status::kOk) return;
    if (ref.screw.parallel) ++parallel;
    theta = std::fmax(theta, std::fabs(c.value().theta_e_rad - ref.screw.theta_rad));
    distance = std::fmax(distance, std::fabs(c.value().d_e_mm - ref.screw.distance_mm));
  }
};

// A unit vector normal to unit a.
Vec3 normal_to(t::Rng& rng, const Vec3& a) {
  const Vec3 r = rng.unit_vector();
  return (r - r.dot(a) * a).normalized();
}

double log_uniform(t::Rng& rng, double lo, double hi) {
  return std::pow(10.0, rng.uniform(std::log10(lo), std::log10(hi)));
}

}  // namespace

TEST_CASE("the closed-form screw error against plucker_from_point and screw_error", "[spindle]") {
  t::Rng rng(84);
  Agreement agree;
  SECTION("random models, tilts of 100 arcsec and 0.2 rad, any angle") {
    for (int trial = 0; trial < 4000; ++trial) {
      const core::SpindleParams p = random_params(rng, trial % 2 == 0 ? 100 * kArcsec : 0.2);
      agree.add(core::spindle_axes(p), rng.uniform(100, 500), rng.uniform(-15, 15));
    }
    CHECK(agree.parallel == 0);
  }
  SECTION("next to the singularity: a on -Z, the tool tilted 1e-15..1e-6 rad, and exactly parallel") {
    for (int trial = 0; trial < 4000; ++trial) {
      core::SpindleAxes x;  // a = -Z exactly
      x.e = Vec3(rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), 0.0);
      const double tilt = trial % 8 == 0 ? 0.0 : log_uniform(rng, 1e-15, 1e-6);
      if (std::fabs(tilt / core::kParallelSin - 1.0) < 1e-6) continue;  // the branch itself is rounding there
      const double beta = rng.uniform(-core::kPi, core::kPi);
      x.w = tilt * Vec3(std::cos(beta), std::sin(beta), 0.0);
      agree.add(x, rng.uniform(100, 500), rng.uniform(-15, 15));
    }
    CHECK(agree.parallel > 1500);               // below 1e-12: screw_error's parallel branch
    CHECK(agree.cases - agree.parallel > 2000);  // above it, |k| down to 1e-12
  }
  SECTION("next to the singularity: a tilted up to 100 arcsec, w cancelling it but for 1e-15..1e-6 rad") {
    for (int trial = 0; trial < 4000; ++trial) {
      const core::SpindleAxes tilted = core::spindle_axes(random_params(rng, 100 * kArcsec));
      const Vec3 a = tilted.a;
      const Vec3 cancel = -Vec3::UnitZ() / -a.z() - a;  // normal to a, a + cancel on -Z
      const double tilt = trial % 8 == 0 ? 0.0 : log_uniform(rng, 1e-15, 1e-6);
      if (std::fabs(tilt / core::kParallelSin - 1.0) < 1e-3) continue;
      core::SpindleAxes x;
      x.a = a;
      x.e = tilted.e;
      x.w = cancel + tilt * normal_to(rng, a);
      agree.add(x, rng.uniform(100, 500), 0.0);  // phi = 0: d = a + w as built
    }
    CHECK(agree.parallel > 1000);
    CHECK(agree.cases - agree.parallel > 2000);
  }
  SECTION("d not of unit length (a scaled), near and far from the singularity, the threshold on both sides") {
    for (int trial = 0; trial < 4000; ++trial) {
      const double scales[4] = {1e-3, 0.5, 3.0, 1e3};
      const double scale = scales[trial % 4];
      core::SpindleAxes x;
      const double tilt = trial % 3 == 0 ? rng.uniform(0.0, 0.3) : log_uniform(rng, 1e-15, 1e-9);
      x.a = -scale * Vec3::UnitZ();
      const double beta = rng.uniform(-core::kPi, core::kPi);
      x.w = scale * tilt * Vec3(std::cos(beta), std::sin(beta), 0.0);
      x.e = Vec3(rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), 0.0);
      if (std::fabs(tilt / core::kParallelSin - 1.0) < 1e-6) continue;
      agree.add(x, rng.uniform(100, 500), rng.uniform(-15, 15));
    }
    for (const double tilt : {0.999e-12, 1.001e-12}) {  // just either side of kParallelSin
      for (const double scale : {1e-3, 1.0, 1e3}) {
        core::SpindleAxes x;
        x.a = -scale * Vec3::UnitZ();
        x.w = scale * tilt * Vec3(0.6, 0.8, 0.0);
        x.e = Vec3(0.003, -0.004, 0.0);  // not along k: the branches differ by millimetres' thousandths
        agree.add(x, 350.0, 0.0);
      }
    }
    CHECK(agree.parallel > 1000);
    CHECK(agree.cases - agree.parallel > 2000);
  }
  SECTION("the tool line reversed (theta pi), extreme lengths of d, and the refusals") {
    core::SpindleAxes x;
    x.a = Vec3::UnitZ();
    x.e = Vec3(0.003, -0.004, 0.0);
    agree.add(x, 350.0, 0.4);  // exactly antiparallel
    x.w = Vec3(1e-9, 0.0, 0.0);
    agree.add(x, 350.0, 0.4);
    for (const double scale : {1e-160, 1e-40, 1e40, 1e150}) {
      for (const double tilt : {0.0, 1e-13, 1e-7, 0.1}) {
        core::SpindleAxes s;
        s.a = -scale * Vec3::UnitZ();
        s.w = scale * tilt * Vec3(0.6, 0.8, 0.0);
        s.e = Vec3(0.003, -0.004, 0.0);
        agree.add(s, 350.0 / scale, 0.0);  // q = (0.003, -0.004, -350) still
      }
    }
    core::SpindleAxes zero;
    zero.a = Vec3::Zero();
    agree.add(zero, 350.0, 0.0);  // d = 0: both kArgumentOutOfRange
    core::SpindleAxes nan;
    nan.w = Vec3(NAN, 0.0, 0.0);
    agree.add(nan, 350.0, 0.0);  // both kNotFinite
    CHECK(core::spindle_correction(zero, 350, 0, 0).status() == Status::kArgumentOutOfRange);
    CHECK(core::spindle_correction(nan, 350, 0, 0).status() == Status::kNotFinite);
    CHECK(agree.parallel >= 6);
  }
  INFO("cases " << agree.cases << ", parallel " << agree.parallel << ", worst theta " << agree.theta
                 << " rad, d_e " << agree.distance << " mm");
  CHECK(agree.status_mismatch == 0);
  CHECK(agree.theta <= 1e-12);
  CHECK(agree.distance <= 1e-9);
}

namespace {

// spindle_phi_rad(phi) and deg_to_rad(fmod(phi, 360)), bit for bit (signed zeros too).
bool same_as_fmod(double phi) {
  const double got = core::spindle_phi_rad(phi);
  const double want = core::deg_to_rad(std::fmod(phi, 360.0));
  return std::memcmp(&got, &want, sizeof got) == 0;
}

}  // namespace

TEST_CASE("spindle_phi_rad is fmod's reduction bit for bit at every multiple of 360 deg and its neighbours, to 2^44 deg",
          "[spindle]") {
  // Near a multiple 360 k the quotient phi / 360 never rounds up to k from
  // below (the distance 360 k - phi, at least an ulp of phi, is over 0.7 of
  // an ulp of k once divided by 360): trunc gives fmod's quotient, so no
  // reduced angle takes the wrong sign. Held here at both sides of every
  // multiple to 360 x 2^17, at every power of two of k and at the largest k
  // below 2^44 deg, and on either side of 2^44 itself (where fmod takes over).
  int cases = 0;
  const auto around = [&cases](double k) {
    const double m = 360.0 * k;
    double lo = m;
    double hi = m;
    for (int step = 0; step < 3; ++step) {
      for (const double phi : {lo, hi, -lo, -hi}) {
        ++cases;
        if (!same_as_fmod(phi)) FAIL_CHECK("phi = " << phi << " (k = " << k << ") is not fmod's reduction");
      }
      if (k >= 1.0 && step == 1 && std::trunc(lo / 360.0) != k - 1.0) {
        FAIL_CHECK("the quotient of " << lo << " / 360 rounded up to " << k);
      }
      lo = std::nextafter(lo, 0.0);
      hi = std::nextafter(hi, HUGE_VAL);
    }
  };
  for (int k = 0; k <= (1 << 17); ++k) around(k);
  for (int e = 17; e <= 35; ++e) {
    for (const double k : {std::ldexp(1.0, e) - 1.0, std::ldexp(1.0, e), std::ldexp(1.0, e) + 1.0}) around(k);
  }
  const double k_max = std::floor(0x1p44 / 360.0);
  for (double k = k_max - 3.0; k <= k_max; k += 1.0) around(k);
  for (const double phi : {0x1p44, std::nextafter(0x1p44, 0.0), std::nextafter(0x1p44, HUGE_VAL), -0x1p44, 1e300}) {
    INFO("phi = " << phi);
    CHECK(same_as_fmod(phi));
  }
  // -720 reduces to -0, as fmod's does; +720 to +0.
  CHECK(std::signbit(core::spindle_phi_rad(-720.0)));
  CHECK_FALSE(std::signbit(core::spindle_phi_rad(720.0)));
  // And between the multiples, log-uniform over 1e-3 .. 2^44 deg.
  t::Rng rng(18);
  for (int i = 0; i < 200000; ++i) {
    const double phi = (i % 2 == 0 ? 1.0 : -1.0) * std::exp(rng.uniform(std::log(1e-3), std::log(0x1p44)));
    ++cases;
    if (!same_as_fmod(phi)) FAIL_CHECK("phi = " << phi << " is not fmod's reduction");
  }
  CHECK(cases > 1700000);
}
