// Reading and writing numbered variables, whole or not at all.
//
// Contract
//  1. read fills out[0..count) with #first .. #first+count-1, or returns the first
//     fault and leaves out untouched.
//  2. write checks every variable and value first, then applies all of them; on
//     any fault it changes nothing (no variable, no stored table) and returns it.
//  3. note_fault records a fault found before the request reached the variables
//     (a misaligned register range), so #9007 tells it like any other.
//  4. The public methods check the arguments every implementation shares and
//     forward to the private virtuals. No allocation, no exceptions.
//  5. Every request names its client (var_info.hpp ClientId; kLocalClient when
//     the caller names none): the module grants the macro interface to one
//     client at a time (module.hpp contract 8); other implementations may
//     ignore it.
#pragma once

#include <cstdint>

#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

class VariableAccess {
 public:
  VariableAccess(const VariableAccess&) = delete;
  VariableAccess& operator=(const VariableAccess&) = delete;

  [[nodiscard]] AccessFault read(std::uint16_t first, std::uint16_t count, double* out,
                                 ClientId client = kLocalClient) {
    if (count == 0 || static_cast<std::uint32_t>(first) + count - 1 > kMaxVariableNumber) {
      return fault(AccessFault::kUndefined);
    }
    return do_read(first, count, out, client);
  }

  [[nodiscard]] AccessFault write(std::uint16_t first, std::uint16_t count, const double* values,
                                  ClientId client = kLocalClient) {
    if (count == 0 || static_cast<std::uint32_t>(first) + count - 1 > kMaxVariableNumber) {
      return fault(AccessFault::kUndefined);
    }
    return do_write(first, count, values, client);
  }

  AccessFault fault(AccessFault f) {
    if (f != AccessFault::kNone) do_note_fault(f);
    return f;
  }

 protected:
  VariableAccess() = default;
  ~VariableAccess() = default;

 private:
  virtual AccessFault do_read(std::uint16_t first, std::uint16_t count, double* out, ClientId client) = 0;
  virtual AccessFault do_write(std::uint16_t first, std::uint16_t count, const double* values,
                               ClientId client) = 0;
  virtual void do_note_fault(AccessFault f) = 0;
};

}  // namespace trueaxis::macros
