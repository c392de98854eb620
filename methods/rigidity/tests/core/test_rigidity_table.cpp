#include <catch2/catch.hpp>

#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_table.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

// Noise-free tolerances, ten times what the build reaches on this cradle (all
// within 1e-13 rad and 1e-11 mm; the worst rotation vector error is printed).
constexpr long double kAngleTol = 1e-12L;   // rad: rotvec, theta, a_error, squareness, directions
constexpr long double kLengthTol = 1e-10L;  // mm: centres, A-axis point, offsets

struct Built {
  std::unique_ptr<core::RigidityBuilder> builder = std::make_unique<core::RigidityBuilder>();
  Status status = Status::kOk;
  const core::RigidityTable& table() const { return builder->table(); }
};

Built build(const std::vector<core::RigiditySample>& samples, const core::RigidityOptions& options = {}) {
  Built b;
  b.status = core::build_rigidity_table(samples.data(), samples.size(), options, *b.builder);
  return b;
}

long double diff(const Vec3& a, const t::Vec3L& b) { return (a.cast<long double>() - b).norm(); }

}  // namespace

TEST_CASE("noise-free samples of a known cradle give its errors exactly", "[rigidity]") {
  const t::Cradle cradle;
  t::Rng rng(301);
  const t::Plan plan;
  const auto samples = t::measure(cradle, plan, rng);
  const Built b = build(samples);
  REQUIRE(b.status == Status::kOk);
  const core::RigidityTable& table = b.table();
  REQUIRE(table.pose_count == plan.a_deg.size());
  CHECK(table.poses[table.reference].a_deg == 0.0);

  SECTION("the A axis is the cradle's") {
    CHECK(diff(table.a_axis_point_mm, cradle.a_axis_point()) < kLengthTol);
    CHECK(diff(table.a_axis_direction, cradle.a_dir) < kAngleTol);
  }
  SECTION("every pose has the true rotation vector, A turn and A error") {
    long double worst = 0.0L;
    for (std::size_t i = 0; i < table.pose_count; ++i) {
      const core::RigidityPose& p = table.poses[i];
      INFO("A = " << p.a_deg);
      CHECK(p.a_deg == plan.a_deg[i]);
      CHECK(diff(p.rotvec_rad, cradle.rotvec(p.a_deg)) < kAngleTol);
      CHECK(std::abs(p.rigidity_rad - cradle.w(p.a_deg).norm()) < kAngleTol);
      CHECK(std::abs(p.theta_rad - cradle.theta(p.a_deg)) < kAngleTol);
      CHECK(std::abs(p.a_error_rad - cradle.a_error(p.a_deg)) < kAngleTol);
      CHECK(p.origin_offset_mm.norm() < kLengthTol);
      CHECK(diff(p.c_centre_mm, cradle.origin(p.a_deg)) < kLengthTol);
      const t::Mat3L actual = cradle.actual_rotation(p.a_deg, 0.0L);
      CHECK(diff(p.c_direction, actual.col(2)) < kAngleTol);
      CHECK(diff(p.c_x_axis, actual.col(0)) < kAngleTol);
      CHECK(p.c_circle_rms_mm < 1e-9);
      CHECK(p.c_count == 8);
      worst = std::max(worst, diff(p.rotvec_rad, cradle.rotvec(p.a_deg)));
    }
    // The deformation is tens of arc-seconds: the test is not passing on zeros.
    CHECK(table.poses[0].rigidity_rad > 5e-5);
    WARN("worst rotation-vector error, noise-free: " << static_cast<double>(worst) << " rad");
  }
  SECTION("the reference pose is exactly zero") {
    const core::RigidityPose& r = table.poses[table.reference];
    CHECK(r.rotvec_rad == Vec3::Zero());
    CHECK(r.rigidity_rad == 0.0);
    CHECK(r.a_error_rad == 0.0);
    CHECK(r.theta_rad == 0.0);
    CHECK(r.origin_offset_mm == Vec3::Zero());
    CHECK(r.rotvec_sigma_rad == Vec3::Zero());
    CHECK(r.rigidity_sigma_rad == 0.0);
    CHECK(r.a_error_sigma_rad == 0.0);
  }
  SECTION("the C-to-A offset and squareness are the cradle's") {
    CHECK(std::abs(table.c_to_a_offset_mm - cradle.offset()) < kLengthTol);
    CHECK(std::abs(table.c_to_a_squareness_rad - cradle.squareness()) < kAngleTol);
    CHECK(cradle.offset() > 0.02L);
    CHECK(std::abs(cradle.squareness()) > 5e-5L);
  }
  SECTION("noise-free data report sigmas of rounding size") {
    for (std::size_t i = 0; i < table.pose_count; ++i) {
      CHECK(table.poses[i].rotvec_sigma_rad.maxCoeff() < 1e-11);
      CHECK(table.poses[i].a_error_sigma_rad < 1e-11);
    }
  }
}

