// M2 frames on exact data from the independent ground truth (gantry_truth.hpp):
// every frame, diagnostic and transform to ~1e-9; the diagnostics against
// long-double references; heap-free.
#include <catch2/catch.hpp>

#include <Eigen/SVD>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "gantry_truth.hpp"
#include "trueaxis/core/gantry_table.hpp"
#include "trueaxis/core/so3.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Vec3;
using t::Mat3L;
using t::Vec3L;

namespace {

Vec3L ld(const Vec3& v) { return v.cast<long double>(); }
Mat3L ld(const core::Mat3& m) { return m.cast<long double>(); }

double rotation_error_rad(const Mat3L& truth, const core::Mat3& est) {
  return core::so3_log((truth.transpose() * ld(est)).cast<double>()).norm();
}

// Long-double plane / line by SVD of the centred points: peak-to-valley of the
// signed distances, and twice the largest distance from the line.
long double flatness_l(const std::vector<Vec3>& p) {
  Vec3L m = Vec3L::Zero();
  for (const Vec3& q : p) m += ld(q);
  m /= static_cast<long double>(p.size());
  Eigen::Matrix<long double, Eigen::Dynamic, 3> a(p.size(), 3);
  for (std::size_t i = 0; i < p.size(); ++i) a.row(static_cast<Eigen::Index>(i)) = (ld(p[i]) - m).transpose();
  const Eigen::JacobiSVD<decltype(a)> svd(a, Eigen::ComputeFullV);
  const Vec3L n = svd.matrixV().col(2);
  long double lo = 0, hi = 0;
  for (const Vec3& q : p) {
    lo = std::min(lo, n.dot(ld(q) - m));
    hi = std::max(hi, n.dot(ld(q) - m));
  }
  return hi - lo;
}

long double straightness_l(const std::vector<Vec3>& p) {
  Vec3L m = Vec3L::Zero();
  for (const Vec3& q : p) m += ld(q);
  m /= static_cast<long double>(p.size());
  Eigen::Matrix<long double, Eigen::Dynamic, 3> a(p.size(), 3);
  for (std::size_t i = 0; i < p.size(); ++i) a.row(static_cast<Eigen::Index>(i)) = (ld(p[i]) - m).transpose();
  const Eigen::JacobiSVD<decltype(a)> svd(a, Eigen::ComputeFullV);
  const Vec3L d = svd.matrixV().col(0);
  long double worst = 0;
  for (const Vec3& q : p) {
    const Vec3L w = ld(q) - m;
    worst = std::max(worst, (w - w.dot(d) * d).norm());
  }
  return 2 * worst;
}

struct Fixture {
  t::Rng rng{701};
  t::TrueGantry truth = t::make_truth(rng);
  t::Samples samples;
  Fixture() {
    t::Sampler sampler(truth, rng, t::NoiseSpec{});
    samples = sampler.sample();
  }
};

}  // namespace

