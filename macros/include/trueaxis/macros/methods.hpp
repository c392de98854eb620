// The one list of methods. Adding a method touches its own files (its map,
// its handlers and state), one entry in each list below, and CMake.
//
//  - kMethodBlocks:     its blocks of #500..#999 and #1000..#4999 (replacing the
//                       reservation), published in the JSON map;
//  - kMethodRowSources: its rows, joined into the register map
//                       (register_map.hpp checks them against its blocks);
//  - Methods:           its state (streaming session, live tables), owned by
//                       the Module, reached by its handlers through
//                       MacroContext::methods();
//  - kMacroSources:     its macros (register_map.hpp checks numbers, inputs
//                       and outputs at compile time).
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/level/level_macros.hpp"
#include "trueaxis/macros/level/level_map.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

// Every method's blocks, in number order. Blocks of methods not built yet are
// reserved so that the published map does not move when they land.
inline constexpr MethodBlock kMethodBlocks[] = {
    level::kBlock,
    {"rigidity", 600, 699, 2000, 2999},
    {"gantry", 700, 799, 3000, 3999},
    {"spindle", 800, 899, 4000, 4999},
};

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
};

struct Methods {
  level::State level;
};

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
