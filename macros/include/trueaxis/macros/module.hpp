// The trueaxis module as a controller sees it: the variables of the register map,
// the handshake, the macros, and the persistent configuration.
//
// Contract
//  1. Owned by main, handed a NvStorage and a Clock; holds every variable in a
//     fixed array. No allocation, no exceptions, no clock but the one handed in.
//  2. start() loads the persistent variables (the newer valid copy of the two
//     kept in storage, see persistent_store.hpp), or the map's defaults when
//     there is none. Call it once before anything else.
//  3. Writing a macro number to #9000 makes the module busy (status 1); the macro
//     runs at the next step(), which the controller calls from its background
//     task. Then status is 2 (done) or 3 (error) with the code in #9002, and
//     #9003 has grown by one. Arguments #1..#26 and the point list are cleared to
//     0 after every macro.
//  4. While busy, writes to #9000 and to any macro input (arguments, point list,
//     work offsets, configuration) are refused with kBusy.
//  5. Writes to persistent variables reach storage before they reach the
//     variables; a storage failure refuses the write and changes nothing.
#pragma once

#include <cstdint>

#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/macro_table.hpp"
#include "trueaxis/macros/persistent_store.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/variable_access.hpp"

namespace trueaxis::macros {

class Module final : public VariableAccess {
 public:
  Module(hal::NvStorage& storage, hal::Clock& clock);

  // kOk, or kStorageFailure when storage could not be read (defaults are used).
  [[nodiscard]] core::Status start();

  // Runs the pending macro, if any, to completion.
  void step();

  bool busy() const { return pending_ != 0; }
  bool unlocked() const { return unlocked_; }

  // The value of #number; 0 for a number the map does not define.
  double value(std::uint16_t number) const;

 private:
  AccessFault do_read(std::uint16_t first, std::uint16_t count, double* out) override;
  AccessFault do_write(std::uint16_t first, std::uint16_t count, const double* values) override;
  void do_note_fault(AccessFault f) override;

  AccessFault check_write(std::uint16_t number, double value) const;
  void set(std::uint16_t number, double value);
  void finish(core::Status status, std::uint64_t started_us);

  PersistentStore store_;
  hal::Clock& clock_;
  double values_[kVariableCount] = {};
  double staged_[kResultSlots] = {};
  PersistentEntry entries_[kPersistentCount] = {};
  std::uint16_t pending_ = 0;
  bool unlocked_ = false;
};

}  // namespace trueaxis::macros
