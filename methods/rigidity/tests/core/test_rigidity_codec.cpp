#include <catch2/catch.hpp>

#include <cstring>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "reference.hpp"
#include "rigidity_samples.hpp"
#include "rigidity_truth.hpp"
#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/rigidity_compensation.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

using Bytes = std::vector<std::uint8_t>;

std::unique_ptr<core::RigidityBuilder> build_16_poses() {
  auto b = std::make_unique<core::RigidityBuilder>();
  t::Rng rng(601);
  t::Plan plan;
  plan.a_deg.clear();
  for (int k = 0; k < 16; ++k) plan.a_deg.push_back(-70.0 + 10.0 * k);
  plan.noise_mm = 0.001;  // sigmas and rms not zero
  const auto samples = t::measure(t::Cradle{}, plan, rng);
  core::RigidityOptions options;
  options.home_identity = 0xBEEF;  // the home it was measured under: both bytes seen
  REQUIRE(core::build_rigidity_table(samples.data(), samples.size(), options, *b) == Status::kOk);
  return b;
}

template <typename T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }
bool same_bits(const core::Mat3& a, const core::Mat3& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 9) == 0;
}

bool same_table(const core::RigidityTable& a, const core::RigidityTable& b) {
  bool same = a.pose_count == b.pose_count && a.reference == b.reference && a.home_identity == b.home_identity &&
              same_bits(a.a_axis_point_mm, b.a_axis_point_mm) && same_bits(a.a_axis_direction, b.a_axis_direction) &&
              same_bits(a.c_to_a_offset_mm, b.c_to_a_offset_mm) &&
              same_bits(a.c_to_a_offset_sigma_mm, b.c_to_a_offset_sigma_mm) &&
              same_bits(a.c_to_a_squareness_rad, b.c_to_a_squareness_rad) &&
              same_bits(a.c_to_a_squareness_sigma_rad, b.c_to_a_squareness_sigma_rad) &&
              same_bits(a.reference_axes, b.reference_axes);
  for (std::size_t i = 0; same && i < a.pose_count; ++i) {
    const core::RigidityPose& p = a.poses[i];
    const core::RigidityPose& q = b.poses[i];
    same = same_bits(p.a_deg, q.a_deg) && same_bits(p.rotvec_rad, q.rotvec_rad) &&
           same_bits(p.rotvec_sigma_rad, q.rotvec_sigma_rad) && same_bits(p.rigidity_rad, q.rigidity_rad) &&
           same_bits(p.rigidity_sigma_rad, q.rigidity_sigma_rad) && same_bits(p.theta_rad, q.theta_rad) &&
           same_bits(p.a_error_rad, q.a_error_rad) && same_bits(p.a_error_sigma_rad, q.a_error_sigma_rad) &&
           same_bits(p.origin_offset_mm, q.origin_offset_mm) && same_bits(p.c_centre_mm, q.c_centre_mm) &&
           same_bits(p.c_direction, q.c_direction) && same_bits(p.c_x_axis, q.c_x_axis) &&
           same_bits(p.c_circle_rms_mm, q.c_circle_rms_mm) && same_bits(p.c_arc_deg, q.c_arc_deg) &&
           p.c_count == q.c_count && same_bits(a.rotation[i], b.rotation[i]) &&
           same_bits(a.geodesic_step_rad[i], b.geodesic_step_rad[i]) && same_bits(a.spline_m[i], b.spline_m[i]);
  }
  return same;
}

// Little-endian writes into an encoded table, independent of the codec.
void put_f64(Bytes& b, std::size_t offset, double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, 8);
  for (std::size_t i = 0; i < 8; ++i) b[offset + i] = static_cast<std::uint8_t>(bits >> (8 * i));
}
double get_f64(const Bytes& b, std::size_t offset) {
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < 8; ++i) bits |= static_cast<std::uint64_t>(b[offset + i]) << (8 * i);
  double v = 0;
  std::memcpy(&v, &bits, 8);
  return v;
}
std::size_t pose_field(std::size_t pose, std::size_t field) { return 88 + 216 * pose + 8 * field; }

}  // namespace

