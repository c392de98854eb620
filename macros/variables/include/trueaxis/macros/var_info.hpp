// The shape of one entry of a register map, and the checks every write passes.
// The module's map (register_map.hpp) and the simulator's own variables are both
// tables of VarInfo, so one encoder, one validator and one JSON writer serve both.
//
// Conventions
//  1. An entry describes `count` consecutive variables #number .. #number+count-1
//     that share access, kind, range and default (count is 1 for most entries;
//     blocks are for buffers such as the leveling point list).
//  2. Values are doubles. kReal takes any finite value in [min, max]; kInteger a
//     finite whole number in [min, max]; kSign exactly -1 or +1.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace trueaxis::macros {

inline constexpr std::uint16_t kMaxVariableNumber = 16383;

enum class Access : std::uint8_t {
  kReadWrite,   // volatile, any client may write (macro arguments)
  kReadOnly,    // written only by the module (results, handshake state)
  kPersistent,  // kept in non-volatile storage, any client may write (work offsets)
  kConfig,      // kept in non-volatile storage, writable only while unlocked
  kCommand,     // #9000: writing runs a macro
  kUnlock,      // #9004: writing the code unlocks, 0 locks; reads 1 when unlocked
  kInterface,   // #9009: 1 takes the macro interface, 0 gives it back; reads 0 free, 1 yours, 2 held
};

// Who sent a request: the transport names its client (a TCP connection, the
// RTU line's one master); the controller itself and anything that names none
// are kLocalClient. The module grants the macro interface to one
// client at a time (module.hpp contract 8).
using ClientId = std::uint32_t;
inline constexpr ClientId kNoClient = 0;
inline constexpr ClientId kLocalClient = 1;
inline constexpr ClientId kRtuMaster = 2;        // a serial line's one master (modbus_rtu.hpp)
inline constexpr ClientId kFirstTcpClient = 3;   // TCP connections are numbered from here

enum class ValueKind : std::uint8_t { kReal, kInteger, kSign };

// Why a register access was refused. Each maps to one Modbus exception code
// (modbus_exception()); the module keeps the last one in #9007 so an HMI can tell
// apart the refusals that share an exception code.
enum class AccessFault : std::uint8_t {
  kNone = 0,
  kUndefined = 1,       // a number the map does not define                    -> 02
  kMisaligned = 2,      // not whole variables (register address or count)      -> 02
  kReadOnly = 3,        // write to a read-only variable                        -> 02
  kLocked = 4,          // write to a configuration variable while locked       -> 02
  kNotFinite = 5,       // NaN or infinity                                      -> 03
  kOutOfRange = 6,      // outside [min, max], not whole, not a sign            -> 03
  kBadUnlockCode = 7,   // #9004 written with neither the code nor 0            -> 03
  kBusy = 8,            // a macro is running                                   -> 06
  kStorageFailure = 9,  // non-volatile storage refused the write               -> 04
  kBadFunction = 10,    // a function code the server does not serve            -> 01
  kUnlockBackoff = 11,  // #9004 written while failed unlocks are slowed down   -> 06
  kInterfaceHeld = 12,  // a write while another client holds the macro interface -> 06
};

// Modbus exception codes (Modbus Application Protocol V1.1b3, section 7).
enum class ModbusException : std::uint8_t {
  kNone = 0,
  kIllegalFunction = 1,
  kIllegalDataAddress = 2,
  kIllegalDataValue = 3,
  kServerDeviceFailure = 4,
  kServerDeviceBusy = 6,
};

constexpr ModbusException modbus_exception(AccessFault f) {
  switch (f) {
    case AccessFault::kNone: return ModbusException::kNone;
    case AccessFault::kUndefined:
    case AccessFault::kMisaligned:
    case AccessFault::kReadOnly:
    case AccessFault::kLocked: return ModbusException::kIllegalDataAddress;
    case AccessFault::kNotFinite:
    case AccessFault::kOutOfRange:
    case AccessFault::kBadUnlockCode: return ModbusException::kIllegalDataValue;
    case AccessFault::kBusy:
    case AccessFault::kUnlockBackoff:
    case AccessFault::kInterfaceHeld: return ModbusException::kServerDeviceBusy;
    case AccessFault::kStorageFailure: return ModbusException::kServerDeviceFailure;
    case AccessFault::kBadFunction: return ModbusException::kIllegalFunction;
  }
  return ModbusException::kServerDeviceFailure;
}

struct AccessFaultInfo {
  AccessFault fault;
  const char* name;     // snake_case, stable
  const char* message;  // one sentence for an HMI
};

