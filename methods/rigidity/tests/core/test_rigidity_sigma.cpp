#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
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

namespace {

// The noise each sample carries in the builder's own model (rigidity_table.hpp
// convention 7), read from the built table and the samples, not from the
// builder's internals: across the circle (along the normal and the radius) the
// circle fit's sigma^2 = SSR / (2n - 6), SSR = n rms^2 (circle_fit.hpp
// convention 5); along the tangent the scatter of the phase offsets about their
// circular mean, r^2 sum sin^2(x_k - mean) / (n - 1), whose mean's variance is
// the phase offset's squared standard error.
std::vector<core::Mat3> sample_covariances(const std::vector<core::RigiditySample>& samples,
                                           const core::RigidityTable& table) {
  std::vector<core::Mat3> q(samples.size(), core::Mat3::Zero());
  for (std::size_t i = 0; i < table.pose_count; ++i) {
    const core::RigidityPose& p = table.poses[i];
    const Vec3 y = p.c_direction.cross(p.c_x_axis);
    std::vector<std::size_t> in_pose;
    std::vector<Vec3> radial;
    double sum_sin = 0.0, sum_cos = 0.0, sum_r = 0.0;
    std::vector<double> offsets;
    for (std::size_t k = 0; k < samples.size(); ++k) {
      if (samples[k].a_deg != p.a_deg) continue;
      const Vec3 d = samples[k].p_mm - p.c_centre_mm;
      const Vec3 in_plane = d - d.dot(p.c_direction) * p.c_direction;
      const double x = std::atan2(in_plane.dot(y), in_plane.dot(p.c_x_axis)) - samples[k].c_deg * core::kPi / 180.0;
      in_pose.push_back(k);
      radial.push_back(in_plane);
      offsets.push_back(x);
      sum_sin += std::sin(x);
      sum_cos += std::cos(x);
      sum_r += in_plane.norm();
    }
    const double n = static_cast<double>(in_pose.size());
    const double mean = std::atan2(sum_sin, sum_cos);
    double scatter = 0.0;
    for (double x : offsets) scatter += std::pow(std::sin(x - mean), 2);
    const double r = sum_r / n;
    const double across = n * p.c_circle_rms_mm * p.c_circle_rms_mm / (2.0 * n - 6.0);
    const double along = r * r * scatter / (n - 1.0);
    for (std::size_t j = 0; j < in_pose.size(); ++j) {
      const Vec3 t = p.c_direction.cross(radial[j]).normalized();
      q[in_pose[j]] = across * (core::Mat3::Identity() - t * t.transpose()) + along * t * t.transpose();
    }
  }
  return q;
}

}  // namespace

