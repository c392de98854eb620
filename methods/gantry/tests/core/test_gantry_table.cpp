// M2 in steps and in storage: GantryBuilder gives compute_gantry_frames's result
// bit for bit and its failures; the stored form (gantry_table.hpp) round-trips
// bit for bit, refuses every malformed record, merges by sub-machine, and its
// point conversion agrees with a long-double inverse of the frame.
#include <catch2/catch.hpp>

#include <cstring>
#include <memory>
#include <vector>

#include "alloc_counter.hpp"
#include "gantry_truth.hpp"
#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/core/gantry_table.hpp"

namespace core = trueaxis::core;
namespace t = trueaxis::test;
using core::Status;
using core::Vec3;

namespace {

struct Fixture {
  t::Rng rng{1123};
  t::TrueGantry truth = t::make_truth(rng);
  t::Samples samples;
  Fixture() {
    t::Sampler sampler(truth, rng, t::kTracker);
    samples = sampler.sample();
  }
};

bool same_bits(const core::Rigid3& a, const core::Rigid3& b) {
  return std::memcmp(a.R.data(), b.R.data(), sizeof(double) * 9) == 0 &&
         std::memcmp(a.t.data(), b.t.data(), sizeof(double) * 3) == 0;
}

template <typename M>
bool same_bits(const M& a, const M& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

// Runs a builder to its end.
core::GantryStep build(core::GantryBuilder& b, const core::GantryInput& in, core::GantryFrames& out,
                       std::size_t& steps) {
  b.start(in, core::GantryOptions{}, out);
  core::GantryStep s;
  steps = 0;
  do {
    s = b.step();
    ++steps;
    if (s.more) CHECK(out.sub_machine_count == 0);  // never a half result
  } while (s.more);
  return s;
}

}  // namespace

TEST_CASE("GantryBuilder gives compute_gantry_frames's frames bit for bit, one fit per step", "[gantry][builder]") {
  const Fixture f;
  const core::GantryInput in = t::make_input(f.truth, f.samples);
  auto whole = std::make_unique<core::GantryFrames>();
  auto stepped = std::make_unique<core::GantryFrames>();
  REQUIRE(core::compute_gantry_frames(in, core::GantryOptions{}, *whole) == Status::kOk);
  auto builder = std::make_unique<core::GantryBuilder>();
  std::size_t steps = 0;
  trueaxis::test::AllocationScope heap;
  const core::GantryStep s = build(*builder, in, *stepped, steps);
  CHECK(heap.count() == 0);
  REQUIRE(s.status == Status::kOk);
  // The checks, bed, side_1, side_2, gantry, global; then x, y, z, C, A, frame per sub-machine.
  CHECK(steps == 6 + 6 * 4);
  CHECK(builder->steps() == steps);
  REQUIRE(stepped->sub_machine_count == whole->sub_machine_count);
  CHECK(same_bits(stepped->global.tracker_T_global, whole->global.tracker_T_global));
  CHECK(same_bits(stepped->global.uncertainty.covariance, whole->global.uncertainty.covariance));
  for (std::size_t i = 0; i < whole->sub_machine_count; ++i) {
    INFO("sub-machine " << i + 1);
    CHECK(stepped->sub_machines[i].id == whole->sub_machines[i].id);
    CHECK(same_bits(stepped->sub_machines[i].global_T_sub, whole->sub_machines[i].global_T_sub));
    CHECK(same_bits(stepped->sub_machines[i].uncertainty.covariance, whole->sub_machines[i].uncertainty.covariance));
    CHECK(same_bits(stepped->sub_machines[i].squareness_arcsec, whole->sub_machines[i].squareness_arcsec));
  }
  // A finished builder stays finished.
  CHECK(builder->step().status == Status::kOk);
  CHECK_FALSE(builder->step().more);
}

TEST_CASE("GantryBuilder fails where compute_gantry_frames fails, naming the sub-machine", "[gantry][builder]") {
  Fixture f;
  auto out = std::make_unique<core::GantryFrames>();
  auto builder = std::make_unique<core::GantryBuilder>();
  std::size_t steps = 0;

  SECTION("sub-machine 3's A circle on a 3-degree arc: arc_too_short at its A step") {
    const t::TrueSub& s = f.truth.subs[2];
    const t::Vec3L target = s.wrist + 50 * s.c + 120 * t::unit_l(s.c.cross(t::Vec3L(0.3L, 0.5L, 0.7L)));
    f.samples.subs[2].a.clear();
    for (int j = 0; j < 6; ++j) {
      const t::Vec3L q = s.wrist + t::rodrigues_l(t::deg_l(0.6L * j) * s.a) * (target - s.wrist);
      f.samples.subs[2].a.push_back((f.truth.R_tg * q + f.truth.O_t).cast<double>());
    }
    const core::GantryInput in = t::make_input(f.truth, f.samples);
    const Status whole = core::compute_gantry_frames(in, core::GantryOptions{}, *out);
    const core::GantryStep s3 = build(*builder, in, *out, steps);
    CHECK(whole == Status::kArcTooShort);
    CHECK(s3.status == Status::kArcTooShort);
    CHECK_FALSE(s3.more);
    CHECK(builder->failed_sub_machine() == 3);
    CHECK(steps == 6 + 6 * 2 + 5);  // failed at sub-machine 3's fifth step
    CHECK(out->sub_machine_count == 0);
  }
  SECTION("a missing bed: missing_group at the bed's step, no sub-machine named") {
    f.samples.bed.clear();
    const core::GantryInput in = t::make_input(f.truth, f.samples);
    const core::GantryStep s = build(*builder, in, *out, steps);
    CHECK(s.status == Status::kMissingGroup);
    CHECK(builder->failed_sub_machine() == 0);
    CHECK(steps == 2);
  }
  SECTION("a builder never started refuses to step") {
    core::GantryBuilder idle;
    const core::GantryStep s = idle.step();
    CHECK(s.status == Status::kArgumentOutOfRange);
    CHECK_FALSE(s.more);
  }
}

namespace {

core::GantryTable table_of(const Fixture& f, core::GantryFrames& frames) {
  core::GantryOptions options;  // with the tracker's noise: every layout-2 figure non-zero
  options.instrument = {t::kTracker.a_mm, t::kTracker.b_per_mm, Vec3::Zero()};
  REQUIRE(core::compute_gantry_frames(t::make_input(f.truth, f.samples), options, frames) == Status::kOk);
  core::GantryTable table;
  core::merge_frames(table, frames);
  return table;
}

std::vector<std::uint8_t> encoded(const core::GantryTable& table) {
  std::vector<std::uint8_t> bytes(core::kGantryTableBytes);
  REQUIRE(core::encode_gantry_table(table, bytes.data(), bytes.size()) == core::kGantryTableBytes);
  return bytes;
}

// Offsets of the layout (gantry_table.hpp).
constexpr std::size_t kGlobal = core::kGantryHeaderBytes;
std::size_t sub_offset(std::size_t id) {
  return core::kGantryHeaderBytes + core::kGantryGlobalBytes + (id - 1) * core::kGantrySubBytes;
}
constexpr std::size_t kGlobalFigures = core::kGantryTableBytesV1;
std::size_t sub_figure_offset(std::size_t id) {
  return core::kGantryTableBytesV1 + core::kGantryGlobalFigureBytes + (id - 1) * core::kGantrySubFigureBytes;
}

// The record a layout-1 encoder wrote for the same table: layout 2's first
// 1880 bytes with version 1 (gantry_table.hpp: layout 1's fields, field for field).
std::vector<std::uint8_t> layout_1(const std::vector<std::uint8_t>& layout_2) {
  std::vector<std::uint8_t> bytes(layout_2.begin(), layout_2.begin() + core::kGantryTableBytesV1);
  core::put_u16(bytes.data(), 1);
  return bytes;
}

}  // namespace

TEST_CASE("the stored frames round-trip bit for bit", "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  const core::GantryTable table = table_of(f, *frames);
  CHECK(core::kGantryTableBytesV1 == 1880);
  CHECK(core::kGantryTableBytes == 2248);
  CHECK(table.count() == 4);
  const std::vector<std::uint8_t> bytes = encoded(table);
  core::GantryTable decoded;
  REQUIRE(core::decode_gantry_table(bytes.data(), bytes.size(), decoded) == Status::kOk);
  CHECK(encoded(decoded) == bytes);
  CHECK(decoded.id_mask() == table.id_mask());
  for (std::size_t i = 0; i < core::kMaxSubMachines; ++i) {
    INFO("sub-machine " << i + 1);
    CHECK(decoded.sub_machines[i].present == table.sub_machines[i].present);
    if (!table.sub_machines[i].present) continue;
    CHECK(same_bits(decoded.sub_machines[i].global_T_sub, table.sub_machines[i].global_T_sub));
    CHECK(same_bits(decoded.sub_machines[i].sub_T_global, table.sub_machines[i].sub_T_global));
    CHECK(decoded.sub_machines[i].master_axis == table.sub_machines[i].master_axis);
    CHECK(decoded.sub_machines[i].c_circle_rms_mm == table.sub_machines[i].c_circle_rms_mm);
    CHECK(same_bits(decoded.sub_machines[i].squareness_sigma_arcsec, table.sub_machines[i].squareness_sigma_arcsec));
    CHECK(decoded.sub_machines[i].a_c_offset_sigma_mm == table.sub_machines[i].a_c_offset_sigma_mm);
    CHECK(decoded.sub_machines[i].a_c_angle_sigma_deg == table.sub_machines[i].a_c_angle_sigma_deg);
    CHECK(table.sub_machines[i].squareness_sigma_arcsec.minCoeff() > 0.0);
    CHECK(table.sub_machines[i].a_c_offset_sigma_mm > 0.0);
    CHECK(table.sub_machines[i].a_c_angle_sigma_deg > 0.0);
  }
  CHECK(same_bits(decoded.global.tracker_T_global, table.global.tracker_T_global));
  const core::StoredGlobal& g = decoded.global;
  const core::StoredGlobal& want = table.global;
  CHECK(g.bed_flatness_noise_floor_mm == want.bed_flatness_noise_floor_mm);
  CHECK(g.gantry_straightness_noise_floor_mm == want.gantry_straightness_noise_floor_mm);
  CHECK(g.bed_form_error_mm == want.bed_form_error_mm);
  CHECK(g.bed_form_error_sigma_mm == want.bed_form_error_sigma_mm);
  CHECK(g.gantry_form_error_mm == want.gantry_form_error_mm);
  CHECK(g.gantry_form_error_sigma_mm == want.gantry_form_error_sigma_mm);
  CHECK(want.bed_flatness_noise_floor_mm > 0.0);
  CHECK(want.gantry_straightness_noise_floor_mm > 0.0);
  CHECK(want.bed_form_error_sigma_mm > 0.0);
  CHECK(want.gantry_form_error_sigma_mm > 0.0);
  CHECK(core::get_f64(bytes.data() + kGlobalFigures) == want.bed_flatness_noise_floor_mm);
  CHECK(core::get_f64(bytes.data() + kGlobalFigures + 8 * 5) == want.gantry_form_error_sigma_mm);
  CHECK(encode_gantry_table(core::GantryTable{}, std::vector<std::uint8_t>(2000).data(), 2000) == 0);  // nothing present
  CHECK(encode_gantry_table(table, std::vector<std::uint8_t>(2000).data(), core::kGantryTableBytes - 1) == 0);
}

TEST_CASE("a malformed gantry record is refused whole, the destination untouched", "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  const core::GantryTable table = table_of(f, *frames);
  const std::vector<std::uint8_t> good = encoded(table);
  std::vector<std::uint8_t> bad = good;
  std::size_t size = good.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t first = sub_offset(table.sub_machines[0].present ? 1 : 2);

  SECTION("one byte short") { size -= 1; }
  SECTION("layout version 3") { core::put_u16(bad.data(), 3); }
  SECTION("layout version 1 at layout 2's size") { core::put_u16(bad.data(), 1); }
  SECTION("layout version 2 at layout 1's size") { size = core::kGantryTableBytesV1; }
  SECTION("a layout-1 record one byte longer") {
    bad = layout_1(good);
    bad.push_back(0);
    size = bad.size();
  }
  SECTION("a NaN in the global figures") { core::put_f64(bad.data() + kGlobalFigures + 8 * 3, nan); }
  SECTION("a negative form error") { core::put_f64(bad.data() + kGlobalFigures + 8 * 2, -1e-9); }
  SECTION("a noise floor of -2 (only -1, not stored, may be negative)") {
    core::put_f64(bad.data() + kGlobalFigures, -2.0);
  }
  SECTION("a NaN in a sub-machine's figures") {
    core::put_f64(bad.data() + sub_figure_offset(table.sub_machines[0].present ? 1 : 2) + 8 * 4, nan);
  }
  SECTION("a negative squareness sigma") {
    core::put_f64(bad.data() + sub_figure_offset(table.sub_machines[0].present ? 1 : 2) + 8, -0.5);
  }
  SECTION("bytes in an absent sub-machine's figures") { bad[sub_figure_offset(8) + 3] = 1; }
  SECTION("no sub-machine present") { core::put_u16(bad.data() + 2, 0); }
  SECTION("a ninth sub-machine") { core::put_u16(bad.data() + 2, static_cast<std::uint16_t>(0x100 | table.id_mask())); }
  SECTION("a reserved header byte") { bad[5] = 1; }
  SECTION("a NaN in the global frame") { core::put_f64(bad.data() + kGlobal + 8 * 10, nan); }
  SECTION("a NaN in a sub-machine") { core::put_f64(bad.data() + first + 8 + 8 * 20, nan); }
  SECTION("a rotation scaled by 1 + 1e-8") {
    for (int k = 0; k < 9; ++k) {
      const std::size_t at = first + 8 + 8 * static_cast<std::size_t>(k);
      core::put_f64(bad.data() + at, core::get_f64(bad.data() + at) * (1 + 1e-8));
    }
  }
  SECTION("a reflection (det -1)") {
    for (int k = 0; k < 3; ++k) {  // the first row negated
      const std::size_t at = kGlobal + 8 * static_cast<std::size_t>(k);
      core::put_f64(bad.data() + at, -core::get_f64(bad.data() + at));
    }
  }
  SECTION("a negative origin sigma") { core::put_f64(bad.data() + first + 8 + 8 * 12, -1e-9); }
  SECTION("an A-to-C angle over 180") { core::put_f64(bad.data() + first + 8 + 8 * 20, std::nextafter(180.0, 200.0)); }
  SECTION("master axis 3") { bad[first] = 3; }
  SECTION("a reserved sub-machine byte") { bad[first + 7] = 1; }
  SECTION("bytes in an absent sub-machine's place") { bad[sub_offset(8) + 100] = 1; }

  core::GantryTable out;
  out.global.bed_flatness_mm = 42.0;
  CHECK(core::decode_gantry_table(bad.data(), size, out) == Status::kTableInvalid);
  CHECK(out.global.bed_flatness_mm == 42.0);
  CHECK(out.count() == 0);
}

TEST_CASE("a layout-1 record (stored before the figures' sigmas) reads with those figures not stored",
          "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  const core::GantryTable table = table_of(f, *frames);
  const std::vector<std::uint8_t> old = layout_1(encoded(table));
  core::GantryTable decoded;
  REQUIRE(core::decode_gantry_table(old.data(), old.size(), decoded) == Status::kOk);
  CHECK(decoded.id_mask() == table.id_mask());
  CHECK(same_bits(decoded.global.tracker_T_global, table.global.tracker_T_global));
  CHECK(decoded.global.bed_flatness_mm == table.global.bed_flatness_mm);
  CHECK(decoded.global.bed_flatness_noise_floor_mm == core::kFigureNotStored);
  CHECK(decoded.global.gantry_straightness_noise_floor_mm == core::kFigureNotStored);
  CHECK(decoded.global.bed_form_error_mm == core::kFigureNotStored);
  CHECK(decoded.global.bed_form_error_sigma_mm == core::kFigureNotStored);
  CHECK(decoded.global.gantry_form_error_mm == core::kFigureNotStored);
  CHECK(decoded.global.gantry_form_error_sigma_mm == core::kFigureNotStored);
  for (std::size_t i = 0; i < core::kMaxSubMachines; ++i) {
    INFO("sub-machine " << i + 1);
    REQUIRE(decoded.sub_machines[i].present == table.sub_machines[i].present);
    if (!table.sub_machines[i].present) continue;
    CHECK(same_bits(decoded.sub_machines[i].global_T_sub, table.sub_machines[i].global_T_sub));
    CHECK(same_bits(decoded.sub_machines[i].squareness_arcsec, table.sub_machines[i].squareness_arcsec));
    CHECK(decoded.sub_machines[i].a_c_offset_mm == table.sub_machines[i].a_c_offset_mm);
    CHECK(decoded.sub_machines[i].squareness_sigma_arcsec == Vec3::Constant(core::kFigureNotStored));
    CHECK(decoded.sub_machines[i].a_c_offset_sigma_mm == core::kFigureNotStored);
    CHECK(decoded.sub_machines[i].a_c_angle_sigma_deg == core::kFigureNotStored);
  }
  // Stored again (a merge keeps it), layout 2 carries "not stored" on.
  const std::vector<std::uint8_t> again = encoded(decoded);
  core::GantryTable round;
  REQUIRE(core::decode_gantry_table(again.data(), again.size(), round) == Status::kOk);
  CHECK(encoded(round) == again);
  CHECK(round.global.bed_form_error_sigma_mm == core::kFigureNotStored);
}

TEST_CASE("the boundaries the decoder accepts", "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  core::GantryTable table = table_of(f, *frames);
  core::GantryTable out;
  for (core::StoredSubMachine& s : table.sub_machines) {
    if (!s.present) continue;
    s.a_c_angle_deg = 180.0;
    s.origin_sigma_mm = 0.0;
  }
  const std::vector<std::uint8_t> bytes = encoded(table);
  CHECK(core::decode_gantry_table(bytes.data(), bytes.size(), out) == Status::kOk);
}

TEST_CASE("merging keeps the sub-machines a computation did not compute", "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  core::GantryTable table = table_of(f, *frames);
  const core::GantryTable before = table;
  // A second computation of two sub-machines only, ids 2 and 7, moved 1 mm.
  core::GantryFrames second;
  second.global = frames->global;
  second.global.bed_flatness_mm = 0.5;
  second.sub_machines[0] = frames->sub_machines[1];
  second.sub_machines[0].global_T_sub.t += Vec3(1, 0, 0);
  second.sub_machines[1] = frames->sub_machines[0];
  second.sub_machines[1].id = 7;
  second.sub_machine_count = 2;
  REQUIRE(second.sub_machines[0].id == 2);
  core::merge_frames(table, second);
  CHECK(table.global.bed_flatness_mm == 0.5);
  CHECK(table.sub_machines[6].present);
  CHECK(table.sub_machines[1].global_T_sub.t.x() == before.sub_machines[1].global_T_sub.t.x() + 1.0);
  for (const std::size_t kept : {0u, 2u, 3u}) {
    CHECK(same_bits(table.sub_machines[kept].global_T_sub, before.sub_machines[kept].global_T_sub));
  }
  CHECK(table.count() == 5);
}

TEST_CASE("the point conversion is the frame's inverse, against long double", "[gantry][table]") {
  const Fixture f;
  auto frames = std::make_unique<core::GantryFrames>();
  const core::GantryTable table = table_of(f, *frames);
  t::Rng rng(77);
  double worst = 0.0;
  for (int n = 0; n < 10000; ++n) {
    const Vec3 p(rng.uniform(-10000, 10000), rng.uniform(-10000, 10000), rng.uniform(-3000, 3000));
    for (const core::StoredSubMachine& s : table.sub_machines) {
      if (!s.present) continue;
      // Solve R q = p - t in long double (no transpose: an LU solve).
      const t::Mat3L r = s.global_T_sub.R.cast<long double>();
      const t::Vec3L q = r.partialPivLu().solve(p.cast<long double>() - s.global_T_sub.t.cast<long double>());
      worst = std::max(worst, static_cast<double>((core::global_to_sub_mm(s, p).cast<long double>() - q).norm()));
    }
  }
  INFO("worst " << worst << " mm");
  // |p - t| reaches 1.5e4 mm, where one ulp is 1.8e-12 mm: a few ulps of rounding.
  CHECK(worst < 2e-11);
}