// Every refusal with its name and message: the register map's JSON and human page
// list them from here.
inline constexpr AccessFaultInfo kAccessFaultTable[] = {
    {AccessFault::kUndefined, "undefined", "The map does not define that variable number."},
    {AccessFault::kMisaligned, "misaligned",
     "The register range does not start on a variable or does not cover whole variables."},
    {AccessFault::kReadOnly, "read_only", "The variable is read-only."},
    {AccessFault::kLocked, "locked", "Configuration is writable only after the unlock code is written to #9004."},
    {AccessFault::kNotFinite, "not_finite", "NaN or infinity where a number is needed."},
    {AccessFault::kOutOfRange, "out_of_range", "Outside the variable's range, or not a whole number or a sign."},
    {AccessFault::kBadUnlockCode, "bad_unlock_code", "#9004 takes the unlock code or 0."},
    {AccessFault::kBusy, "busy", "A macro is running: commands and macro inputs wait until it is done."},
    {AccessFault::kStorageFailure, "storage_failure", "Non-volatile storage refused the write; nothing changed."},
    {AccessFault::kBadFunction, "bad_function", "The server does not serve that Modbus function code."},
    {AccessFault::kUnlockBackoff, "unlock_backoff",
     "A wrong unlock code was written moments ago: #9004 takes no code until the back-off (1 s, doubling "
     "with each further wrong code up to 64 s) has passed; #9011 tells the seconds left."},
    {AccessFault::kInterfaceHeld, "interface_held",
     "Another client holds the macro interface (#9009): its macro runs or ended less than 2 s ago, or it "
     "wrote an argument less than 2 s ago, or it has a session open or wrote #9009 = 1 (then it keeps it until "
     "#903 s after its last macro or argument). Until then no other client may write, not even a work offset "
     "(a lock, #9004 = 0, is always accepted); reads stay open. Wait and start again."},
};

struct VarInfo {
  std::uint16_t number;
  std::uint16_t count;
  Access access;
  ValueKind kind;
  double min;
  double max;
  double default_value;
  const char* name;         // snake_case, unique in the map
  const char* unit;         // "mm", "deg", "arcsec", "" for plain numbers
  const char* description;  // one sentence
};

// One output of a macro: a result variable (#100..#199) and what that macro puts
// there. Results are shared by every macro, so their meaning is per macro.
struct OutputInfo {
  std::uint16_t number;
  const char* name;         // snake_case, unique within the macro
  const char* unit;
  const char* description;  // one sentence
};

// Variables a macro reads: #first .. #first+count-1 of the map, and what for.
struct InputRef {
  std::uint16_t first;
  std::uint16_t count;
  const char* note;  // one sentence; "" when the variable's own description says it
};

// The numbers a method may define rows in: its block of the persistent range
// #500..#999 and its block of macro-input data (#1000..#4999); a block of
// {0, 0} is none. Both are published in the JSON map; register_map.hpp checks
// every row against them.
struct MethodBlock {
  const char* method;
  std::uint16_t config_first, config_last;
  std::uint16_t data_first, data_last;

  constexpr bool has_config() const { return config_first != 0 || config_last != 0; }
  constexpr bool has_data() const { return data_first != 0 || data_last != 0; }
};

// The first fault a value would meet being written to `info` (kind and range only;
// access is the owner's to check).
constexpr AccessFault check_value(const VarInfo& info, double value) {
  if (!(value == value) || value - value != 0.0) return AccessFault::kNotFinite;  // NaN or inf, constexpr-safe
  if (info.kind == ValueKind::kSign) {
    return (value == 1.0 || value == -1.0) ? AccessFault::kNone : AccessFault::kOutOfRange;
  }
  if (!(value >= info.min && value <= info.max)) return AccessFault::kOutOfRange;
  // In range, so the cast below is defined (every integer range fits in long long).
  if (info.kind == ValueKind::kInteger && static_cast<double>(static_cast<long long>(value)) != value) {
    return AccessFault::kOutOfRange;
  }
  return AccessFault::kNone;
}

// Compile-time checks of a table: sorted by number, blocks not overlapping, every
// number in 0..kMaxVariableNumber, every range and default consistent.
constexpr bool map_is_well_formed(const VarInfo* table, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    const VarInfo& v = table[i];
    if (v.count == 0) return false;
    if (static_cast<std::uint32_t>(v.number) + v.count - 1 > kMaxVariableNumber) return false;
    if (!(v.min <= v.max)) return false;
    if (v.access != Access::kCommand && v.access != Access::kUnlock && v.access != Access::kInterface &&
        check_value(v, v.default_value) != AccessFault::kNone) {
      return false;
    }
    if (i > 0 && static_cast<std::uint32_t>(table[i - 1].number) + table[i - 1].count > v.number) {
      return false;
    }
  }
  return true;
}

// Total number of variables (blocks expanded) in a table.
constexpr std::size_t variable_count(const VarInfo* table, std::size_t size) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < size; ++i) n += table[i].count;
  return n;
}

// The entry holding #number, or nullptr; binary search over a sorted table.
constexpr const VarInfo* find_in(const VarInfo* table, std::size_t size, std::uint16_t number) {
  std::size_t lo = 0;
  std::size_t hi = size;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    const VarInfo& v = table[mid];
    if (number < v.number) {
      hi = mid;
    } else if (number >= static_cast<std::uint32_t>(v.number) + v.count) {
      lo = mid + 1;
    } else {
      return &v;
    }
  }
  return nullptr;
}

}  // namespace trueaxis::macros
