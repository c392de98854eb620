# Cross toolchain: arm-none-eabi GCC for the Cortex-M7 of the MPS2 AN500 board,
# run under QEMU (qemu-system-arm -M mps2-an500).
#
# Conventions
#  1. Every C, C++ and assembly file is built for -mcpu=cortex-m7 with the
#     double-precision FPU (fpv5-d16, hard-float ABI, Thumb-2), one section per
#     function and per object so --gc-sections drops what nothing uses.
#  2. C++ is built without exceptions, RTTI or thread-safe statics (bare metal,
#     one thread: the guards would only pull libsupc++'s abort path in).
#  3. No heap. Every executable is linked with the allocator entry points of
#     newlib and libsupc++ wrapped (--wrap=SYM turns a reference to SYM into a
#     reference to __wrap_SYM, which nothing defines), so an image that calls
#     malloc, new, printf or anything else that allocates fails to link.
#     tests/target proves it with the heap_canary image.
#  4. The board itself (vector table, start-up, linker script mps2-an500.ld,
#     semihosting) comes with the library trueaxis_hal_mps2 (hal/mps2/).
#  5. CMAKE_CROSSCOMPILING_EMULATOR runs an image under QEMU with semihosting, so
#     add_test(COMMAND <executable target>) runs it like a host test; the image's
#     semihosting exit code is QEMU's exit code.
#  6. CMake's compiler checks build a static library, never a linked image (the
#     image would need the board library).

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar CACHE FILEPATH "")
set(CMAKE_RANLIB arm-none-eabi-ranlib CACHE FILEPATH "")
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")

set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(TRUEAXIS_CPU_FLAGS "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb")
set(CMAKE_C_FLAGS_INIT "${TRUEAXIS_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${TRUEAXIS_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_ASM_FLAGS_INIT "${TRUEAXIS_CPU_FLAGS}")

set(TRUEAXIS_NO_HEAP_LINK_FLAGS
    "-Wl,--wrap=malloc,--wrap=free,--wrap=calloc,--wrap=realloc,--wrap=_malloc_r,--wrap=_free_r,--wrap=_calloc_r,--wrap=_realloc_r,--wrap=_sbrk,--wrap=_sbrk_r")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,--gc-sections ${TRUEAXIS_NO_HEAP_LINK_FLAGS}")

# Nothing of the host but programs (the emulator, size) is found.
set(CMAKE_FIND_ROOT_PATH /usr/lib/arm-none-eabi)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# ctest appends the image's path after -kernel.
set(CMAKE_CROSSCOMPILING_EMULATOR
    qemu-system-arm;-M;mps2-an500;-nographic;-monitor;none;-serial;none;-semihosting;-no-reboot;-kernel)
