// Holding registers <-> variables (docs/INTERFACE.md, "Encoding"). Knows nothing of
// sockets or frames: a Modbus server decodes a request, calls these, and turns a
// fault into modbus_exception(fault).
//
// Contract
//  1. Variable #N is the four registers 4N .. 4N+3; register 4N holds bits 63..48
//     of the IEEE-754 binary64, register 4N+3 bits 15..0.
//  2. A range that does not start at 4N or does not cover whole variables is
//     kMisaligned; so is a read of more than kMaxVariablesPerRead variables or a
//     write of more than kMaxVariablesPerWrite (Modbus caps a read at 125 and a
//     write at 123 registers; FC23 writes at most 121).
//  3. Reads and writes are whole or nothing (variable_access.hpp).
#pragma once

#include <cstdint>
#include <cstring>

#include "trueaxis/macros/variable_access.hpp"

namespace trueaxis::modbus {

// The variable interface this room depends on, and nothing else of the module.
using macros::AccessFault;
using macros::ClientId;
using macros::kLocalClient;
using macros::ModbusException;
using macros::VariableAccess;
using macros::modbus_exception;

inline constexpr std::uint16_t kRegistersPerVariable = 4;
inline constexpr std::uint16_t kMaxVariablesPerRead = 31;   // 124 registers
inline constexpr std::uint16_t kMaxVariablesPerWrite = 30;  // 120 registers

constexpr std::uint32_t register_of(std::uint16_t variable) {
  return static_cast<std::uint32_t>(variable) * kRegistersPerVariable;
}

inline void encode_double(double value, std::uint16_t* words) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) {
    words[i] = static_cast<std::uint16_t>(bits >> (48 - 16 * i));
  }
}

inline double decode_double(const std::uint16_t* words) {
  std::uint64_t bits = 0;
  for (int i = 0; i < 4; ++i) bits = (bits << 16) | words[i];
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

[[nodiscard]] AccessFault read_registers(VariableAccess& vars, std::uint16_t address, std::uint16_t count,
                                         std::uint16_t* words_out, ClientId client = kLocalClient);

[[nodiscard]] AccessFault write_registers(VariableAccess& vars, std::uint16_t address, std::uint16_t count,
                                          const std::uint16_t* words, ClientId client = kLocalClient);

}  // namespace trueaxis::modbus
