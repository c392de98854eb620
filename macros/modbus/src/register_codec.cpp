#include "trueaxis/modbus/register_codec.hpp"

namespace trueaxis::modbus {

namespace {

// Turns a register range into a variable range; false when it is not whole
// variables or is longer than one request may be.
bool to_variables(std::uint16_t address, std::uint16_t count, std::uint16_t max_variables, std::uint16_t& first,
                  std::uint16_t& n) {
  if (count == 0 || address % kRegistersPerVariable != 0 || count % kRegistersPerVariable != 0) return false;
  n = static_cast<std::uint16_t>(count / kRegistersPerVariable);
  if (n > max_variables) return false;
  first = static_cast<std::uint16_t>(address / kRegistersPerVariable);
  return true;
}

}  // namespace

AccessFault read_registers(VariableAccess& vars, std::uint16_t address, std::uint16_t count,
                           std::uint16_t* words_out, ClientId client) {
  std::uint16_t first = 0;
  std::uint16_t n = 0;
  if (!to_variables(address, count, kMaxVariablesPerRead, first, n)) return vars.fault(AccessFault::kMisaligned);
  double values[kMaxVariablesPerRead];
  const AccessFault f = vars.read(first, n, values, client);
  if (f != AccessFault::kNone) return f;
  for (std::uint16_t i = 0; i < n; ++i) encode_double(values[i], words_out + kRegistersPerVariable * i);
  return AccessFault::kNone;
}

AccessFault write_registers(VariableAccess& vars, std::uint16_t address, std::uint16_t count,
                            const std::uint16_t* words, ClientId client) {
  std::uint16_t first = 0;
  std::uint16_t n = 0;
  if (!to_variables(address, count, kMaxVariablesPerWrite, first, n)) return vars.fault(AccessFault::kMisaligned);
  double values[kMaxVariablesPerWrite];
  for (std::uint16_t i = 0; i < n; ++i) values[i] = decode_double(words + kRegistersPerVariable * i);
  return vars.write(first, n, values, client);
}

}  // namespace trueaxis::modbus
