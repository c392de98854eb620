// The Modbus protocol core of trueaxis-sim: one request PDU in, the decision out.
// Knows nothing of sockets or of libmodbus; the TCP server (modbus_server.hpp)
// strips the MBAP header, calls handle(), and answers with modbus_reply over the
// register image this fills, or with modbus_reply_exception(code).
//
// Contract
//  1. `pdu` is the function code and its data (no MBAP header), `length` bytes.
//  2. `image` is a 65536-register image indexed by protocol address. For a read,
//     handle() fills the registers read from the variables (register_codec.hpp)
//     so that a reply built from the image carries them; nothing else in it is
//     meaningful.
//  3. Returns ModbusException::kNone when the request was carried out, else the
//     exception to answer with; in that case the variables are unchanged and the
//     fault is noted (#9007).
//  4. Served: FC3, FC16, FC23 (write first, then read, as the standard says).
//     FC6 can never write a whole variable: exception 02. Any other function
//     code: exception 01. A PDU shorter than its function needs, or whose byte
//     count disagrees with its quantity, is exception 03.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/register_codec.hpp"
#include "trueaxis/macros/variable_access.hpp"

namespace trueaxis::sim {

inline constexpr std::size_t kImageRegisters = 65536;

class RequestHandler {
 public:
  explicit RequestHandler(macros::VariableAccess& vars) : vars_(vars) {}

  [[nodiscard]] macros::ModbusException handle(const std::uint8_t* pdu, std::size_t length, std::uint16_t* image);

  // libmodbus's modbus_reply answers FC23 by writing the request's words into the
  // image and reading the image back, so an overlap of the two ranges would echo
  // the written words (#9004 would read the code, not 1). After a successful
  // handle(), this overwrites the request's written words inside the read range
  // with what the read produced. Other function codes are left alone.
  static void prepare_read_write_reply(std::uint8_t* pdu, std::size_t length, const std::uint16_t* image);

 private:
  macros::ModbusException read_holding(const std::uint8_t* pdu, std::size_t length, std::uint16_t* image);
  macros::ModbusException write_multiple(const std::uint8_t* pdu, std::size_t length);
  macros::ModbusException read_write_multiple(const std::uint8_t* pdu, std::size_t length, std::uint16_t* image);
  macros::ModbusException write_single(std::size_t length);

  macros::ModbusException read_into(std::uint16_t address, std::uint16_t quantity, std::uint16_t* image);
  macros::ModbusException write_from(std::uint16_t address, std::uint16_t quantity, const std::uint8_t* bytes);

  macros::VariableAccess& vars_;
};

}  // namespace trueaxis::sim
