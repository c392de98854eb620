// The compile-time checks of the joined register map, fed bad lists: each
// check must refuse what it exists to refuse (the product's own lists pass it
// in a static_assert, which alone would never show that it can fail).
#include <catch2/catch.hpp>

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

m::MacroStep noop(m::MacroContext&) { return m::done(trueaxis::core::Status::kOk); }

}  // namespace

TEST_CASE("method blocks must lie in their ranges, in order, without overlap", "[map]") {
  CHECK(m::blocks_are_well_formed(kBlocks, 2));
  CHECK(m::blocks_are_well_formed(m::kMethodBlocks, 4));
  const MethodBlock overlapping[] = {{"a", 500, 600, 1000, 1999}, {"b", 600, 699, 2000, 2999}};
  CHECK_FALSE(m::blocks_are_well_formed(overlapping, 2));
  const MethodBlock data_overlapping[] = {{"a", 500, 599, 1000, 2000}, {"b", 600, 699, 2000, 2999}};
  CHECK_FALSE(m::blocks_are_well_formed(data_overlapping, 2));
  const MethodBlock unordered[] = {{"b", 600, 699, 2000, 2999}, {"a", 500, 599, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(unordered, 2));
  const MethodBlock below[] = {{"a", 499, 599, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(below, 1));
  const MethodBlock above[] = {{"a", 900, 1000, 1000, 1999}};
  CHECK_FALSE(m::blocks_are_well_formed(above, 1));
  const MethodBlock data_above[] = {{"a", 900, 999, 4000, 5000}};
  CHECK_FALSE(m::blocks_are_well_formed(data_above, 1));
  const MethodBlock at_edges[] = {{"a", 500, 999, 1000, 4999}};
  CHECK(m::blocks_are_well_formed(at_edges, 1));
}

TEST_CASE("a method's rows must lie inside its blocks, the platform's outside all", "[map]") {
  const VarInfo inside[] = {cfg(500), cfg(599), cfg(1000, 1000)};
  CHECK(m::source_is_well_formed({inside, 3, &kBlocks[0]}, kBlocks, 2));
  const VarInfo past_config[] = {cfg(599, 2)};  // #599..#600: one number in the next block
  CHECK_FALSE(m::source_is_well_formed({past_config, 1, &kBlocks[0]}, kBlocks, 2));
  const VarInfo in_other_block[] = {cfg(650)};
  CHECK_FALSE(m::source_is_well_formed({in_other_block, 1, &kBlocks[0]}, kBlocks, 2));
  CHECK(m::source_is_well_formed({in_other_block, 1, &kBlocks[1]}, kBlocks, 2));
  const VarInfo past_data[] = {cfg(1999, 2)};
  CHECK_FALSE(m::source_is_well_formed({past_data, 1, &kBlocks[0]}, kBlocks, 2));

  const VarInfo platform_outside[] = {cfg(450), cfg(700)};
  CHECK(m::source_is_well_formed({platform_outside, 2, nullptr}, kBlocks, 2));
  const VarInfo platform_touching[] = {cfg(498, 2)};  // #498..#499
  CHECK(m::source_is_well_formed({platform_touching, 1, nullptr}, kBlocks, 2));
  const VarInfo platform_inside[] = {cfg(499, 2)};  // #499..#500
  CHECK_FALSE(m::source_is_well_formed({platform_inside, 1, nullptr}, kBlocks, 2));
  const VarInfo platform_data[] = {cfg(2999)};
  CHECK_FALSE(m::source_is_well_formed({platform_data, 1, nullptr}, kBlocks, 2));
}

TEST_CASE("a source must be sorted and its rows must not overlap", "[map]") {
  const VarInfo unsorted[] = {cfg(510), cfg(505)};
  CHECK_FALSE(m::source_is_well_formed({unsorted, 2, &kBlocks[0]}, kBlocks, 2));
  const VarInfo overlapping[] = {cfg(505, 3), cfg(507)};
  CHECK_FALSE(m::source_is_well_formed({overlapping, 2, &kBlocks[0]}, kBlocks, 2));
  const VarInfo adjacent[] = {cfg(505, 2), cfg(507)};
  CHECK(m::source_is_well_formed({adjacent, 2, &kBlocks[0]}, kBlocks, 2));
  VarInfo bad_default = cfg(505);
  bad_default.default_value = 2.0;  // outside [0, 1]
  const VarInfo defaults[] = {bad_default};
  CHECK_FALSE(m::source_is_well_formed({defaults, 1, &kBlocks[0]}, kBlocks, 2));
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
    const m::MacroSource source{macros.data(), macros.size(), "test"};
    return m::macros_are_well_formed(&source, 1);
  };
  CHECK(check({m::macro(9900, &noop, "a", "", good_in, good_out), m::macro(9901, &noop, "b", "", good_out)}));
  CHECK_FALSE(check({m::macro(9900, &noop, "a", "", good_out), m::macro(9900, &noop, "b", "", good_out)}));
  CHECK_FALSE(check({m::macro(0, &noop, "a", "", good_out)}));
  CHECK_FALSE(check({m::macro(10000, &noop, "a", "", good_out)}));
  CHECK_FALSE(check({m::macro(9900, nullptr, "a", "", good_out)}));
  CHECK_FALSE(check({m::macro(9900, &noop, "a", "", low_out)}));
  CHECK_FALSE(check({m::macro(9900, &noop, "a", "", high_out)}));
  CHECK_FALSE(check({m::macro(9900, &noop, "a", "", undefined_in, good_out)}));
  CHECK_FALSE(check({m::macro(9900, &noop, "a", "", past_block_in, good_out)}));
  // The product's macros against a duplicate from another source.
  const m::MacroInfo clash[] = {m::macro(9810, &noop, "clash", "", good_out)};
  const m::MacroSource two[] = {m::kMacroSources[0], {clash, 1, "other"}};
  CHECK_FALSE(m::macros_are_well_formed(two, 2));
  CHECK(m::macros_are_well_formed(m::kMacroSources, 1));
}

TEST_CASE("slot_of agrees with a linear walk of the joined map for every number", "[map]") {
  std::size_t slot = 0;
  std::vector<std::size_t> expected(m::kMaxVariableNumber + 1, m::kVariableCount);
  for (const VarInfo& v : m::kRegisterMap) {
    for (std::uint16_t k = 0; k < v.count; ++k) expected[v.number + k] = slot++;
  }
  REQUIRE(slot == m::kVariableCount);
  std::size_t mismatches = 0;
  for (std::uint32_t n = 0; n <= m::kMaxVariableNumber; ++n) {
    if (m::slot_of(static_cast<std::uint16_t>(n)) != expected[n]) ++mismatches;
  }
  CHECK(mismatches == 0);
  for (std::size_t i = 1; i < m::kRegisterMapSize; ++i) {
    CHECK(m::kRegisterMap[i - 1].number + m::kRegisterMap[i - 1].count <= m::kRegisterMap[i].number);
  }
}
