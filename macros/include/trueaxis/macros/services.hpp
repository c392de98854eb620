// What one method offers the others through the platform, so that no method
// includes another: each entry is filled by the method that owns it
// (its descriptor's provide(), method.hpp) when that method is built, and is
// nullptr otherwise; a user says so with kMethodNotBuilt.
//
//   calibrated_axes   M3's stored rigidity table: M1 levels on the calibrated
//                     axes with it (#508 level_axes = 1).
#pragma once

#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros {

// The record of M3's table (key 3), named here because M1 reads the table too.
struct RigidityTableRecord {
  using Type = core::RigidityTable;
  static constexpr RecordSpec kRecord{3, 1, 4096, "rigidity_table"};
  static core::Status decode(const std::uint8_t* bytes, std::size_t length, Type& out) {
    return core::decode_rigidity_table(bytes, length, out);
  }
  static std::size_t encode(const Type& t, std::uint8_t* out, std::size_t capacity) {
    return core::encode_rigidity_table(t, out, capacity);
  }
  static std::size_t bytes(const Type& t) { return core::rigidity_table_bytes(t.pose_count); }
};
static_assert(core::kRigidityTableMaxBytes <= RigidityTableRecord::kRecord.capacity_bytes);

struct Services {
  const StoredTable<RigidityTableRecord>* calibrated_axes = nullptr;
};

}  // namespace trueaxis::macros
