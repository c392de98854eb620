// The compile-time checks of the joined register map, fed bad lists: each
// check must refuse what it exists to refuse (the product's own lists pass it
// in a static_assert, which alone would never show that it can fail).
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace m = trueaxis::macros;
using m::MethodBlock;
using m::RowSource;
using m::VarInfo;

namespace {

constexpr MethodBlock kBlocks[] = {{"one", 500, 599, 1000, 1999}, {"two", 600, 699, 2000, 2999}};

constexpr VarInfo cfg(std::uint16_t n, std::uint16_t count = 1) {
  return {n, count, m::Access::kConfig, m::ValueKind::kReal, 0.0, 1.0, 0.0, "c", "", "test"};
}

m::MacroStep noop(m::PlatformContext&) { return m::done(trueaxis::core::Status::kOk); }

template <std::size_t N>
constexpr m::RowSource src(const VarInfo (&rows)[N], const MethodBlock* block) {
  return {m::list_of(rows), block};
}

}  // namespace

TEST_CASE("method blocks must lie in their ranges, in order, without overlap", "[map]") {
  CHECK(m::blocks_are_well_formed(kBlocks, 2));
  CHECK(m::blocks_are_well_formed(m::BuiltMethods::kBlocks.data(), m::BuiltMethods::kCount));
  const MethodBlock overlapping[] = {{"a", 500, 600, 1000, 1999}, {"b", 600, 699, 2000, 2999}};
  CHECK_FALSE(m::blocks_are_well_formed(overlapping, 2));
  const MethodBlock data_overlapping[] = {{"a", 500, 599, 1000, 2000}, {"b", 600, 699, 2000, 2999}};
  CHECK_FALSE(m::blocks_are_well_formed(data_overlapping, 2));
  const MethodBlock unordered[] = {{"b", 600, 699, 2000, 2999}, {"a", 500, 599, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(unordered, 2));
  const MethodBlock below[] = {{"a", 499, 599, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(below, 1));
  const MethodBlock above[] = {{"a", 901, 1000, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(above, 1));
  const MethodBlock data_above[] = {{"a", 901, 999, 4000, 5000}};
  CHECK_FALSE(m::blocks_are_well_formed(data_above, 1));
  const MethodBlock at_edges[] = {{"a", 500, 899, 1000, 4999}};
  CHECK(m::blocks_are_well_formed(at_edges, 1));
  const MethodBlock over_unlock_code[] = {{"a", 850, 900, 1000, 4999}};  // #900 is the platform's
  CHECK_FALSE(m::blocks_are_well_formed(over_unlock_code, 1));
}

TEST_CASE("a method's rows must lie inside its blocks, the platform's outside all", "[map]") {
  const VarInfo inside[] = {cfg(500), cfg(599), cfg(1000, 1000)};
  CHECK(m::source_is_well_formed(src(inside, &kBlocks[0]), kBlocks, 2));
  const VarInfo past_config[] = {cfg(599, 2)};  // #599..#600: one number in the next block
  CHECK_FALSE(m::source_is_well_formed(src(past_config, &kBlocks[0]), kBlocks, 2));
  const VarInfo in_other_block[] = {cfg(650)};
  CHECK_FALSE(m::source_is_well_formed(src(in_other_block, &kBlocks[0]), kBlocks, 2));
  CHECK(m::source_is_well_formed(src(in_other_block, &kBlocks[1]), kBlocks, 2));
  const VarInfo past_data[] = {cfg(1999, 2)};
  CHECK_FALSE(m::source_is_well_formed(src(past_data, &kBlocks[0]), kBlocks, 2));

  const VarInfo platform_outside[] = {cfg(450), cfg(700)};
  CHECK(m::source_is_well_formed(src(platform_outside, nullptr), kBlocks, 2));
  const VarInfo platform_touching[] = {cfg(498, 2)};  // #498..#499
  CHECK(m::source_is_well_formed(src(platform_touching, nullptr), kBlocks, 2));
  const VarInfo platform_inside[] = {cfg(499, 2)};  // #499..#500
  CHECK_FALSE(m::source_is_well_formed(src(platform_inside, nullptr), kBlocks, 2));
  const VarInfo platform_data[] = {cfg(2999)};
  CHECK_FALSE(m::source_is_well_formed(src(platform_data, nullptr), kBlocks, 2));
}

TEST_CASE("a source must be sorted and its rows must not overlap", "[map]") {
  const VarInfo unsorted[] = {cfg(510), cfg(505)};
  CHECK_FALSE(m::source_is_well_formed(src(unsorted, &kBlocks[0]), kBlocks, 2));
  const VarInfo overlapping[] = {cfg(505, 3), cfg(507)};
  CHECK_FALSE(m::source_is_well_formed(src(overlapping, &kBlocks[0]), kBlocks, 2));
  const VarInfo adjacent[] = {cfg(505, 2), cfg(507)};
  CHECK(m::source_is_well_formed(src(adjacent, &kBlocks[0]), kBlocks, 2));
  VarInfo bad_default = cfg(505);
  bad_default.default_value = 2.0;  // outside [0, 1]
  const VarInfo defaults[] = {bad_default};
  CHECK_FALSE(m::source_is_well_formed(src(defaults, &kBlocks[0]), kBlocks, 2));
}

TEST_CASE("macros must have unique numbers, results as outputs and defined inputs", "[map]") {
  constexpr m::OutputInfo good_out[] = {{100, "a", "", "x"}, {199, "b", "", "x"}};
  constexpr m::OutputInfo low_out[] = {{99, "a", "", "x"}};
  constexpr m::OutputInfo high_out[] = {{200, "a", "", "x"}};
  constexpr m::InputRef good_in[] = {{1, 3, ""}, {m::var::kPointList, m::var::kPointListCount, ""}};
  constexpr m::InputRef undefined_in[] = {{8, 3, ""}};  // #10 is not defined
  constexpr m::InputRef past_block_in[] = {{m::var::kPointList, m::var::kPointListCount + 1, ""}};
  const auto check = [](std::initializer_list<m::MacroInfo> list) {
    const std::vector<m::MacroInfo> macros(list);
    const m::List<m::MacroInfo> source{macros.data(), macros.size()};
    return m::macros_are_well_formed(&source, 1);
  };
  m::MacroInfo no_handler = m::macro<&noop>(9900, "a", "", good_out);
  no_handler.run = nullptr;
  CHECK(check({m::macro<&noop>(9900, "a", "", good_in, good_out), m::macro<&noop>(9901, "b", "", good_out)}));
  CHECK_FALSE(check({m::macro<&noop>(9900, "a", "", good_out), m::macro<&noop>(9900, "b", "", good_out)}));
  CHECK_FALSE(check({m::macro<&noop>(0, "a", "", good_out)}));
  CHECK_FALSE(check({m::macro<&noop>(10000, "a", "", good_out)}));
  CHECK_FALSE(check({no_handler}));
  CHECK_FALSE(check({m::macro<&noop>(9900, "a", "", low_out)}));
  CHECK_FALSE(check({m::macro<&noop>(9900, "a", "", high_out)}));
  CHECK_FALSE(check({m::macro<&noop>(9900, "a", "", undefined_in, good_out)}));
  CHECK_FALSE(check({m::macro<&noop>(9900, "a", "", past_block_in, good_out)}));
  // The product's macros against a duplicate from another method.
  const m::MacroInfo clash[] = {m::macro<&noop>(9810, "clash", "", good_out)};
  const m::List<m::MacroInfo> two[] = {m::BuiltMethods::kMacros[0], m::list_of(clash)};
  CHECK_FALSE(m::macros_are_well_formed(two, 2));
  CHECK(m::macros_are_well_formed(m::BuiltMethods::kMacros.data(), m::BuiltMethods::kCount));
}

TEST_CASE("status codes: the platform's below 1000, a method's in its block or published before, none twice",
          "[map]") {
  using trueaxis::core::Status;
  using trueaxis::core::StatusInfo;
  const auto code = [](unsigned n) { return static_cast<Status>(n); };
  const StatusInfo platform[] = {{code(0), "ok", ""}, {code(400), "p", ""}};
  const StatusInfo platform_high[] = {{code(0), "ok", ""}, {code(1000), "p", ""}};
  const StatusInfo method_a[] = {{code(1100), "a1", ""}, {code(1199), "a2", ""}, {code(208), "legacy", ""}};
  const StatusInfo method_b[] = {{code(1200), "b1", ""}};
  const StatusInfo outside[] = {{code(1200), "a1", ""}};
  const StatusInfo above_legacy[] = {{code(223), "a1", ""}};
  const StatusInfo repeats_platform[] = {{code(400), "a1", ""}};
  const m::StatusBlock blocks[] = {{1100, 1199}, {1200, 1299}};
  const m::List<StatusInfo> good[] = {m::list_of(method_a), m::list_of(method_b)};
  CHECK(m::statuses_are_well_formed(good, blocks, 2, m::list_of(platform)));
  CHECK_FALSE(m::statuses_are_well_formed(good, blocks, 2, m::list_of(platform_high)));
  const m::List<StatusInfo> out_of_block[] = {m::list_of(outside), m::list_of(method_b)};
  CHECK_FALSE(m::statuses_are_well_formed(out_of_block, blocks, 2, m::list_of(platform)));
  const m::List<StatusInfo> new_below_1000[] = {m::list_of(above_legacy)};
  CHECK_FALSE(m::statuses_are_well_formed(new_below_1000, blocks, 1, m::list_of(platform)));
  const m::List<StatusInfo> twice[] = {m::list_of(repeats_platform)};
  CHECK_FALSE(m::statuses_are_well_formed(twice, blocks, 1, m::list_of(platform)));
  const m::StatusBlock overlapping[] = {{1100, 1250}, {1200, 1299}};
  CHECK_FALSE(m::statuses_are_well_formed(good, overlapping, 2, m::list_of(platform)));
  const m::StatusBlock in_platform[] = {{900, 1099}};
  const m::List<StatusInfo> none[] = {m::List<StatusInfo>{}};
  CHECK_FALSE(m::statuses_are_well_formed(none, in_platform, 1, m::list_of(platform)));
  // The module's own table: sorted, every built method's codes in it.
  for (std::size_t i = 1; i < m::kStatusTable.size(); ++i) CHECK(m::kStatusTable[i - 1].status < m::kStatusTable[i].status);
  for (const m::List<StatusInfo>& l : m::BuiltMethods::kStatuses) {
    for (const StatusInfo& st : l) CHECK(std::string(m::status_name(st.status)) == st.name);
  }
}

TEST_CASE("slot_of gives every defined number a slot of its own: the platform's where platform_slot says, a "
          "method's after its base in its own order", "[map]") {
  using Built = m::BuiltMethods;
  std::vector<int> owner(m::kVariableCount, -1);
  std::size_t defined = 0, misplaced = 0;
  for (std::uint32_t n32 = 0; n32 <= m::kMaxVariableNumber; ++n32) {
    const auto n = static_cast<std::uint16_t>(n32);
    const std::size_t slot = m::slot_of(n);
    if (m::find_var(n) == nullptr) {
      CHECK(slot == m::kVariableCount);
      continue;
    }
    ++defined;
    REQUIRE(slot < m::kVariableCount);
    CHECK(owner[slot] == -1);
    owner[slot] = n;
    std::size_t expected = m::platform_slot(n);
    for (std::size_t i = 0; expected == m::kNoSlot && i < Built::kCount; ++i) {
      std::size_t local = 0;
      for (const VarInfo& v : Built::kRows[i]) {
        if (n >= v.number && n < v.number + v.count) expected = Built::kSlotBase[i] + local + (n - v.number);
        local += v.count;
      }
    }
    if (slot != expected) ++misplaced;
  }
  CHECK(defined == m::kVariableCount);
  CHECK(misplaced == 0);
  for (std::size_t i = 1; i < m::kRegisterMapSize; ++i) {
    CHECK(m::kRegisterMap[i - 1].number + m::kRegisterMap[i - 1].count <= m::kRegisterMap[i].number);
  }
}
