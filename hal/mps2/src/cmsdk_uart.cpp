#include "trueaxis/hal/mps2/cmsdk_uart.hpp"

namespace trueaxis::hal::mps2 {
namespace {

constexpr std::uintptr_t kData = 0x00;
constexpr std::uintptr_t kState = 0x04;
constexpr std::uintptr_t kCtrl = 0x08;
constexpr std::uintptr_t kIntClear = 0x0C;
constexpr std::uintptr_t kBaudDiv = 0x10;

constexpr std::uint32_t kStateTxFull = 1u << 0;
constexpr std::uint32_t kStateRxFull = 1u << 1;
constexpr std::uint32_t kStateRxOverrun = 1u << 3;
constexpr std::uint32_t kCtrlTxEnable = 1u << 0;
constexpr std::uint32_t kCtrlRxEnable = 1u << 1;
constexpr std::uint32_t kMinBaudDiv = 16;

}  // namespace

CmsdkUart::CmsdkUart(std::uintptr_t base, std::uint32_t baud, std::uint32_t pclk_hz) : base_(base) {
  reg(kCtrl) = 0;
  const std::uint32_t div = baud == 0 ? kMinBaudDiv : pclk_hz / baud;
  reg(kBaudDiv) = div < kMinBaudDiv ? kMinBaudDiv : div;
  reg(kState) = 0xF;      // clear both overruns
  reg(kIntClear) = 0xF;   // and any interrupt status
  reg(kCtrl) = kCtrlTxEnable | kCtrlRxEnable;
}

volatile std::uint32_t& CmsdkUart::reg(std::uintptr_t offset) const {
  return *reinterpret_cast<volatile std::uint32_t*>(base_ + offset);
}

bool CmsdkUart::read(std::uint8_t& byte) {
  const std::uint32_t state = reg(kState);
  if ((state & kStateRxOverrun) != 0) {
    ++rx_overruns_;
    reg(kState) = kStateRxOverrun;
  }
  if ((state & kStateRxFull) == 0) return false;
  byte = static_cast<std::uint8_t>(reg(kData));
  return true;
}

void CmsdkUart::write(const std::uint8_t* bytes, std::size_t length) {
  for (std::size_t i = 0; i < length; ++i) {
    while ((reg(kState) & kStateTxFull) != 0) {
    }
    reg(kData) = bytes[i];
  }
}

}  // namespace trueaxis::hal::mps2
