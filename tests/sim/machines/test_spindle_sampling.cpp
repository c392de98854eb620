// The spindle analyser's sampling modes (spindle_analyser.hpp conventions 1 and
// 3, issue 18 item 4) and trueaxis-measure-spindle's options for them:
// encoder-synchronous at N samples a revolution (exactly N angles, repeating
// every revolution; N = 72 reads as step_deg 5, bit for bit), time-sampled
// with a drifting speed (angles strictly increasing, none repeated modulo 360,
// the spacing and the per-revolution counts of the drift, the start angle and
// the clock's phase drawn first, reproducible), and the command's new options,
// files and refusals.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
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

// phi modulo 360 in [0, 360).
double wrap(double phi) {
  const double m = std::fmod(phi, 360.0);
  return m < 0.0 ? m + 360.0 : m;
}

// The smallest distance between two of `angles` modulo 360 (around the circle).
double closest_modulo_360(std::vector<double> angles) {
  for (double& a : angles) a = wrap(a);
  std::sort(angles.begin(), angles.end());
  double gap = angles.front() + 360.0 - angles.back();
  for (std::size_t i = 1; i < angles.size(); ++i) gap = std::min(gap, angles[i] - angles[i - 1]);
  return gap;
}

// The distinct values of `angles` modulo 360, those within tol of each other one.
std::vector<double> distinct_modulo_360(std::vector<double> angles, double tol) {
  for (double& a : angles) a = wrap(a);
  std::sort(angles.begin(), angles.end());
  std::vector<double> out;
  for (double a : angles) {
    if (out.empty() || a - out.back() > tol) out.push_back(a);
  }
  if (out.size() > 1 && out.front() + 360.0 - out.back() <= tol) out.pop_back();
  return out;
}

std::vector<double> ball_angles(const std::vector<core::SpindleSample>& samples) {
  std::vector<double> phi;
  for (std::size_t i = 0; i < samples.size(); i += 2) phi.push_back(samples[i].phi_deg);
  return phi;
}

// Every pair read at one instant: ball 1 then ball 2, one phi; each reading the
// ball's centre plus its form error (noise off).
void check_pairs_and_readings(const std::vector<core::SpindleSample>& samples, const sim::VirtualAnalyser& an,
                              const sim::VirtualSpindle& s) {
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& x = samples[i];
    CHECK(x.ball == 1 + static_cast<int>(i % 2));
    if (i % 2 == 1) CHECK(x.phi_deg == samples[i - 1].phi_deg);
    const Vec3 want = s.ball_mm(x.ball, x.phi_deg) + an.form_error_mm(x.ball, x.phi_deg);
    CHECK((x.p_mm - want).norm() < 1e-12);
  }
}

}  // namespace

TEST_CASE("encoder-synchronous sampling at N a revolution: exactly N angles, the same every revolution") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  for (const int n : {8, 72, 100, 360, 1000, 1023, 4096}) {
    CAPTURE(n);
    sim::AnalyserConfig ac;
    ac.noise_sigma_mm = 0.0;
    ac.samples_per_revolution = n;
    ac.step_deg = 7.0;  // not used when samples_per_revolution is set
    ac.revolutions = n == 4096 ? 5 : 3;
    const sim::VirtualAnalyser an(ac);
    CHECK(an.steps_per_revolution() == n);
    sim::SimRng rng(3);
    const auto samples = sim::measure_spindle(an, s, rng);
    CHECK(rng.next_u64() == sim::SimRng(3).next_u64());  // no noise: no draws
    const std::size_t per_rev = static_cast<std::size_t>(n);
    REQUIRE(samples.size() == 2u * per_rev * static_cast<std::size_t>(ac.revolutions));
    check_pairs_and_readings(samples, an, s);
    for (std::size_t k = 0; k < samples.size() / 2; ++k) {
      const int r = static_cast<int>(k / per_rev);
      const int i = static_cast<int>(k % per_rev);
      const double phi = samples[2 * k].phi_deg;
      CHECK(phi == 360.0 * r + 360.0 * i / n);  // convention 1, computed so
      CHECK(std::abs((phi - 360.0 * r) - 360.0 * i / n) < 1e-11);
      if (k >= per_rev) CHECK(std::abs(phi - samples[2 * (k - per_rev)].phi_deg - 360.0) < 1e-11);
    }
    const std::vector<double> phi = ball_angles(samples);
    const auto distinct = distinct_modulo_360(phi, 1e-9);
    REQUIRE(distinct.size() == per_rev);  // exactly N angles, every revolution the same
    for (std::size_t i = 0; i < per_rev; ++i) CHECK(std::abs(distinct[i] - 360.0 * static_cast<double>(i) / n) < 1e-9);
    CHECK(closest_modulo_360(std::vector<double>(phi.begin(), phi.begin() + n)) ==
          Approx(360.0 / n).epsilon(1e-9));
  }
}

