// The module's register map: the one table from which the variable numbers, the
// Modbus addresses (variable #N = holding registers 4N .. 4N+3), the JSON map
// (macros/register_map.json) and the human page (macros/REGISTER_MAP.md) come.
//
// It joins the platform's rows (platform_map.hpp) and the rows of every built
// method (method_list.hpp) into one sorted constexpr array and checks, at
// compile time, that
//  1. every source table is sorted and the joined table has no overlap;
//  2. every row is well formed (var_info.hpp map_is_well_formed);
//  3. each method's rows lie inside its blocks, and the platform's rows
//     outside every method block;
//  4. the result range #100..#199 is defined whole, so results are one
//     contiguous run of slots;
//  5. every macro has a unique number in 1..9999, outputs inside #100..#199
//     and inputs the map defines;
//  6. every status code is listed once, the platform's below 1000 and each
//     method's inside its block (method.hpp convention 2).
// A number not in the table is not defined: reading or writing it is refused.
// The checks take their lists as arguments so that tests can feed them bad
// ones (tests/portable/platform_map_test.cpp).
#pragma once

#include <array>
#include <cstddef>

#include "trueaxis/macros/method_list.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/selected_methods.hpp"
#include "trueaxis/macros/statuses.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

using BuiltMethods = MethodSet<SelectedMethods>;

struct RowSource {
  List<VarInfo> rows;
  const MethodBlock* block;  // nullptr: the platform's rows
};

namespace detail {

// The result variables #100..#199: named by the method that names them
// (interface version 1: M1's outputs), the rest one block.
constexpr std::size_t named_result_count() {
  std::size_t n = 0;
  for (const List<OutputInfo>& l : BuiltMethods::kNamedResults) n += l.size;
  return n;
}
inline constexpr std::size_t kNamedResultCount = named_result_count();

constexpr std::array<VarInfo, kNamedResultCount + 1> result_rows() {
  std::array<VarInfo, kNamedResultCount + 1> out{};
  std::size_t n = 0;
  for (const List<OutputInfo>& l : BuiltMethods::kNamedResults) {
    for (const OutputInfo& o : l) out[n++] = rows::result(o.number, 1, o.name, o.unit, o.description);
  }
  const auto first_free = static_cast<std::uint16_t>(var::kResultFirst + n);
  out[n] = rows::result(first_free, static_cast<std::uint16_t>(var::kResultLast - first_free + 1), "results", "",
                        "Results of the last macro; their meaning is per macro (see each macro's outputs).");
  return out;
}
inline constexpr auto kResultRows = result_rows();

inline constexpr std::size_t kSourceCount = 3 + BuiltMethods::kCount;

constexpr std::array<RowSource, kSourceCount> row_sources() {
  std::array<RowSource, kSourceCount> s{};
  s[0] = {list_of(kPlatformArgRows), nullptr};
  s[1] = {{kResultRows.data(), kResultRows.size()}, nullptr};
  s[2] = {list_of(kPlatformRows), nullptr};
  for (std::size_t i = 0; i < BuiltMethods::kCount; ++i) s[3 + i] = {BuiltMethods::kRows[i], &BuiltMethods::kBlocks[i]};
  return s;
}
inline constexpr auto kRowSources = row_sources();

// The slot of the first variable of source s's row r (convention 7 of
// platform_map.hpp: results by number, the rest in their source's order).
constexpr std::size_t first_slot(std::size_t s, std::size_t r) {
  const VarInfo& v = kRowSources[s].rows[r];
  if (s == 1) return kArgSlots + (v.number - var::kResultFirst);
  std::size_t slot = s == 0 ? 0 : s == 2 ? kArgSlots + kResultSlots : BuiltMethods::kSlotBase[s - 3];
  for (std::size_t k = 0; k < r; ++k) slot += kRowSources[s].rows[k].count;
  return slot;
}

constexpr std::size_t total_rows() {
  std::size_t n = 0;
  for (const RowSource& s : kRowSources) n += s.rows.size;
  return n;
}

constexpr bool inside(std::uint16_t first, std::uint16_t last, const VarInfo& v) {
  return v.number >= first && static_cast<std::uint32_t>(v.number) + v.count - 1 <= last;
}

constexpr bool overlaps_any_block(const VarInfo& v, const MethodBlock* blocks, std::size_t block_count) {
  for (std::size_t b = 0; b < block_count; ++b) {
    const std::uint32_t end = static_cast<std::uint32_t>(v.number) + v.count - 1;
    if (blocks[b].has_config() && end >= blocks[b].config_first && v.number <= blocks[b].config_last) return true;
    if (blocks[b].has_data() && end >= blocks[b].data_first && v.number <= blocks[b].data_last) return true;
  }
  return false;
}

}  // namespace detail

