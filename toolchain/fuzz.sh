#!/usr/bin/env bash
# The libFuzzer targets (tests/fuzz) with ASan and UBSan: configures build/fuzz
# with Debian's clang and TRUEAXIS_FUZZ=ON, builds the targets, and runs the
# bounded smoke run (ctest fuzz_smoke: 20 s per target from the checked-in seeds).
#
#   toolchain/fuzz.sh                  the smoke run; exit code 0 when nothing was found
#   toolchain/fuzz.sh --long SECONDS   every target (tests/fuzz/fuzz_*.cpp) for SECONDS, all at once, into
#                                      build/fuzz/long (corpora kept between runs)
#   toolchain/fuzz.sh --long SECONDS TARGET...   only those targets
#
# Warnings are not errors here: this build is for the sanitizers, and clang's
# warnings differ from gcc's (the gcc build holds them at zero).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build/fuzz"

long=""
if [ "${1:-}" = "--long" ]; then
  long="${2:?--long takes the seconds per target}"
  shift 2
fi

bash "$root/toolchain/setup.sh"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DTRUEAXIS_FUZZ=ON -DTRUEAXIS_WERROR=OFF
cmake --build "$build" --target fuzz_targets

if [ -z "$long" ]; then
  cd "$build" && ctest -R '^fuzz_smoke$' --output-on-failure
else
  bash "$root/tests/fuzz/run_fuzz.sh" --bin-dir "$build/bin" --work-dir "$build/long" \
    --seconds "$long" --parallel "$@"
fi
