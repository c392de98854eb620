#include "trueaxis/modbus/modbus_rtu.hpp"

#include <array>

namespace trueaxis::modbus {

namespace {

constexpr std::size_t kMinFrameBytes = 4;  // address, function code, CRC

// CRC-16/MODBUS one byte at a time: the table holds the eight shift-and-xor
// steps of the reflected polynomial 0xA001 for each value of the low byte.
constexpr std::array<std::uint16_t, 256> make_crc_table() {
  std::array<std::uint16_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t crc = i;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ 0xA001u : crc >> 1;
    table[i] = static_cast<std::uint16_t>(crc);
  }
  return table;
}

constexpr std::array<std::uint16_t, 256> kCrcTable = make_crc_table();

std::uint8_t valid_address(std::uint8_t address) {
  return address >= 1 && address <= kRtuMaxAddress ? address : std::uint8_t{1};
}

}  // namespace

std::uint16_t crc16_modbus(const std::uint8_t* data, std::size_t length) {
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < length; ++i) {
    crc = static_cast<std::uint16_t>((crc >> 8) ^ kCrcTable[(crc ^ data[i]) & 0xFFu]);
  }
  return crc;
}

ModbusRtu::ModbusRtu(ModbusCore& core, hal::Clock& clock, std::uint8_t address, std::uint32_t baud)
    : core_(core),
      clock_(clock),
      address_(valid_address(address)),
      character_us_(rtu_character_us(baud)),
      silence_us_(rtu_silence_us(baud)) {}

bool ModbusRtu::set_address(std::uint8_t address) {
  if (address < 1 || address > kRtuMaxAddress) return false;
  address_ = address;
  return true;
}

std::size_t ModbusRtu::receive(std::uint8_t byte, std::uint8_t* reply) {
  const std::uint64_t now = clock_.now_us();
  std::size_t reply_bytes = 0;
  // Convention 3: the silence before this byte, never negative.
  const std::uint64_t since_last = now - last_byte_us_;
  if (length_ > 0 && since_last >= std::uint64_t{character_us_} + silence_us_) reply_bytes = end_frame(reply);
  last_byte_us_ = now;
  if (length_ < kRtuMaxFrameBytes) frame_[length_] = byte;
  if (length_ <= kRtuMaxFrameBytes) ++length_;  // one past the buffer marks an over-long frame
  return reply_bytes;
}

std::size_t ModbusRtu::poll(std::uint8_t* reply) {
  if (length_ == 0) return 0;
  const std::uint64_t since_last = clock_.now_us() - last_byte_us_;
  if (since_last < std::uint64_t{character_us_} + silence_us_) return 0;
  return end_frame(reply);
}

std::size_t ModbusRtu::end_frame(std::uint8_t* reply) {
  const std::size_t n = length_;
  length_ = 0;
  if (n > kRtuMaxFrameBytes) {
    ++counters_.too_long;
    return 0;
  }
  if (n < kMinFrameBytes) {
    ++counters_.too_short;
    return 0;
  }
  const std::uint16_t crc = static_cast<std::uint16_t>(frame_[n - 2] | (frame_[n - 1] << 8));
  if (crc16_modbus(frame_, n - 2) != crc) {
    ++counters_.bad_crc;
    return 0;
  }
  const std::uint8_t to = frame_[0];
  const std::uint8_t* pdu = frame_ + 1;
  const std::size_t pdu_bytes = n - 3;
  if (to == kRtuBroadcast) {
    if (pdu[0] == kFcReadHolding || pdu[0] == kFcReadWriteMultiple) {
      ++counters_.ignored_reads;
      return 0;
    }
    ++counters_.broadcasts;
    static_cast<void>(core_.respond(pdu, pdu_bytes, reply + 1, macros::kRtuMaster));  // executed, never answered
    return 0;
  }
  if (to != address_) {
    ++counters_.other_address;
    return 0;
  }
  ++counters_.served;
  reply[0] = address_;
  const std::size_t reply_pdu = core_.respond(pdu, pdu_bytes, reply + 1, macros::kRtuMaster);
  const std::uint16_t reply_crc = crc16_modbus(reply, 1 + reply_pdu);
  reply[1 + reply_pdu] = static_cast<std::uint8_t>(reply_crc);
  reply[2 + reply_pdu] = static_cast<std::uint8_t>(reply_crc >> 8);
  return 3 + reply_pdu;
}

}  // namespace trueaxis::modbus