// Blocks inside #500..#999 (not #900, the unlock code) and #1000..#4999, in
// order, not overlapping; a method may have no block of either kind.
constexpr bool blocks_are_well_formed(const MethodBlock* blocks, std::size_t count) {
  std::uint16_t config_end = 0;  // the last number of the blocks so far
  std::uint16_t data_end = 0;
  for (std::size_t b = 0; b < count; ++b) {
    const MethodBlock& m = blocks[b];
    if (m.has_config()) {
      if (m.config_first > m.config_last) return false;
      if (m.config_first < var::kConfigFirst || m.config_last > var::kConfigLast) return false;
      if (m.config_first <= var::kUnlockCodeSetting && var::kUnlockCodeSetting <= m.config_last) return false;
      if (m.config_first <= config_end) return false;
      config_end = m.config_last;
    }
    if (m.has_data()) {
      if (m.data_first > m.data_last) return false;
      if (m.data_first < var::kDataFirst || m.data_last > var::kDataLast) return false;
      if (m.data_first <= data_end) return false;
      data_end = m.data_last;
    }
  }
  return true;
}

// A source is sorted and well formed; a method's rows lie inside its blocks;
// the platform's (block nullptr) outside every block.
constexpr bool source_is_well_formed(const RowSource& s, const MethodBlock* blocks, std::size_t block_count) {
  if (!map_is_well_formed(s.rows.data, s.rows.size)) return false;
  for (const VarInfo& v : s.rows) {
    if (s.block == nullptr) {
      if (detail::overlaps_any_block(v, blocks, block_count)) return false;
    } else if (!(s.block->has_config() && detail::inside(s.block->config_first, s.block->config_last, v)) &&
               !(s.block->has_data() && detail::inside(s.block->data_first, s.block->data_last, v))) {
      return false;
    }
  }
  return true;
}

namespace detail {

constexpr bool sources_are_well_formed() {
  if (!blocks_are_well_formed(BuiltMethods::kBlocks.data(), BuiltMethods::kCount)) return false;
  for (const RowSource& s : kRowSources) {
    if (!source_is_well_formed(s, BuiltMethods::kBlocks.data(), BuiltMethods::kCount)) return false;
  }
  return true;
}
static_assert(sources_are_well_formed(),
              "a row source is unsorted or malformed, a block overlaps another or #900, a method row lies "
              "outside its block, or a platform row lies inside a method block");

struct JoinedRows {
  std::array<VarInfo, total_rows()> rows{};
  std::array<std::size_t, total_rows()> first_slot{};
};

constexpr JoinedRows joined_rows() {
  JoinedRows out{};
  std::size_t n = 0;
  for (std::size_t s = 0; s < kSourceCount; ++s) {
    for (std::size_t r = 0; r < kRowSources[s].rows.size; ++r) {
      out.rows[n] = kRowSources[s].rows[r];
      out.first_slot[n] = first_slot(s, r);
      ++n;
    }
  }
  for (std::size_t i = 1; i < n; ++i) {  // insertion sort: a few hundred rows, once, at compile time
    for (std::size_t j = i; j > 0 && out.rows[j - 1].number > out.rows[j].number; --j) {
      const VarInfo t = out.rows[j];
      out.rows[j] = out.rows[j - 1];
      out.rows[j - 1] = t;
      const std::size_t u = out.first_slot[j];
      out.first_slot[j] = out.first_slot[j - 1];
      out.first_slot[j - 1] = u;
    }
  }
  return out;
}
inline constexpr JoinedRows kJoined = joined_rows();

}  // namespace detail

