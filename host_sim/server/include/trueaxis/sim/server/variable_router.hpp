// The variables trueaxis-sim serves: the module's map plus the simulator's own
// #12000..#12056, behind one VariableAccess.
//
// Contract
//  1. A range wholly inside #12000..#12056 (simvar::kFirst..kLast) goes to the simulator; a range that
//     touches none of them goes to the module; a range spanning both is refused
//     as kUndefined (no variable next to the simulator's block is defined, so a
//     whole-or-nothing access cannot succeed there anyway).
//  2. Every fault, wherever it was found, is noted in the module (#9007).
#pragma once

#include <cstdint>

#include "trueaxis/macros/variable_access.hpp"
#include "trueaxis/sim/server/sim_map.hpp"

namespace trueaxis::sim {

class VariableRouter final : public macros::VariableAccess {
 public:
  VariableRouter(macros::VariableAccess& module, macros::VariableAccess& simulator)
      : module_(module), simulator_(simulator) {}

 private:
  enum class Route : std::uint8_t { kModule, kSimulator, kSpanning };

  static Route route(std::uint16_t first, std::uint16_t count) {
    const std::uint32_t last = static_cast<std::uint32_t>(first) + count - 1;
    if (last < simvar::kFirst || first > simvar::kLast) return Route::kModule;
    if (first >= simvar::kFirst && last <= simvar::kLast) return Route::kSimulator;
    return Route::kSpanning;
  }

  macros::AccessFault do_read(std::uint16_t first, std::uint16_t count, double* out,
                              macros::ClientId client) override {
    switch (route(first, count)) {
      case Route::kModule: return module_.read(first, count, out, client);
      case Route::kSimulator: return fault(simulator_.read(first, count, out, client));
      case Route::kSpanning: break;
    }
    return fault(macros::AccessFault::kUndefined);
  }

  macros::AccessFault do_write(std::uint16_t first, std::uint16_t count, const double* values,
                               macros::ClientId client) override {
    switch (route(first, count)) {
      case Route::kModule: return module_.write(first, count, values, client);
      case Route::kSimulator: return fault(simulator_.write(first, count, values, client));
      case Route::kSpanning: break;
    }
    return fault(macros::AccessFault::kUndefined);
  }

  void do_note_fault(macros::AccessFault f) override { module_.fault(f); }

  macros::VariableAccess& module_;
  macros::VariableAccess& simulator_;
};

}  // namespace trueaxis::sim
