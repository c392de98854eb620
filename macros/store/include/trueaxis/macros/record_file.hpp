// A stored record as a file: how a controller's calibration table leaves the
// module for a consumer that cannot read its storage (the LinuxCNC
// kinematics, integrations/linuxcnc/kins). Pure bytes in, bytes out: no I/O,
// no heap, so a real-time module's start can check a file with it.
//
// Layout (integers little-endian), N the payload's length:
//   0    8   "TRUEAXIS"
//   8    2   layout version = 1
//   10   1   the record's key (records.hpp: 3 the rigidity table, 5 the spindle model)
//   11   1   reserved, 0
//   12   4   N
//   16   N   the payload: the record's bytes exactly as the module stores them
//   16+N 4   CRC-32 (keyed_store.hpp's) of bytes 0 .. 16+N-1
// Size: N + 20.
#pragma once

#include <cstddef>
#include <cstdint>

namespace trueaxis::macros {

inline constexpr std::size_t kRecordFileOverhead = 20;
inline constexpr std::uint16_t kRecordFileVersion = 1;

// Why a file is refused (record_file_text names each in one line).
enum class RecordFileError : std::uint8_t {
  kNone = 0,
  kNotAFile,      // shorter than the overhead, or not starting with the magic
  kVersion,       // a layout version this build does not read
  kWrongRecord,   // another record's key
  kLength,        // N disagrees with the file's size: truncated or extended
  kChecksum,      // the CRC does not match: damaged
};

// What a refusal means, one line without a trailing period.
const char* record_file_text(RecordFileError e);

// Writes the file of record `key` with payload[0, length) into out[0,
// capacity); returns its size, or 0 when it does not fit.
std::size_t encode_record_file(std::uint8_t key, const std::uint8_t* payload, std::size_t length, std::uint8_t* out,
                               std::size_t capacity);

// Checks file[0, size) as record `key`'s; on kNone, payload and length name
// the payload inside `file`.
RecordFileError decode_record_file(std::uint8_t key, const std::uint8_t* file, std::size_t size,
                                   const std::uint8_t*& payload, std::size_t& length);

}  // namespace trueaxis::macros