inline constexpr const std::array<VarInfo, detail::total_rows()>& kRegisterMap = detail::kJoined.rows;
inline constexpr std::size_t kRegisterMapSize = kRegisterMap.size();
static_assert(map_is_well_formed(kRegisterMap.data(), kRegisterMapSize),
              "kRegisterMap: two sources define overlapping numbers");

// Every variable of the map, blocks expanded: the platform's slots and every
// built method's.
inline constexpr std::size_t kVariableCount = BuiltMethods::kSlotBase[BuiltMethods::kCount];
static_assert(variable_count(kRegisterMap.data(), kRegisterMapSize) == kVariableCount);

constexpr const VarInfo* find_var(std::uint16_t number) {
  return find_in(kRegisterMap.data(), kRegisterMapSize, number);
}

// Position of #number in the module's array of every variable
// (platform_map.hpp convention 7); kVariableCount when the number is not
// defined. A binary search plus a table look-up.
constexpr std::size_t slot_of(std::uint16_t number) {
  const VarInfo* v = find_var(number);
  if (v == nullptr) return kVariableCount;
  return detail::kJoined.first_slot[static_cast<std::size_t>(v - kRegisterMap.data())] + (number - v->number);
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

// Results are one contiguous run of slots (convention 4), and the platform's
// slots are where platform_slot() says.
static_assert(slot_of(var::kResultLast) - slot_of(var::kResultFirst) == kResultSlots - 1);
static_assert(slot_of(var::kResultFirst) == platform_slot(var::kResultFirst) &&
              slot_of(var::kFailedUnlocks) == platform_slot(var::kFailedUnlocks) &&
              slot_of(var::kG59 + 5) == platform_slot(var::kG59 + 5));
static_assert(is_defined(var::kCmd) && is_defined(var::kStepCount));
static_assert(is_defined(var::kG59 + 5) && !is_defined(var::kG59 + 6));
static_assert(!is_defined(10), "#10 (letter G) is not an argument");

// Macro numbers unique and in 1..9999, a handler, outputs inside #100..#199,
// inputs defined in the map.
constexpr bool macros_are_well_formed(const List<MacroInfo>* sources, std::size_t count) {
  for (std::size_t a = 0; a < count; ++a) {
    for (const MacroInfo& m : sources[a]) {
      if (m.number == 0 || m.number > 9999 || m.run == nullptr) return false;
      for (std::size_t b = 0; b < count; ++b) {
        for (const MacroInfo& other : sources[b]) {
          if (&other != &m && other.number == m.number) return false;
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
static_assert(macros_are_well_formed(BuiltMethods::kMacros.data(), BuiltMethods::kCount),
              "a macro number repeats or is out of 1..9999, an output lies outside #100..#199, "
              "or an input is not defined in the map");

// A method's session (its clear, add, compute and compute_also) and its check
// name macros of that method's own kMacros (0: none), so that a descriptor that
// names another method's macro, or a number it does not define, does not compile.
constexpr bool is_own_macro(const List<MacroInfo>& own, std::uint16_t number) {
  if (number == 0) return true;
  for (const MacroInfo& m : own) {
    if (m.number == number) return true;
  }
  return false;
}
constexpr bool sessions_name_own_macros() {
  for (std::size_t i = 0; i < BuiltMethods::kCount; ++i) {
    const SessionInfo& s = BuiltMethods::kSessions[i];
    const List<MacroInfo>& own = BuiltMethods::kMacros[i];
    if (!is_own_macro(own, s.clear) || !is_own_macro(own, s.add) || !is_own_macro(own, s.compute) ||
        !is_own_macro(own, s.compute_also) || !is_own_macro(own, BuiltMethods::kChecks[i].macro)) {
      return false;
    }
  }
  return true;
}
static_assert(sessions_name_own_macros(), "a method's session or check names a macro that is not its own");

// The built macro of that number and the index of its method, or nullptr.
struct MacroEntry {
  const MacroInfo* info;
  std::size_t method;
};
constexpr MacroEntry find_macro_entry(std::uint16_t number) {
  for (std::size_t i = 0; i < BuiltMethods::kCount; ++i) {
    for (const MacroInfo& m : BuiltMethods::kMacros[i]) {
      if (m.number == number) return {&m, i};
    }
  }
  return {nullptr, 0};
}
constexpr const MacroInfo* find_macro(std::uint16_t number) { return find_macro_entry(number).info; }

// True when a built method has macro `number`.
constexpr bool is_macro(std::uint16_t number) {
  for (const List<MacroInfo>& l : BuiltMethods::kMacros) {
    for (const MacroInfo& m : l) {
      if (m.number == number) return true;
    }
  }
  return false;
}

// Status codes (convention 6): the platform's and each method's, joined.
constexpr bool statuses_are_well_formed(const List<core::StatusInfo>* lists, const StatusBlock* blocks,
                                        std::size_t count, List<core::StatusInfo> platform) {
  for (const core::StatusInfo& s : platform) {
    if (static_cast<unsigned>(s.status) > kPlatformStatusLast) return false;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (blocks[i].first <= kPlatformStatusLast || blocks[i].first > blocks[i].last) return false;
    for (std::size_t j = 0; j < i; ++j) {
      if (blocks[i].first <= blocks[j].last && blocks[j].first <= blocks[i].last) return false;
    }
    for (const core::StatusInfo& s : lists[i]) {
      const auto code = static_cast<unsigned>(s.status);
      const bool in_block = code >= blocks[i].first && code <= blocks[i].last;
      const bool legacy = code > 0 && code <= kLegacyStatusLast;
      if (!in_block && !legacy) return false;
    }
  }
  // Unique over everything.
  auto repeats = [&](core::Status code, const core::StatusInfo* self) {
    for (const core::StatusInfo& s : platform) {
      if (&s != self && s.status == code) return true;
    }
    for (std::size_t i = 0; i < count; ++i) {
      for (const core::StatusInfo& s : lists[i]) {
        if (&s != self && s.status == code) return true;
      }
    }
    return false;
  };
  for (const core::StatusInfo& s : platform) {
    if (repeats(s.status, &s)) return false;
  }
  for (std::size_t i = 0; i < count; ++i) {
    for (const core::StatusInfo& s : lists[i]) {
      if (repeats(s.status, &s)) return false;
    }
  }
  return true;
}
static_assert(statuses_are_well_formed(BuiltMethods::kStatuses.data(), BuiltMethods::kStatusBlocks.data(),
                                       BuiltMethods::kCount, list_of(kPlatformStatuses)),
              "a status code repeats, a platform code is 1000 or above, a method's block overlaps another or "
              "the platform's, or a method's code lies outside its block");

namespace detail {
constexpr std::size_t status_count() {
  std::size_t n = sizeof kPlatformStatuses / sizeof kPlatformStatuses[0];
  for (const List<core::StatusInfo>& l : BuiltMethods::kStatuses) n += l.size;
  return n;
}
constexpr std::array<core::StatusInfo, status_count()> joined_statuses() {
  std::array<core::StatusInfo, status_count()> out{};
  std::size_t n = 0;
  for (const core::StatusInfo& s : kPlatformStatuses) out[n++] = s;
  for (const List<core::StatusInfo>& l : BuiltMethods::kStatuses) {
    for (const core::StatusInfo& s : l) out[n++] = s;
  }
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t j = i; j > 0 && out[j - 1].status > out[j].status; --j) {
      const core::StatusInfo t = out[j];
      out[j] = out[j - 1];
      out[j - 1] = t;
    }
  }
  return out;
}
}  // namespace detail

// Every status of this module with its name and message, sorted by number.
inline constexpr auto kStatusTable = detail::joined_statuses();

// The operator message of a status; "Unknown status." for a number not in the table.
constexpr const char* status_message(core::Status s) {
  for (const core::StatusInfo& info : kStatusTable) {
    if (info.status == s) return info.message;
  }
  return "Unknown status.";
}

constexpr const char* status_name(core::Status s) {
  for (const core::StatusInfo& info : kStatusTable) {
    if (info.status == s) return info.name;
  }
  return "unknown";
}

}  // namespace trueaxis::macros
