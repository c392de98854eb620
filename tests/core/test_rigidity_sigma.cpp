#include <catch2/catch.hpp>

#include <memory>
#include <vector>

#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_table.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;

namespace {

// Observed spread (about the truth) and reported sigma (RMS over the runs) of one figure.
struct Figure {
  double sum_sq_error = 0.0;
  double sum_sq_sigma = 0.0;
  int n = 0;
  void add(double error, double sigma) {
    sum_sq_error += error * error;
    sum_sq_sigma += sigma * sigma;
    ++n;
  }
  double observed() const { return std::sqrt(sum_sq_error / n); }
  double reported() const { return std::sqrt(sum_sq_sigma / n); }
  double ratio() const { return reported() / observed(); }
};

constexpr std::size_t kPoses = 5;

void check_sigmas(const t::Plan& plan, t::Rng& rng) {
  const t::Cradle cradle;
  const std::vector<core::RigiditySample> exact = t::measure(cradle, plan, rng);
  constexpr double kNoise = 0.001;
  constexpr int kRuns = 300;

  Figure rotvec[kPoses][3];
  Figure rigidity[kPoses];
  Figure a_error[kPoses];
  Figure offset;
  Figure squareness;
  int inside = 0;
  int components = 0;
  auto builder = std::make_unique<core::RigidityBuilder>();
  std::vector<core::RigiditySample> noisy = exact;
  for (int run = 0; run < kRuns; ++run) {
    for (std::size_t k = 0; k < exact.size(); ++k) {
      noisy[k].p_mm = exact[k].p_mm + kNoise * Vec3(rng.normal(), rng.normal(), rng.normal());
    }
    REQUIRE(core::build_rigidity_table(noisy.data(), noisy.size(), {}, *builder) == core::Status::kOk);
    const core::RigidityTable& table = builder->table();
    REQUIRE(table.pose_count == kPoses);
    for (std::size_t i = 0; i < kPoses; ++i) {
      if (i == table.reference) continue;
      const core::RigidityPose& p = table.poses[i];
      const Vec3 truth = cradle.rotvec(p.a_deg).cast<double>();
      for (int c = 0; c < 3; ++c) {
        const double error = p.rotvec_rad(c) - truth(c);
        rotvec[i][c].add(error, p.rotvec_sigma_rad(c));
        inside += std::abs(error) <= 3.0 * p.rotvec_sigma_rad(c) ? 1 : 0;
        ++components;
      }
      rigidity[i].add(p.rigidity_rad - static_cast<double>(cradle.w(p.a_deg).norm()), p.rigidity_sigma_rad);
      a_error[i].add(p.a_error_rad - static_cast<double>(cradle.a_error(p.a_deg)), p.a_error_sigma_rad);
    }
    offset.add(table.c_to_a_offset_mm - static_cast<double>(cradle.offset()), table.c_to_a_offset_sigma_mm);
    squareness.add(table.c_to_a_squareness_rad - static_cast<double>(cradle.squareness()),
                   table.c_to_a_squareness_sigma_rad);
  }

  const auto within = [](const Figure& f) { return f.ratio() > 1.0 / 1.5 && f.ratio() < 1.5; };
  double worst = 1.0;
  for (std::size_t i = 0; i < kPoses; ++i) {
    if (plan.a_deg[i] == 0.0) continue;
    INFO("A = " << plan.a_deg[i]);
    for (int c = 0; c < 3; ++c) {
      INFO("rotvec component " << c << ": reported " << rotvec[i][c].reported() << ", observed "
                               << rotvec[i][c].observed());
      CHECK(within(rotvec[i][c]));
      worst = std::max({worst, rotvec[i][c].ratio(), 1.0 / rotvec[i][c].ratio()});
    }
    INFO("rigidity: reported " << rigidity[i].reported() << ", observed " << rigidity[i].observed());
    CHECK(within(rigidity[i]));
    INFO("A error: reported " << a_error[i].reported() << ", observed " << a_error[i].observed());
    CHECK(within(a_error[i]));
    worst = std::max({worst, rigidity[i].ratio(), 1.0 / rigidity[i].ratio(), a_error[i].ratio(),
                      1.0 / a_error[i].ratio()});
  }
  INFO("C-to-A offset: reported " << offset.reported() << ", observed " << offset.observed());
  CHECK(within(offset));
  INFO("squareness: reported " << squareness.reported() << ", observed " << squareness.observed());
  CHECK(within(squareness));
  const double coverage = static_cast<double>(inside) / components;
  CHECK(coverage >= 0.99);
  WARN(plan.c_per_pose << " C positions " << plan.c_step_deg << " deg apart: worst sigma ratio " << worst << "; rotvec within 3 sigma: " << coverage << "; rotvec sigma ~ "
                            << rotvec[0][1].reported() * 206264.8 << " arcsec");
}

}  // namespace

TEST_CASE("reported sigmas match the Monte-Carlo spread under 1 um noise", "[rigidity][montecarlo]") {
  t::Rng rng(401);
  t::Plan plan;
  plan.a_deg = {-60.0, -30.0, 0.0, 30.0, 60.0};
  plan.shuffle = false;
  SECTION("C over a whole turn") {
    plan.c_per_pose = 10;
    plan.c_step_deg = 36.0;
    check_sigmas(plan, rng);
  }
  SECTION("C over 120 deg") {
    plan.c_per_pose = 9;
    plan.c_step_deg = 15.0;
    check_sigmas(plan, rng);
  }
}
