// M2 bad input: each failure its own status, and no half result.
#include <catch2/catch.hpp>

#include <memory>

#include "gantry_truth.hpp"
#include "trueaxis/core/so3.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;
using t::Vec3L;

namespace {

struct Fixture {
  t::Rng rng{901};
  t::TrueGantry truth = t::make_truth(rng);
  t::Samples samples;
  t::Samples good;
  std::unique_ptr<core::GantryFrames> out = std::make_unique<core::GantryFrames>();
  Fixture() {
    t::Sampler sampler(truth, rng, t::kTracker);
    samples = sampler.sample();
    good = samples;
  }
  core::GantryInput input() const { return t::make_input(truth, samples); }
  Status run(const core::GantryInput& in, const core::GantryOptions& options = {}) {
    // A previous good result must not survive as a half result of a failure.
    REQUIRE(core::compute_gantry_frames(t::make_input(truth, good), core::GantryOptions{}, *out) == Status::kOk);
    const Status s = core::compute_gantry_frames(in, options, *out);
    if (s != Status::kOk) CHECK(out->sub_machine_count == 0);
    return s;
  }
};

// Re-samples sub-machine 1's C circle over `arc_deg` only (no noise).
std::vector<Vec3> c_arc(const t::TrueGantry& g, double arc_deg) {
  const t::TrueSub& s = g.subs[0];
  const Vec3L target = s.wrist + 200 * s.c + 120 * t::unit_l(s.c.cross(Vec3L(0.3L, 0.5L, 0.7L)));
  std::vector<Vec3> p;
  for (int j = 0; j < 8; ++j) {
    const long double th = t::deg_l(arc_deg * j / 7.0);
    const Vec3L q = s.wrist + t::rodrigues_l(th * s.c) * (target - s.wrist);
    p.push_back((g.R_tg * q + g.O_t).cast<double>());
  }
  return p;
}

}  // namespace

TEST_CASE("the sample data compute", "[gantry][errors]") {
  Fixture f;
  CHECK(f.run(f.input()) == Status::kOk);
}

TEST_CASE("missing groups and group sizes have their own codes", "[gantry][errors]") {
  Fixture f;
  core::GantryInput in = f.input();
  SECTION("a sub-machine without a C circle is a missing group") {
    in.sub_machines[2].c_circle = {};
    CHECK(f.run(in) == Status::kMissingGroup);
  }
  SECTION("no gantry passes is a missing group") {
    in.gantry_pass_count = 0;
    CHECK(f.run(in) == Status::kMissingGroup);
  }
  SECTION("an axis without passes is a missing group") {
    in.sub_machines[1].pass_count[2] = 0;
    CHECK(f.run(in) == Status::kMissingGroup);
  }
  SECTION("no side face is a missing group") {
    in.side_2 = {};
    CHECK(f.run(in) == Status::kMissingGroup);
  }
  SECTION("no sub-machine is a missing group") {
    in.sub_machine_count = 0;
    CHECK(f.run(in) == Status::kMissingGroup);
  }
  SECTION("too few points in a pass, a plane, a circle") {
    core::GantryInput a = in;
    a.sub_machines[0].passes[1][2].count = core::kMinPassPoints - 1;
    CHECK(f.run(a) == Status::kTooFewPoints);
    core::GantryInput b = in;
    b.side_1.count = core::kMinPlanePoints - 1;
    CHECK(f.run(b) == Status::kTooFewPoints);
    core::GantryInput c = in;
    c.sub_machines[3].a_circle.count = core::kMinCirclePoints - 1;
    CHECK(f.run(c) == Status::kTooFewPoints);
  }
  SECTION("more points, passes or sub-machines than the capacities") {
    std::vector<Vec3> big(core::kMaxGroupPoints + 1, Vec3::Zero());
    core::GantryInput a = in;
    a.bed = t::span(big);
    CHECK(f.run(a) == Status::kTooManyPoints);
    core::GantryInput b = in;
    b.sub_machines[0].pass_count[0] = core::kMaxPasses + 1;
    CHECK(f.run(b) == Status::kTooManyPoints);
    core::GantryInput c = in;
    c.sub_machine_count = core::kMaxSubMachines + 1;
    CHECK(f.run(c) == Status::kTooManyPoints);
  }
  SECTION("a repeated or out-of-range id is refused") {
    core::GantryInput a = in;
    a.sub_machines[3].id = 1;
    CHECK(f.run(a) == Status::kArgumentOutOfRange);
    core::GantryInput b = in;
    b.sub_machines[3].id = 9;
    CHECK(f.run(b) == Status::kArgumentOutOfRange);
  }
}

