// The records of the models a machine applies outside the method that
// measured them: M3's rigidity table (M1 levels on it, services.hpp; the
// LinuxCNC kinematics compensate with it) and M4's spindle model (the
// kinematics correct the tool tip with it). Named in the platform, beside
// their codecs in firmware_core, so that their readers include no method.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/core/rigidity_codec.hpp"
#include "trueaxis/core/rigidity_table.hpp"
#include "trueaxis/core/spindle_correction.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros {

// The encoded length of M3's table (its poses').
inline std::size_t rigidity_record_bytes(const core::RigidityTable& t) {
  return core::rigidity_table_bytes(t.pose_count);
}

// The record of M3's table (key 3).
struct RigidityTableRecord : TableCodec<core::RigidityTable, &core::decode_rigidity_table,
                                        &core::encode_rigidity_table, &rigidity_record_bytes> {
  static constexpr RecordSpec kRecord{3, 1, 4096, "rigidity_table"};
  // stored_table.hpp contract 4: applied only under the home it was measured under.
  static std::uint16_t home_of(const core::RigidityTable& t) { return t.home_identity; }
};
static_assert(core::kRigidityTableMaxBytes <= RigidityTableRecord::kRecord.capacity_bytes);

// The record of M4's stored model (key 5).
struct SpindleModelRecord : TableCodec<core::SpindleModel, &core::decode_spindle_model, &core::encode_spindle_model,
                                       core::kSpindleModelBytes> {
  static constexpr RecordSpec kRecord{5, 1, 2048, "spindle_model"};
};
static_assert(core::kSpindleModelBytes <= SpindleModelRecord::kRecord.capacity_bytes, "the model must fit its record");

}  // namespace trueaxis::macros
