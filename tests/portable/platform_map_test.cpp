// The compile-time checks of the joined register map
// (macros/include/trueaxis/macros/register_map.hpp), fed bad lists, on the host
// and on the Cortex-M7: each check must refuse what it exists to refuse (the
// product's own lists pass it in a static_assert, which alone would never show
// that it can fail). And the module's status table and slots, in every set.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "portable_test.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace {

namespace m = trueaxis::macros;
using m::MethodBlock;
using m::RowSource;
using m::VarInfo;

constexpr MethodBlock kBlocks[] = {{"one", 500, 599, 1000, 1999}, {"two", 600, 699, 2000, 2999}};

constexpr VarInfo cfg(std::uint16_t n, std::uint16_t count = 1) {
  return {n, count, m::Access::kConfig, m::ValueKind::kReal, 0.0, 1.0, 0.0, "c", "", "test"};
}

m::MacroStep noop(m::PlatformContext&) { return m::done(trueaxis::core::Status::kOk); }

template <std::size_t N>
constexpr m::RowSource src(const VarInfo (&rows)[N], const MethodBlock* block) {
  return {m::list_of(rows), block};
}

// The macros as one method's list.
bool macros_ok(std::initializer_list<m::MacroInfo> list) {
  const m::List<m::MacroInfo> source{list.begin(), list.size()};
  return m::macros_are_well_formed(&source, 1);
}

// The owner of each slot (slot_of), static: the target's stack is 64 KiB.
std::array<int, m::kVariableCount> g_owner;

}  // namespace

// The product's blocks pass blocks_are_well_formed in register_map.hpp's
// static_assert (sources_are_well_formed).
TA_TEST("map: method blocks must lie in their ranges, in order, without overlap") {
  TA_CHECK(m::blocks_are_well_formed(kBlocks, 2));
  const MethodBlock overlapping[] = {{"a", 500, 600, 1000, 1999}, {"b", 600, 699, 2000, 2999}};
  TA_CHECK(!m::blocks_are_well_formed(overlapping, 2));
  const MethodBlock data_overlapping[] = {{"a", 500, 599, 1000, 2000}, {"b", 600, 699, 2000, 2999}};
  TA_CHECK(!m::blocks_are_well_formed(data_overlapping, 2));
  const MethodBlock unordered[] = {{"b", 600, 699, 2000, 2999}, {"a", 500, 599, 1000, 1999}};
  TA_CHECK(!m::blocks_are_well_formed(unordered, 2));
  const MethodBlock below[] = {{"a", 499, 599, 1000, 1999}};
  TA_CHECK(!m::blocks_are_well_formed(below, 1));
  const MethodBlock above[] = {{"a", 901, 1000, 1000, 1999}};
  TA_CHECK(!m::blocks_are_well_formed(above, 1));
  const MethodBlock data_above[] = {{"a", 901, 999, 4000, 5000}};
  TA_CHECK(!m::blocks_are_well_formed(data_above, 1));
  const MethodBlock at_edges[] = {{"a", 500, 899, 1000, 4999}};
  TA_CHECK(m::blocks_are_well_formed(at_edges, 1));
  const MethodBlock over_unlock_code[] = {{"a", 850, 900, 1000, 4999}};  // #900 is the platform's
  TA_CHECK(!m::blocks_are_well_formed(over_unlock_code, 1));
}

TA_TEST("map: a method's rows must lie inside its blocks, the platform's outside all") {
  const VarInfo inside[] = {cfg(500), cfg(599), cfg(1000, 1000)};
  TA_CHECK(m::source_is_well_formed(src(inside, &kBlocks[0]), kBlocks, 2));
  const VarInfo past_config[] = {cfg(599, 2)};  // #599..#600: one number in the next block
  TA_CHECK(!m::source_is_well_formed(src(past_config, &kBlocks[0]), kBlocks, 2));
  const VarInfo in_other_block[] = {cfg(650)};
  TA_CHECK(!m::source_is_well_formed(src(in_other_block, &kBlocks[0]), kBlocks, 2));
  TA_CHECK(m::source_is_well_formed(src(in_other_block, &kBlocks[1]), kBlocks, 2));
  const VarInfo past_data[] = {cfg(1999, 2)};
  TA_CHECK(!m::source_is_well_formed(src(past_data, &kBlocks[0]), kBlocks, 2));

  const VarInfo platform_outside[] = {cfg(450), cfg(700)};
  TA_CHECK(m::source_is_well_formed(src(platform_outside, nullptr), kBlocks, 2));
  const VarInfo platform_touching[] = {cfg(498, 2)};  // #498..#499
  TA_CHECK(m::source_is_well_formed(src(platform_touching, nullptr), kBlocks, 2));
  const VarInfo platform_inside[] = {cfg(499, 2)};  // #499..#500
  TA_CHECK(!m::source_is_well_formed(src(platform_inside, nullptr), kBlocks, 2));
  const VarInfo platform_data[] = {cfg(2999)};
  TA_CHECK(!m::source_is_well_formed(src(platform_data, nullptr), kBlocks, 2));
}

TA_TEST("map: a source must be sorted and its rows must not overlap") {
  const VarInfo unsorted[] = {cfg(510), cfg(505)};
  TA_CHECK(!m::source_is_well_formed(src(unsorted, &kBlocks[0]), kBlocks, 2));
  const VarInfo overlapping[] = {cfg(505, 3), cfg(507)};
  TA_CHECK(!m::source_is_well_formed(src(overlapping, &kBlocks[0]), kBlocks, 2));
  const VarInfo adjacent[] = {cfg(505, 2), cfg(507)};
  TA_CHECK(m::source_is_well_formed(src(adjacent, &kBlocks[0]), kBlocks, 2));
  VarInfo bad_default = cfg(505);
  bad_default.default_value = 2.0;  // outside [0, 1]
  const VarInfo defaults[] = {bad_default};
  TA_CHECK(!m::source_is_well_formed(src(defaults, &kBlocks[0]), kBlocks, 2));
}

