// The virtual spindle and analyser (virtual_spindle.hpp): each ball on a circle
// about the spindle axis, turning right-handed about it; the axis, the housing
// axes and the screw error from closed forms and a separate line-to-line
// solve; identifiable_truth() reproducing the balls and the tool tip to the
// stated second-order term, and matching the first-order merge of the study
// (docs/M4_IDENTIFIABILITY.md finding 2); the error-free and run-out-free
// spindles; the form error (repeats, harmonics 2..15 only, its RMS) and the
// probes' noise; trueaxis-measure-spindle's files.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "calibrate_support.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/spindle_measure.hpp"

namespace {

namespace core = trueaxis::core;
namespace sim = trueaxis::sim;
namespace t = trueaxis::test;
using core::Vec3;

constexpr double kArcsec = core::kPi / (180.0 * 3600.0);

double rad(double deg) { return core::deg_to_rad(deg); }

// Distance of p from the line (o, unit u), and p's coordinate along it.
double off_line(const Vec3& p, const Vec3& o, const Vec3& u) { return ((p - o) - (p - o).dot(u) * u).norm(); }

}  // namespace

TEST_CASE("the axis and the housing axes have the closed forms of convention 1") {
  const sim::SpindleConfig c = sim::realistic_spindle();
  const sim::VirtualSpindle s(c);
  const double tx = c.tilt_x_arcsec * kArcsec, ty = c.tilt_y_arcsec * kArcsec;
  const Vec3 a(std::sin(tx), std::cos(tx) * std::sin(ty), -std::cos(tx) * std::cos(ty));
  const Vec3 e1(std::cos(tx), -std::sin(tx) * std::sin(ty), std::sin(tx) * std::cos(ty));
  const Vec3 e2(0.0, std::cos(ty), std::sin(ty));
  CHECK((s.axis() - a).norm() < 1e-15);
  CHECK((s.housing_x() - e1).norm() < 1e-15);
  CHECK((s.housing_y() - e2).norm() < 1e-15);
  CHECK((s.housing_x().cross(s.housing_y()) + s.axis()).norm() < 1e-15);
  CHECK(s.gauge_mm() == 350.0);
}

TEST_CASE("each ball runs on a circle about the spindle axis, right-handed about a") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  const Vec3 o1 = s.config().o1_mm;
  const Vec3 a = s.axis();
  for (int ball = 1; ball <= 2; ++ball) {
    const Vec3 p0 = s.ball_mm(ball, 0.0);
    const double radius = off_line(p0, o1, a);
    const double along = (p0 - o1).dot(a);
    CAPTURE(ball, radius);
    CHECK(radius > 0.001);  // a few micrometres: the check below is not trivial
    for (double phi = 0.0; phi < 1080.0; phi += 7.3) {
      const Vec3 p = s.ball_mm(ball, phi);
      CHECK(std::abs(off_line(p, o1, a) - radius) < 1e-12);
      CHECK(std::abs((p - o1).dot(a) - along) < 1e-12);  // the circle's plane is normal to a
      // M03, right-handed about a: the chord from phi - 1 deg to phi + 1 deg is
      // 2 sin(1 deg) a x (p - axis) on a circle
      const Vec3 chord = s.ball_mm(ball, phi + 1.0) - s.ball_mm(ball, phi - 1.0);
      CHECK((chord - 2.0 * std::sin(rad(1.0)) * a.cross(p - o1)).norm() < 1e-8 * chord.norm());
    }
    // the turned angle is phi itself: a quarter turn is a quarter of the circle
    const Vec3 r0 = (p0 - o1) - along * a;
    const Vec3 r90 = (s.ball_mm(ball, 90.0) - o1) - along * a;
    CHECK((r90 - a.cross(r0)).norm() < 1e-12);
  }
}

TEST_CASE("identifiable_truth reproduces the balls and the tool tip to the second-order term") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  const core::SpindleParams q = s.identifiable_truth();
  const core::SpindleGeometry g = s.geometry();
  for (int ball = 1; ball <= 2; ++ball) {
    const double bound = s.mapping_error_mm(g.ball_mm[ball - 1]);
    CAPTURE(ball, bound);
    CHECK(bound < 0.3e-6);  // 0.18 nm with realistic_spindle()
    CHECK(bound > 0.1e-6);  // ... and not zero: the term is there and measured
    for (double phi = 0.0; phi < 1080.0; phi += 3.7) {
      const double err = (core::spindle_ball_mm(q, g, ball, rad(phi)) - s.ball_mm(ball, phi)).norm();
      CHECK(std::abs(err - bound) < 1e-12);
    }
  }
  for (double length : {0.0, 100.0, 250.0}) {
    const core::SpindleGeometry at_tip{g.gauge_mm, {length, length + 1.0}};
    const double bound = s.mapping_error_mm(length);
    CAPTURE(length, bound);
    CHECK(bound < 0.6e-6);  // 0.55 nm at 250 mm, 0 at the balls' mid-depth
    for (double phi = 0.0; phi < 360.0; phi += 10.0) {
      const double err = (core::spindle_ball_mm(q, at_tip, 1, rad(phi)) - s.tool_tip_mm(length, phi)).norm();
      CHECK(std::abs(err - bound) < 1e-12);
    }
  }
}

