// The one list of methods. Adding a method touches its own files (its map,
// its handlers and state), one entry in each list below, and CMake.
//
//  - kMethodBlocks:     its blocks of #500..#999 and #1000..#4999 (replacing the
//                       reservation), published in the JSON map;
//  - kMethodRowSources: its rows, joined into the register map
//                       (register_map.hpp checks them against its blocks);
//  - Methods:           its state (streaming session, live tables), owned by
//                       the Module, reached by its handlers through
//                       MacroContext::methods(); on_table_loaded,
//                       on_table_committed and kTableRecords when it
//                       stores a table;
//  - kMacroSources:     its macros (register_map.hpp checks numbers, inputs
//                       and outputs at compile time).
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/gantry/gantry_macros.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/level/level_macros.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/rigidity/rigidity_macros.hpp"
#include "trueaxis/macros/rigidity/rigidity_map.hpp"
#include "trueaxis/macros/spindle/spindle_macros.hpp"
#include "trueaxis/macros/spindle/spindle_map.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

// Every method's blocks, in number order. Blocks of methods not built yet are
// reserved so that the published map does not move when they land.
inline constexpr MethodBlock kMethodBlocks[] = {
    level::kBlock,
    rigidity::kBlock,
    gantry::kBlock,
    spindle::kBlock,
};

// The names interface version 1 gave the result variables #100..#116: M1's
// outputs. The variable list keeps them (the JSON map only grows); every other
// macro's meaning of #100..#199 is in its own outputs.
inline constexpr const auto& kNamedResults = level::kLevelOutputs;

struct RowSource {
  const VarInfo* rows;
  std::size_t count;
  const MethodBlock* block;  // nullptr: the platform's rows
};

template <std::size_t N>
constexpr RowSource row_source(const VarInfo (&t)[N], const MethodBlock* block) {
  return {t, N, block};
}

inline constexpr RowSource kMethodRowSources[] = {
    row_source(level::kRows, &level::kBlock),
    row_source(rigidity::kRows, &rigidity::kBlock),
    row_source(gantry::kRows, &gantry::kBlock),
    row_source(spindle::kRows, &spindle::kBlock),
};

struct Methods {
  level::State level;
  rigidity::State rigidity;
  gantry::State gantry;
  spindle::State spindle;
};

// A method's table record loaded at start(): its owner decodes it and makes
// it the live table. Keys without a table do nothing.
inline void on_table_loaded(Methods& methods, RecordKey key, const std::uint8_t* bytes, std::size_t length) {
  if (key == RecordKey::kRigidityTable) rigidity::on_record(methods.rigidity, bytes, length);
  if (key == RecordKey::kGantryFrames) gantry::on_record(methods.gantry, bytes, length);
  if (key == RecordKey::kSpindleModel) spindle::on_record(methods.spindle, bytes, length);
}

// A method's table record failed its CRC at start() (KeyedStore::damaged): its
// owner has no live table and says kTableDamaged, not kNoTable, to a query.
inline void on_table_damaged(Methods& methods, RecordKey key) {
  if (key == RecordKey::kRigidityTable) rigidity::on_damaged(methods.rigidity);
  if (key == RecordKey::kGantryFrames) gantry::on_damaged(methods.gantry);
  if (key == RecordKey::kSpindleModel) spindle::on_damaged(methods.spindle);
}

// A table a macro staged has just been committed: its owner makes the table it
// encoded the live one (bit for bit what decoding the record gives, without
// the cost of decoding it inside the commit's step).
inline void on_table_committed(Methods& methods, RecordKey key) {
  if (key == RecordKey::kRigidityTable) rigidity::on_committed(methods.rigidity);
  if (key == RecordKey::kGantryFrames) gantry::on_committed(methods.gantry);
  if (key == RecordKey::kSpindleModel) spindle::on_committed(methods.spindle);
}

// The table records, in the order start() loads them.
inline constexpr RecordKey kTableRecords[] = {RecordKey::kRigidityTable, RecordKey::kGantryFrames,
                                              RecordKey::kSpindleModel};

struct MacroSource {
  const MacroInfo* macros;
  std::size_t count;
  const char* method;
};

template <std::size_t N>
constexpr MacroSource macro_source(const MacroInfo (&t)[N], const char* method) {
  return {t, N, method};
}

inline constexpr MacroSource kMacroSources[] = {
    macro_source(level::kMacros, "level"),
    macro_source(rigidity::kMacros, "rigidity"),
    macro_source(gantry::kMacros, "gantry"),
    macro_source(spindle::kMacros, "spindle"),
};

constexpr const MacroInfo* find_macro(std::uint16_t number) {
  for (const MacroSource& s : kMacroSources) {
    for (std::size_t i = 0; i < s.count; ++i) {
      if (s.macros[i].number == number) return &s.macros[i];
    }
  }
  return nullptr;
}

}  // namespace trueaxis::macros