// The product's macros pass macros_are_well_formed in register_map.hpp's
// static_assert. Every portable set builds levelling, whose first macro is 9810.
TA_TEST("map: macros must have unique numbers, results as outputs and defined inputs") {
  constexpr m::OutputInfo good_out[] = {{100, "a", "", "x"}, {199, "b", "", "x"}};
  constexpr m::OutputInfo low_out[] = {{99, "a", "", "x"}};
  constexpr m::OutputInfo high_out[] = {{200, "a", "", "x"}};
  constexpr m::InputRef good_in[] = {{1, 3, ""}, {m::var::kPointList, m::var::kPointListCount, ""}};
  constexpr m::InputRef undefined_in[] = {{8, 3, ""}};  // #10 is not defined
  constexpr m::InputRef past_block_in[] = {{m::var::kPointList, m::var::kPointListCount + 1, ""}};
  m::MacroInfo no_handler = m::macro<&noop>(9900, "a", "", good_out);
  no_handler.run = nullptr;
  TA_CHECK(macros_ok({m::macro<&noop>(9900, "a", "", good_in, good_out), m::macro<&noop>(9901, "b", "", good_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(9900, "a", "", good_out), m::macro<&noop>(9900, "b", "", good_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(0, "a", "", good_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(10000, "a", "", good_out)}));
  TA_CHECK(!macros_ok({no_handler}));
  TA_CHECK(!macros_ok({m::macro<&noop>(9900, "a", "", low_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(9900, "a", "", high_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(9900, "a", "", undefined_in, good_out)}));
  TA_CHECK(!macros_ok({m::macro<&noop>(9900, "a", "", past_block_in, good_out)}));
  // The product's macros against a duplicate from another method.
  const m::MacroInfo clash[] = {m::macro<&noop>(9810, "clash", "", good_out)};
  const m::List<m::MacroInfo> two[] = {m::BuiltMethods::kMacros[0], m::list_of(clash)};
  TA_CHECK(!m::macros_are_well_formed(two, 2));
}

TA_TEST("map: status codes: the platform's below 1000, a method's in its block or published before, none twice") {
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
  TA_CHECK(m::statuses_are_well_formed(good, blocks, 2, m::list_of(platform)));
  TA_CHECK(!m::statuses_are_well_formed(good, blocks, 2, m::list_of(platform_high)));
  const m::List<StatusInfo> out_of_block[] = {m::list_of(outside), m::list_of(method_b)};
  TA_CHECK(!m::statuses_are_well_formed(out_of_block, blocks, 2, m::list_of(platform)));
  const m::List<StatusInfo> new_below_1000[] = {m::list_of(above_legacy)};
  TA_CHECK(!m::statuses_are_well_formed(new_below_1000, blocks, 1, m::list_of(platform)));
  const m::List<StatusInfo> twice[] = {m::list_of(repeats_platform)};
  TA_CHECK(!m::statuses_are_well_formed(twice, blocks, 1, m::list_of(platform)));
  const m::StatusBlock overlapping[] = {{1100, 1250}, {1200, 1299}};
  TA_CHECK(!m::statuses_are_well_formed(good, overlapping, 2, m::list_of(platform)));
  const m::StatusBlock in_platform[] = {{900, 1099}};
  const m::List<StatusInfo> none[] = {m::List<StatusInfo>{}};
  TA_CHECK(!m::statuses_are_well_formed(none, in_platform, 1, m::list_of(platform)));
  // The module's own table: sorted, every built method's codes in it.
  for (std::size_t i = 1; i < m::kStatusTable.size(); ++i) {
    TA_CASE_INDEX(i);
    TA_CHECK(m::kStatusTable[i - 1].status < m::kStatusTable[i].status);
  }
  TA_CASE_INDEX(-1);
  for (const m::List<StatusInfo>& l : m::BuiltMethods::kStatuses) {
    for (const StatusInfo& st : l) {
      TA_CASE_INDEX(static_cast<int>(st.status));
      TA_CHECK(std::strcmp(m::status_name(st.status), st.name) == 0);
    }
  }
}

TA_TEST("map: slot_of gives every defined number a slot of its own: the platform's where platform_slot says, a "
        "method's after its base in its own order") {
  using Built = m::BuiltMethods;
  g_owner.fill(-1);
  std::size_t defined = 0, misplaced = 0;
  for (std::uint32_t n32 = 0; n32 <= m::kMaxVariableNumber; ++n32) {
    TA_CASE_INDEX(n32);
    const auto n = static_cast<std::uint16_t>(n32);
    const std::size_t slot = m::slot_of(n);
    if (m::find_var(n) == nullptr) {
      TA_CHECK_EQ(slot, m::kVariableCount);
      continue;
    }
    ++defined;
    TA_REQUIRE(slot < m::kVariableCount);
    TA_CHECK_EQ(g_owner[slot], -1);
    g_owner[slot] = n;
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
  TA_CASE_INDEX(-1);
  TA_CHECK_EQ(defined, m::kVariableCount);
  TA_CHECK_EQ(misplaced, std::size_t{0});
  for (std::size_t i = 1; i < m::kRegisterMapSize; ++i) {
    TA_CASE_INDEX(i);
    TA_CHECK(m::kRegisterMap[i - 1].number + m::kRegisterMap[i - 1].count <= m::kRegisterMap[i].number);
  }
}
