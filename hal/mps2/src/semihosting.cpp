#include "trueaxis/hal/mps2/semihosting.hpp"

namespace trueaxis::hal::mps2 {
namespace {

constexpr std::uint32_t kSysWriteC = 0x03;
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysExitExtended = 0x20;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026;

std::uint32_t semihost_call(std::uint32_t operation, const void* argument) {
  std::uint32_t result;
  asm volatile(
      "mov r0, %1\n"
      "mov r1, %2\n"
      "bkpt 0xAB\n"
      "mov %0, r0\n"
      : "=r"(result)
      : "r"(operation), "r"(argument)
      : "r0", "r1", "memory");
  return result;
}

}  // namespace

void console_write(const char* text) { static_cast<void>(semihost_call(kSysWrite0, text)); }

void console_write_char(char c) { static_cast<void>(semihost_call(kSysWriteC, &c)); }

void console_write_uint(std::uint64_t value) {
  char digits[21];
  std::size_t i = sizeof(digits) - 1;
  digits[i] = '\0';
  do {
    digits[--i] = static_cast<char>('0' + static_cast<int>(value % 10));
    value /= 10;
  } while (value != 0);
  console_write(&digits[i]);
}

void exit_program(int code) {
  const std::uint32_t block[2] = {kAdpStoppedApplicationExit, static_cast<std::uint32_t>(code)};
  for (;;) static_cast<void>(semihost_call(kSysExitExtended, block));
}

}  // namespace trueaxis::hal::mps2
