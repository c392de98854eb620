#!/usr/bin/env bash
# Every test: installs what is missing, builds for the host and for the Cortex-M7,
# runs the host tests and the target tests (under QEMU) with ctest; the LinuxCNC
# scenarios run beside the Cortex-M7 part.
set -euo pipefail
cd "$(dirname "$0")/.."

bash toolchain/setup.sh

cmake -S . -B build/host -G Ninja
cmake --build build/host
ctest --test-dir build/host --output-on-failure -j 2 -E '^linuxcnc_scenario_'

# The full-LinuxCNC scenarios (tests/linuxcnc/README.md) mostly wait on the
# simulated machine's motion: they run one at a time beside the Cortex-M7 build
# and tests, and their result is taken at the end.
scenario_log="$(mktemp)"
ctest --test-dir build/host --output-on-failure -R '^linuxcnc_scenario_' >"$scenario_log" 2>&1 &
scenarios=$!
trap 'kill "$scenarios" 2>/dev/null || true; rm -f "$scenario_log"' EXIT

cmake -S . -B build/target -G Ninja -DCMAKE_TOOLCHAIN_FILE=toolchain/arm-none-eabi.cmake
cmake --build build/target
ctest --test-dir build/target --output-on-failure

scenario_status=0
wait "$scenarios" || scenario_status=$?
trap - EXIT
cat "$scenario_log"
rm -f "$scenario_log"
if [ "$scenario_status" -ne 0 ]; then
  echo "test.sh: the LinuxCNC scenarios failed (above)" >&2
  exit 1
fi

# The libFuzzer targets (ASan + UBSan, clang) for a bounded time each: any crash
# or sanitizer finding fails (tests/fuzz/README.md; a long run: toolchain/fuzz.sh --long).
bash toolchain/fuzz.sh