TEST_CASE("the build does not depend on the samples' order or C sampling", "[rigidity]") {
  const t::Cradle cradle;
  t::Rng rng(302);
  t::Plan plan;
  plan.shuffle = false;
  const auto ordered = t::measure(cradle, plan, rng);
  auto reversed = ordered;
  std::reverse(reversed.begin(), reversed.end());
  const Built a = build(ordered);
  const Built b = build(reversed);
  REQUIRE(a.status == Status::kOk);
  REQUIRE(b.status == Status::kOk);
  for (std::size_t i = 0; i < a.table().pose_count; ++i) {
    CHECK((a.table().poses[i].rotvec_rad - b.table().poses[i].rotvec_rad).norm() < 1e-12);
  }
  SECTION("a partial C arc of 120 deg without C = 0 gives the same answers") {
    t::Plan partial;
    partial.c_per_pose = 5;
    partial.c_step_deg = 30.0;  // offset in [0, 30): never C = 0 unless drawn
    const Built c = build(t::measure(cradle, partial, rng));
    REQUIRE(c.status == Status::kOk);
    for (std::size_t i = 0; i < c.table().pose_count; ++i) {
      const core::RigidityPose& p = c.table().poses[i];
      CHECK(diff(p.rotvec_rad, cradle.rotvec(p.a_deg)) < kAngleTol);
      CHECK(std::abs(p.a_error_rad - cradle.a_error(p.a_deg)) < kAngleTol);
    }
  }
  SECTION("A beyond 180 deg of span stays on the continuous branch") {
    t::Plan wide;
    wide.a_deg = {-120.0, -60.0, 0.0, 60.0, 120.0, 170.0};
    const Built c = build(t::measure(cradle, wide, rng));
    REQUIRE(c.status == Status::kOk);
    for (std::size_t i = 0; i < c.table().pose_count; ++i) {
      const core::RigidityPose& p = c.table().poses[i];
      CHECK(std::abs(p.theta_rad - cradle.theta(p.a_deg)) < kAngleTol);
      CHECK(diff(p.rotvec_rad, cradle.rotvec(p.a_deg)) < kAngleTol);
    }
  }
  SECTION("a repeated C is a repeat measurement, not an error") {
    auto repeated = ordered;
    repeated.push_back(ordered.front());
    repeated.back().c_deg += 360.0;
    const Built c = build(repeated);
    REQUIRE(c.status == Status::kOk);
  }
}

TEST_CASE("the build runs in bounded steps and allocates nothing", "[rigidity][alloc]") {
  const t::Cradle cradle;
  t::Rng rng(303);
  t::Plan plan;
  plan.noise_mm = 0.001;
  const auto samples = t::measure(cradle, plan, rng);
  auto builder = std::make_unique<core::RigidityBuilder>();
  const core::RigidityOptions options;
  const t::AllocationScope scope;
  builder->start(samples.data(), samples.size(), options);
  std::size_t steps = 0;
  core::RigidityStep s;
  do {
    s = builder->step();
    ++steps;
  } while (s.more);
  CHECK(scope.count() == 0);
  REQUIRE(s.status == Status::kOk);
  // 1 grouping step (56 samples), sort, 7 fits, nominal, 2 x 6 x 7 Jacobian sides
  // (none of rounding-zero size here), the end of the Jacobian, finish.
  CHECK(steps == 1 + 1 + 7 + 1 + 84 + 1 + 1);
  CHECK(builder->steps() == steps);
  // After the end, step() repeats the outcome.
  const core::RigidityStep again = builder->step();
  CHECK(!again.more);
  CHECK(again.status == Status::kOk);
}

