// The measuring log (docs/INTERFACE.md "The measuring log"): what a machine
// was measured to be, when, and what became of it. Every calibration (a build
// with R = 0), store (R = 1), check and refused calibration or store of a
// method that logs appends one entry to kLogEntries in one persistent record
// (records.hpp), so the controller keeps years of checks beside the tables
// they judged.
//
// Conventions
//  1. An entry: its serial (1, 2, ...: one more than the newest's; never 0),
//     the time (Unix seconds, UTC: #9015 as the client wrote it with the
//     macro, else the clock's wall time (hal/clock.hpp), else 0, unknown),
//     the macro, its type (calibration, check or refusal), its verdict (a check's,
//     check.hpp; kNoVerdict for a calibration), whether it stored its table,
//     the sequence of the method's stored table after it (the table a check
//     judged against; 0 none), and up to kLogFigures figures: kind (the
//     method's kLogFigures for a calibration, its kCheck figures for a
//     check, numbered from 1), item (pose, sub-machine, 1-based; 0 the
//     whole; a pose of the table the entry carries the sequence of: M3's
//     check names the stored table's pose it judged against, CheckFigure::
//     log_item, so a reader asks that table for its A), value (a check's deviation), its 1-sigma and the tolerance
//     (0 for a calibration's). A check logs, per kind, its worst figure (the
//     largest (|deviation| + 2 sigma) / tolerance). A refusal (a method's
//     compute macro that a gate refused, or whose store was refused as
//     table_locked) has as its first figure kind 0, the refusal: item, value
//     and limit as #9012..#9014 give them (the item a byte: where #9012 is
//     not a whole number 0..255, the method's own, Refusal::log_item; M4's
//     change gate logs its angle's step, angle / 10 + 1), and the status code
//     in place of the sigma; the figures the macro had logged follow it.
//  2. A store, a check or a refusal that follows its own method's
//     calibration, with no other entry between, replaces that calibration's
//     entry (the same serial): "measured, then stored", "measured, then
//     checked" and "measured, then refused" are one entry each. After a
//     restart nothing is replaced.
//  3. The record's payload is the entries, oldest first, kLogEntryBytes each,
//     little-endian:
//       0  u32 serial          4  u32 time (s)        8  u16 macro
//      10  u8 type (0 calibration, 1 check, 2 refusal)   11  u8 verdict (0 pass, 1 warn, 2 fail, 255 none)
//      12  u8 stored (0, 1)   13  u8 figures (0..6)  14  u32 table sequence
//      18  6 x { u8 kind, u8 item, f32 value, f32 sigma, f32 tolerance } (14 bytes each)
//     Binary32 holds a logged figure to 7 digits. Appending writes the whole
//     record again through the keyed store: a power cut at any byte leaves
//     the log as it was or with the new entry, never a torn one.
//  4. A payload that is not a whole number of valid entries (count, type,
//     verdict, serials rising) is treated as empty: the next append starts a
//     new log (the module counts it in #9019 with the lost appends).
//  5. What is kept when the log is full. Each entry has a rank: 3 the stored
//     calibration of its method's present table (its table sequence is the
//     table's), 2 a check of that table, 1 any other stored calibration or
//     check (the history), 0 a calibration that stored nothing and a refusal
//     (scratch). An append to a full log drops the oldest entry of the lowest
//     rank; when the new entry ranks below every entry held, it is the one
//     not kept. So scratch runs, any number of them, never push out a stored
//     calibration or a check, and the present table's entry and its checks
//     outlast the history.
//  No allocation, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "trueaxis/core/byte_order.hpp"

