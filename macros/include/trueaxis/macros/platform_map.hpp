// The platform's rows of the register map: what every method shares.
//
// Conventions (docs/INTERFACE.md, Fanuc / LinuxCNC custom-macro numbering)
//  1. #1 .. #26      arguments of the next macro, by G65 letter; cleared to 0 after
//                    every macro. Letters G L N O P have no variable.
//  2. #100 .. #199   results of the last successful macro; read-only. Their
//                    meaning is per macro (each macro's outputs in the JSON map).
//  3. #500 .. #999   configuration; persistent; writable only while unlocked.
//                    Each method owns a block (its descriptor's kBlock,
//                    method.hpp); #900 .. #903 are the platform's (the
//                    unlock code, the gates' confidence, the machine's
//                    identity, the macro interface's idle limit), #904 the
//                    home's identity; #905 .. #999 is free for further methods.
//  4. #1000 .. #4999 macro-input data of the methods (point lists), one block
//                    per method; volatile, cleared after every macro.
//  5. #5221 .. #5326 work offsets G54 .. G59 (+0 X .. +5 C); persistent.
//  6. #9000 .. #9009 the handshake; #9010 the count of wrong unlock codes,
//     #9011 the seconds of unlock back-off left; #9012 .. #9014 what the last
//     macro's gate refused (gates.hpp).
//  7. Slots: every module keeps its variables in one array, the platform's
//     first (kPlatformSlots: the arguments, the 100 results, then
//     kPlatformRows), then each method's own rows in the order of the method
//     list. platform_slot() gives a platform variable's slot at compile time,
//     without knowing which methods are built.
// A number is written once, here or in its method's map file; rows are built
// from these names.
#pragma once

#include <cstdint>

#include <cstddef>

#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

