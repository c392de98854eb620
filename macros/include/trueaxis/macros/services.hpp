// What one method offers the others through the platform, so that no method
// includes another: each entry is filled by the method that owns it
// (its descriptor's provide(), method.hpp) when that method is built, and is
// nullptr otherwise; a user says so with kMethodNotBuilt.
//
//   calibrated_axes   M3's stored rigidity table: M1 levels on the calibrated
//                     axes with it (#508 level_axes = 1).
#pragma once

#include "trueaxis/macros/applied_records.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros {

struct Services {
  const StoredTable<RigidityTableRecord>* calibrated_axes = nullptr;
};

}  // namespace trueaxis::macros