TEST_CASE("the identifiable truth is the study's first-order merge of the seed's errors") {
  const sim::SpindleConfig c = sim::realistic_spindle();
  const sim::VirtualSpindle s(c);
  const Vec3 e1 = s.housing_x(), e2 = s.housing_y();
  auto polar = [&](double r, double deg) { return r * (std::cos(rad(deg)) * e1 + std::sin(rad(deg)) * e2); };
  const Vec3 a1 = polar(c.upper_runout_mm, c.upper_runout_deg);
  const Vec3 a2 = polar(c.lower_runout_mm, c.lower_runout_deg);
  const Vec3 c1 = polar(c.collet_lower_offset_mm, c.collet_lower_deg);
  const Vec3 c2 = polar(c.collet_upper_offset_mm, c.collet_upper_deg);
  // the true lengths
  const double h = c.bearing_spacing_mm + c.bearing_spacing_error_mm;
  const double l_chuck = c.collet_length_mm + c.collet_length_error_mm;
  const double h1 = c.collet_depth_mm + c.collet_depth_error_mm;
  const Vec3 w = (a2 - a1) / h + (c1 - c2) / l_chuck;
  const Vec3 e = a1 + (a2 - a1) * s.gauge_mm() / h + c1 + (c2 - c1) * h1 / l_chuck;
  const core::SpindleParams q = s.identifiable_truth();
  // Neglected: products of two small terms, in e at most delta |w| = 6 um x 18" =
  // 0.5 nm (0.17 nm found), in w about 1e-14 rad.
  CHECK(std::abs(q(5) - e.x()) < 0.5e-6);
  CHECK(std::abs(q(6) - e.y()) < 0.5e-6);
  CHECK(std::abs(q(7) - w.x()) < 1e-12);
  CHECK(std::abs(q(8) - w.y()) < 1e-12);
  CHECK(std::abs(q(3) - s.axis().x()) == 0.0);
  CHECK(std::abs(q(4) - s.axis().y()) == 0.0);
  // delta: every axial error (h +3, l2 -2, Delta3 +3, h1 +2 um) in one number
  CHECK(s.axial_error_mm() == Approx(0.006).margin(2e-6));
  CHECK((q.head<3>() - (c.o1_mm + s.axial_error_mm() * s.axis())).norm() < 1e-15 * 400);
  CHECK(std::abs(e.norm() - 0.0058) < 0.0002);  // realistic_spindle()'s comment: 5 um and 18"
  CHECK(std::abs(w.norm() / kArcsec - 17.7) < 0.1);
}

TEST_CASE("the screw error agrees with a separate solve of the two lines' closest points") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  const Vec3 o1 = s.config().o1_mm, z(0.0, 0.0, -1.0);
  for (double phi = 0.0; phi < 360.0; phi += 15.0) {
    const sim::Line l = s.tool_axis(phi);
    // min over (u, v) of |o1 + u z - (P + v d)|: the 2 x 2 normal equations, in
    // long double (their condition is 1 / theta_e^2, about 1e7)
    using V = Eigen::Matrix<long double, 3, 1>;
    const V zl = z.cast<long double>(), dl = l.direction.cast<long double>();
    const V r = (l.point_mm - o1).cast<long double>();
    Eigen::Matrix<long double, 2, 2> m;
    m << 1.0L, -zl.dot(dl), -zl.dot(dl), 1.0L;
    const Eigen::Matrix<long double, 2, 1> rhs(zl.dot(r), -dl.dot(r));
    const Eigen::Matrix<long double, 2, 1> uv = m.inverse() * rhs;
    const double gap = static_cast<double>((uv(0) * zl - r - uv(1) * dl).norm());
    const sim::ScrewError e = s.screw_error(phi);
    CAPTURE(phi);
    CHECK(e.d_e_mm == Approx(gap).margin(1e-9));
    CHECK(e.theta_e_rad == Approx(std::acos(z.dot(l.direction))).margin(1e-9));
    CHECK(e.theta_e_rad / kArcsec > 10.0);
    // the tool line through the balls
    CHECK(off_line(s.ball_mm(1, phi), l.point_mm, l.direction) < 1e-12);
    CHECK(off_line(s.ball_mm(2, phi), l.point_mm, l.direction) < 1e-12);
    const Vec3 tip = s.tool_tip_error_mm(250.0, phi);
    CHECK((tip - (s.tool_tip_mm(250.0, phi) - o1 - 600.0 * z)).norm() < 1e-12);
    CHECK(std::abs(tip.z() + s.axial_error_mm()) < 20e-6);  // the unseen axial error, plus the tilt's cosine
  }
}

