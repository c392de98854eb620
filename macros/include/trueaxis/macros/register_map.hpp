// The module's register map: the one table from which the variable numbers, the
// Modbus addresses (variable #N = holding registers 4N .. 4N+3), the JSON map
// (macros/register_map.json) and the human page (macros/REGISTER_MAP.md) come.
//
// It joins the platform's rows (platform_map.hpp) and each method's rows
// (macros/<method>/<method>_map.hpp) into one sorted constexpr array and checks,
// at compile time, that
//  1. every source table is sorted and the joined table has no overlap;
//  2. every row is well formed (var_info.hpp map_is_well_formed);
//  3. each method's rows lie inside its blocks (kMethodBlocks), and the
//     platform's rows outside every method block;
//  4. the result range #100..#199 is defined whole, so results are one
//     contiguous run of slots;
//  5. every macro of methods.hpp has a unique number in 1..9999, outputs inside
//     #100..#199 and inputs the map defines.
// A number not in the table is not defined: reading or writing it is refused.
// The lists of methods are in methods.hpp; the checks take their lists as
// arguments so that tests can feed them bad ones (tests/macros/test_register_map.cpp).
#pragma once

#include <array>
#include <cstddef>

#include "trueaxis/macros/methods.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

namespace detail {

// The result variables named in methods.hpp (kNamedResults) keep their names;
// the rest of the result range is one block.
template <std::size_t N>
constexpr std::array<VarInfo, N + 1> result_rows(const OutputInfo (&named)[N]) {
  std::array<VarInfo, N + 1> out{};
  for (std::size_t i = 0; i < N; ++i) {
    out[i] = rows::result(named[i].number, 1, named[i].name, named[i].unit, named[i].description);
  }
  const auto first_free = static_cast<std::uint16_t>(var::kResultFirst + N);
  out[N] = rows::result(first_free, static_cast<std::uint16_t>(var::kResultLast - first_free + 1), "results", "",
                        "Results of the last macro; their meaning is per macro (see each macro's outputs).");
  return out;
}
inline constexpr auto kResultRows = result_rows(kNamedResults);

template <std::size_t N>
constexpr RowSource platform_source(const std::array<VarInfo, N>& t) {
  return {t.data(), N, nullptr};
}

// The platform's rows; the methods' come from methods.hpp.
inline constexpr RowSource kPlatformRowSources[] = {
    row_source(kPlatformArgRows, nullptr),
    platform_source(kResultRows),
    row_source(kPlatformRows, nullptr),
};

template <typename F>
constexpr bool all_sources(F f) {
  for (const RowSource& s : kPlatformRowSources) {
    if (!f(s)) return false;
  }
  for (const RowSource& s : kMethodRowSources) {
    if (!f(s)) return false;
  }
  return true;
}

constexpr std::size_t total_rows() {
  std::size_t n = 0;
  all_sources([&n](const RowSource& s) {
    n += s.count;
    return true;
  });
  return n;
}

constexpr bool inside(std::uint16_t first, std::uint16_t last, const VarInfo& v) {
  return v.number >= first && static_cast<std::uint32_t>(v.number) + v.count - 1 <= last;
}

constexpr bool overlaps_any_block(const VarInfo& v, const MethodBlock* blocks, std::size_t block_count) {
  for (std::size_t b = 0; b < block_count; ++b) {
    const std::uint32_t end = static_cast<std::uint32_t>(v.number) + v.count - 1;
    if (end >= blocks[b].config_first && v.number <= blocks[b].config_last) return true;
    if (end >= blocks[b].data_first && v.number <= blocks[b].data_last) return true;
  }
  return false;
}

}  // namespace detail

// Blocks inside #500..#999 and #1000..#4999, in order, not overlapping.
constexpr bool blocks_are_well_formed(const MethodBlock* blocks, std::size_t count) {
  for (std::size_t b = 0; b < count; ++b) {
    const MethodBlock& m = blocks[b];
    if (m.config_first > m.config_last || m.data_first > m.data_last) return false;
    if (m.config_first < var::kConfigFirst || m.config_last > var::kConfigLast) return false;
    if (m.data_first < var::kDataFirst || m.data_last > var::kDataLast) return false;
    if (b > 0 && (blocks[b - 1].config_last >= m.config_first || blocks[b - 1].data_last >= m.data_first)) {
      return false;
    }
  }
  return true;
}

// A source is sorted and well formed; a method's rows lie inside its blocks;
// the platform's (block nullptr) outside every block.
constexpr bool source_is_well_formed(const RowSource& s, const MethodBlock* blocks, std::size_t block_count) {
  if (!map_is_well_formed(s.rows, s.count)) return false;
  for (std::size_t i = 0; i < s.count; ++i) {
    const VarInfo& v = s.rows[i];
    if (s.block == nullptr) {
      if (detail::overlaps_any_block(v, blocks, block_count)) return false;
    } else if (!detail::inside(s.block->config_first, s.block->config_last, v) &&
               !detail::inside(s.block->data_first, s.block->data_last, v)) {
      return false;
    }
  }
  return true;
}

