// ARM semihosting on the MPS2 board: console output and program exit through the
// debugger (QEMU with -semihosting), the only I/O the test and bench images use.
//
// Contract
//  1. Each call is one `bkpt 0xAB` with the operation in r0 and its argument in
//     r1 (Semihosting for AArch32 and AArch64, v2.0). Without a debugger attached
//     the breakpoint faults: these are for QEMU and the bench, never production.
//  2. No allocation, no stdio: newlib's printf allocates and is never linked.
//  3. exit_program ends QEMU with `code` as its exit status (SYS_EXIT_EXTENDED,
//     reason ADP_Stopped_ApplicationExit, supported by QEMU 7.2).
#pragma once

#include <cstdint>

namespace trueaxis::hal::mps2 {

// Writes a NUL-terminated string to the debugger's console (SYS_WRITE0).
void console_write(const char* text);

// Writes one character to the debugger's console (SYS_WRITEC).
void console_write_char(char c);

// Writes `value` in decimal (no allocation, no printf).
void console_write_uint(std::uint64_t value);

// Ends the program; QEMU exits with status `code` (0 = success).
[[noreturn]] void exit_program(int code);

}  // namespace trueaxis::hal::mps2
