// The one list of methods: the state each keeps in the module (its streaming
// session) and the macros each brings. The register-map rows and blocks are
// joined in register_map.hpp.
//
// Adding a method touches its own files (map, handlers, state), one member of
// Methods, one entry of kMacroSources, one of kRowSources and kMethodBlocks
// (register_map.hpp), and CMake.
//
// Compile-time checks: macro numbers unique and in 1..9999; every output inside
// #100..#199 and every input defined in the map.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/level/level_macros.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::macros {

// Owned by the Module; each handler reaches its own member through
// MacroContext::methods().
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

namespace detail {
constexpr bool macros_are_well_formed() {
  for (const MacroSource& s : kMacroSources) {
    for (std::size_t i = 0; i < s.count; ++i) {
      const MacroInfo& m = s.macros[i];
      if (m.number == 0 || m.number > 9999 || find_macro(m.number) != &m || m.run == nullptr) return false;
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
static_assert(macros_are_well_formed(),
              "a macro number repeats or is out of 1..9999, an output lies outside #100..#199, "
              "or an input is not defined in the map");
}  // namespace detail

}  // namespace trueaxis::macros