TEST_CASE("step_deg reads as before: samples_per_revolution 0 is step_deg, N = 72 is step_deg 5 bit for bit") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  sim::AnalyserConfig by_step;  // the defaults: 3 revolutions at 5 deg, noise and form on
  sim::AnalyserConfig by_count = by_step;
  by_count.samples_per_revolution = 72;
  sim::AnalyserConfig drift_ignored = by_step;
  drift_ignored.speed_drift = 0.07;  // convention 3 only
  CHECK(sim::VirtualAnalyser(by_step).steps_per_revolution() == 72);
  sim::SimRng a(11), b(11), c(11);
  const auto x = sim::measure_spindle(sim::VirtualAnalyser(by_step), s, a);
  const auto y = sim::measure_spindle(sim::VirtualAnalyser(by_count), s, b);
  const auto z = sim::measure_spindle(sim::VirtualAnalyser(drift_ignored), s, c);
  REQUIRE(x.size() == 3u * 72u * 2u);
  REQUIRE(y.size() == x.size());
  REQUIRE(z.size() == x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    CHECK(x[i].phi_deg == 5.0 * static_cast<double>(i / 2));
    CHECK(y[i].phi_deg == x[i].phi_deg);
    CHECK(y[i].ball == x[i].ball);
    CHECK(y[i].p_mm == x[i].p_mm);
    CHECK(z[i].p_mm == x[i].p_mm);
  }
  sim::AnalyserConfig fine;
  fine.step_deg = 0.1;
  fine.noise_sigma_mm = 0.0;
  sim::SimRng d(1);
  const auto w = sim::measure_spindle(sim::VirtualAnalyser(fine), s, d);
  REQUIRE(w.size() == 3u * 3600u * 2u);
  for (std::size_t k = 0; k < w.size() / 2; ++k) {
    CHECK(w[2 * k].phi_deg == 360.0 * static_cast<double>(k / 3600) + 0.1 * static_cast<double>(k % 3600));
  }
}

