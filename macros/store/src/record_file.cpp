#include "trueaxis/macros/record_file.hpp"

#include <cstring>

#include "trueaxis/core/byte_order.hpp"
#include "trueaxis/macros/keyed_store.hpp"

namespace trueaxis::macros {

namespace {

constexpr char kMagic[8] = {'T', 'R', 'U', 'E', 'A', 'X', 'I', 'S'};

}  // namespace

const char* record_file_text(RecordFileError e) {
  switch (e) {
    case RecordFileError::kNone:
      return "a valid record file";
    case RecordFileError::kNotAFile:
      return "not a trueaxis record file (it does not start with TRUEAXIS, or is shorter than its header)";
    case RecordFileError::kVersion:
      return "a record file layout this build does not read";
    case RecordFileError::kWrongRecord:
      return "the file holds another record than the one expected (a spindle file given for a rigidity table?)";
    case RecordFileError::kLength:
      return "its length disagrees with its header: truncated or extended";
    case RecordFileError::kChecksum:
      return "its CRC-32 does not match: the file is damaged";
  }
  return "unknown";
}

std::size_t encode_record_file(std::uint8_t key, const std::uint8_t* payload, std::size_t length, std::uint8_t* out,
                               std::size_t capacity) {
  if (out == nullptr || (payload == nullptr && length > 0) || length > 0xFFFFFFFFu ||
      capacity < length + kRecordFileOverhead) {
    return 0;
  }
  std::memcpy(out, kMagic, sizeof kMagic);
  core::put_u16(out + 8, kRecordFileVersion);
  out[10] = key;
  out[11] = 0;
  core::put_u32(out + 12, static_cast<std::uint32_t>(length));
  if (length > 0) std::memcpy(out + 16, payload, length);
  core::put_u32(out + 16 + length, checksum::crc32(out, 16 + length));
  return length + kRecordFileOverhead;
}

RecordFileError decode_record_file(std::uint8_t key, const std::uint8_t* file, std::size_t size,
                                   const std::uint8_t*& payload, std::size_t& length) {
  if (file == nullptr || size < kRecordFileOverhead || std::memcmp(file, kMagic, sizeof kMagic) != 0) {
    return RecordFileError::kNotAFile;
  }
  if (core::get_u16(file + 8) != kRecordFileVersion || file[11] != 0) return RecordFileError::kVersion;
  if (file[10] != key) return RecordFileError::kWrongRecord;
  const std::size_t n = core::get_u32(file + 12);
  if (n != size - kRecordFileOverhead) return RecordFileError::kLength;
  if (core::get_u32(file + 16 + n) != checksum::crc32(file, 16 + n)) return RecordFileError::kChecksum;
  payload = file + 16;
  length = n;
  return RecordFileError::kNone;
}

}  // namespace trueaxis::macros
