// What the platform's tests take from whichever methods a module set has, so
// that they run in every set: a configuration variable of one of the built
// methods (the platform's own, #900, reads 0), and the first table record.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"

namespace trueaxis::test {

// The first configuration variable of the map other than #900, and two values
// it takes: `changed` differs from its default, `other` from `changed`.
struct ConfigVariable {
  std::uint16_t number = 0;
  double default_value = 0.0;
  double changed = 0.0;
  double other = 0.0;
};

inline ConfigVariable config_variable() {
  for (const macros::VarInfo& v : macros::kRegisterMap) {
    if (v.access != macros::Access::kConfig || v.number == macros::var::kUnlockCodeSetting) continue;
    ConfigVariable c;
    c.number = v.number;
    c.default_value = v.default_value;
    c.changed = v.default_value == v.min ? v.max : v.min;
    c.other = c.changed == v.min ? v.max : v.min;
    return c;
  }
  return {};
}

// The first table record of the built set (key 0 when no built method
// stores a table) and how many doubles it holds, at most `limit`.
struct TableRecord {
  std::uint8_t key = 0;
  std::size_t values = 0;
};

inline TableRecord table_record(std::size_t limit) {
  for (const macros::RecordSpec& s : macros::kRecordSpecs) {
    if (s.key == macros::record_key(macros::RecordKey::kConfig) ||
        s.key == macros::record_key(macros::RecordKey::kWorkOffsets)) {
      continue;
    }
    const std::size_t n = s.capacity_bytes / 8;
    return {s.key, n < limit ? n : limit};
  }
  return {};
}

// Bytes [first, end) of a record's two slots in the storage layout.
struct Region {
  std::size_t first = 0;
  std::size_t end = 0;
};
inline Region region_of(std::uint8_t key) {
  std::size_t at = 0;
  for (const macros::RecordSpec& spec : macros::kRecordSpecs) {
    const std::size_t n = 2 * macros::KeyedStore::slot_bytes(spec);
    if (spec.key == key) return {at, at + n};
    at += n;
  }
  return {};
}

}  // namespace trueaxis::test