TEST_CASE("a rigidity table survives encode and decode bit for bit", "[rigidity][codec]") {
  const auto builder = build_16_poses();
  const core::RigidityTable& table = builder->table();
  REQUIRE(table.pose_count == 16);
  Bytes bytes(4096, 0xA5);
  const std::size_t size = core::encode_rigidity_table(table, bytes.data(), bytes.size());
  CHECK(size == 88 + 16 * 216);
  CHECK(size <= 4096);
  CHECK(bytes[0] == 1);
  CHECK(bytes[1] == 0);
  CHECK(bytes[2] == 16);
  CHECK(table.home_identity == 0xBEEF);  // the builder records the options' home
  CHECK(bytes[6] == 0xEF);               // and the layout holds it little-endian at offset 6
  CHECK(bytes[7] == 0xBE);
  CHECK(get_f64(bytes, pose_field(3, 0)) == table.poses[3].a_deg);
  CHECK(get_f64(bytes, pose_field(15, 26)) == static_cast<double>(table.poses[15].c_count));

  auto decoded = std::make_unique<core::RigidityTable>();
  const t::AllocationScope scope;
  REQUIRE(core::decode_rigidity_table(bytes.data(), size, *decoded) == Status::kOk);
  CHECK(scope.count() == 0);
  CHECK(same_table(table, *decoded));
  // And queries on it answer alike.
  for (auto blend : {core::Blend::kLinear, core::Blend::kGeodesic, core::Blend::kCubic}) {
    CHECK(same_bits(core::rigidity_rotvec_rad(table, 13.7, blend, false).value(),
                    core::rigidity_rotvec_rad(*decoded, 13.7, blend, false).value()));
  }
  SECTION("a buffer too small is not written") {
    Bytes small(size - 1, 0x5A);
    CHECK(core::encode_rigidity_table(table, small.data(), small.size()) == 0);
    CHECK(small == Bytes(size - 1, 0x5A));
    CHECK(core::encode_rigidity_table(table, nullptr, 4096) == 0);
    CHECK(core::encode_rigidity_table(core::RigidityTable{}, bytes.data(), bytes.size()) == 0);
  }
}

TEST_CASE("a corrupted, short or unsorted table is refused and changes nothing", "[rigidity][codec]") {
  const auto builder = build_16_poses();
  const core::RigidityTable& table = builder->table();
  Bytes good(core::kRigidityTableMaxBytes);
  REQUIRE(core::encode_rigidity_table(table, good.data(), good.size()) == good.size());
  auto out = std::make_unique<core::RigidityTable>(table);

  const auto refused = [&](const Bytes& b, std::size_t size) {
    const Status s = core::decode_rigidity_table(b.data(), size, *out);
    return s == Status::kTableInvalid && same_table(*out, table);
  };
  const auto with_value = [&](std::size_t offset, double v) {
    Bytes b = good;
    put_f64(b, offset, v);
    return b;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();

  CHECK(refused(good, good.size() - 1));
  CHECK(refused(good, 87));
  CHECK(refused(good, 0));
  Bytes longer = good;
  longer.push_back(0);
  CHECK(refused(longer, longer.size()));
  CHECK(core::decode_rigidity_table(nullptr, 100, *out) == Status::kTableInvalid);

  Bytes b = good;
  b[0] = 2;  // layout version
  CHECK(refused(b, b.size()));
  b = good;
  b[2] = 17;  // pose count beyond the capacity
  CHECK(refused(b, b.size()));
  b = good;
  b[2] = 2;  // too few poses (and the size no longer matches)
  CHECK(refused(b, core::rigidity_table_bytes(2)));
  b = good;
  b[4] = 16;  // reference index
  CHECK(refused(b, b.size()));
  b = good;
  b[6] = 1;  // the home identity: any value decodes, as itself
  b[7] = 0;
  REQUIRE(core::decode_rigidity_table(b.data(), b.size(), *out) == Status::kOk);
  CHECK(out->home_identity == 1);
  REQUIRE(core::decode_rigidity_table(good.data(), good.size(), *out) == Status::kOk);

  CHECK(refused(with_value(8 + 8 * 1, nan), good.size()));                     // A-axis point
  CHECK(refused(with_value(8 + 8 * 3, 2.0), good.size()));                     // A direction not unit
  CHECK(refused(with_value(8 + 8 * 6, -0.01), good.size()));                   // negative offset
  CHECK(refused(with_value(pose_field(5, 2), std::numeric_limits<double>::infinity()), good.size()));
  CHECK(refused(with_value(pose_field(9, 0), table.poses[8].a_deg), good.size()));  // A repeated
  CHECK(refused(with_value(pose_field(9, 0), table.poses[8].a_deg - 1.0), good.size()));  // A unsorted
  CHECK(refused(with_value(pose_field(table.reference, 0), 1e-3), good.size()));  // reference not at A = 0
  CHECK(refused(with_value(pose_field(4, 1), 4.0), good.size()));              // |rotvec| > pi
  CHECK(refused(with_value(pose_field(4, 5), -1e-9), good.size()));            // negative sigma
  CHECK(refused(with_value(pose_field(4, 19), 0.5), good.size()));             // C direction not unit
  CHECK(refused(with_value(pose_field(4, 25), 360.0), good.size()));           // arc
  CHECK(refused(with_value(pose_field(4, 26), 3.0), good.size()));             // too few C
  CHECK(refused(with_value(pose_field(4, 26), 8.5), good.size()));             // not a count
  {
    // X not normal to Z: turn X towards Z by 1e-6 rad, still unit.
    Bytes tilted = good;
    const Vec3 x = table.poses[4].c_x_axis;
    const Vec3 z = table.poses[4].c_direction;
    const Vec3 x2 = (x + 1e-6 * z).normalized();
    for (std::size_t k = 0; k < 3; ++k) put_f64(tilted, pose_field(4, 21 + k), x2(static_cast<Eigen::Index>(k)));
    CHECK(refused(tilted, good.size()));
  }
  // The untouched buffer still decodes.
  CHECK(core::decode_rigidity_table(good.data(), good.size(), *out) == Status::kOk);
}