TEST_CASE("non-finite input is refused", "[gantry][errors]") {
  Fixture f;
  core::GantryInput in = f.input();
  SECTION("a NaN point in a pass") {
    f.samples.subs[2].passes[0][1][5].y() = NAN;
    CHECK(f.run(f.input()) == Status::kNotFinite);
  }
  SECTION("an infinite point on the bed") {
    f.samples.bed[3].z() = INFINITY;
    CHECK(f.run(f.input()) == Status::kNotFinite);
  }
  SECTION("a NaN swing length, tool direction or noise option") {
    core::GantryInput a = in;
    a.sub_machines[1].swing_mm = NAN;
    CHECK(f.run(a) == Status::kNotFinite);
    core::GantryInput b = in;
    b.sub_machines[1].tool_direction.x() = NAN;
    CHECK(f.run(b) == Status::kNotFinite);
    core::GantryOptions o;
    o.noise.range_sigma_per_mm = NAN;
    CHECK(f.run(in, o) == Status::kNotFinite);
  }
  SECTION("a negative swing length or a zero tool direction is out of range") {
    core::GantryInput a = in;
    a.sub_machines[1].swing_mm = -1.0;
    CHECK(f.run(a) == Status::kArgumentOutOfRange);
    core::GantryInput b = in;
    b.sub_machines[1].tool_direction = Vec3::Zero();
    CHECK(f.run(b) == Status::kArgumentOutOfRange);
  }
}

TEST_CASE("degenerate geometry has its own codes", "[gantry][errors]") {
  Fixture f;
  SECTION("A parallel to C, and nearly parallel, is refused; just wider is accepted") {
    t::TrueGantry g = f.truth;
    const Vec3L c = g.subs[1].c;
    const Vec3L perp = t::unit_l(c.cross(g.subs[1].a));
    for (const long double angle : {1e-8L, 5e-4L, 2e-3L}) {
      g.subs[1].a = t::rodrigues_l(angle * perp) * c;
      t::Sampler sampler(g, f.rng, t::NoiseSpec{});
      f.samples = sampler.sample();
      const Status s = f.run(t::make_input(g, f.samples));
      CHECK(s == (angle < 1e-3L ? Status::kAxesParallel : Status::kOk));
    }
  }
  SECTION("a C arc too short is refused") {
    const std::vector<Vec3> arc = c_arc(f.truth, 3.0);
    core::GantryInput in = f.input();
    in.sub_machines[0].c_circle = t::span(arc);
    CHECK(f.run(in) == Status::kArcTooShort);
    const std::vector<Vec3> longer = c_arc(f.truth, 60.0);
    in.sub_machines[0].c_circle = t::span(longer);
    CHECK(f.run(in) == Status::kOk);
  }
  SECTION("an X axis measured against the gantry's direction is refused") {
    for (auto& pass : f.samples.subs[3].passes[0]) std::reverse(pass.begin(), pass.end());
    CHECK(f.run(f.input()) == Status::kAxisOppositeGantry);
  }
  SECTION("one pass measured backwards disagrees with the others") {
    auto& pass = f.samples.subs[0].passes[2][1];
    std::reverse(pass.begin(), pass.end());
    CHECK(f.run(f.input()) == Status::kPassesDisagree);
  }
  SECTION("a tool direction perpendicular to the C axis is ambiguous") {
    core::GantryInput in = f.input();
    const Vec3 c = (f.truth.R_tg * f.truth.subs[2].c).cast<double>();
    in.sub_machines[2].tool_direction = c.unitOrthogonal();
    CHECK(f.run(in) == Status::kToolDirectionAmbiguous);
  }
  SECTION("the C axis follows the tool direction's sense") {
    core::GantryInput in = f.input();
    in.sub_machines[2].tool_direction = -in.sub_machines[2].tool_direction;
    REQUIRE(f.run(in) == Status::kOk);
    CHECK(f.out->sub_machines[2].c_circle.normal.dot((f.truth.subs[2].c).cast<double>()) < -0.99);
  }
  SECTION("side faces parallel to each other do not make an origin") {
    f.samples.side_2 = f.samples.side_1;
    CHECK(f.run(f.input()) == Status::kPlanesDegenerate);
  }
  SECTION("data that are not levelled are refused") {
    // The whole measurement turned 90 deg about the tracker's X: the bed stands upright.
    const core::Mat3 r = core::so3_exp(Vec3(core::kPi / 2, 0, 0));
    const auto turn = [&](std::vector<Vec3>& v) {
      for (Vec3& p : v) p = r * p;
    };
    turn(f.samples.bed);
    turn(f.samples.side_1);
    turn(f.samples.side_2);
    for (auto& p : f.samples.gantry) turn(p);
    CHECK(f.run(f.input()) == Status::kBedNotLevel);
  }
}