TEST_CASE("the rigidity figure's sigma is its propagated uncertainty within 1 %, on random cradles",
          "[rigidity][sigma]") {
  // Independent of the builder's propagation: the figure |rotvec_i| as a
  // function of every sample coordinate (a central difference of whole builds),
  // times each sample's noise covariance, summed; the same for each component
  // of the rotation vector. With C over whole turns evenly spaced the
  // correlation the builder neglects is zero, and 0.1 um steps make the
  // linearisation exact to far below 1 % (measured: 4e-6 relative at worst).
  // The isotropic rule sqrt(trace / 3) for the figure misses it by up to 38 %
  // on these cradles (the issue saw 26 % on its own).
  t::Rng rng(1703);
  t::Plan plan;
  plan.a_deg = {-60.0, -30.0, 0.0, 30.0, 60.0};
  plan.c_per_pose = 10;
  plan.c_step_deg = 36.0;
  plan.shuffle = false;
  plan.noise_mm = 0.001;
  auto nominal = std::make_unique<core::RigidityBuilder>();
  auto perturbed = std::make_unique<core::RigidityBuilder>();
  constexpr double kStep = 1e-4;  // mm
  double worst = 0.0, worst_isotropic = 0.0;
  for (int input = 0; input < 6; ++input) {
    t::Cradle cradle;
    cradle.k1 = static_cast<long double>(rng.uniform(15.0, 40.0) / 206264.8);
    cradle.w1 = rng.unit_vector().cast<long double>();
    cradle.k2 = static_cast<long double>(rng.uniform(-20.0, 20.0) / 206264.8);
    cradle.w2 = rng.unit_vector().cast<long double>();
    const std::vector<core::RigiditySample> samples = t::measure(cradle, plan, rng);
    REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), {}, *nominal) == core::Status::kOk);
    const core::RigidityTable& table = nominal->table();
    const std::vector<core::Mat3> q = sample_covariances(samples, table);

    const std::size_t m = table.pose_count;
    std::vector<double> var_rigidity(m, 0.0);
    std::vector<Vec3> var_rotvec(m, Vec3::Zero());
    std::vector<core::RigiditySample> moved = samples;
    std::vector<double> plus(m), minus(m);
    std::vector<Vec3> plus_v(m), minus_v(m);
    for (std::size_t k = 0; k < samples.size(); ++k) {
      std::vector<Vec3> g_rigidity(m);      // d rigidity_i / d p_k
      std::vector<core::Mat3> g_rotvec(m);  // (axis, c): d rotvec_i(c) / d p_k(axis)
      for (int axis = 0; axis < 3; ++axis) {
        for (const double sign : {1.0, -1.0}) {
          moved[k].p_mm = samples[k].p_mm + sign * kStep * Vec3::Unit(axis);
          REQUIRE(core::build_rigidity_table(moved.data(), moved.size(), {}, *perturbed) == core::Status::kOk);
          for (std::size_t i = 0; i < m; ++i) {
            (sign > 0 ? plus : minus)[i] = perturbed->table().poses[i].rigidity_rad;
            (sign > 0 ? plus_v : minus_v)[i] = perturbed->table().poses[i].rotvec_rad;
          }
        }
        moved[k].p_mm = samples[k].p_mm;
        for (std::size_t i = 0; i < m; ++i) {
          g_rigidity[i](axis) = (plus[i] - minus[i]) / (2.0 * kStep);
          g_rotvec[i].row(axis) = (plus_v[i] - minus_v[i]).transpose() / (2.0 * kStep);
        }
      }
      for (std::size_t i = 0; i < m; ++i) {
        var_rigidity[i] += g_rigidity[i].dot(q[k] * g_rigidity[i]);
        for (int c = 0; c < 3; ++c) {
          const Vec3 gc = g_rotvec[i].col(c);
          var_rotvec[i](c) += gc.dot(q[k] * gc);
        }
      }
    }
    for (std::size_t i = 0; i < m; ++i) {
      if (i == table.reference) continue;
      const core::RigidityPose& p = table.poses[i];
      const double propagated = std::sqrt(var_rigidity[i]);
      const Vec3 propagated_v = var_rotvec[i].cwiseSqrt();
      const double isotropic = p.rotvec_sigma_rad.norm() / std::sqrt(3.0);
      INFO("input " << input << ", A = " << p.a_deg << ": rigidity " << p.rigidity_rad * 206264.8 << "\" sigma "
                    << p.rigidity_sigma_rad * 206264.8 << "\", propagated " << propagated * 206264.8
                    << "\", isotropic rule " << isotropic * 206264.8 << "\"; rotvec sigma "
                    << p.rotvec_sigma_rad(0) * 206264.8 << " " << p.rotvec_sigma_rad(1) * 206264.8 << " "
                    << p.rotvec_sigma_rad(2) * 206264.8 << ", propagated " << propagated_v(0) * 206264.8 << " "
                    << propagated_v(1) * 206264.8 << " " << propagated_v(2) * 206264.8);
      REQUIRE(p.rigidity_rad > 5.0 * propagated);  // the figure is differentiable here
      CHECK(p.rigidity_sigma_rad == Approx(propagated).epsilon(0.01));
      for (int c = 0; c < 3; ++c) CHECK(p.rotvec_sigma_rad(c) == Approx(propagated_v(c)).epsilon(0.01));
      worst = std::max(worst, std::abs(p.rigidity_sigma_rad / propagated - 1.0));
      worst_isotropic = std::max(worst_isotropic, std::abs(isotropic / propagated - 1.0));
    }
  }
  WARN("rigidity sigma against its propagation: worst " << 100.0 * worst << " %; the isotropic rule's worst "
                                                        << 100.0 * worst_isotropic << " %");
  CHECK(worst_isotropic > 0.1);  // the inputs are ones where the rule matters
}
