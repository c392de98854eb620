// The canary method as one type (macros/include/trueaxis/macros/method.hpp).
#pragma once

#include "trueaxis/macros/canary/canary_macros.hpp"
#include "trueaxis/macros/method.hpp"

namespace trueaxis::macros::canary {

struct Method : Shape {
  static constexpr const char* kName = "canary";
  static constexpr MethodBlock kBlock = canary::kBlock;
  static constexpr StatusBlock kStatusBlock{1900, 1999};
  static constexpr List<core::StatusInfo> kStatuses = list_of(canary::kStatuses);
  static constexpr List<MacroInfo> kMacros = list_of(canary::kMacros);
  static constexpr SessionInfo kSession{4, "values", "A (#1)", 9851, 9852, 9853, {}};
  using State = canary::State;
  using Table = SumRecord;
  static StoredTable<Table>& table(State& s) { return s.table; }
};

}  // namespace trueaxis::macros::canary