TEST_CASE("the error-free spindle has no errors; the run-out-free one only its tilt") {
  const sim::VirtualSpindle ideal(sim::SpindleConfig{});
  for (double phi = 0.0; phi < 360.0; phi += 30.0) {
    CHECK(ideal.screw_error(phi).theta_e_rad == 0.0);
    CHECK(ideal.screw_error(phi).d_e_mm == 0.0);
    CHECK(ideal.tool_tip_error_mm(100.0, phi).norm() < 1e-12);
    CHECK((ideal.ball_mm(2, phi) - Vec3(0.0, 0.0, 400.0 - 500.0)).norm() < 1e-12);
  }
  core::SpindleParams zero = core::SpindleParams::Zero();
  zero(2) = 400.0;
  CHECK((ideal.identifiable_truth() - zero).norm() < 1e-12);
  CHECK(ideal.axial_error_mm() == 0.0);

  sim::SpindleConfig c = sim::realistic_spindle();
  c.upper_runout_mm = c.lower_runout_mm = c.collet_lower_offset_mm = c.collet_upper_offset_mm = 0.0;
  const sim::VirtualSpindle tilted(c);
  const core::SpindleParams q = tilted.identifiable_truth();
  CHECK(q.tail<4>().norm() < 1e-15);  // e = w = 0
  const double tilt = std::acos(-tilted.axis().z());
  for (double phi = 0.0; phi < 360.0; phi += 30.0) {
    CHECK(tilted.screw_error(phi).theta_e_rad == Approx(tilt).epsilon(1e-9));
    CHECK(tilted.screw_error(phi).d_e_mm < 1e-12);  // the tool line is the axis, through O1
    CHECK((tilted.ball_mm(1, phi) - tilted.ball_mm(1, 0.0)).norm() < 1e-12);
  }
}

TEST_CASE("the form error repeats every revolution, holds harmonics 2..15 only and has its RMS") {
  sim::AnalyserConfig ac;
  ac.form_seed = 17;
  const sim::VirtualAnalyser an(ac);
  for (int ball = 1; ball <= 2; ++ball) {
    CAPTURE(ball);
    constexpr int kN = 360;
    std::complex<double> harmonic[3][40] = {};
    double sq[2] = {0.0, 0.0};
    for (int i = 0; i < kN; ++i) {
      const double phi = 360.0 * i / kN;
      const Vec3 f = an.form_error_mm(ball, phi);
      CHECK((an.form_error_mm(ball, phi + 360.0) - f).norm() < 1e-15);
      CHECK((an.form_error_mm(ball, phi + 1080.0) - f).norm() < 1e-15);
      CHECK(f.x() == an.form_radius_mm(ball, phi));
      for (int axis = 0; axis < 3; ++axis) {
        for (int n = 0; n < 40; ++n) harmonic[axis][n] += f(axis) * std::polar(2.0 / kN, -n * rad(phi));
      }
      sq[0] += f.x() * f.x() / kN;
      sq[1] += f.y() * f.y() / kN;
    }
    CHECK(std::sqrt(sq[0]) == Approx(50e-6).epsilon(1e-12));
    CHECK(std::sqrt(sq[1]) == Approx(50e-6).epsilon(1e-12));
    for (int axis = 0; axis < 2; ++axis) {
      double in_band = 0.0;
      for (int n = 0; n < 40; ++n) {
        const double amp = std::abs(harmonic[axis][n]);
        CAPTURE(axis, n, amp);
        if (n < 2 || n > 15) CHECK(amp < 1e-16);
        in_band += n >= 2 && n <= 15 ? 0.5 * amp * amp : 0.0;
      }
      CHECK(std::sqrt(in_band) == Approx(50e-6).epsilon(1e-9));
    }
    for (int n = 0; n < 40; ++n) CHECK(std::abs(harmonic[2][n]) == 0.0);
  }
  CHECK(an.form_error_mm(1, 30.0) != an.form_error_mm(2, 30.0));
  sim::AnalyserConfig other = ac;
  other.form_seed = 18;
  CHECK(sim::VirtualAnalyser(other).form_error_mm(1, 30.0) != an.form_error_mm(1, 30.0));
  CHECK(sim::VirtualAnalyser(ac).form_error_mm(2, 30.0) == an.form_error_mm(2, 30.0));
}

