// The module's register map: the one table from which the variable numbers, the
// Modbus addresses (variable #N = holding registers 4N .. 4N+3), the JSON map
// (macros/register_map.json) and the human page (macros/REGISTER_MAP.md) come.
//
// Conventions (INTERFACE.md, Fanuc / LinuxCNC custom-macro numbering)
//  1. #1 .. #26      arguments of the next macro, by G65 letter; cleared to 0 after
//                    every macro. Letters G L N O P have no variable.
//  2. #100 .. #199   results of the last successful macro; read-only.
//  3. #500 .. #999   configuration; persistent; writable only while unlocked.
//  4. #1000 .. #1096 the point list of macro 9811 (X, Y, Z of point k at
//                    #1000 + 3k - 2 .. #1000 + 3k); cleared after every macro.
//  5. #5221 .. #5326 work offsets G54 .. G59 (+0 X .. +5 C); persistent.
//  6. #9000 .. #9009 the handshake.
// A number not in the table is not defined: reading or writing it is refused.
#pragma once

#include <array>

#include "trueaxis/core/leveling.hpp"
#include "trueaxis/core/plane_fit.hpp"
#include "trueaxis/macros/var_info.hpp"

namespace trueaxis::macros {

// Variable numbers the code refers to by name.
namespace var {
inline constexpr std::uint16_t kArgA = 1;
inline constexpr std::uint16_t kArgC = 3;
inline constexpr std::uint16_t kArgI = 4;
inline constexpr std::uint16_t kArgJ = 5;
inline constexpr std::uint16_t kArgK = 6;
inline constexpr std::uint16_t kArgQ = 17;
inline constexpr std::uint16_t kArgLast = 26;

inline constexpr std::uint16_t kResultFirst = 100;
inline constexpr std::uint16_t kLevelC = 100;
inline constexpr std::uint16_t kLevelA = 101;
inline constexpr std::uint16_t kLevelOtherC = 102;
inline constexpr std::uint16_t kLevelOtherA = 103;
inline constexpr std::uint16_t kLevelNormalX = 104;
inline constexpr std::uint16_t kLevelNormalY = 105;
inline constexpr std::uint16_t kLevelNormalZ = 106;
inline constexpr std::uint16_t kLevelTilt = 107;
inline constexpr std::uint16_t kLevelTiltSigma = 108;
inline constexpr std::uint16_t kLevelCSigma = 109;
inline constexpr std::uint16_t kLevelDirectionSigma = 110;
inline constexpr std::uint16_t kLevelFlatness = 111;
inline constexpr std::uint16_t kLevelPointCount = 112;
inline constexpr std::uint16_t kLevelOutlierPoint = 113;
inline constexpr std::uint16_t kLevelMaxResidual = 114;
inline constexpr std::uint16_t kLevelOtherReachable = 115;
inline constexpr std::uint16_t kResultLast = 199;

inline constexpr std::uint16_t kAMin = 500;
inline constexpr std::uint16_t kAMax = 501;
inline constexpr std::uint16_t kCMin = 502;
inline constexpr std::uint16_t kCMax = 503;
inline constexpr std::uint16_t kASign = 504;
inline constexpr std::uint16_t kCSign = 505;
inline constexpr std::uint16_t kProbeSigma = 506;
inline constexpr std::uint16_t kMaxDirectionSigma = 507;

inline constexpr std::uint16_t kPointList = 1001;
inline constexpr std::uint16_t kPointListCount = static_cast<std::uint16_t>(3 * core::kMaxPlanePoints);

inline constexpr std::uint16_t kG54 = 5221;
inline constexpr std::uint16_t kG57 = 5281;
inline constexpr std::uint16_t kG58 = 5301;
inline constexpr std::uint16_t kG59 = 5321;

inline constexpr std::uint16_t kCmd = 9000;
inline constexpr std::uint16_t kStatus = 9001;
inline constexpr std::uint16_t kError = 9002;
inline constexpr std::uint16_t kDoneCount = 9003;
inline constexpr std::uint16_t kUnlock = 9004;
inline constexpr std::uint16_t kRunTime = 9005;
inline constexpr std::uint16_t kInterfaceVersion = 9006;
inline constexpr std::uint16_t kAccessFault = 9007;
}  // namespace var

// #9001 values.
enum class MacroState : std::uint8_t { kIdle = 0, kBusy = 1, kDone = 2, kError = 3 };

inline constexpr double kUnlockCode = 2718.0;
inline constexpr double kInterfaceVersionValue = 1.0;

namespace detail {
inline constexpr double kBig = 1e5;  // bound of coordinates (mm) and angles (deg) macros take
inline constexpr core::LevelConfig kDefaults{};

constexpr VarInfo arg(std::uint16_t n, const char* name, const char* what) {
  return {n, 1, Access::kReadWrite, ValueKind::kReal, -kBig, kBig, 0.0, name, "", what};
}
constexpr VarInfo result(std::uint16_t n, const char* name, const char* unit, const char* what) {
  return {n, 1, Access::kReadOnly, ValueKind::kReal, -kBig * 1e3, kBig * 1e3, 0.0, name, unit, what};
}
constexpr VarInfo offset(std::uint16_t n, const char* name, const char* unit) {
  return {n, 1, Access::kPersistent, ValueKind::kReal, -kBig, kBig, 0.0, name, unit, "Work offset."};
}
}  // namespace detail

// clang-format off
inline constexpr VarInfo kRegisterMap[] = {
  detail::arg(1,  "arg_a", "G65 argument A. Macro 9810/9811: the commanded A (deg) while probing."),
  detail::arg(2,  "arg_b", "G65 argument B."),
  detail::arg(3,  "arg_c", "G65 argument C. Macro 9810/9811: the commanded C (deg) while probing."),
  detail::arg(4,  "arg_i", "G65 argument I. Macro 9810/9811: X of the face's outward direction (machine frame, as probed); I=J=K=0 means +Z."),
  detail::arg(5,  "arg_j", "G65 argument J. Macro 9810/9811: Y of the outward direction."),
  detail::arg(6,  "arg_k", "G65 argument K. Macro 9810/9811: Z of the outward direction."),
  detail::arg(7,  "arg_d", "G65 argument D."),
  detail::arg(8,  "arg_e", "G65 argument E."),
  detail::arg(9,  "arg_f", "G65 argument F."),
  detail::arg(11, "arg_h", "G65 argument H."),
  detail::arg(13, "arg_m", "G65 argument M."),
  detail::arg(17, "arg_q", "G65 argument Q. Macro 9811: the number of points in the point list."),
  detail::arg(18, "arg_r", "G65 argument R."),
  detail::arg(19, "arg_s", "G65 argument S."),
  detail::arg(20, "arg_t", "G65 argument T."),
  detail::arg(21, "arg_u", "G65 argument U."),
  detail::arg(22, "arg_v", "G65 argument V."),
  detail::arg(23, "arg_w", "G65 argument W."),
  detail::arg(24, "arg_x", "G65 argument X."),
  detail::arg(25, "arg_y", "G65 argument Y."),
  detail::arg(26, "arg_z", "G65 argument Z."),

  detail::result(100, "level_c", "deg", "Leveling: C of the chosen solution (absolute, commanded)."),
  detail::result(101, "level_a", "deg", "Leveling: A of the chosen solution (absolute, commanded)."),
  detail::result(102, "level_other_c", "deg", "Leveling: C of the other solution."),
  detail::result(103, "level_other_a", "deg", "Leveling: A of the other solution."),
  detail::result(104, "level_normal_x", "", "Leveling: X of the face's outward unit normal, table at zero."),
  detail::result(105, "level_normal_y", "", "Leveling: Y of the outward unit normal, table at zero."),
  detail::result(106, "level_normal_z", "", "Leveling: Z of the outward unit normal, table at zero."),
  detail::result(107, "level_tilt", "deg", "Leveling: the face's tilt from horizontal, table at zero."),
  detail::result(108, "level_tilt_sigma", "arcsec", "Leveling: standard uncertainty (1 sigma) of the tilt from the probe repeatability."),
  detail::result(109, "level_c_sigma", "arcsec", "Leveling: standard uncertainty of C (capped at 180 deg; large when the face is nearly level)."),
  detail::result(110, "level_direction_sigma", "arcsec", "Leveling: largest 1-sigma error of the normal's direction."),
  detail::result(111, "level_flatness", "mm", "Leveling: flatness (max minus min distance to the fitted plane); 0 for 3 points."),
  detail::result(112, "level_point_count", "", "Leveling: number of points used."),
  detail::result(113, "level_outlier_point", "", "Leveling: number of the point flagged as an outlier (5 or more points), 0 if none."),
  detail::result(114, "level_max_residual", "sigma", "Leveling: largest standardised residual (5 or more points)."),
  detail::result(115, "level_other_reachable", "", "Leveling: 1 when the other solution is inside the travel limits too, else 0."),

  {500, 1, Access::kConfig, ValueKind::kReal, -360.0, 360.0, detail::kDefaults.a_min_deg, "a_min", "deg", "A-axis travel: lower limit."},
  {501, 1, Access::kConfig, ValueKind::kReal, -360.0, 360.0, detail::kDefaults.a_max_deg, "a_max", "deg", "A-axis travel: upper limit."},
  {502, 1, Access::kConfig, ValueKind::kReal, -detail::kBig, detail::kBig, detail::kDefaults.c_min_deg, "c_min", "deg", "C-axis travel: lower limit."},
  {503, 1, Access::kConfig, ValueKind::kReal, -detail::kBig, detail::kBig, detail::kDefaults.c_max_deg, "c_max", "deg", "C-axis travel: upper limit."},
  {504, 1, Access::kConfig, ValueKind::kSign, -1.0, 1.0, detail::kDefaults.a_sign, "a_sign", "", "A direction: +1 when +A turns the table right-handed about +X, -1 when it turns it the other way (ISO 841)."},
  {505, 1, Access::kConfig, ValueKind::kSign, -1.0, 1.0, detail::kDefaults.c_sign, "c_sign", "", "C direction: +1 when +C turns the table right-handed about +Z, -1 otherwise."},
  {506, 1, Access::kConfig, ValueKind::kReal, 0.0, 1.0, detail::kDefaults.probe_sigma_mm, "probe_sigma", "mm", "Touch-probe repeatability, 1 sigma."},
  {507, 1, Access::kConfig, ValueKind::kReal, 1e-6, 90.0, detail::kDefaults.max_direction_sigma_deg, "max_direction_sigma", "deg", "Leveling refuses points whose normal would be uncertain by more than this (1 sigma)."},

  {var::kPointList, var::kPointListCount, Access::kReadWrite, ValueKind::kReal, -detail::kBig, detail::kBig, 0.0,
   "level_points", "mm", "Macro 9811: X, Y, Z of points 1..32, interleaved, machine frame."},

  detail::offset(5221, "g54_x", "mm"), detail::offset(5222, "g54_y", "mm"), detail::offset(5223, "g54_z", "mm"),
  detail::offset(5224, "g54_a", "deg"), detail::offset(5225, "g54_b", "deg"), detail::offset(5226, "g54_c", "deg"),
  detail::offset(5241, "g55_x", "mm"), detail::offset(5242, "g55_y", "mm"), detail::offset(5243, "g55_z", "mm"),
  detail::offset(5244, "g55_a", "deg"), detail::offset(5245, "g55_b", "deg"), detail::offset(5246, "g55_c", "deg"),
  detail::offset(5261, "g56_x", "mm"), detail::offset(5262, "g56_y", "mm"), detail::offset(5263, "g56_z", "mm"),
  detail::offset(5264, "g56_a", "deg"), detail::offset(5265, "g56_b", "deg"), detail::offset(5266, "g56_c", "deg"),
  detail::offset(5281, "g57_x", "mm"), detail::offset(5282, "g57_y", "mm"), detail::offset(5283, "g57_z", "mm"),
  detail::offset(5284, "g57_a", "deg"), detail::offset(5285, "g57_b", "deg"), detail::offset(5286, "g57_c", "deg"),
  detail::offset(5301, "g58_x", "mm"), detail::offset(5302, "g58_y", "mm"), detail::offset(5303, "g58_z", "mm"),
  detail::offset(5304, "g58_a", "deg"), detail::offset(5305, "g58_b", "deg"), detail::offset(5306, "g58_c", "deg"),
  detail::offset(5321, "g59_x", "mm"), detail::offset(5322, "g59_y", "mm"), detail::offset(5323, "g59_z", "mm"),
  detail::offset(5324, "g59_a", "deg"), detail::offset(5325, "g59_b", "deg"), detail::offset(5326, "g59_c", "deg"),

  {9000, 1, Access::kCommand, ValueKind::kInteger, 0.0, 9999.0, 0.0, "cmd", "", "Write a macro number to run that macro (0 runs nothing); reads the last number written."},
  {9001, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 3.0, 0.0, "status", "", "0 idle, 1 busy, 2 done, 3 error."},
  {9002, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 65535.0, 0.0, "error", "", "0 when the last macro succeeded, else its error code."},
  {9003, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 9.0e15, 0.0, "done_count", "", "+1 each time a macro finishes, with success or error."},
  {9004, 1, Access::kUnlock, ValueKind::kInteger, 0.0, 9999.0, 0.0, "unlock", "", "Write the unlock code to allow writes to #500..#999, 0 to lock; reads 1 when unlocked."},
  {9005, 1, Access::kReadOnly, ValueKind::kReal, 0.0, 9.0e15, 0.0, "run_time", "us", "Time the last macro ran, from the clock the controller hands the module."},
  {9006, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 65535.0, kInterfaceVersionValue, "interface_version", "", "Version of this register map."},
  {9007, 1, Access::kReadOnly, ValueKind::kInteger, 0.0, 255.0, 0.0, "access_fault", "", "Why the last refused register access was refused (see access_faults)."},
};
// clang-format on

static_assert(map_is_well_formed(kRegisterMap), "kRegisterMap: unsorted, overlapping or inconsistent entry");

inline constexpr std::size_t kRegisterMapSize = sizeof(kRegisterMap) / sizeof(kRegisterMap[0]);
inline constexpr std::size_t kVariableCount = variable_count(kRegisterMap);

constexpr const VarInfo* find_var(std::uint16_t number) {
  return find_in(kRegisterMap, kRegisterMapSize, number);
}

namespace detail {
// The slot of each entry's first variable: the running sum of the counts before it.
constexpr std::array<std::size_t, kRegisterMapSize> first_slots() {
  std::array<std::size_t, kRegisterMapSize> slots{};
  std::size_t slot = 0;
  for (std::size_t i = 0; i < kRegisterMapSize; ++i) {
    slots[i] = slot;
    slot += kRegisterMap[i].count;
  }
  return slots;
}
inline constexpr std::array<std::size_t, kRegisterMapSize> kFirstSlot = first_slots();
}  // namespace detail

// Position of #number in a flat array of every variable of the map (blocks
// expanded, table order); kVariableCount when the number is not defined.
// A binary search plus a table look-up: it runs on every variable access.
constexpr std::size_t slot_of(std::uint16_t number) {
  const VarInfo* v = find_var(number);
  if (v == nullptr) return kVariableCount;
  return detail::kFirstSlot[static_cast<std::size_t>(v - kRegisterMap)] + (number - v->number);
}

constexpr bool is_persistent(const VarInfo& v) {
  return v.access == Access::kConfig || v.access == Access::kPersistent;
}

constexpr std::size_t persistent_count() {
  std::size_t n = 0;
  for (const VarInfo& v : kRegisterMap) {
    if (is_persistent(v)) n += v.count;
  }
  return n;
}
inline constexpr std::size_t kPersistentCount = persistent_count();

constexpr bool is_defined(std::uint16_t number) { return slot_of(number) < kVariableCount; }

static_assert(is_defined(var::kCmd) && is_defined(var::kAccessFault) && is_defined(var::kLevelOtherReachable));
static_assert(is_defined(var::kMaxDirectionSigma) && is_defined(var::kG59 + 5) && !is_defined(var::kG59 + 6));
static_assert(!is_defined(10), "#10 (letter G) is not an argument");
static_assert(slot_of(var::kAccessFault) == kVariableCount - 1);

}  // namespace trueaxis::macros