namespace var {
inline constexpr std::uint16_t kArgA = 1;
inline constexpr std::uint16_t kArgB = 2;
inline constexpr std::uint16_t kArgC = 3;
inline constexpr std::uint16_t kArgI = 4;
inline constexpr std::uint16_t kArgJ = 5;
inline constexpr std::uint16_t kArgK = 6;
inline constexpr std::uint16_t kArgD = 7;
inline constexpr std::uint16_t kArgE = 8;
inline constexpr std::uint16_t kArgF = 9;
inline constexpr std::uint16_t kArgH = 11;
inline constexpr std::uint16_t kArgM = 13;
inline constexpr std::uint16_t kArgQ = 17;
inline constexpr std::uint16_t kArgR = 18;
inline constexpr std::uint16_t kArgS = 19;
inline constexpr std::uint16_t kArgT = 20;
inline constexpr std::uint16_t kArgU = 21;
inline constexpr std::uint16_t kArgV = 22;
inline constexpr std::uint16_t kArgW = 23;
inline constexpr std::uint16_t kArgX = 24;
inline constexpr std::uint16_t kArgY = 25;
inline constexpr std::uint16_t kArgZ = 26;
inline constexpr std::uint16_t kArgFirst = kArgA;
inline constexpr std::uint16_t kArgLast = kArgZ;

inline constexpr std::uint16_t kResultFirst = 100;
inline constexpr std::uint16_t kResultLast = 199;

inline constexpr std::uint16_t kConfigFirst = 500;
inline constexpr std::uint16_t kConfigLast = 999;
inline constexpr std::uint16_t kDataFirst = 1000;
inline constexpr std::uint16_t kDataLast = 4999;

inline constexpr std::uint16_t kG54 = 5221;
inline constexpr std::uint16_t kG55 = 5241;
inline constexpr std::uint16_t kG56 = 5261;
inline constexpr std::uint16_t kG57 = 5281;
inline constexpr std::uint16_t kG58 = 5301;
inline constexpr std::uint16_t kG59 = 5321;
inline constexpr std::uint16_t kWorkOffsetStride = 20;  // G(n+1) = G(n) + 20
inline constexpr std::uint16_t kWorkOffsetAxes = 6;     // X Y Z A B C

inline constexpr std::uint16_t kUnlockCodeSetting = 900;
inline constexpr std::uint16_t kGateConfidence = 901;
inline constexpr std::uint16_t kMachineId = 902;
inline constexpr std::uint16_t kInterfaceIdleLimit = 903;
inline constexpr std::uint16_t kHomeIdentity = 904;
inline constexpr double kMaxHomeIdentity = 65535.0;  // 16 bits: a table's record holds it

inline constexpr std::uint16_t kCmd = 9000;
inline constexpr std::uint16_t kStatus = 9001;
inline constexpr std::uint16_t kError = 9002;
inline constexpr std::uint16_t kDoneCount = 9003;
inline constexpr std::uint16_t kUnlock = 9004;
inline constexpr std::uint16_t kRunTime = 9005;
inline constexpr std::uint16_t kInterfaceVersion = 9006;
inline constexpr std::uint16_t kAccessFault = 9007;
inline constexpr std::uint16_t kStepCount = 9008;
inline constexpr std::uint16_t kInterface = 9009;
inline constexpr std::uint16_t kFailedUnlocks = 9010;
inline constexpr std::uint16_t kUnlockBackoffLeft = 9011;
inline constexpr std::uint16_t kGateItem = 9012;
inline constexpr std::uint16_t kGateValue = 9013;
inline constexpr std::uint16_t kGateLimit = 9014;
// The measuring log (measuring_log.hpp).
inline constexpr std::uint16_t kLogTime = 9015;
inline constexpr std::uint16_t kLogCount = 9016;
inline constexpr std::uint16_t kLogNewest = 9017;
inline constexpr std::uint16_t kLogSelect = 9018;
inline constexpr std::uint16_t kLogLost = 9019;
inline constexpr std::uint16_t kLogSerial = 9020;
inline constexpr std::uint16_t kLogEntryTime = 9021;
inline constexpr std::uint16_t kLogMacro = 9022;
inline constexpr std::uint16_t kLogType = 9023;
inline constexpr std::uint16_t kLogVerdict = 9024;
inline constexpr std::uint16_t kLogStored = 9025;
inline constexpr std::uint16_t kLogTableSequence = 9026;
inline constexpr std::uint16_t kLogFigureCount = 9027;
inline constexpr std::uint16_t kLogIndex = 9028;
inline constexpr std::uint16_t kLogFigureFirst = 9030;  // 6 figures x (kind, item, value, sigma, tolerance)
inline constexpr std::uint16_t kLogFigureValues = 5;
}  // namespace var

// #9001 values.
enum class MacroState : std::uint8_t { kIdle = 0, kBusy = 1, kDone = 2, kError = 3 };

// The published unlock code: the default of #900, for commissioning only (the
// integrator sets the machine's own, module.hpp contract 7).
inline constexpr double kUnlockCode = 2718.0;
inline constexpr double kInterfaceVersionValue = 1.0;
// The default of #901: a fit of pure instrument noise is refused once in a
// million (gates.hpp convention 2).
inline constexpr double kDefaultGateConfidence = 0.999999;
// #903 (module.hpp contract 8): how long a client with a session keeps the
// macro interface after its last write or macro, in seconds, and its range.
inline constexpr double kDefaultInterfaceIdleS = 30.0;
inline constexpr double kMinInterfaceIdleS = 5.0;
inline constexpr double kMaxInterfaceIdleS = 600.0;

