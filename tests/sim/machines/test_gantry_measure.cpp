// The virtual laser tracker (laser_tracker.hpp) and the measured files
// (gantry_measure.hpp): the noise's sigmas at 2 m and 6 m, the placement, the
// samples and MACHINE CSV through host_sim's CSV reader, the order of passes and
// circles, and reproducibility from the seed.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/gantry_measure.hpp"

namespace {

using trueaxis::core::Mat3;
using trueaxis::core::Vec3;
using trueaxis::sim::GantryMachine;
using trueaxis::sim::GantryPlan;
using trueaxis::sim::LaserTracker;
using trueaxis::sim::RigidTransform;
using trueaxis::sim::SimRng;
using trueaxis::sim::TrackerSample;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerArcsec = kPi / (180.0 * 3600.0);

std::vector<TrackerSample> group(const std::vector<TrackerSample>& all, const std::string& name) {
  std::vector<TrackerSample> out;
  for (const auto& s : all) {
    if (s.group == name) out.push_back(s);
  }
  return out;
}

}  // namespace

TEST_CASE("the tracker's noise has the documented sigmas at 2 m and at 6 m") {
  const LaserTracker tracker(RigidTransform{}, trueaxis::sim::TrackerSpec{}, true);
  struct Case {
    Vec3 p;
    double sigma_r_mm, sigma_t_mm;
  };
  // 2 sigma = 10 um along the beam; 15 um + 6 um/m across it.
  const Case cases[] = {{Vec3(2000.0, 0.0, 0.0), 0.005, 0.0135},
                        {Vec3(1200.0, -1500.0, 400.0).normalized() * 2000.0, 0.005, 0.0135},
                        {Vec3(3000.0, 4000.0, -2000.0).normalized() * 6000.0, 0.005, 0.0255},
                        {Vec3(0.0, 0.0, 6000.0), 0.005, 0.0255}};  // straight up: X as horizontal
  for (const Case& c : cases) {
    INFO("point " << c.p.x() << ", " << c.p.y() << ", " << c.p.z());
    CHECK(tracker.radial_sigma_mm(c.p.norm()) == Approx(c.sigma_r_mm).epsilon(1e-12));
    CHECK(tracker.transverse_sigma_mm(c.p.norm()) == Approx(c.sigma_t_mm).epsilon(1e-12));
    const Mat3 basis = LaserTracker::sight_basis(c.p);
    CHECK((basis.transpose() * basis - Mat3::Identity()).norm() < 1e-15);
    CHECK(std::abs(basis.col(1).z()) < 1e-15);  // horizontal
    SimRng rng(2024);
    SimRng again(2024);
    constexpr int kN = 4000;
    Vec3 sum = Vec3::Zero();
    Mat3 sum_sq = Mat3::Zero();
    for (int i = 0; i < kN; ++i) {
      const Vec3 d = basis.transpose() * (tracker.measure(c.p, rng) - c.p);
      REQUIRE((basis.transpose() * (tracker.measure(c.p, again) - c.p) - d).norm() == 0.0);
      sum += d;
      sum_sq += d * d.transpose();
    }
    const Vec3 mean = sum / kN;
    const Mat3 cov = sum_sq / kN - mean * mean.transpose();
    const Vec3 sigma(c.sigma_r_mm, c.sigma_t_mm, c.sigma_t_mm);
    for (int k = 0; k < 3; ++k) {
      INFO("direction " << k);
      CHECK(std::abs(mean[k]) < 4.0 * sigma[k] / std::sqrt(double(kN)));
      CHECK(std::sqrt(cov(k, k)) == Approx(sigma[k]).epsilon(0.04));
      for (int j = 0; j < k; ++j) CHECK(std::abs(cov(k, j)) / std::sqrt(cov(k, k) * cov(j, j)) < 0.07);
    }
  }
}

TEST_CASE("with the noise off the tracker reports the point exactly and draws nothing") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const LaserTracker t = trueaxis::sim::place_tracker(m, trueaxis::sim::TrackerPlacement{}, {}, false);
  SimRng rng(9);
  const Vec3 p(100.0, 200.0, 300.0);
  CHECK(t.measure(p, rng) == t.to_tracker(p));
  CHECK(rng.next_u64() == SimRng(9).next_u64());
}

