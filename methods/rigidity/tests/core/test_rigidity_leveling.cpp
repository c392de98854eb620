#include <catch2/catch.hpp>

#include <array>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_leveling.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Blend;
using core::Status;
using core::Vec3;

namespace {

const core::RigidityTable& level_table() {
  static const auto builder = [] {
    auto b = std::make_unique<core::RigidityBuilder>();
    t::Rng rng(701);
    t::Plan plan;
    plan.a_deg = {-60.0, -30.0, 0.0, 20.0, 45.0, 70.0};
    const auto samples = t::measure(t::Cradle{}, plan, rng);
    REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), {}, *b) == Status::kOk);
    return b;
  }();
  return builder->table();
}

// A face on the cradle's table (table coordinates, long double) whose outward
// normal is n_table, probed with the table at `probe`: four points in the machine.
struct Face {
  t::Vec3L n_table;
  std::array<Vec3, 4> points;
  Vec3 hint;
};

Face make_face(const t::Cradle& cradle, const t::Vec3L& n_table, const core::TablePose& probe) {
  Face f;
  f.n_table = n_table.normalized();
  const t::Vec3L u = f.n_table.cross(t::Vec3L(0.3L, 1.0L, 0.2L)).normalized();
  const t::Vec3L v = f.n_table.cross(u);
  const t::Vec3L centre(30.0L, -20.0L, 40.0L);
  for (std::size_t k = 0; k < 4; ++k) {
    const long double phase = 0.4L + static_cast<long double>(k) * t::kPiL / 2.0L;
    const t::Vec3L q = centre + 60.0L * (std::cos(phase) * u + std::sin(phase) * v);
    f.points[k] = cradle.point(probe.a_deg, probe.c_deg, q).cast<double>();
  }
  f.hint = (cradle.actual_rotation(probe.a_deg, probe.c_deg) * f.n_table).cast<double>();
  return f;
}

core::LevelInput input_for(const Face& f, const core::TablePose& probe) {
  core::LevelInput in;
  in.points_mm = f.points.data();
  in.count = f.points.size();
  in.probe_pose = probe;
  in.current_pose = probe;
  in.outward_hint_machine = f.hint;
  return in;
}

// Angle between +Z and the face's normal with the TRUE table at commanded (A, C).
long double true_tilt(const t::Cradle& cradle, const t::Vec3L& n_table, const core::LevelSolution& s) {
  return t::angle_l(cradle.actual_rotation(s.a_deg, s.c_deg) * n_table, t::Vec3L::UnitZ());
}

// The same on the table's model.
double model_tilt(const core::RigidityTable& table, const Vec3& q, const core::LevelSolution& s, Blend blend) {
  const auto f = core::rigidity_frames(table, s.a_deg, s.c_deg, blend, true);
  REQUIRE(f.ok());
  return core::angle_between(f.value().machine_T_table_actual.rotation * q, Vec3::UnitZ());
}

}  // namespace

TEST_CASE("leveling on the calibrated axes levels the face on the true machine", "[rigidity][level]") {
  const t::Cradle cradle;
  const core::RigidityTable& table = level_table();
  // The face that the true machine levels at (A, C) = (45, 123.4), 45 a measured pose.
  const t::Vec3L n_table = cradle.actual_rotation(45.0L, 123.4L).transpose() * t::Vec3L::UnitZ();
  const core::TablePose probe{0.0, 30.0};
  const Face face = make_face(cradle, n_table, probe);
  const core::LevelConfig cfg;
  for (Blend blend : {Blend::kLinear, Blend::kGeodesic, Blend::kCubic}) {
    const auto r = core::level_on_table(input_for(face, probe), cfg, table, blend, false);
    REQUIRE(r.ok());
    const core::LevelResult& res = r.value();
    const core::LevelSolution& at_pose =
        std::abs(res.chosen.a_deg - 45.0) < std::abs(res.other.a_deg - 45.0) ? res.chosen : res.other;
    const core::LevelSolution& between = &at_pose == &res.chosen ? res.other : res.chosen;
    CHECK(std::abs(at_pose.a_deg - 45.0) < 1e-9);
    CHECK(std::abs(at_pose.c_deg - 123.4) < 1e-9);
    CHECK(true_tilt(cradle, face.n_table, at_pose) < 1e-12L);
    // The other solution lies between poses: level on the table's model.
    CHECK(model_tilt(table, res.normal_table, between, blend) < 1e-12);
    CHECK(std::abs(between.a_deg) > 1.0);
    CHECK(res.chosen.reachable);
  }

  SECTION("leveling on ideal axes leaves the face tilted by the axes' errors") {
    const auto ideal = core::level_face(input_for(face, probe), cfg);
    REQUIRE(ideal.ok());
    const auto calibrated = core::level_on_table(input_for(face, probe), cfg, table, Blend::kLinear, false);
    REQUIRE(calibrated.ok());
    const auto near_45 = [](const core::LevelResult& res) {
      return std::abs(res.chosen.a_deg - 45.0) < std::abs(res.other.a_deg - 45.0) ? res.chosen : res.other;
    };
    const long double ideal_tilt = true_tilt(cradle, face.n_table, near_45(ideal.value()));
    const long double calibrated_tilt = true_tilt(cradle, face.n_table, near_45(calibrated.value()));
    CHECK(ideal_tilt > 2e-5L);  // several arc-seconds
    CHECK(calibrated_tilt < 1e-12L);
    // Between poses the table's blend, not the solver, sets what remains.
    const long double between_tilt = true_tilt(
        cradle, face.n_table,
        near_45(calibrated.value()).a_deg == calibrated.value().chosen.a_deg ? calibrated.value().other
                                                                              : calibrated.value().chosen);
    WARN("true tilt after leveling, solution at A = 45: ideal axes "
         << static_cast<double>(ideal_tilt) * 206264.8 << " arcsec, calibrated " << static_cast<double>(calibrated_tilt)
         << " rad; calibrated solution between poses (linear blend) " << static_cast<double>(between_tilt) * 206264.8
         << " arcsec");
    // The diagnostics are level_face's.
    CHECK(calibrated.value().flatness_mm == ideal.value().flatness_mm);
    CHECK(calibrated.value().direction_sigma_arcsec == ideal.value().direction_sigma_arcsec);
  }
}