namespace rows {
inline constexpr double kBig = 1e5;  // bound of coordinates (mm) and angles (deg) macros take

constexpr VarInfo arg(std::uint16_t n, const char* name, const char* what) {
  return {n, 1, Access::kReadWrite, ValueKind::kReal, -kBig, kBig, 0.0, name, "", what};
}
constexpr VarInfo result(std::uint16_t n, std::uint16_t count, const char* name, const char* unit, const char* what) {
  return {n, count, Access::kReadOnly, ValueKind::kReal, -kBig * 1e3, kBig * 1e3, 0.0, name, unit, what};
}
constexpr VarInfo config(std::uint16_t n, double min, double max, double dflt, const char* name, const char* unit,
                         const char* what) {
  return {n, 1, Access::kConfig, ValueKind::kReal, min, max, dflt, name, unit, what};
}
constexpr VarInfo sign_config(std::uint16_t n, double dflt, const char* name, const char* what) {
  return {n, 1, Access::kConfig, ValueKind::kSign, -1.0, 1.0, dflt, name, "", what};
}
constexpr VarInfo data_block(std::uint16_t n, std::uint16_t count, const char* name, const char* unit,
                             const char* what) {
  return {n, count, Access::kReadWrite, ValueKind::kReal, -kBig, kBig, 0.0, name, unit, what};
}
constexpr VarInfo offset(std::uint16_t n, const char* name, const char* unit) {
  return {n, 1, Access::kPersistent, ValueKind::kReal, -kBig, kBig, 0.0, name, unit, "Work offset."};
}
}  // namespace rows

// clang-format off
inline constexpr VarInfo kPlatformArgRows[] = {
  rows::arg(var::kArgA, "arg_a", "G65 argument A. Macro 9810/9811: the commanded A (deg) while probing."),
  rows::arg(var::kArgB, "arg_b", "G65 argument B."),
  rows::arg(var::kArgC, "arg_c", "G65 argument C. Macro 9810/9811: the commanded C (deg) while probing."),
  rows::arg(var::kArgI, "arg_i", "G65 argument I. Macro 9810/9811: X of the face's outward direction (machine frame, as probed); I=J=K=0 means +Z."),
  rows::arg(var::kArgJ, "arg_j", "G65 argument J. Macro 9810/9811: Y of the outward direction."),
  rows::arg(var::kArgK, "arg_k", "G65 argument K. Macro 9810/9811: Z of the outward direction."),
  rows::arg(var::kArgD, "arg_d", "G65 argument D."),
  rows::arg(var::kArgE, "arg_e", "G65 argument E."),
  rows::arg(var::kArgF, "arg_f", "G65 argument F."),
  rows::arg(var::kArgH, "arg_h", "G65 argument H."),
  rows::arg(var::kArgM, "arg_m", "G65 argument M."),
  rows::arg(var::kArgQ, "arg_q", "G65 argument Q. Macro 9811: the number of points in the point list."),
  rows::arg(var::kArgR, "arg_r", "G65 argument R."),
  rows::arg(var::kArgS, "arg_s", "G65 argument S."),
  rows::arg(var::kArgT, "arg_t", "G65 argument T."),
  rows::arg(var::kArgU, "arg_u", "G65 argument U."),
  rows::arg(var::kArgV, "arg_v", "G65 argument V."),
  rows::arg(var::kArgW, "arg_w", "G65 argument W."),
  rows::arg(var::kArgX, "arg_x", "G65 argument X."),
  rows::arg(var::kArgY, "arg_y", "G65 argument Y."),
  rows::arg(var::kArgZ, "arg_z", "G65 argument Z."),
};