TEST_CASE("exact data give every frame of the ground truth", "[gantry]") {
  const Fixture f;
  const core::GantryInput in = t::make_input(f.truth, f.samples);
  auto out = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(in, core::GantryOptions{}, *out) == core::Status::kOk);

  SECTION("the tracker ranges are those of a tracker 2 to 6 m away") {
    double lo = 1e9, hi = 0;
    for (const auto* g : {&f.samples.bed, &f.samples.side_1, &f.samples.subs[1].c, &f.samples.subs[2].a}) {
      for (const Vec3& p : *g) {
        lo = std::min(lo, p.norm());
        hi = std::max(hi, p.norm());
      }
    }
    CHECK(lo > 2000.0);
    CHECK(hi < 6000.0);
  }
  SECTION("the global frame is S1's, written in the tracker frame") {
    const core::Rigid3& g = out->global.tracker_T_global;
    CHECK(static_cast<double>((ld(g.t) - f.truth.O_t).norm()) < 1e-9);
    CHECK(rotation_error_rad(f.truth.R_tg, g.R) < 1e-12);
    CHECK(out->global.bed_flatness_mm < 1e-9);
    CHECK(out->global.gantry_straightness_mm < 1e-9);
  }
  SECTION("each sub-machine's origin, axes and diagnostics are the truth's") {
    REQUIRE(out->sub_machine_count == 4);
    for (std::size_t i = 0; i < 4; ++i) {
      const t::TrueSub& s = f.truth.subs[i];
      const core::SubMachineFrame& r = out->sub_machines[i];
      INFO("sub-machine " << s.id);
      CHECK(r.id == s.id);
      CHECK(r.master_axis == s.master);
      CHECK(static_cast<double>((ld(r.global_T_sub.t) - s.origin).norm()) < 1e-9);
      CHECK(rotation_error_rad(s.R, r.global_T_sub.R) < 1e-12);
      CHECK(static_cast<double>((ld(r.wrist_centre_mm) - s.wrist).norm()) < 1e-9);
      for (int k = 0; k < 3; ++k) {
        CHECK(r.squareness_arcsec(k) == Approx(static_cast<double>(s.squareness_arcsec(k))).margin(1e-6));
        CHECK(static_cast<double>((ld(r.measured_axes[k]) - s.dirs[k]).norm()) < 1e-12);
        CHECK(r.straightness_mm[k] < 1e-9);
        CHECK(r.stroke_mm[k] == Approx(static_cast<double>(s.stroke[k])).epsilon(1e-12));
      }
      CHECK(r.a_c_offset_mm == Approx(static_cast<double>(s.offset)).margin(1e-9));
      CHECK(r.a_c_angle_deg == Approx(static_cast<double>(s.ac_angle_deg)).margin(1e-9));
      CHECK(static_cast<double>((ld(r.c_circle.normal) - s.c).norm()) < 1e-12);
      CHECK(static_cast<double>((ld(r.a_circle.normal) - s.a).norm()) < 1e-12);
      CHECK(r.c_circle.rms_distance_mm < 1e-9);
      CHECK(r.a_circle.max_distance_mm < 1e-9);
      // Exact data: no uncertainty beyond the streaming line fit's floor, which
      // reads an exact 6 m pass's residual as a few nm (fit_accumulator.hpp item 6).
      CHECK(r.uncertainty.origin_sigma_mm < 1e-6);
    }
  }
  SECTION("a workpiece point maps into each sub-machine's program frame") {
    const Vec3L p_global(1234.5L, 2345.6L, 456.7L);
    for (std::size_t i = 0; i < 4; ++i) {
      const t::TrueSub& s = f.truth.subs[i];
      const Vec3L expected = s.R.transpose() * (p_global - s.origin);
      const Vec3 got = core::global_to_sub_mm(out->sub_machines[i], p_global.cast<double>());
      CHECK(static_cast<double>((ld(got) - expected).norm()) < 1e-9);
      const core::Mat4 m = core::homogeneous(out->sub_machines[i].global_T_sub);
      CHECK((m.topRightCorner<3, 1>() - out->sub_machines[i].global_T_sub.t).norm() == 0.0);
    }
  }
}

TEST_CASE("eight sub-machines, the documented maximum, are computed, stored and read back", "[gantry]") {
  // Sub-machines 5..8 measured as 1..4 were: the same data, so the same frames.
  const Fixture f;
  core::GantryInput in = t::make_input(f.truth, f.samples);
  REQUIRE(core::kMaxSubMachines == 8);
  for (std::size_t i = 0; i < 4; ++i) {
    in.sub_machines[4 + i] = in.sub_machines[i];
    in.sub_machines[4 + i].id = in.sub_machines[i].id + 4;
  }
  in.sub_machine_count = 8;
  auto out = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(in, core::GantryOptions{}, *out) == core::Status::kOk);
  REQUIRE(out->sub_machine_count == 8);
  for (std::size_t i = 0; i < 4; ++i) {
    const core::SubMachineFrame& a = out->sub_machines[i];
    const core::SubMachineFrame& b = out->sub_machines[4 + i];
    CHECK(b.id == a.id + 4);
    CHECK((b.global_T_sub.t - a.global_T_sub.t).norm() <= 1e-12);
    CHECK((b.global_T_sub.R - a.global_T_sub.R).cwiseAbs().maxCoeff() <= 1e-15);
  }
  auto table = std::make_unique<core::GantryTable>();
  core::merge_frames(*table, *out);
  CHECK(table->id_mask() == 0xFF);
  CHECK(table->count() == 8);
  std::vector<std::uint8_t> bytes(core::kGantryTableBytes);
  REQUIRE(core::encode_gantry_table(*table, bytes.data(), bytes.size()) == core::kGantryTableBytes);
  auto back = std::make_unique<core::GantryTable>();
  REQUIRE(core::decode_gantry_table(bytes.data(), bytes.size(), *back) == core::Status::kOk);
  CHECK(back->id_mask() == 0xFF);
  const Vec3 p(1234.5, 2345.6, 456.7);
  CHECK((core::global_to_sub_mm(back->sub_machines[7], p) - core::global_to_sub_mm(table->sub_machines[7], p)).norm() ==
        0.0);
  CHECK((core::global_to_sub_mm(back->sub_machines[7], p) - core::global_to_sub_mm(out->sub_machines[3], p)).norm() <=
        1e-9);
}

