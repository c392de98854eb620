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

// The encoded length of M3's table (its poses').
inline std::size_t rigidity_record_bytes(const core::RigidityTable& t) {
  return core::rigidity_table_bytes(t.pose_count);
}

// The record of M3's table (key 3), named here because M1 reads the table too.
struct RigidityTableRecord : TableCodec<core::RigidityTable, &core::decode_rigidity_table,
                                        &core::encode_rigidity_table, &rigidity_record_bytes> {
  static constexpr RecordSpec kRecord{3, 1, 4096, "rigidity_table"};
  // stored_table.hpp contract 4: applied only under the home it was measured under.
  static std::uint16_t home_of(const core::RigidityTable& t) { return t.home_identity; }
};
static_assert(core::kRigidityTableMaxBytes <= RigidityTableRecord::kRecord.capacity_bytes);

struct Services {
  const StoredTable<RigidityTableRecord>* calibrated_axes = nullptr;
};

}  // namespace trueaxis::macros