namespace detail {

constexpr std::size_t kBlockCount = sizeof(kMethodBlocks) / sizeof(kMethodBlocks[0]);

constexpr bool sources_are_well_formed() {
  if (!blocks_are_well_formed(kMethodBlocks, kBlockCount)) return false;
  return all_sources([](const RowSource& s) { return source_is_well_formed(s, kMethodBlocks, kBlockCount); });
}
static_assert(sources_are_well_formed(),
              "a row source is unsorted or malformed, a method row lies outside its block, "
              "or a platform row lies inside a method block");

constexpr std::array<VarInfo, total_rows()> joined_rows() {
  std::array<VarInfo, total_rows()> out{};
  std::size_t n = 0;
  all_sources([&out, &n](const RowSource& s) {
    for (std::size_t i = 0; i < s.count; ++i) out[n++] = s.rows[i];
    return true;
  });
  for (std::size_t i = 1; i < n; ++i) {  // insertion sort: a few hundred rows, once, at compile time
    for (std::size_t j = i; j > 0 && out[j - 1].number > out[j].number; --j) {
      const VarInfo t = out[j];
      out[j] = out[j - 1];
      out[j - 1] = t;
    }
  }
  return out;
}

}  // namespace detail

inline constexpr std::array<VarInfo, detail::total_rows()> kRegisterMap = detail::joined_rows();
inline constexpr std::size_t kRegisterMapSize = kRegisterMap.size();
static_assert(map_is_well_formed(kRegisterMap.data(), kRegisterMapSize),
              "kRegisterMap: two sources define overlapping numbers");

inline constexpr std::size_t kVariableCount = variable_count(kRegisterMap.data(), kRegisterMapSize);

constexpr const VarInfo* find_var(std::uint16_t number) {
  return find_in(kRegisterMap.data(), kRegisterMapSize, number);
}

namespace detail {
// The slot of each entry's first variable: the running sum of the counts before it.
constexpr std::array<std::size_t, kRegisterMapSize> first_slots() {
  std::array<std::size_t, kRegisterMapSize> slots{};
  std::size_t slot = 0;
  for (std::size_t i = 0; i < kRegisterMapSize; ++i) {
    slots[i] = slot;
    slot += kRegisterMap[i].count;
  }
  return slots;
}
inline constexpr std::array<std::size_t, kRegisterMapSize> kFirstSlot = first_slots();
}  // namespace detail

// Position of #number in a flat array of every variable of the map (blocks
// expanded, table order); kVariableCount when the number is not defined.
// A binary search plus a table look-up; handlers use slot<N>(), computed at
// compile time, instead.
constexpr std::size_t slot_of(std::uint16_t number) {
  const VarInfo* v = find_var(number);
  if (v == nullptr) return kVariableCount;
  return detail::kFirstSlot[static_cast<std::size_t>(v - kRegisterMap.data())] + (number - v->number);
}

constexpr bool is_defined(std::uint16_t number) { return slot_of(number) < kVariableCount; }

// The slot of #N, for a number known at compile time; does not compile for a
// number the map does not define.
template <std::uint16_t N>
constexpr std::size_t slot() {
  static_assert(slot_of(N) < kVariableCount, "the register map does not define this variable number");
  return slot_of(N);
}

constexpr bool is_persistent(const VarInfo& v) {
  return v.access == Access::kConfig || v.access == Access::kPersistent;
}

constexpr std::size_t count_of(Access access) {
  std::size_t n = 0;
  for (const VarInfo& v : kRegisterMap) {
    if (v.access == access) n += v.count;
  }
  return n;
}
inline constexpr std::size_t kConfigCount = count_of(Access::kConfig);
inline constexpr std::size_t kWorkOffsetCount = count_of(Access::kPersistent);
inline constexpr std::size_t kResultSlots = var::kResultLast - var::kResultFirst + 1;

// Results are one contiguous run of slots (convention 4).
static_assert(slot_of(var::kResultLast) - slot_of(var::kResultFirst) == kResultSlots - 1);
static_assert(is_defined(var::kCmd) && is_defined(var::kStepCount) && is_defined(var::kLevelOtherReachable));
static_assert(is_defined(var::kMaxDirectionSigma) && is_defined(var::kG59 + 5) && !is_defined(var::kG59 + 6));
static_assert(!is_defined(10), "#10 (letter G) is not an argument");
static_assert(slot_of(var::kFailedUnlocks) == kVariableCount - 1);

// Macro numbers unique and in 1..9999, a handler, outputs inside #100..#199,
// inputs defined in the map.
constexpr bool macros_are_well_formed(const MacroSource* sources, std::size_t count) {
  for (std::size_t a = 0; a < count; ++a) {
    for (std::size_t i = 0; i < sources[a].count; ++i) {
      const MacroInfo& m = sources[a].macros[i];
      if (m.number == 0 || m.number > 9999 || m.run == nullptr) return false;
      for (std::size_t b = 0; b < count; ++b) {
        for (std::size_t j = 0; j < sources[b].count; ++j) {
          if (&sources[b].macros[j] != &m && sources[b].macros[j].number == m.number) return false;
        }
      }
      for (std::size_t k = 0; k < m.output_count; ++k) {
        const std::uint16_t n = m.outputs[k].number;
        if (n < var::kResultFirst || n > var::kResultLast) return false;
      }
      for (std::size_t k = 0; k < m.input_count; ++k) {
        for (std::uint16_t j = 0; j < m.inputs[k].count; ++j) {
          if (!is_defined(static_cast<std::uint16_t>(m.inputs[k].first + j))) return false;
        }
      }
    }
  }
  return true;
}
static_assert(macros_are_well_formed(kMacroSources, sizeof(kMacroSources) / sizeof(kMacroSources[0])),
              "a macro number repeats or is out of 1..9999, an output lies outside #100..#199, "
              "or an input is not defined in the map");

}  // namespace trueaxis::macros