TEST_CASE("the analyser reads revolutions in order, repeats its form error and adds the probes' noise") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  sim::AnalyserConfig ac;
  ac.noise_sigma_mm = 0.0;
  const sim::VirtualAnalyser quiet(ac);
  sim::SimRng rng(3);
  const auto samples = sim::measure_spindle(quiet, s, rng);
  REQUIRE(samples.size() == 3u * 72u * 2u);
  CHECK(rng.next_u64() == sim::SimRng(3).next_u64());  // no noise: no draws
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& x = samples[i];
    CHECK(x.phi_deg == 5.0 * static_cast<double>(i / 2));
    CHECK(x.ball == 1 + static_cast<int>(i % 2));
    CHECK((x.p_mm - s.ball_mm(x.ball, x.phi_deg) - quiet.form_error_mm(x.ball, x.phi_deg)).norm() < 1e-12);
    if (i >= 144) CHECK((x.p_mm - samples[i - 144].p_mm).norm() < 1e-12);  // synchronous: every revolution alike
  }
  ac.noise_sigma_mm = 15e-6;
  ac.form_rms_mm = 0.0;
  ac.revolutions = 40;
  const sim::VirtualAnalyser noisy(ac);
  sim::SimRng noise(4);
  const auto read = sim::measure_spindle(noisy, s, noise);
  Vec3 sum = Vec3::Zero(), sq = Vec3::Zero();
  for (const auto& x : read) {
    const Vec3 d = x.p_mm - s.ball_mm(x.ball, x.phi_deg);
    sum += d;
    sq += d.cwiseProduct(d);
  }
  const double n = static_cast<double>(read.size());
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    CHECK(std::abs(sum(k) / n) < 4.0 * 15e-6 / std::sqrt(n));
    CHECK(std::sqrt(sq(k) / n) == Approx(15e-6).epsilon(0.04));
  }
}