inline constexpr VarInfo kPlatformRows[] = {
  {var::kUnlockCodeSetting, 1, Access::kConfig, ValueKind::kInteger, 1.0, 9999.0, kUnlockCode, "unlock_code", "", "The code #9004 takes: set it while unlocked (persistent); it reads 0. The default 2718 is published, for commissioning only. An unlock closes by itself 300 s after its client's last write that succeeded, when another client takes the macro interface, and when the connection that opened it closes."},

  {var::kGateConfidence, 1, Access::kConfig, ValueKind::kReal, 0.999, 0.999999999, kDefaultGateConfidence, "gate_confidence", "", "The fit-quality gate's confidence (every method that compares its residuals with its instrument's stated noise): a fit whose weighted sum of squared residuals exceeds the chi-square quantile at this confidence is refused (fit_beyond_noise). The default 0.999999 refuses pure noise once in a million computations."},

  {var::kMachineId, 1, Access::kConfig, ValueKind::kInteger, 0.0, 999999999.0, 0.0, "machine_id", "", "The machine's identity as a whole number (a variable holds numbers only: the serial's digits or an asset number), set by the integrator: every calibration report shows it beside the operator and the date. 0: not set."},

  {var::kInterfaceIdleLimit, 1, Access::kConfig, ValueKind::kInteger, kMinInterfaceIdleS, kMaxInterfaceIdleS, kDefaultInterfaceIdleS, "interface_idle_s", "s", "How long a client keeps the macro interface (#9009) after its last write that took it or its last macro's end, while it has a session open (after its clear macro, until its compute, 9815 or check macro succeeds) or has taken it with #9009 = 1: the LinuxCNC rigidity program probes for many seconds between two adds. A client without either keeps it 2 s. A hold already running keeps its length when this changes."},

  {var::kHomeIdentity, 1, Access::kConfig, ValueKind::kInteger, 0.0, var::kMaxHomeIdentity, 0.0, "home_identity", "", "The axes' home as a number the integrator sets, and changes whenever an axis' zero moves (a home switch moved, a home offset changed; LinuxCNC: the remap computes it from the ini's [TRUEAXIS] HOME_ID and the joints' HOME and HOME_OFFSET and refuses G65 while this differs). M3's table records it at its build (9832); a stored table recorded under another value is not applied (home_changed) by 9833, 9835, 9836, leveling on the calibrated axes (#508 = 1) or the controller's direct queries, until this is set back (the axes homed as then) or the table is measured and stored again. 0: none set."},

  rows::offset(var::kG54 + 0, "g54_x", "mm"), rows::offset(var::kG54 + 1, "g54_y", "mm"), rows::offset(var::kG54 + 2, "g54_z", "mm"),
  rows::offset(var::kG54 + 3, "g54_a", "deg"), rows::offset(var::kG54 + 4, "g54_b", "deg"), rows::offset(var::kG54 + 5, "g54_c", "deg"),
  rows::offset(var::kG55 + 0, "g55_x", "mm"), rows::offset(var::kG55 + 1, "g55_y", "mm"), rows::offset(var::kG55 + 2, "g55_z", "mm"),
  rows::offset(var::kG55 + 3, "g55_a", "deg"), rows::offset(var::kG55 + 4, "g55_b", "deg"), rows::offset(var::kG55 + 5, "g55_c", "deg"),
  rows::offset(var::kG56 + 0, "g56_x", "mm"), rows::offset(var::kG56 + 1, "g56_y", "mm"), rows::offset(var::kG56 + 2, "g56_z", "mm"),
  rows::offset(var::kG56 + 3, "g56_a", "deg"), rows::offset(var::kG56 + 4, "g56_b", "deg"), rows::offset(var::kG56 + 5, "g56_c", "deg"),
  rows::offset(var::kG57 + 0, "g57_x", "mm"), rows::offset(var::kG57 + 1, "g57_y", "mm"), rows::offset(var::kG57 + 2, "g57_z", "mm"),
  rows::offset(var::kG57 + 3, "g57_a", "deg"), rows::offset(var::kG57 + 4, "g57_b", "deg"), rows::offset(var::kG57 + 5, "g57_c", "deg"),
  rows::offset(var::kG58 + 0, "g58_x", "mm"), rows::offset(var::kG58 + 1, "g58_y", "mm"), rows::offset(var::kG58 + 2, "g58_z", "mm"),
  rows::offset(var::kG58 + 3, "g58_a", "deg"), rows::offset(var::kG58 + 4, "g58_b", "deg"), rows::offset(var::kG58 + 5, "g58_c", "deg"),
  rows::offset(var::kG59 + 0, "g59_x", "mm"), rows::offset(var::kG59 + 1, "g59_y", "mm"), rows::offset(var::kG59 + 2, "g59_z", "mm"),
  rows::offset(var::kG59 + 3, "g59_a", "deg"), rows::offset(var::kG59 + 4, "g59_b", "deg"), rows::offset(var::kG59 + 5, "g59_c", "deg"),

  {var::kCmd, 1, Access::kCommand, ValueKind::kInteger, 0.0, 9999.0, 0.0, "cmd", "", "Write a macro number to run that macro (0 runs nothing); reads the last number written."},
  {var::kStatus, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 3.0, 0.0, "status", "", "0 idle, 1 busy, 2 done, 3 error."},
  {var::kError, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 65535.0, 0.0, "error", "", "0 when the last macro succeeded, else its error code."},
  {var::kDoneCount, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9.0e15, 0.0, "done_count", "", "+1 each time a macro finishes, with success or error."},
  {var::kUnlock, 1, Access::kUnlock, ValueKind::kInteger, 0.0, 9999.0, 0.0, "unlock", "", "Write the unlock code to allow writes to #500..#999, 0 to lock; reads 1 when unlocked."},
  {var::kRunTime, 1, Access::kReadOnly, ValueKind::kReal, 0.0, 9.0e15, 0.0, "run_time", "us", "Time the last macro ran, from the clock the controller hands the module."},
  {var::kInterfaceVersion, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 65535.0, kInterfaceVersionValue, "interface_version", "", "Version of this register map."},
  {var::kAccessFault, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 255.0, 0.0, "access_fault", "", "Why the last refused register access was refused (see access_faults)."},
  {var::kStepCount, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9.0e15, 0.0, "step_count", "", "Number of step() calls the last macro took (1 for a macro that finishes in one step)."},
  {var::kInterface, 1, Access::kInterface, ValueKind::kInteger, 0.0, 1.0, 0.0, "interface", "", "The macro interface, granted to one client (TCP connection) at a time. A write of an argument (#1..#26), a data block, #9000, #9015, #9018 or #9009 = 1 takes it; a write of a work offset, a configuration variable or #9004 takes nothing and is accepted from any client while no other holds it. The holder keeps it while its macro runs, then 2 s after its macro's end or its last write that took it; with a session of its own open or after #9009 = 1, up to #903 s (default 30) after them. A client that takes over a hold that ran out finds the arguments and data blocks its holder left cleared. Others' writes meanwhile get exception 06 (#9007 = interface_held). Write 1 to take it (refused while another holds it), 0 to give it back; a closed connection gives it back too. Reads 0 free, 1 held by you, 2 held by another client. A lock (#9004 = 0) is accepted from anyone."},
  {var::kFailedUnlocks, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9.0e15, 0.0, "failed_unlocks", "", "Wrong codes written to #9004 since start; each makes #9004 refuse codes for a back-off (1 s, doubling up to 64 s)."},
  {var::kUnlockBackoffLeft, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 64.0, 0.0, "unlock_backoff_s", "s", "Seconds left (rounded up) before #9004 takes a code again after a wrong one; 0 when it takes one now."},
  {var::kGateItem, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 65535.0, 0.0, "gate_item", "", "When the last macro's gate refused its result (fit_beyond_noise, change_beyond_limit, a method's implausible_...): the pose, group or sub-machine it names (1-based, as that method's reports number them; 0 the whole result). 0 after any other end."},
  {var::kGateValue, 1, Access::kReadOnly, ValueKind::kReal, -1e15, 1e15, 0.0, "gate_value", "", "The refused figure: for fit_beyond_noise the ratio of the residuals' chi-square statistic to its quantile at #901 (above 1), else the figure in the unit of its limit. 0 after any other end."},
  {var::kGateLimit, 1, Access::kReadOnly, ValueKind::kReal, -1e15, 1e15, 0.0, "gate_limit", "", "The limit that figure exceeded (1 for fit_beyond_noise; else the configuration value, in its unit). 0 after any other end."},

  {var::kLogTime, 1, Access::kReadWrite, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_time", "s", "Measuring log: the time of the macro about to run (Unix s, UTC), written with its arguments; 0: the controller's clock or unknown."},
  {var::kLogCount, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 32.0, 0.0, "log_entries", "", "Measuring log: entries held (at most 32: every calibration, store, check and refusal of M2, M3, M4; a full log drops scratch first, then history, never the present table's stored entry)."},
  {var::kLogNewest, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_newest", "", "Measuring log: the newest entry's serial (from 1; serials rise but need not be contiguous: read the entries by #9028); 0 empty."},
  {var::kLogSelect, 1, Access::kReadWrite, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_select", "", "Measuring log: write a serial to show that entry in #9020..#9059 (0 when not held). Cleared after every macro."},
  {var::kLogLost, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9.0e15, 0.0, "log_lost", "", "Measuring log: entries lost since start (an append the storage refused, or a log that did not read and was started again)."},
  {var::kLogSerial, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_serial", "", "Log entry: serial; 0 none shown."},
  {var::kLogEntryTime, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_entry_time", "s", "Log entry: time (Unix s, UTC; 0 unknown)."},
  {var::kLogMacro, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9999.0, 0.0, "log_macro", "", "Log entry: its macro."},
  {var::kLogType, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 2.0, 0.0, "log_type", "", "Log entry: 0 calibration, 1 check, 2 refusal (a calibration or store a gate refused, or a store refused as table_locked: its figure 0, kind 0, holds the gate's item, value and limit, and the status code in place of the sigma)."},
  {var::kLogVerdict, 1, Access::kReadOnly, ValueKind::kInteger, -1.0, 2.0, 0.0, "log_verdict", "", "Log entry: a check's verdict (0 pass, 1 warn, 2 fail); -1 none."},
  {var::kLogStored, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 1.0, 0.0, "log_stored", "", "Log entry: 1 when it stored its table."},
  {var::kLogTableSequence, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 4294967295.0, 0.0, "log_table_sequence", "", "Log entry: the stored table's sequence after it (+1 a store; what a check judged against); 0 none."},
  {var::kLogFigureCount, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 6.0, 0.0, "log_figures", "", "Log entry: its figures (0..6)."},
  {var::kLogIndex, 1, Access::kReadWrite, ValueKind::kInteger, 0.0, 32.0, 0.0, "log_index", "", "Measuring log: write k (1 .. #9016) to show the k-th entry held, oldest first, in #9020..#9059 (0 none): serials are not contiguous once a full log has kept what matters. Cleared after every macro."},
  {var::kLogFigureFirst, 30, Access::kReadOnly, ValueKind::kReal, -1e15, 1e15, 0.0, "log_figure", "", "Log entry: figure k (0..5) at #9030 + 5 k: kind (the method's log or check figures, from 1), item, value (a check's deviation), 1-sigma, tolerance."},
};
// clang-format on

// Convention 7: the platform's slots.
inline constexpr std::size_t kArgSlots = variable_count(kPlatformArgRows, sizeof kPlatformArgRows / sizeof kPlatformArgRows[0]);
inline constexpr std::size_t kResultSlots = var::kResultLast - var::kResultFirst + 1;
inline constexpr std::size_t kPlatformSlots =
    kArgSlots + kResultSlots + variable_count(kPlatformRows, sizeof kPlatformRows / sizeof kPlatformRows[0]);
inline constexpr std::size_t kNoSlot = static_cast<std::size_t>(-1);

// The slot of `number` in a table's own slots (its rows in order, blocks
// expanded), or kNoSlot when the table does not define it.
template <std::size_t N>
constexpr std::size_t slot_in(const VarInfo (&table)[N], std::uint16_t number) {
  std::size_t slot = 0;
  for (const VarInfo& v : table) {
    if (number >= v.number && number - v.number < v.count) return slot + (number - v.number);
    slot += v.count;
  }
  return kNoSlot;
}

// A platform variable's slot (convention 7), or kNoSlot for a number the
// platform does not define.
constexpr std::size_t platform_slot(std::uint16_t number) {
  if (number >= var::kResultFirst && number <= var::kResultLast) return kArgSlots + (number - var::kResultFirst);
  const std::size_t arg = slot_in(kPlatformArgRows, number);
  if (arg != kNoSlot) return arg;
  const std::size_t rest = slot_in(kPlatformRows, number);
  return rest == kNoSlot ? kNoSlot : kArgSlots + kResultSlots + rest;
}
static_assert(platform_slot(var::kArgA) == 0 && platform_slot(var::kResultFirst) == kArgSlots &&
              platform_slot(var::kLogFigureFirst + 29) == kPlatformSlots - 1 && platform_slot(10) == kNoSlot);

}  // namespace trueaxis::macros