TEST_CASE("degenerate rigidity inputs are refused, each with its status", "[rigidity]") {
  const t::Cradle cradle;
  t::Rng rng(304);
  const t::Plan plan;
  const auto good = t::measure(cradle, plan, rng);
  auto builder = std::make_unique<core::RigidityBuilder>();
  const auto run = [&](const std::vector<core::RigiditySample>& s, const core::RigidityOptions& o = {}) {
    return core::build_rigidity_table(s.data(), s.size(), o, *builder);
  };
  const auto only_poses = [&](std::initializer_list<double> keep) {
    std::vector<core::RigiditySample> out;
    for (const auto& s : good) {
      for (double a : keep) {
        if (s.a_deg == a) out.push_back(s);
      }
    }
    return out;
  };

  SECTION("no samples, or two poses") {
    CHECK(run({}) == Status::kTooFewPoses);
    CHECK(run(only_poses({0.0, 25.0})) == Status::kTooFewPoses);
  }
  SECTION("no pose at A = 0") { CHECK(run(only_poses({-30.0, 25.0, 50.0})) == Status::kNoReferencePose); }
  SECTION("A within the tolerance of 0 is the reference; beyond it is not") {
    auto near = only_poses({-30.0, 0.0, 25.0});
    for (auto& s : near) {
      if (s.a_deg == 0.0) s.a_deg = 0.9e-6;
    }
    CHECK(run(near) == Status::kOk);
    for (auto& s : near) {
      if (s.a_deg == 0.9e-6) s.a_deg = 1.1e-6;
    }
    CHECK(run(near) == Status::kNoReferencePose);
  }
  SECTION("more than 16 poses") {
    t::Plan many;
    many.a_deg.clear();
    for (int i = 0; i < 17; ++i) many.a_deg.push_back(-80.0 + 10.0 * i);
    many.c_per_pose = 4;
    many.c_step_deg = 90.0;
    CHECK(run(t::measure(cradle, many, rng)) == Status::kTooManyPoses);
    many.a_deg.pop_back();
    CHECK(run(t::measure(cradle, many, rng)) == Status::kOk);
  }
  SECTION("more samples than the capacity") {
    std::vector<core::RigiditySample> big;
    while (big.size() <= core::kMaxRigiditySamples) big.insert(big.end(), good.begin(), good.end());
    big.resize(core::kMaxRigiditySamples + 1);
    CHECK(run(big) == Status::kTooManyPoints);
  }
  SECTION("more samples in one pose than a circle fit holds") {
    t::Plan dense;
    dense.a_deg = {-30.0, 0.0, 30.0};
    dense.c_per_pose = static_cast<int>(core::kMaxCirclePoints);
    dense.c_step_deg = 360.0 / static_cast<double>(core::kMaxCirclePoints);
    auto s = t::measure(cradle, dense, rng);
    CHECK(run(s) == Status::kOk);
    // Every sample into A = 0 (3 x kMaxCirclePoints), then 4 new ones at +-30.
    for (auto& x : s) x.a_deg = 0.0;
    for (double a : {-30.0, 30.0}) {
      for (double c : {0.0, 90.0, 180.0, 270.0}) s.push_back({a, c, cradle.ball(a, c).cast<double>()});
    }
    CHECK(run(s) == Status::kTooManyPoints);
    CHECK(builder->failed_pose() == 2);
  }
  SECTION("a value that is not finite") {
    for (int field = 0; field < 3; ++field) {
      auto s = good;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      if (field == 0) s[17].a_deg = nan;
      if (field == 1) s[17].c_deg = std::numeric_limits<double>::infinity();
      if (field == 2) s[17].p_mm.y() = nan;
      CHECK(run(s) == Status::kNotFinite);
    }
    core::RigidityOptions o;
    o.min_c_arc_deg = std::numeric_limits<double>::quiet_NaN();
    CHECK(run(good, o) == Status::kNotFinite);
  }
  SECTION("options out of range, no sample array, no start") {
    core::RigidityOptions o;
    o.min_c_arc_deg = 360.0;
    CHECK(run(good, o) == Status::kArgumentOutOfRange);
    o = {};
    o.min_a_arc_deg = -1.0;
    CHECK(run(good, o) == Status::kArgumentOutOfRange);
    CHECK(core::build_rigidity_table(nullptr, 3, {}, *builder) == Status::kArgumentOutOfRange);
    auto fresh = std::make_unique<core::RigidityBuilder>();
    CHECK(fresh->step().status == Status::kArgumentOutOfRange);
  }
  SECTION("a pose with 3 distinct C (one repeated modulo 360)") {
    std::vector<core::RigiditySample> s;
    for (const auto& x : good) {
      if (x.a_deg != 25.0) s.push_back(x);
    }
    for (double c : {10.0, 100.0, 190.0, 370.0}) s.push_back({25.0, c, cradle.ball(25.0, c).cast<double>()});
    CHECK(run(s) == Status::kTooFewCPositions);
    CHECK(builder->failed_pose() == 5);  // 25 deg is the fifth pose in A order
    s.push_back({25.0, 280.0, cradle.ball(25.0, 280.0).cast<double>()});
    CHECK(run(s) == Status::kOk);
  }
  SECTION("a pose whose C positions straddle 0/360 (C = 0, 90, 180 and -5e-7): 3 distinct") {
    std::vector<core::RigiditySample> s;
    for (const auto& x : good) {
      if (x.a_deg != 25.0) s.push_back(x);
    }
    for (double c : {0.0, 90.0, 180.0, -5e-7}) s.push_back({25.0, c, cradle.ball(25.0, c).cast<double>()});
    CHECK(run(s) == Status::kTooFewCPositions);  // -5e-7 is 0 within kPoseAToleranceDeg, across the wrap
    CHECK(builder->failed_pose() == 5);
    s.push_back({25.0, 270.0, cradle.ball(25.0, 270.0).cast<double>()});
    CHECK(run(s) == Status::kOk);
  }
  SECTION("a C arc shorter than the configured one") {
    t::Plan short_arc;
    short_arc.c_per_pose = 4;
    short_arc.c_step_deg = 10.0;  // 30 deg of arc
    const auto s = t::measure(cradle, short_arc, rng);
    CHECK(run(s) == Status::kArcTooShort);
    CHECK(builder->failed_pose() == 1);
    core::RigidityOptions o;
    o.min_c_arc_deg = 25.0;
    CHECK(run(s, o) == Status::kOk);
  }
  SECTION("C labels that do not match the ball's motion") {
    auto s = only_poses({-30.0, 0.0, 25.0});
    // Swap the commanded C of two samples of the reference pose.
    std::size_t first = s.size();
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (s[k].a_deg != 0.0) continue;
      if (first == s.size()) {
        first = k;
      } else {
        std::swap(s[first].c_deg, s[k].c_deg);
        break;
      }
    }
    CHECK(run(s) == Status::kCPhaseInconsistent);
    CHECK(builder->failed_pose() == 2);
  }
  SECTION("C centres that do not determine the A axis") {
    // The ball's C centre on the A axis: every pose has the same centre.
    t::Cradle on_axis = cradle;
    on_axis.c_point = on_axis.a_point - on_axis.c_dir * 150.0L;
    on_axis.ball_at_zero = on_axis.a_point + 80.0L * on_axis.c_dir.cross(t::Vec3L::UnitY()).normalized();
    t::Plan p;
    p.a_deg = {-30.0, 0.0, 30.0};
    CHECK(run(t::measure(on_axis, p, rng)) == Status::kAAxisUndetermined);
    // Poses spanning 2 deg of A: an arc below min_a_arc_deg.
    p.a_deg = {-1.0, 0.0, 1.0};
    CHECK(run(t::measure(cradle, p, rng)) == Status::kAAxisUndetermined);
  }
  SECTION("a failed build leaves the status for later steps") {
    CHECK(run(only_poses({0.0, 25.0})) == Status::kTooFewPoses);
    CHECK(builder->step().status == Status::kTooFewPoses);
    CHECK(!builder->step().more);
  }
}