TEST_CASE("time-sampled: strictly increasing angles, none repeated modulo 360, the drift's spacing and counts") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  sim::AnalyserConfig ac;
  ac.time_sampled = true;
  ac.noise_sigma_mm = 0.0;
  ac.revolutions = 5;
  ac.speed_drift = 0.01;
  const sim::VirtualAnalyser an(ac);
  REQUIRE(an.steps_per_revolution() == 1024);  // the default nominal rate
  const int n = 1024;
  const double d = 0.01;
  const double r_total = 5.0;

  sim::SimRng rng(2);
  const auto samples = sim::measure_spindle(an, s, rng);
  REQUIRE(samples.size() == 2u * 1024u * 5u);  // N R instants: the clock's count
  check_pairs_and_readings(samples, an, s);

  // Two draws first (phi0, then the clock's phase tau), nothing else with the noise off.
  sim::SimRng draws(2);
  const double phi0 = 360.0 * (1.0 - draws.uniform01());
  const double tau = 1.0 - draws.uniform01();
  CHECK(rng.next_u64() == draws.next_u64());
  CHECK(phi0 >= 0.0);
  CHECK(phi0 < 360.0);

  const std::vector<double> phi = ball_angles(samples);
  for (std::size_t k = 0; k < phi.size(); ++k) {
    CAPTURE(k);
    const double tk = (static_cast<double>(k) + tau) / n;
    CHECK(phi[k] == phi0 + an.time_sampled_angle_deg(tk));  // convention 3, computed so
    CHECK(phi[k] == Approx(phi0 + 360.0 * (tk * (1.0 - d / 2.0) + d * tk * tk / (2.0 * r_total))).epsilon(1e-14));
    if (k == 0) continue;
    const double step = phi[k] - phi[k - 1];
    CHECK(step > 360.0 / n * (1.0 - d / 2.0));  // strictly increasing, at the drifting speed
    CHECK(step < 360.0 / n * (1.0 + d / 2.0));
    const double kk = static_cast<double>(k - 1);
    CHECK(step == Approx(360.0 / n * (1.0 - d / 2.0 + d * (2.0 * kk + 1.0 + 2.0 * tau) / (2.0 * n * r_total)))
                      .epsilon(1e-9));
    if (k >= 2) CHECK(step > phi[k - 1] - phi[k - 2]);  // the speed rises
  }
  CHECK(phi.back() < phi0 + 360.0 * r_total);  // R revolutions, not more

  // No two angles alike modulo 360: in this session the closest two are far apart.
  const double closest = closest_modulo_360(phi);
  CAPTURE(closest);
  CHECK(closest > 1e-6);
  CHECK(distinct_modulo_360(phi, 1e-6).size() == phi.size());

  // Each whole revolution from phi0 holds N within the drift: from N / (1 + D/2) to
  // N / (1 - D/2), to one; more at the slow start, fewer at the fast end.
  std::vector<int> per_rev(5, 0);
  for (double p : phi) per_rev[static_cast<std::size_t>(std::floor((p - phi0) / 360.0))] += 1;
  for (int count : per_rev) {
    CAPTURE(count);
    CHECK(count >= std::floor(n / (1.0 + d / 2.0)));
    CHECK(count <= std::ceil(n / (1.0 - d / 2.0)));
    CHECK(count != 0);
  }
  CHECK(per_rev.front() > n);
  CHECK(per_rev.back() < n);
  CHECK(per_rev.front() > per_rev[2]);
  CHECK(per_rev[2] > per_rev.back());

  // Reproducible: the same seed the same readings; another seed, another start.
  sim::SimRng again(2), other(3);
  const auto same = sim::measure_spindle(an, s, again);
  REQUIRE(same.size() == samples.size());
  for (std::size_t i = 0; i < same.size(); ++i) {
    CHECK(same[i].phi_deg == samples[i].phi_deg);
    CHECK(same[i].p_mm == samples[i].p_mm);
  }
  CHECK(sim::measure_spindle(an, s, other)[0].phi_deg != samples[0].phi_deg);
}

