#include "trueaxis/hal/mps2/systick_clock.hpp"

namespace trueaxis::hal::mps2 {
namespace {

// SysTick registers (ARMv7-M Architecture Reference Manual, B3.3).
constexpr std::uintptr_t kSystCsr = 0xE000E010;  // control and status
constexpr std::uintptr_t kSystRvr = 0xE000E014;  // reload value
constexpr std::uintptr_t kSystCvr = 0xE000E018;  // current value
constexpr std::uint32_t kCsrEnable = 1u << 0;
constexpr std::uint32_t kCsrTickInt = 1u << 1;
constexpr std::uint32_t kCsrClkSource = 1u << 2;  // 1: the processor clock
constexpr std::uint32_t kReload = 0x00FFFFFF;
constexpr std::uint64_t kTicksPerWrap = std::uint64_t{kReload} + 1;

volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// Written only by SysTick_Handler: the one piece of state the exception needs.
volatile std::uint32_t g_wraps = 0;

}  // namespace

SysTickClock::SysTickClock(std::uint32_t cpu_hz) : cpu_hz_(cpu_hz) {
  reg(kSystCsr) = 0;
  g_wraps = 0;
  reg(kSystRvr) = kReload;
  reg(kSystCvr) = 0;  // any write clears the counter and COUNTFLAG
  reg(kSystCsr) = kCsrEnable | kCsrTickInt | kCsrClkSource;
}

std::uint64_t SysTickClock::ticks() const {
  std::uint32_t wraps = g_wraps;
  std::uint32_t count = reg(kSystCvr);
  for (std::uint32_t again = g_wraps; again != wraps; again = g_wraps) {
    wraps = again;
    count = reg(kSystCvr);
  }
  return std::uint64_t{wraps} * kTicksPerWrap + (kReload - count);
}

std::uint64_t SysTickClock::do_now_us() {
  const std::uint64_t t = ticks();
  const std::uint64_t hz = cpu_hz_;
  return (t / hz) * 1'000'000u + (t % hz) * 1'000'000u / hz;
}

}  // namespace trueaxis::hal::mps2

// The SysTick exception (vector 15); startup.cpp's vector table refers to it.
extern "C" void SysTick_Handler();
extern "C" void SysTick_Handler() {
  trueaxis::hal::mps2::g_wraps = trueaxis::hal::mps2::g_wraps + 1;
}