TEST_CASE("the tracker stands in front of the machine, levelled, turned by its yaw") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  trueaxis::sim::TrackerPlacement place;
  place.distance_m = 3.0;
  place.machine_tilt_x_arcsec = 0.0;
  place.machine_tilt_y_arcsec = 0.0;
  const LaserTracker level = trueaxis::sim::place_tracker(m, place);
  const Vec3 at = level.machine_T_tracker().translation_mm;
  CHECK(m.config().front_y_mm - at.y() == Approx(3000.0).epsilon(1e-15));
  CHECK((level.tracker_T_machine().rotation * Vec3::UnitZ() - Vec3::UnitZ()).norm() < 1e-15);
  const Vec3 x = level.tracker_T_machine().rotation * Vec3::UnitX();
  CHECK(std::atan2(x.y(), x.x()) * 180.0 / kPi == Approx(-place.yaw_deg).epsilon(1e-12));
  CHECK((level.to_tracker(at)).norm() < 1e-12);
  // The machine's levelling error shows as the bed normal's tilt in the tracker frame.
  place.machine_tilt_x_arcsec = 10.0;
  place.machine_tilt_y_arcsec = -15.0;
  const LaserTracker tilted = trueaxis::sim::place_tracker(m, place);
  const Vec3 up = tilted.tracker_T_machine().rotation * Vec3::UnitZ();
  CHECK(std::acos(up.z()) / kRadPerArcsec == Approx(std::hypot(10.0, 15.0)).epsilon(1e-4));
}

TEST_CASE("at 2 to 6 m from the machine every point is between 2 and 6.5 m from the tracker") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  for (double d : {2.0, 2.5, 3.0}) {
    trueaxis::sim::TrackerPlacement place;
    place.distance_m = d;
    SimRng rng(1);
    const auto samples = measure_gantry(m, trueaxis::sim::place_tracker(m, place), GantryPlan{}, rng);
    double near = 1e300, far = 0.0;
    for (const auto& s : samples) {
      near = std::min(near, s.p_mm.norm());
      far = std::max(far, s.p_mm.norm());
    }
    INFO("distance " << d << " m: " << near << " .. " << far << " mm");
    CHECK(near > 2000.0);
    CHECK(far < 6500.0);
  }
}

TEST_CASE("the samples CSV round-trips through the CSV reader with every group sized as stated") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const LaserTracker tracker = trueaxis::sim::place_tracker(m, trueaxis::sim::TrackerPlacement{});
  SimRng rng(11);
  const GantryPlan plan;
  const auto samples = measure_gantry(m, tracker, plan, rng);
  const std::string text = trueaxis::sim::samples_csv_text(samples, {"a comment", "another"});
  const auto csv = trueaxis::sim::parse_csv("samples.csv", text, {{"group", false}, {"x_mm"}, {"y_mm"}, {"z_mm"}});
  REQUIRE(csv.ok);
  CHECK(csv.header_line == 3);
  REQUIRE(csv.rows.size() == samples.size());
  std::vector<std::pair<std::string, int>> runs;  // groups in file order with their sizes
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& row = csv.rows[i];
    REQUIRE(row.texts[0] == samples[i].group);
    CHECK((Vec3(row.numbers[1], row.numbers[2], row.numbers[3]) - samples[i].p_mm).norm() < 1e-9);
    if (runs.empty() || runs.back().first != row.texts[0]) runs.emplace_back(row.texts[0], 0);
    ++runs.back().second;
  }
  std::vector<std::pair<std::string, int>> expected = {{"bed", 100}, {"side_1", 20}, {"side_2", 20}};
  for (int k = 1; k <= 3; ++k) expected.emplace_back("gantry_" + std::to_string(k), 15);
  for (int n = 1; n <= 4; ++n) {
    const std::string sp = "sp" + std::to_string(n) + "_";
    for (const char* axis : {"x_", "y_", "z_"}) {
      for (int k = 1; k <= 3; ++k) expected.emplace_back(sp + axis + std::to_string(k), 15);
    }
    expected.emplace_back(sp + "c", 24);
    expected.emplace_back(sp + "a", 24);
  }
  CHECK(runs == expected);
  CHECK(samples.size() == 100 + 40 + 45 + 4 * (9 * 15 + 48));

  const std::string machine = trueaxis::sim::machine_csv_text(m, tracker);
  const auto mcsv = trueaxis::sim::parse_csv("machine.csv", machine,
                                             {{"sub_machine"}, {"swing_mm"}, {"tool_x"}, {"tool_y"}, {"tool_z"}});
  REQUIRE(mcsv.ok);
  REQUIRE(mcsv.rows.size() == 4);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& r = mcsv.rows[i].numbers;
    const auto& s = m.config().sub_machines[i];
    CHECK(r[0] == s.id);
    CHECK(r[1] == s.swing_mm);
    const Vec3 tool(r[2], r[3], r[4]);
    CHECK((tool - tracker.tracker_T_machine().rotation * s.tool_nominal).norm() < 1e-9);
    // Its sense orients C towards the tool tip.
    CHECK(tool.dot(tracker.tracker_T_machine().rotation * m.truth(i).c_dir) > 0.999);
  }
}