TEST_CASE("time-sampled: noise after the two draws, other rates and drifts, no drift a fixed step") {
  const sim::VirtualSpindle s(sim::realistic_spindle());
  SECTION("the noise's deviates follow phi0 and tau, ball 1 then ball 2, x y z") {
    sim::AnalyserConfig ac;
    ac.time_sampled = true;
    ac.samples_per_revolution = 64;
    ac.revolutions = 2;
    const sim::VirtualAnalyser an(ac);
    sim::SimRng rng(8);
    const auto samples = sim::measure_spindle(an, s, rng);
    REQUIRE(samples.size() == 2u * 64u * 2u);
    sim::SimRng draws(8);
    draws.uniform01();
    draws.uniform01();
    for (const auto& x : samples) {
      const double nx = draws.normal();
      const double ny = draws.normal();
      const double nz = draws.normal();
      const Vec3 want = s.ball_mm(x.ball, x.phi_deg) + an.form_error_mm(x.ball, x.phi_deg) + 15e-6 * Vec3(nx, ny, nz);
      CHECK((x.p_mm - want).norm() < 1e-15);
    }
  }
  SECTION("4096 a revolution over 5, and 8 over 100 at 10 %: the counts of the drift") {
    struct Case {
      int n, revolutions;
      double drift;
    };
    for (const Case c : {Case{4096, 5, 0.01}, Case{8, 100, 0.10}, Case{512, 4, 0.05}}) {
      CAPTURE(c.n, c.revolutions, c.drift);
      sim::AnalyserConfig ac;
      ac.time_sampled = true;
      ac.samples_per_revolution = c.n;
      ac.revolutions = c.revolutions;
      ac.speed_drift = c.drift;
      ac.noise_sigma_mm = 0.0;
      const sim::VirtualAnalyser an(ac);
      sim::SimRng rng(5);
      const auto samples = sim::measure_spindle(an, s, rng);
      REQUIRE(samples.size() == 2u * static_cast<std::size_t>(c.n) * static_cast<std::size_t>(c.revolutions));
      const std::vector<double> phi = ball_angles(samples);
      double smallest = 1e9, largest = 0.0;
      for (std::size_t k = 1; k < phi.size(); ++k) {
        smallest = std::min(smallest, phi[k] - phi[k - 1]);
        largest = std::max(largest, phi[k] - phi[k - 1]);
      }
      CHECK(smallest > 360.0 / c.n * (1.0 - c.drift / 2.0));
      CHECK(largest < 360.0 / c.n * (1.0 + c.drift / 2.0));
      const double instants = static_cast<double>(c.n) * c.revolutions;  // steps 0 .. N R - 2
      CHECK(largest - smallest == Approx(360.0 / c.n * c.drift * (instants - 2.0) / instants).margin(1e-9));
      sim::SimRng first(5);
      const double phi0 = 360.0 * (1.0 - first.uniform01());
      std::vector<int> per_rev(static_cast<std::size_t>(c.revolutions), 0);
      for (double p : phi) per_rev[static_cast<std::size_t>(std::floor((p - phi0) / 360.0))] += 1;
      for (int count : per_rev) {
        CHECK(count >= std::floor(c.n / (1.0 + c.drift / 2.0)));
        CHECK(count <= std::ceil(c.n / (1.0 - c.drift / 2.0)));
      }
    }
  }
  SECTION("no drift: a fixed step 360 / N from phi0 + 360 tau / N") {
    sim::AnalyserConfig ac;
    ac.time_sampled = true;
    ac.samples_per_revolution = 360;
    ac.speed_drift = 0.0;
    ac.noise_sigma_mm = 0.0;
    sim::SimRng rng(4);
    const auto samples = sim::measure_spindle(sim::VirtualAnalyser(ac), s, rng);
    REQUIRE(samples.size() == 2u * 360u * 3u);
    const std::vector<double> phi = ball_angles(samples);
    for (std::size_t k = 1; k < phi.size(); ++k) CHECK(std::abs(phi[k] - phi[k - 1] - 1.0) < 1e-9);
    CHECK(distinct_modulo_360(phi, 1e-9).size() == 360u);
  }
}