namespace trueaxis::macros {

inline constexpr std::size_t kLogEntries = 32;
inline constexpr std::size_t kLogFigures = 6;
inline constexpr std::size_t kLogFigureBytes = 14;
inline constexpr std::size_t kLogEntryBytes = 18 + kLogFigures * kLogFigureBytes;
inline constexpr std::size_t kLogBytes = kLogEntries * kLogEntryBytes;
inline constexpr std::uint8_t kNoVerdict = 255;

enum class LogType : std::uint8_t { kCalibration = 0, kCheck = 1, kRefusal = 2 };
inline constexpr std::uint8_t kRefusalFigure = 0;  // convention 1: a refusal's own figure

struct LogFigure {
  std::uint8_t kind = 0;
  std::uint8_t item = 0;
  float value = 0.0F;
  float sigma = 0.0F;
  float tolerance = 0.0F;
};

struct LogEntry {
  std::uint32_t serial = 0;
  std::uint32_t time_s = 0;
  std::uint16_t macro = 0;
  LogType type = LogType::kCalibration;
  std::uint8_t verdict = kNoVerdict;
  bool stored = false;
  std::uint32_t table_sequence = 0;
  std::uint8_t figure_count = 0;
  LogFigure figures[kLogFigures] = {};

  // Adds a figure (kind from 1); beyond kLogFigures it is dropped. An item
  // over 255 is logged as 255.
  void add(std::uint16_t kind, std::size_t item, double value, double sigma, double tolerance = 0.0) {
    if (figure_count >= kLogFigures) return;
    figures[figure_count++] = {static_cast<std::uint8_t>(kind), static_cast<std::uint8_t>(item > 255 ? 255 : item),
                               static_cast<float>(value), static_cast<float>(sigma), static_cast<float>(tolerance)};
  }
};

namespace log_codec {

inline void put_f32(std::uint8_t* p, float v) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  core::put_u32(p, bits);
}
inline float get_f32(const std::uint8_t* p) {
  const std::uint32_t bits = core::get_u32(p);
  float v = 0.0F;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

// Convention 3: one entry into out[0, kLogEntryBytes).
inline void encode(const LogEntry& e, std::uint8_t* out) {
  core::put_u32(out, e.serial);
  core::put_u32(out + 4, e.time_s);
  core::put_u16(out + 8, e.macro);
  out[10] = static_cast<std::uint8_t>(e.type);
  out[11] = e.verdict;
  out[12] = e.stored ? 1 : 0;
  out[13] = e.figure_count;
  core::put_u32(out + 14, e.table_sequence);
  for (std::size_t k = 0; k < kLogFigures; ++k) {
    std::uint8_t* f = out + 18 + k * kLogFigureBytes;
    const LogFigure& g = e.figures[k];
    f[0] = g.kind;
    f[1] = g.item;
    put_f32(f + 2, g.value);
    put_f32(f + 6, g.sigma);
    put_f32(f + 10, g.tolerance);
  }
}

// True for bytes that are an entry (convention 4), read in place.
inline bool valid(const std::uint8_t* in) {
  return core::get_u32(in) != 0 && in[10] <= 2 && (in[11] <= 2 || in[11] == kNoVerdict) && in[12] <= 1 &&
         in[13] <= kLogFigures;
}

// One entry from in[0, kLogEntryBytes); false for bytes that are no entry.
inline bool decode(const std::uint8_t* in, LogEntry& e) {
  e.serial = core::get_u32(in);
  e.time_s = core::get_u32(in + 4);
  e.macro = core::get_u16(in + 8);
  e.type = static_cast<LogType>(in[10]);
  e.verdict = in[11];
  e.stored = in[12] != 0;
  e.figure_count = in[13];
  e.table_sequence = core::get_u32(in + 14);
  for (std::size_t k = 0; k < kLogFigures; ++k) {
    const std::uint8_t* f = in + 18 + k * kLogFigureBytes;
    e.figures[k] = {f[0], f[1], get_f32(f + 2), get_f32(f + 6), get_f32(f + 10)};
  }
  return valid(in);
}

// The register window's values of the entry at `entry` (#9020..#9027, then
// #9030 + 5 k: kind, item, value, sigma, tolerance), or zeros for nullptr, read
// in place (no LogEntry on the stack: a register write's stack bound is small).
inline void window(const std::uint8_t* entry, double* head, double* figures, std::size_t values_per_figure) {
  const bool held_entry = entry != nullptr;
  head[0] = held_entry ? static_cast<double>(core::get_u32(entry)) : 0.0;
  head[1] = held_entry ? static_cast<double>(core::get_u32(entry + 4)) : 0.0;
  head[2] = held_entry ? static_cast<double>(core::get_u16(entry + 8)) : 0.0;
  head[3] = held_entry ? static_cast<double>(entry[10]) : 0.0;
  head[4] = !held_entry ? 0.0 : entry[11] == kNoVerdict ? -1.0 : static_cast<double>(entry[11]);
  head[5] = held_entry ? static_cast<double>(entry[12]) : 0.0;
  head[6] = held_entry ? static_cast<double>(core::get_u32(entry + 14)) : 0.0;
  const std::size_t count = held_entry ? entry[13] : 0;
  head[7] = static_cast<double>(count);
  for (std::size_t k = 0; k < kLogFigures; ++k) {
    double* out = figures + k * values_per_figure;
    const std::uint8_t* f = k < count ? entry + 18 + k * kLogFigureBytes : nullptr;
    out[0] = f != nullptr ? f[0] : 0.0;
    out[1] = f != nullptr ? f[1] : 0.0;
    out[2] = f != nullptr ? static_cast<double>(get_f32(f + 2)) : 0.0;
    out[3] = f != nullptr ? static_cast<double>(get_f32(f + 6)) : 0.0;
    out[4] = f != nullptr ? static_cast<double>(get_f32(f + 10)) : 0.0;
  }
}

// The entries of a payload of `length` bytes (convention 4: 0 when it is not
// a valid log).
inline std::size_t count(const std::uint8_t* payload, std::size_t length) {
  if (length % kLogEntryBytes != 0 || length > kLogBytes) return 0;
  const std::size_t n = length / kLogEntryBytes;
  std::uint32_t last = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* entry = payload + i * kLogEntryBytes;
    if (!valid(entry) || (i > 0 && core::get_u32(entry) <= last)) return 0;
    last = core::get_u32(entry);
  }
  return n;
}

// The serial of entry i (0-based, oldest first).
inline std::uint32_t serial_at(const std::uint8_t* payload, std::size_t i) {
  return core::get_u32(payload + i * kLogEntryBytes);
}

// Entry i's type, stored flag, macro and table sequence, read in place.
inline LogType type_at(const std::uint8_t* payload, std::size_t i) {
  return static_cast<LogType>(payload[i * kLogEntryBytes + 10]);
}
inline bool stored_at(const std::uint8_t* payload, std::size_t i) { return payload[i * kLogEntryBytes + 12] != 0; }
inline std::uint16_t macro_at(const std::uint8_t* payload, std::size_t i) {
  return core::get_u16(payload + i * kLogEntryBytes + 8);
}
inline std::uint32_t sequence_at(const std::uint8_t* payload, std::size_t i) {
  return core::get_u32(payload + i * kLogEntryBytes + 14);
}

// The n entries less entry i (the later ones moved up); returns n - 1.
inline std::size_t remove(std::uint8_t* payload, std::size_t n, std::size_t i) {
  std::memmove(payload + i * kLogEntryBytes, payload + (i + 1) * kLogEntryBytes, (n - 1 - i) * kLogEntryBytes);
  return n - 1;
}

// The payload after adding `e` to the n valid entries in payload (capacity
// kLogBytes): in place of the newest when `replace_newest` (e keeps its
// serial), else after it, the oldest dropped at kLogEntries. Returns the new
// length in bytes.
inline std::size_t add(std::uint8_t* payload, std::size_t n, const LogEntry& e, bool replace_newest) {
  if (replace_newest && n > 0) {
    encode(e, payload + (n - 1) * kLogEntryBytes);
    return n * kLogEntryBytes;
  }
  if (n == kLogEntries) {
    std::memmove(payload, payload + kLogEntryBytes, (kLogEntries - 1) * kLogEntryBytes);
    --n;
  }
  encode(e, payload + n * kLogEntryBytes);
  return (n + 1) * kLogEntryBytes;
}

}  // namespace log_codec

}  // namespace trueaxis::macros