TEST_CASE("a level face keeps C and gets the A nearest level", "[rigidity][level]") {
  const t::Cradle cradle;
  const core::RigidityTable& table = level_table();
  const core::TablePose probe{0.0, 30.0};
  const Face face = make_face(cradle, t::Vec3L::UnitZ(), probe);
  const auto r = core::level_on_table(input_for(face, probe), core::LevelConfig{}, table, Blend::kLinear, false);
  REQUIRE(r.ok());
  const core::LevelResult& res = r.value();
  CHECK(res.chosen.c_deg == 30.0);
  CHECK(res.other.a_deg == res.chosen.a_deg);
  // No A nearby brings the normal nearer +Z.
  const double tilt = model_tilt(table, res.normal_table, res.chosen, Blend::kLinear);
  for (double da : {-1e-3, 1e-3}) {
    core::LevelSolution s = res.chosen;
    s.a_deg += da;
    CHECK(model_tilt(table, res.normal_table, s, Blend::kLinear) > tilt);
  }
  CHECK(std::abs(res.chosen.a_deg) < 0.1);
}

TEST_CASE("calibrated leveling refuses what it cannot reach", "[rigidity][level]") {
  const t::Cradle cradle;
  const core::RigidityTable& table = level_table();
  const core::TablePose probe{0.0, 30.0};
  const t::Vec3L n45 = cradle.actual_rotation(45.0L, 123.4L).transpose() * t::Vec3L::UnitZ();
  const Face face = make_face(cradle, n45, probe);
  SECTION("travel limits exclude both solutions") {
    core::LevelConfig cfg;
    cfg.a_min_deg = -1.0;
    cfg.a_max_deg = 1.0;
    CHECK(core::level_on_table(input_for(face, probe), cfg, table, Blend::kLinear, false).status() ==
          Status::kUnreachable);
  }
  SECTION("solutions beyond the table's A range, unless clamped") {
    const t::Vec3L n85 = cradle.actual_rotation(85.0L, 10.0L).transpose() * t::Vec3L::UnitZ();
    const Face steep = make_face(cradle, n85, probe);
    CHECK(core::level_on_table(input_for(steep, probe), core::LevelConfig{}, table, Blend::kLinear, false).status() ==
          Status::kUnreachable);
    const auto clamped = core::level_on_table(input_for(steep, probe), core::LevelConfig{}, table, Blend::kLinear, true);
    REQUIRE(clamped.ok());
    CHECK(std::abs(std::abs(clamped.value().chosen.a_deg) - 85.0) < 0.1);
  }
  SECTION("a probe pose beyond the range, an invalid configuration, no table") {
    const core::TablePose far{80.0, 0.0};
    const Face f = make_face(cradle, n45, far);
    CHECK(core::level_on_table(input_for(f, far), core::LevelConfig{}, table, Blend::kLinear, false).status() ==
          Status::kOutsideMeasuredRange);
    core::LevelConfig bad;
    bad.a_min_deg = 10.0;
    bad.a_max_deg = -10.0;
    CHECK(core::level_on_table(input_for(face, probe), bad, table, Blend::kLinear, false).status() ==
          Status::kConfigInvalid);
    CHECK(core::level_on_table(input_for(face, probe), core::LevelConfig{}, core::RigidityTable{}, Blend::kLinear,
                               false)
              .status() == Status::kNoTable);
  }
}

TEST_CASE("calibrated leveling allocates nothing", "[rigidity][level][alloc]") {
  const t::Cradle cradle;
  const core::RigidityTable& table = level_table();
  const core::TablePose probe{-30.0, 75.0};
  const Face face = make_face(cradle, t::Vec3L(0.3L, -0.5L, 0.8L), probe);
  const auto in = input_for(face, probe);
  const t::AllocationScope scope;
  const auto r = core::level_on_table(in, core::LevelConfig{}, table, Blend::kGeodesic, false);
  CHECK(scope.count() == 0);
  CHECK(r.ok());
}