TEST_CASE("passes run in the positive direction, circles by increasing angle, on the true geometry") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const LaserTracker tracker = trueaxis::sim::place_tracker(m, trueaxis::sim::TrackerPlacement{}, {}, false);
  SimRng rng(3);
  const auto samples = measure_gantry(m, tracker, GantryPlan{}, rng);
  const Mat3 r = tracker.tracker_T_machine().rotation;
  const auto machine_T = tracker.machine_T_tracker();
  for (const auto& s : group(samples, "bed")) CHECK(std::abs(machine_T.apply(s.p_mm).z()) < 1e-9);
  for (int k = 1; k <= 2; ++k) {
    const auto& plane = m.side_plane(k);
    for (const auto& s : group(samples, "side_" + std::to_string(k))) {
      CHECK(std::abs(plane.normal.dot(machine_T.apply(s.p_mm) - plane.point_mm)) < 1e-9);
    }
  }
  const auto pass_increases = [&](const std::vector<TrackerSample>& pass, const Vec3& dir_machine) {
    REQUIRE(pass.size() == 15);
    for (std::size_t i = 1; i < pass.size(); ++i) CHECK((pass[i].p_mm - pass[i - 1].p_mm).dot(r * dir_machine) > 10.0);
  };
  pass_increases(group(samples, "gantry_2"), m.gantry_direction());
  for (std::size_t i = 0; i < m.sub_machine_count(); ++i) {
    const auto& t = m.truth(i);
    const std::string sp = "sp" + std::to_string(t.id) + "_";
    pass_increases(group(samples, sp + "x_3"), t.d_x);
    pass_increases(group(samples, sp + "y_1"), t.d_y);
    pass_increases(group(samples, sp + "z_2"), t.d_z);
    const auto turns_about = [&](const std::vector<TrackerSample>& circle, const Vec3& point, const Vec3& dir) {
      REQUIRE(circle.size() == 24);
      const Vec3 p = tracker.to_tracker(point);
      const Vec3 d = r * dir;
      for (std::size_t j = 1; j < circle.size(); ++j) {
        CHECK((circle[j - 1].p_mm - p).cross(circle[j].p_mm - p).dot(d) > 0.0);
      }
    };
    turns_about(group(samples, sp + "c"), t.wrist_mm, t.c_dir);
    turns_about(group(samples, sp + "a"), t.a_point_mm, t.a_dir);
  }
}

TEST_CASE("the same seed gives the same files, another seed other samples") {
  const GantryMachine m(trueaxis::sim::realistic_gantry());
  const LaserTracker tracker = trueaxis::sim::place_tracker(m, trueaxis::sim::TrackerPlacement{});
  const auto text_for = [&](std::uint64_t seed, const LaserTracker& t) {
    SimRng rng(seed);
    return trueaxis::sim::samples_csv_text(measure_gantry(m, t, GantryPlan{}, rng), {});
  };
  CHECK(text_for(5, tracker) == text_for(5, tracker));
  CHECK(text_for(5, tracker) != text_for(6, tracker));
  const LaserTracker quiet = trueaxis::sim::place_tracker(m, trueaxis::sim::TrackerPlacement{}, {}, false);
  CHECK(text_for(5, quiet) == text_for(6, quiet));
  const std::string json = trueaxis::sim::truth_json_text(m, tracker, GantryPlan{});
  CHECK(json == trueaxis::sim::truth_json_text(m, tracker, GantryPlan{}));
  CHECK(json.find("\"method\": \"gantry\"") != std::string::npos);
  CHECK(json.find("nan") == std::string::npos);
  std::size_t ids = 0;
  for (auto at = json.find("\"id\":"); at != std::string::npos; at = json.find("\"id\":", at + 1)) ++ids;
  CHECK(ids == 4);
}
