// Start-up of the MPS2 AN500 image: the vector table, Reset_Handler and the fault
// handlers. Memory layout and symbols: toolchain/mps2-an500.ld.
#include <cstdint>

#include "trueaxis/hal/mps2/semihosting.hpp"

extern "C" {
// Linker-script symbols (toolchain/mps2-an500.ld).
extern std::uint32_t __data_load__[];
extern std::uint32_t __data_start__[];
extern std::uint32_t __data_end__[];
extern std::uint32_t __bss_start__[];
extern std::uint32_t __bss_end__[];
extern std::uint32_t __stack_top__[];
extern void (*__preinit_array_start[])();
extern void (*__preinit_array_end[])();
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();

void Reset_Handler();
void SysTick_Handler();
void trueaxis_mps2_init();
[[noreturn]] void trueaxis_mps2_exit(int code);
[[noreturn]] void trueaxis_mps2_fault();
void __cxa_pure_virtual();
}

namespace {

using Vector = void (*)();

constexpr int kFaultExitCode = 70;  // distinct from a test failure's 1

}  // namespace

// Runs before any C++ object exists and before main: .data, .bss, then the
// constructors (the init arrays, walked here: no crti/_init, no newlib crt0).
extern "C" void trueaxis_mps2_init() {
  const std::uint32_t* src = __data_load__;
  for (std::uint32_t* dst = __data_start__; dst < __data_end__; ++dst, ++src) *dst = *src;
  for (std::uint32_t* dst = __bss_start__; dst < __bss_end__; ++dst) *dst = 0;
  for (Vector* f = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (Vector* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

extern "C" void trueaxis_mps2_exit(int code) { trueaxis::hal::mps2::exit_program(code); }

// The FPU is switched on (CPACR: CP10 and CP11 full access) before any code
// that the compiler may have given a floating-point instruction. main is called
// from assembly: C++ forbids calling it.
extern "C" __attribute__((naked, noreturn)) void Reset_Handler() {
  asm volatile(
      "movw r0, #0xED88\n"
      "movt r0, #0xE000\n"
      "ldr r1, [r0]\n"
      "orr r1, r1, #(0xF << 20)\n"
      "str r1, [r0]\n"
      "dsb\n"
      "isb\n"
      "bl trueaxis_mps2_init\n"
      "bl main\n"
      "b trueaxis_mps2_exit\n");
}

extern "C" void trueaxis_mps2_fault() {
  trueaxis::hal::mps2::console_write("trueaxis: fault or unexpected exception\n");
  trueaxis::hal::mps2::exit_program(kFaultExitCode);
}

// A call through a vtable slot of an abstract class: a bug, never data.
extern "C" void __cxa_pure_virtual() { trueaxis_mps2_fault(); }

namespace {

void default_handler() { trueaxis_mps2_fault(); }

}  // namespace

// The vector table: the initial stack pointer, then the Cortex-M7 system
// exceptions, then the board's interrupts (none used; all fault). A struct, so the
// stack pointer needs no cast and the whole table is constant-initialised.
struct VectorTable {
  std::uint32_t* initial_sp;
  Vector handlers[15 + 32];
};

extern "C" __attribute__((section(".isr_vector"), used)) const VectorTable trueaxis_mps2_vector_table = {
    __stack_top__,
    {
        Reset_Handler,
        default_handler,  // NMI
        default_handler,  // HardFault
        default_handler,  // MemManage
        default_handler,  // BusFault
        default_handler,  // UsageFault
        nullptr, nullptr, nullptr, nullptr,
        default_handler,  // SVCall
        default_handler,  // DebugMonitor
        nullptr,
        default_handler,  // PendSV
        SysTick_Handler,
        default_handler, default_handler, default_handler, default_handler, default_handler, default_handler,
        default_handler, default_handler, default_handler, default_handler, default_handler, default_handler,
        default_handler, default_handler, default_handler, default_handler, default_handler, default_handler,
        default_handler, default_handler, default_handler, default_handler, default_handler, default_handler,
        default_handler, default_handler, default_handler, default_handler, default_handler, default_handler,
        default_handler, default_handler,
    },
};
