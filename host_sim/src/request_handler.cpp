#include "trueaxis/sim/request_handler.hpp"

namespace trueaxis::sim {

using macros::AccessFault;
using macros::ModbusException;

namespace {

constexpr std::uint8_t kReadHolding = 0x03;
constexpr std::uint8_t kWriteSingle = 0x06;
constexpr std::uint8_t kWriteMultiple = 0x10;
constexpr std::uint8_t kReadWriteMultiple = 0x17;

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

}  // namespace

ModbusException RequestHandler::handle(const std::uint8_t* pdu, std::size_t length, std::uint16_t* image) {
  if (length < 1) return ModbusException::kIllegalDataValue;
  switch (pdu[0]) {
    case kReadHolding: return read_holding(pdu, length, image);
    case kWriteMultiple: return write_multiple(pdu, length);
    case kReadWriteMultiple: return read_write_multiple(pdu, length, image);
    case kWriteSingle: return write_single(length);
    default: break;
  }
  return modbus_exception(vars_.fault(AccessFault::kBadFunction));
}

// FC3 read holding registers
//   request:  | 0x03 | address u16 | quantity u16 |
//   response: | 0x03 | byte count u8 = 2 quantity | quantity x register u16 |
ModbusException RequestHandler::read_holding(const std::uint8_t* pdu, std::size_t length, std::uint16_t* image) {
  if (length < 5) return ModbusException::kIllegalDataValue;
  return read_into(be16(pdu + 1), be16(pdu + 3), image);
}

// FC16 write multiple registers
//   request:  | 0x10 | address u16 | quantity u16 | byte count u8 | quantity x register u16 |
//   response: | 0x10 | address u16 | quantity u16 |
ModbusException RequestHandler::write_multiple(const std::uint8_t* pdu, std::size_t length) {
  if (length < 6) return ModbusException::kIllegalDataValue;
  const std::uint16_t quantity = be16(pdu + 3);
  if (pdu[5] != 2u * quantity || length < 6u + 2u * quantity) return ModbusException::kIllegalDataValue;
  return write_from(be16(pdu + 1), quantity, pdu + 6);
}

// FC23 read/write multiple registers (the write is done before the read)
//   request:  | 0x17 | read address u16 | read quantity u16 | write address u16 |
//             | write quantity u16 | byte count u8 | write quantity x register u16 |
//   response: | 0x17 | byte count u8 = 2 read quantity | read quantity x register u16 |
ModbusException RequestHandler::read_write_multiple(const std::uint8_t* pdu, std::size_t length,
                                                    std::uint16_t* image) {
  if (length < 10) return ModbusException::kIllegalDataValue;
  const std::uint16_t write_quantity = be16(pdu + 7);
  if (pdu[9] != 2u * write_quantity || length < 10u + 2u * write_quantity) {
    return ModbusException::kIllegalDataValue;
  }
  // The read range is checked before the write is applied, so a request whose
  // read would be refused changes nothing.
  const ModbusException checked = read_into(be16(pdu + 1), be16(pdu + 3), image);
  if (checked != ModbusException::kNone) return checked;
  const ModbusException e = write_from(be16(pdu + 5), write_quantity, pdu + 10);
  if (e != ModbusException::kNone) return e;
  return read_into(be16(pdu + 1), be16(pdu + 3), image);
}

void RequestHandler::prepare_read_write_reply(std::uint8_t* pdu, std::size_t length, const std::uint16_t* image) {
  if (length < 10 || pdu[0] != kReadWriteMultiple) return;
  const std::uint32_t read_first = be16(pdu + 1);
  const std::uint32_t read_end = read_first + be16(pdu + 3);
  const std::uint32_t write_first = be16(pdu + 5);
  const std::uint16_t write_quantity = be16(pdu + 7);
  for (std::uint32_t i = 0; i < write_quantity && 10u + 2u * i + 1u < length; ++i) {
    const std::uint32_t reg = write_first + i;
    if (reg < read_first || reg >= read_end) continue;
    pdu[10 + 2 * i] = static_cast<std::uint8_t>(image[reg] >> 8);
    pdu[11 + 2 * i] = static_cast<std::uint8_t>(image[reg]);
  }
}

// FC6 write single register
//   request:  | 0x06 | address u16 | value u16 |
//   response: exception 02 always: one register is never a whole variable.
ModbusException RequestHandler::write_single(std::size_t length) {
  if (length < 5) return ModbusException::kIllegalDataValue;
  return modbus_exception(vars_.fault(AccessFault::kMisaligned));
}

ModbusException RequestHandler::read_into(std::uint16_t address, std::uint16_t quantity, std::uint16_t* image) {
  if (static_cast<std::size_t>(address) + quantity > kImageRegisters) {
    return modbus_exception(vars_.fault(AccessFault::kUndefined));
  }
  return modbus_exception(macros::read_registers(vars_, address, quantity, image + address));
}

ModbusException RequestHandler::write_from(std::uint16_t address, std::uint16_t quantity, const std::uint8_t* bytes) {
  std::uint16_t words[macros::kMaxVariablesPerWrite * macros::kRegistersPerVariable];
  if (quantity > sizeof words / sizeof words[0]) {
    return modbus_exception(vars_.fault(AccessFault::kMisaligned));
  }
  for (std::uint16_t i = 0; i < quantity; ++i) words[i] = be16(bytes + 2 * i);
  return modbus_exception(macros::write_registers(vars_, address, quantity, words));
}

}  // namespace trueaxis::sim
