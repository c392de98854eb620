// Modbus RTU framing over the protocol core (modbus_core.hpp): bytes of a serial
// line in, reply frames out. Knows nothing of a UART; the board's server loop
// (tests/target/rtu_server_main.cpp on mps2) moves the bytes. Firmware side: no
// allocation, no exceptions, no clock but the one it is handed.
//
// Conventions (Modbus over Serial Line V1.02, 2.5.1 and 2.5.1.1)
//  1. A frame is | address u8 | PDU (function code, data) | CRC u16 |, at most
//     256 bytes; the CRC is CRC-16/MODBUS (polynomial 0xA001 reflected, initial
//     0xFFFF, no final xor) over address and PDU, sent low byte first.
//  2. A character is 11 bits on the line (start, 8 data, parity or a second
//     stop, stop) whatever the parity setting, so one character lasts
//     11 / baud s. The silence that ends a frame is 3.5 characters up to
//     19200 baud and a fixed 1750 us above; rtu_silence_us() rounds it up to a
//     whole microsecond (19200 baud: 2005.2 us -> 2006 us).
//  3. Time: the clock handed to the constructor (microseconds) is read once for
//     each byte received and once per poll() while a frame is open (never when
//     none is); the framer reads no other. A
//     byte's time is when it was taken from the UART, which is taken as the
//     end of its stop bit; the silence before a byte is its time minus the
//     previous byte's time minus one character. A poll() at time t sees a
//     silence of t minus the last byte's time minus one character (a character
//     that started before t and has not ended is not yet silence).
//  4. A frame ends at the first silence of at least rtu_silence_us(): in
//     receive(), when the byte after the silence arrives (the byte then opens
//     the next frame), or in poll(). The 1.5-character rule inside a frame is
//     not applied (as libmodbus and nanoMODBUS do): a frame torn by a gap of
//     1.5..3.5 characters fails its CRC instead.
//  5. A frame that ended is discarded silently, and counted, when it is shorter
//     than 4 bytes, longer than 256 bytes, fails its CRC, or is for another
//     address. Address 0 is broadcast: a read (function code 3 or 23) is
//     ignored without reaching the core; any other request is handed to the
//     core (so a write is executed) and its reply dropped. A frame for this
//     slave's address is handed to ModbusCore::respond and its reply framed.
//  6. The reply (address, PDU, CRC) is written into the caller's buffer of
//     kRtuMaxFrameBytes; receive() and poll() return its length, 0 when no reply
//     is due. The caller sends it before it feeds the next byte.
//  7. The slave address is 1..247; set_address() refuses anything else and
//     keeps the one it had.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/hal/clock.hpp"
#include "trueaxis/modbus/modbus_core.hpp"

namespace trueaxis::modbus {

inline constexpr std::size_t kRtuMaxFrameBytes = 256;
inline constexpr std::uint8_t kRtuBroadcast = 0;
inline constexpr std::uint8_t kRtuMaxAddress = 247;

// CRC-16/MODBUS of `length` bytes (convention 1), table-driven.
[[nodiscard]] std::uint16_t crc16_modbus(const std::uint8_t* data, std::size_t length);

// One character on the line in microseconds, rounded up (convention 2).
constexpr std::uint32_t rtu_character_us(std::uint32_t baud) { return (11'000'000u + baud - 1u) / baud; }

// The silence that ends a frame in microseconds, rounded up (convention 2).
constexpr std::uint32_t rtu_silence_us(std::uint32_t baud) {
  return baud > 19200u ? 1750u : (38'500'000u + baud - 1u) / baud;
}

// Frames seen since construction, by what became of them.
struct RtuCounters {
  std::uint32_t served = 0;         // addressed to this slave, answered
  std::uint32_t broadcasts = 0;     // broadcast requests handed to the core
  std::uint32_t ignored_reads = 0;  // broadcast reads, ignored
  std::uint32_t other_address = 0;  // for another slave
  std::uint32_t bad_crc = 0;
  std::uint32_t too_short = 0;  // fewer than 4 bytes
  std::uint32_t too_long = 0;   // more than kRtuMaxFrameBytes
};

class ModbusRtu {
 public:
  // baud > 0; address 1..247 (a bad one is replaced by 1).
  ModbusRtu(ModbusCore& core, hal::Clock& clock, std::uint8_t address, std::uint32_t baud);

  // One byte taken from the line (conventions 3, 4, 6).
  [[nodiscard]] std::size_t receive(std::uint8_t byte, std::uint8_t* reply);

  // Ends the frame in progress if the silence since its last byte is long
  // enough (conventions 3, 4, 6).
  [[nodiscard]] std::size_t poll(std::uint8_t* reply);

  // Convention 7: false (address unchanged) unless 1..247.
  bool set_address(std::uint8_t address);
  std::uint8_t address() const { return address_; }
  std::uint32_t silence_us() const { return silence_us_; }
  // True while a frame has begun and not yet ended.
  bool receiving() const { return length_ > 0; }
  const RtuCounters& counters() const { return counters_; }

 private:
  std::size_t end_frame(std::uint8_t* reply);

  ModbusCore& core_;
  hal::Clock& clock_;
  std::uint8_t address_;
  std::uint32_t character_us_;
  std::uint32_t silence_us_;
  std::uint64_t last_byte_us_ = 0;
  std::size_t length_ = 0;  // bytes of the frame in progress, counted past the buffer
  RtuCounters counters_;
  std::uint8_t frame_[kRtuMaxFrameBytes] = {};
};

}  // namespace trueaxis::modbus