TEST_CASE("flatness and straightness match long-double references on bent data", "[gantry]") {
  Fixture f;
  // Raise one pad by 12 um and bow the second gantry pass by 30 um.
  for (std::size_t i = 18; i < 27; ++i) {
    f.samples.bed[i] += 0.012 * (f.truth.z0_t.cast<double>());
  }
  auto& pass = f.samples.gantry[1];
  const Vec3 up = f.truth.R_tg.col(2).cast<double>();
  for (std::size_t i = 0; i < pass.size(); ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(pass.size() - 1);
    pass[i] += 0.030 * 4.0 * u * (1.0 - u) * up;
  }
  const core::GantryInput in = t::make_input(f.truth, f.samples);
  auto out = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(in, core::GantryOptions{}, *out) == core::Status::kOk);
  CHECK(out->global.bed_flatness_mm == Approx(static_cast<double>(flatness_l(f.samples.bed))).margin(1e-9));
  CHECK(out->global.bed_flatness_mm > 0.005);
  CHECK(out->global.gantry_straightness_mm == Approx(static_cast<double>(straightness_l(pass))).margin(1e-9));
  CHECK(out->global.gantry_straightness_mm > 0.01);
  CHECK(out->global.side_1_flatness_mm < 1e-9);
}

TEST_CASE("the frame computation allocates nothing", "[gantry]") {
  const Fixture f;
  const core::GantryInput in = t::make_input(f.truth, f.samples);
  auto out = std::make_unique<core::GantryFrames>();
  core::GantryOptions options;
  options.noise = {0.0075, 3e-6, Vec3::Zero()};
  const t::AllocationScope scope;
  const core::Status status = core::compute_gantry_frames(in, options, *out);
  CHECK(scope.count() == 0);
  CHECK(status == core::Status::kOk);
}

TEST_CASE("the reported covariance is the numeric Jacobian over every point", "[gantry]") {
  // Model noise, exact data: the first-order covariance of sub-machine 1's frame
  // is sum_i sigma_i^2 J_i J_i^T over every coordinate of every point that
  // reaches it (global groups and its own), J_i by central differences of the
  // whole computation. It shares with the module only compute_gantry_frames.
  // C is turned through 120 deg only, so its centre and normal correlate.
  Fixture f;
  f.samples.subs[0].c.resize(9);
  core::GantryOptions options;
  options.noise = {0.0075, 3e-6, Vec3::Zero()};
  auto out = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(t::make_input(f.truth, f.samples), options, *out) == core::Status::kOk);
  const core::SubMachineFrame nominal = out->sub_machines[0];
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  core::Mat6 cov = core::Mat6::Zero();
  std::vector<std::vector<Vec3>*> groups = {&f.samples.bed, &f.samples.side_1, &f.samples.side_2, &f.samples.subs[0].c,
                                            &f.samples.subs[0].a};
  for (auto& p : f.samples.gantry) groups.push_back(&p);
  for (auto& axis : f.samples.subs[0].passes) {
    for (auto& p : axis) groups.push_back(&p);
  }
  for (std::vector<Vec3>* g : groups) {
    for (Vec3& p : *g) {
      const double sigma = options.noise.sigma_mm(p);
      for (int k = 0; k < 3; ++k) {
        Vec6 d[2];
        for (int side = 0; side < 2; ++side) {
          const Vec3 keep = p;
          p(k) += side == 0 ? sigma : -sigma;
          REQUIRE(core::compute_gantry_frames(t::make_input(f.truth, f.samples), options, *out) == core::Status::kOk);
          p = keep;
          const core::Rigid3& r = out->sub_machines[0].global_T_sub;
          d[side] << r.t - nominal.global_T_sub.t, core::so3_log(nominal.global_T_sub.R.transpose() * r.R);
        }
        const Vec6 g6 = 0.5 * (d[0] - d[1]);
        cov += g6 * g6.transpose();
      }
    }
  }
  const core::Mat6& reported = nominal.uncertainty.covariance;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      INFO("element " << i << ", " << j);
      // Correlation-scaled difference; 3 %: the circles take the RMS of their
      // points' sigmas (gantry_fits.hpp item 6).
      CHECK(std::abs(reported(i, j) - cov(i, j)) < 0.03 * std::sqrt(cov(i, i) * cov(j, j)));
    }
  }
}
