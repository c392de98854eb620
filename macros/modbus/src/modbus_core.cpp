#include "trueaxis/modbus/modbus_core.hpp"

#include <algorithm>

namespace trueaxis::modbus {

namespace {

// Quantity limits of the Modbus Application Protocol V1.1b3 (6.3, 6.12, 6.17).
constexpr std::uint16_t kMaxReadQuantity = 0x7D;
constexpr std::uint16_t kMaxWriteQuantity = 0x7B;
constexpr std::uint16_t kMaxReadWriteWriteQuantity = 0x79;

// Protocol addresses 0..0xFFFF.
constexpr std::size_t kRegisterSpace = 65536;

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

void put_be16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}

}  // namespace

std::size_t ModbusCore::respond(const std::uint8_t* pdu, std::size_t length, std::uint8_t* response,
                                ClientId client) {
  client_ = client;
  ReadWords read;
  const ModbusException e = decide(pdu, length, read);
  const std::uint8_t fc = length > 0 ? pdu[0] : 0;
  if (e != ModbusException::kNone) {
    response[0] = static_cast<std::uint8_t>(fc | 0x80);
    response[1] = static_cast<std::uint8_t>(e);
    return 2;
  }
  response[0] = fc;
  if (fc == kFcWriteMultiple) {  // echo of address and quantity
    std::copy(pdu + 1, pdu + 5, response + 1);
    return 5;
  }
  response[1] = static_cast<std::uint8_t>(2 * read.count);
  for (std::uint16_t i = 0; i < read.count; ++i) put_be16(response + 2 + 2 * i, read.words[i]);
  return 2u + 2u * read.count;
}

ModbusException ModbusCore::decide(const std::uint8_t* pdu, std::size_t length, ReadWords& read) {
  if (length < 1) return ModbusException::kIllegalDataValue;
  switch (pdu[0]) {
    case kFcReadHolding: return read_holding(pdu, length, read);
    case kFcWriteMultiple: return write_multiple(pdu, length);
    case kFcReadWriteMultiple: return read_write_multiple(pdu, length, read);
    case kFcWriteSingle: return write_single(length);
    default: break;
  }
  return modbus_exception(vars_.fault(AccessFault::kBadFunction));
}

// FC3 read holding registers
//   request:  | 0x03 | address u16 | quantity u16 |
//   response: | 0x03 | byte count u8 = 2 quantity | quantity x register u16 |
ModbusException ModbusCore::read_holding(const std::uint8_t* pdu, std::size_t length, ReadWords& read) {
  if (length != 5) return ModbusException::kIllegalDataValue;
  const std::uint16_t address = be16(pdu + 1);
  const std::uint16_t quantity = be16(pdu + 3);
  if (quantity < 1 || quantity > kMaxReadQuantity) return ModbusException::kIllegalDataValue;
  const ModbusException range = past_last_register(address, quantity);
  if (range != ModbusException::kNone) return range;
  return read_into(address, quantity, read);
}

// FC16 write multiple registers
//   request:  | 0x10 | address u16 | quantity u16 | byte count u8 | quantity x register u16 |
//   response: | 0x10 | address u16 | quantity u16 |
ModbusException ModbusCore::write_multiple(const std::uint8_t* pdu, std::size_t length) {
  if (length < 6) return ModbusException::kIllegalDataValue;
  const std::uint16_t address = be16(pdu + 1);
  const std::uint16_t quantity = be16(pdu + 3);
  const std::size_t byte_count = pdu[5];
  if (quantity < 1 || quantity > kMaxWriteQuantity || byte_count != 2u * quantity || length != 6u + byte_count) {
    return ModbusException::kIllegalDataValue;
  }
  const ModbusException range = past_last_register(address, quantity);
  if (range != ModbusException::kNone) return range;
  return write_from(address, quantity, pdu + 6);
}

// FC23 read/write multiple registers (the write is done before the read)
//   request:  | 0x17 | read address u16 | read quantity u16 | write address u16 |
//             | write quantity u16 | byte count u8 | write quantity x register u16 |
//   response: | 0x17 | byte count u8 = 2 read quantity | read quantity x register u16 |
ModbusException ModbusCore::read_write_multiple(const std::uint8_t* pdu, std::size_t length, ReadWords& read) {
  if (length < 10) return ModbusException::kIllegalDataValue;
  const std::uint16_t read_address = be16(pdu + 1);
  const std::uint16_t read_quantity = be16(pdu + 3);
  const std::uint16_t write_address = be16(pdu + 5);
  const std::uint16_t write_quantity = be16(pdu + 7);
  const std::size_t byte_count = pdu[9];
  if (read_quantity < 1 || read_quantity > kMaxReadQuantity || write_quantity < 1 ||
      write_quantity > kMaxReadWriteWriteQuantity || byte_count != 2u * write_quantity ||
      length != 10u + byte_count) {
    return ModbusException::kIllegalDataValue;
  }
  ModbusException e = past_last_register(read_address, read_quantity);
  if (e == ModbusException::kNone) e = past_last_register(write_address, write_quantity);
  // The read range is checked before the write is applied, so a request whose
  // read would be refused changes nothing.
  if (e == ModbusException::kNone) e = read_into(read_address, read_quantity, read);
  if (e == ModbusException::kNone) e = write_from(write_address, write_quantity, pdu + 10);
  if (e == ModbusException::kNone) e = read_into(read_address, read_quantity, read);
  return e;
}

// FC6 write single register
//   request:  | 0x06 | address u16 | value u16 |
//   response: exception 02 always: one register is never a whole variable.
ModbusException ModbusCore::write_single(std::size_t length) {
  if (length != 5) return ModbusException::kIllegalDataValue;
  return modbus_exception(vars_.fault(AccessFault::kMisaligned));
}

ModbusException ModbusCore::past_last_register(std::uint16_t address, std::uint16_t quantity) {
  if (static_cast<std::size_t>(address) + quantity <= kRegisterSpace) return ModbusException::kNone;
  return modbus_exception(vars_.fault(AccessFault::kUndefined));
}

ModbusException ModbusCore::read_into(std::uint16_t address, std::uint16_t quantity, ReadWords& read) {
  const ModbusException e = modbus_exception(read_registers(vars_, address, quantity, read.words, client_));
  if (e == ModbusException::kNone) {
    read.address = address;
    read.count = quantity;
  }
  return e;
}

ModbusException ModbusCore::write_from(std::uint16_t address, std::uint16_t quantity, const std::uint8_t* bytes) {
  std::uint16_t words[kMaxWriteQuantity];
  for (std::uint16_t i = 0; i < quantity; ++i) words[i] = be16(bytes + 2 * i);
  return modbus_exception(write_registers(vars_, address, quantity, words, client_));
}

}  // namespace trueaxis::modbus