TEST_CASE("trueaxis-measure-spindle writes samples, MACHINE and the truth that parse and agree") {
  t::Workspace ws("measure-spindle");
  const std::string bin = TRUEAXIS_MEASURE_SPINDLE_BINARY;
  const sim::VirtualSpindle s(sim::realistic_spindle());
  auto samples_of = [&](const std::string& path) {
    const auto csv = sim::read_csv(path, {{"phi_deg"}, {"ball"}, {"x_mm"}, {"y_mm"}, {"z_mm"}});
    INFO(csv.error);
    REQUIRE(csv.ok);
    CHECK(csv.header_line == 3);
    CHECK(t::slurp(path).find("\nphi_deg,ball,x_mm,y_mm,z_mm\n") != std::string::npos);
    return csv.rows;
  };
  SECTION("noise off: the true ball centres, the nominal lengths, the truth of the spindle") {
    const auto r = t::run({bin, "--out", ws.file("s.csv"), "--machine", ws.file("m.csv"), "--noise", "off", "--truth",
                           ws.file("t.json"), "--revolutions", "2", "--step-deg", "10"},
                          ws.file("err"));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto rows = samples_of(ws.file("s.csv"));
    REQUIRE(rows.size() == 2u * 36u * 2u);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& v = rows[i].numbers;
      CHECK(v[0] == 10.0 * static_cast<double>(i / 2));  // growing past 360 on the second revolution
      const Vec3 p(v[2], v[3], v[4]);
      CHECK((p - s.ball_mm(static_cast<int>(v[1]), v[0])).cwiseAbs().maxCoeff() <= 0.5e-9 + 1e-12);
    }
    const auto m = sim::read_csv(ws.file("m.csv"), {{"name", false}, {"value"}});
    REQUIRE(m.ok);
    const std::pair<std::string, double> want[] = {{"bearing_spacing_mm", 300.0}, {"gauge_from_upper_bearing_mm", 350.0},
                                                   {"ball_1_mm", 50.0}, {"ball_2_mm", 150.0}, {"tool_length_mm", 250.0}};
    REQUIRE(m.rows.size() == 5u);
    for (std::size_t i = 0; i < 5; ++i) {
      CHECK(m.rows[i].texts[0] == want[i].first);
      CHECK(m.rows[i].numbers[1] == want[i].second);
    }
    const t::Json j = t::parse(t::slurp(ws.file("t.json")));
    CHECK(j["method"].text == "spindle");
    const core::SpindleParams q = s.identifiable_truth();
    const char* names[9] = {"o_x_mm", "o_y_mm", "o_z_mm", "a_x", "a_y", "e_x_mm", "e_y_mm", "w_x", "w_y"};
    for (int k = 0; k < 9; ++k) {
      CAPTURE(names[k]);
      CHECK(j["parameters"][names[k]]["value"].number == Approx(q(k)).epsilon(1e-14));
      CHECK(j["parameters"][names[k]]["sigma"].number == 0.0);
    }
    const auto& per = j["per_angle"].items;
    REQUIRE(per.size() == 72u);
    double theta_max = 0.0;
    for (std::size_t i = 0; i < per.size(); ++i) {
      const double phi = 5.0 * static_cast<double>(i);
      CHECK(per[i]["phi_deg"].number == phi);
      CHECK(per[i]["theta_e_arcsec"].number == Approx(s.screw_error(phi).theta_e_rad / kArcsec).epsilon(1e-13));
      CHECK(per[i]["d_e_mm"].number == Approx(s.screw_error(phi).d_e_mm).epsilon(1e-13));
      const auto tip = per[i]["tool_tip_error_mm"].numbers();
      REQUIRE(tip.size() == 3u);
      CHECK((Vec3(tip[0], tip[1], tip[2]) - s.tool_tip_error_mm(250.0, phi)).norm() < 1e-15);
      theta_max = std::max(theta_max, per[i]["theta_e_arcsec"].number);
    }
    CHECK(j["theta_e_max_arcsec"].number == theta_max);
    CHECK(j["d_e_max_mm"].kind == t::Json::kNumber);
    CHECK(j["axial_error_mm"].number == Approx(s.axial_error_mm()).epsilon(1e-13));
  }
  SECTION("noise on: the default session, the same seed the same file, another seed another") {
    for (const char* name : {"a.csv", "b.csv"}) {
      REQUIRE(t::run({bin, "--out", ws.file(name), "--machine", ws.file("m.csv"), "--seed", "5"}, ws.file("err"))
                  .exit_code == 0);
    }
    REQUIRE(t::run({bin, "--out", ws.file("c.csv"), "--machine", ws.file("m.csv"), "--seed", "6"}, ws.file("err"))
                .exit_code == 0);
    CHECK(t::slurp(ws.file("a.csv")) == t::slurp(ws.file("b.csv")));
    CHECK(t::slurp(ws.file("a.csv")) != t::slurp(ws.file("c.csv")));
    const auto rows = samples_of(ws.file("a.csv"));
    REQUIRE(rows.size() == 3u * 72u * 2u);
    Vec3 sq = Vec3::Zero();
    for (const auto& row : rows) {
      const Vec3 d = Vec3(row.numbers[2], row.numbers[3], row.numbers[4]) -
                     s.ball_mm(static_cast<int>(row.numbers[1]), row.numbers[0]);
      sq += d.cwiseProduct(d) / static_cast<double>(rows.size());
    }
    CHECK(std::sqrt(sq.x()) == Approx(std::hypot(15e-6, 50e-6)).epsilon(0.2));  // noise and form in x, y
    CHECK(std::sqrt(sq.y()) == Approx(std::hypot(15e-6, 50e-6)).epsilon(0.2));
    CHECK(std::sqrt(sq.z()) == Approx(15e-6).epsilon(0.2));  // noise only in z
  }
  SECTION("bad options are refused with one line and no file") {
    for (const std::vector<std::string>& extra : std::vector<std::vector<std::string>>{
             {"--step-deg", "7"}, {"--step-deg", "50"}, {"--revolutions", "0"}, {"--revolutions", "1.5"},
             {"--noise", "maybe"}, {"--seed", "-1"}, {"--form-nm", "nan"}, {"--frobnicate", "1"}, {"--seed"}}) {
      std::vector<std::string> argv = {bin, "--out", ws.file("x.csv"), "--machine", ws.file("xm.csv")};
      argv.insert(argv.end(), extra.begin(), extra.end());
      const auto r = t::run(argv, ws.file("err"));
      CAPTURE(extra[0]);
      CHECK(r.exit_code == 1);
      CHECK(r.err.find("trueaxis-measure-spindle: ") == 0);
      CHECK(!t::exists(ws.file("x.csv")));
    }
  }
}
