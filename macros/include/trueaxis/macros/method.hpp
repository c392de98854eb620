// A method is one type: the descriptor every method exports, and the pieces it
// is made of. The module, the register map, the record list, the status table,
// the JSON map and the calibrate command are all folds over the list of
// descriptors (method_list.hpp); nothing else lists methods.
//
// The descriptor (methods/<name>/module/include/trueaxis/macros/<name>/method.hpp):
//
//   struct Method : Shape {               Shape: kRows, Session, Work (method_context.hpp)
//     static constexpr const char* kName;            "level": its name in TRUEAXIS_METHODS
//     static constexpr MethodBlock kBlock;           its blocks of #500..#999 and #1000..#4999
//     static constexpr StatusBlock kStatusBlock;     its reserved block of status codes
//     static constexpr List<core::StatusInfo> kStatuses;  the codes it owns, with names and messages
//     static constexpr List<MacroInfo> kMacros;      its macros (handlers, inputs, outputs)
//     static constexpr SessionInfo kSession;         its calibration session, for the map's readers
//     using State = ...;                             what it keeps between macros (the module holds it)
//     using Table = ...;                             its stored table's record (stored_table.hpp), or NoTable
//     static StoredTable<Table>& table(State&);      where State keeps that table (only with a Table)
//     static void provide(State&, Services&);        optional: what it offers other methods (services.hpp)
//     static constexpr List<OutputInfo> kNamedResults;  optional: names of #100.. (interface version 1, M1 only)
//     static constexpr List<GateInfo> kGates;        optional: its gates, for the map (gates.hpp)
//     static constexpr CheckInfo kCheck;             optional: its check macro and figures (check.hpp)
//     static constexpr List<CheckFigureInfo> kLogFigures;  optional: what its calibrations log
//                                                    (measuring_log.hpp); a method with them logs its
//                                                    builds, stores and checks
//   };
//
// Conventions
//  1. A method's sources include the platform (macros/include) and firmware_core,
//     never another method: its library's include path holds no other method's
//     headers. Its handlers receive its own State (macro_info.hpp contract 1).
//  2. Status codes: the platform's are below 1000 (statuses.hpp); a method's new
//     codes lie in its kStatusBlock (1000 and above). Codes that interface
//     versions before the method descriptors had already published below 1000
//     keep their numbers and are listed by the method that owns them
//     (kLegacyStatusLast). The joined table is checked at compile time: sorted,
//     unique, each code inside its owner's block.
//  3. Only one macro runs at a time, so the calibration sessions share one
//     arena and the computations (builders, the last result, start()'s decode
//     scratch) another (arena.hpp, method_context.hpp contract 4).
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/check.hpp"
#include "trueaxis/macros/gates.hpp"
#include "trueaxis/macros/list.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

// Convention 2.
struct StatusBlock {
  std::uint16_t first;
  std::uint16_t last;
};
inline constexpr std::uint16_t kPlatformStatusLast = 999;
inline constexpr std::uint16_t kLegacyStatusLast = 222;

// A limit of a session the map states beside its capacity: `group` names an
// object of the method's entry in the JSON map ("" for the entry itself).
struct SessionLimit {
  const char* group;
  const char* name;
  std::size_t value;
};

// A calibration session, for the map's readers: how many samples it holds,
// what one sample is, and the macros that clear it, add to it and compute
// from it (compute_also: a second macro that computes from it, 0 none).
// capacity 0: the method has none. The module holds its macro interface for
// the client whose session is open, from its clear to its compute, its
// compute_also or its check (module.hpp contract 8).
struct SessionInfo {
  std::size_t capacity;
  const char* capacity_unit;  // what capacity counts ("samples", "distinct angles per ball")
  const char* sample;
  std::uint16_t clear, add, compute;
  List<SessionLimit> limits;
  std::uint16_t compute_also = 0;
};
inline constexpr SessionInfo kNoSession{0, "", "", 0, 0, 0, {}};

// A method that stores no table.
struct NoTable {};

}  // namespace trueaxis::macros