TEST_CASE("trueaxis-measure-spindle: --samples-per-rev, --time-sampled, --drift-percent, and their refusals") {
  t::Workspace ws("measure-spindle-modes");
  const std::string bin = TRUEAXIS_MEASURE_SPINDLE_BINARY;
  const sim::VirtualSpindle s(sim::realistic_spindle());
  auto measure = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> argv = {bin, "--out", ws.file(name), "--machine", ws.file("m.csv")};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return t::run(argv, ws.file("err"));
  };
  auto rows_of = [&](const std::string& name) {
    const auto csv = sim::read_csv(ws.file(name), {{"phi_deg"}, {"ball"}, {"x_mm"}, {"y_mm"}, {"z_mm"}});
    INFO(csv.error);
    REQUIRE(csv.ok);
    CHECK(csv.header_line == 3);  // the columns of before: an existing reader reads the file
    return csv.rows;
  };
  auto about_of = [&](const std::string& name) {
    const std::string text = t::slurp(ws.file(name));
    const std::size_t second = text.find('\n') + 1;
    return text.substr(second, text.find('\n', second) - second);
  };
  auto data_of = [&](const std::string& name) {
    const std::string text = t::slurp(ws.file(name));
    return text.substr(text.find("\nphi_deg,"));
  };

  SECTION("--samples-per-rev 4096 over 5 revolutions: N angles, repeating, read back exactly") {
    const auto r = measure("e.csv", {"--samples-per-rev", "4096", "--revolutions", "5", "--noise", "off"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(about_of("e.csv").find("5 revolutions at 4096 encoder-synchronous samples per revolution") !=
          std::string::npos);
    CHECK(r.out.find("4096 encoder-synchronous") != std::string::npos);
    const auto rows = rows_of("e.csv");
    REQUIRE(rows.size() == 2u * 4096u * 5u);
    std::vector<double> phi;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& v = rows[i].numbers;
      const std::size_t k = i / 2;
      CHECK(v[0] == 360.0 * static_cast<double>(k / 4096) + 360.0 * static_cast<double>(k % 4096) / 4096);
      CHECK(v[1] == static_cast<double>(1 + i % 2));
      if (i % 2 == 0) phi.push_back(v[0]);
    }
    CHECK(distinct_modulo_360(phi, 1e-9).size() == 4096u);
  }
  SECTION("--samples-per-rev 72 writes the data of --step-deg 5 (the default), and says so") {
    REQUIRE(measure("n.csv", {"--samples-per-rev", "72", "--seed", "4"}).exit_code == 0);
    REQUIRE(measure("s.csv", {"--step-deg", "5", "--seed", "4"}).exit_code == 0);
    REQUIRE(measure("d.csv", {"--seed", "4"}).exit_code == 0);
    CHECK(data_of("n.csv") == data_of("s.csv"));
    CHECK(t::slurp(ws.file("d.csv")) == t::slurp(ws.file("s.csv")));
    CHECK(about_of("s.csv") == "# seed 4, 3 revolutions at 5 deg, noise on (15 nm), form 50 nm RMS");
    CHECK(about_of("n.csv").find("72 encoder-synchronous samples per revolution (every 5 deg)") != std::string::npos);
  }
  SECTION("--time-sampled: 1024 a nominal revolution, 1 % drift by default, angles never repeated") {
    const auto r = measure("t.csv", {"--time-sampled", "--revolutions", "5", "--seed", "2", "--noise", "off"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string about = about_of("t.csv");
    CAPTURE(about);
    CHECK(about.find("5 revolutions time-sampled at 1024 samples per nominal revolution (5120 instants)") !=
          std::string::npos);
    CHECK(about.find("speed rising linearly by 1% (0.995 to 1.005 of nominal)") != std::string::npos);
    CHECK(about.find(", the first at ") != std::string::npos);
    const auto rows = rows_of("t.csv");
    REQUIRE(rows.size() == 2u * 1024u * 5u);
    std::vector<double> phi;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& v = rows[i].numbers;
      if (i % 2 == 1) {
        CHECK(v[0] == rows[i - 1].numbers[0]);  // both balls at one instant
        continue;
      }
      if (!phi.empty()) {
        CHECK(v[0] - phi.back() > 360.0 / 1024 * 0.995);
        CHECK(v[0] - phi.back() < 360.0 / 1024 * 1.005);
      }
      phi.push_back(v[0]);
      CHECK((Vec3(v[2], v[3], v[4]) - s.ball_mm(1, v[0])).cwiseAbs().maxCoeff() <= 0.5e-9 + 1e-12);
    }
    CHECK(closest_modulo_360(phi) > 1e-6);
    // The analyser's own angles, as the file has them (17 digits read back exactly).
    sim::AnalyserConfig ac;
    ac.time_sampled = true;
    ac.revolutions = 5;
    ac.noise_sigma_mm = 0.0;
    ac.form_rms_mm = 0.0;
    sim::SimRng rng(2);
    const auto want = sim::measure_spindle(sim::VirtualAnalyser(ac), s, rng);
    REQUIRE(want.size() == rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) CHECK(rows[i].numbers[0] == want[i].phi_deg);
  }
  SECTION("--time-sampled with N and P: the same seed the same file, the drift in the spacing") {
    for (const char* name : {"a.csv", "b.csv"}) {
      REQUIRE(measure(name, {"--time-sampled", "--samples-per-rev", "256", "--drift-percent", "10", "--seed", "7"})
                  .exit_code == 0);
    }
    REQUIRE(measure("c.csv", {"--time-sampled", "--samples-per-rev", "256", "--drift-percent", "0", "--seed", "7"})
                .exit_code == 0);
    CHECK(t::slurp(ws.file("a.csv")) == t::slurp(ws.file("b.csv")));
    CHECK(about_of("a.csv").find("by 10% (0.95 to 1.05 of nominal)") != std::string::npos);
    const auto a = rows_of("a.csv");
    const auto c = rows_of("c.csv");
    REQUIRE(a.size() == 2u * 256u * 3u);
    REQUIRE(c.size() == a.size());
    const double first = a[2].numbers[0] - a[0].numbers[0];
    const double last = a[a.size() - 2].numbers[0] - a[a.size() - 4].numbers[0];
    CHECK(first == Approx(360.0 / 256 * 0.95).epsilon(1e-3));
    CHECK(last == Approx(360.0 / 256 * 1.05).epsilon(1e-3));
    CHECK(c[2].numbers[0] - c[0].numbers[0] == Approx(360.0 / 256).epsilon(1e-12));
    CHECK(std::abs(c[0].numbers[0] - a[0].numbers[0]) < 360.0 / 256);  // one phi0 and tau per seed
  }
  SECTION("bad values are refused with one line that says why, and no file") {
    struct Bad {
      std::vector<std::string> extra;
      const char* says;
    };
    const std::vector<Bad> bad = {
        {{"--samples-per-rev", "7"}, "'--samples-per-rev 7': a whole number of samples per revolution from 8 to 4096"},
        {{"--samples-per-rev", "4097"}, "from 8 to 4096"},
        {{"--samples-per-rev", "100.5"}, "from 8 to 4096"},
        {{"--samples-per-rev", "x"}, "from 8 to 4096"},
        {{"--step-deg", "5", "--samples-per-rev", "72"}, "--step-deg and --samples-per-rev are exclusive"},
        {{"--samples-per-rev", "72", "--step-deg", "5"}, "--step-deg and --samples-per-rev are exclusive"},
        {{"--time-sampled", "--drift-percent", "11"}, "'--drift-percent 11': a speed drift in percent from 0 to 10"},
        {{"--time-sampled", "--drift-percent", "-1"}, "from 0 to 10"},
        {{"--time-sampled", "--drift-percent", "nan"}, "from 0 to 10"},
        {{"--drift-percent", "2"}, "--drift-percent goes with --time-sampled only"},
        {{"--time-sampled", "--step-deg", "5"}, "--step-deg does not go with --time-sampled"},
        {{"--time-sampled", "--drift-percent"}, "--drift-percent needs a value"},
        {{"--revolutions", "101"}, "from 1 to 100"},
        {{"--time-sampled", "yes"}, "bad option 'yes'"},
    };
    for (const Bad& b : bad) {
      CAPTURE(b.extra);
      const auto r = measure("x.csv", b.extra);
      CHECK(r.exit_code == 1);
      CHECK(r.err.find("trueaxis-measure-spindle: ") == 0);
      CHECK(r.err.find(b.says) != std::string::npos);
      CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
      CHECK(!t::exists(ws.file("x.csv")));
    }
  }
  SECTION("--help names the new options") {
    const auto r = t::run({bin, "--help"}, ws.file("err"));
    REQUIRE(r.exit_code == 0);
    for (const char* option : {"--samples-per-rev N", "--time-sampled", "--drift-percent P", "1..100", "8..4096"}) {
      CHECK(r.out.find(option) != std::string::npos);
    }
  }
}
