#!/usr/bin/env bash
# Every test: installs what is missing, builds for the host and for the Cortex-M7,
# runs the host tests and the target tests (under QEMU) with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."

bash toolchain/setup.sh

cmake -S . -B build/host -G Ninja
cmake --build build/host
ctest --test-dir build/host --output-on-failure -j 2

cmake -S . -B build/target -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchain/arm-none-eabi.cmake
cmake --build build/target
ctest --test-dir build/target --output-on-failure

# The libFuzzer targets (ASan + UBSan, clang) for a bounded time each: any crash
# or sanitizer finding fails (tests/fuzz/README.md; a long run: toolchain/fuzz.sh --long).
bash toolchain/fuzz.sh
