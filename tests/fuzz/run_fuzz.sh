#!/usr/bin/env bash
# Runs the libFuzzer targets of tests/fuzz for a bounded time each, from the
# checked-in seeds, and fails on any crash, sanitizer finding, time-out or leak.
# Used by ctest fuzz_smoke and toolchain/fuzz.sh.
#
#   run_fuzz.sh --bin-dir DIR --work-dir DIR --seconds N [--runs N] [--parallel]
#               [TARGET...]
#
# Without TARGETs: every fuzz_*.cpp of this directory (ctest fuzz_smoke passes
# the list of tests/fuzz/CMakeLists.txt).
#
# Each target reads tests/fuzz/corpus/<name>/ (never written) and keeps what it
# finds in WORK/<name>/corpus; a reproducer lands in WORK/<name>/ as
# crash-*, leak-*, timeout-* or oom-* (replay: bin/<target> FILE). The last
# lines are one row per target: executions, executions per second, result.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bin_dir="" work_dir="" seconds=20 runs=-1 parallel=0 targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin-dir) bin_dir="$2"; shift 2 ;;
    --work-dir) work_dir="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --parallel) parallel=1; shift ;;
    -*) echo "run_fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
if [ -z "$bin_dir" ] || [ -z "$work_dir" ]; then
  echo "usage: run_fuzz.sh --bin-dir DIR --work-dir DIR --seconds N [--runs N] [--parallel] [TARGET...]" >&2
  exit 2
fi
if [ "${#targets[@]}" -eq 0 ]; then
  for source in "$here"/fuzz_*.cpp; do targets+=("$(basename "$source" .cpp)"); done
fi

# The largest input each target reads in full (its format's natural bound).
max_len() {
  case "$1" in
    fuzz_modbus_core) echo 4096 ;;      # 16 requests of up to 255 bytes
    fuzz_tcp_framer) echo 8192 ;;       # 32 chunks of up to 255 bytes
    fuzz_keyed_store) echo 32768 ;;     # several slots of up to 4 KiB
    fuzz_rtu_framer) echo 4096 ;;       # ~2,000 bytes on the line, several frames
    *) echo 4096 ;;                     # one record of up to 3544 bytes
  esac
}

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

run_one() {
  local name="$1" dir="$work_dir/$1"
  mkdir -p "$dir/corpus"
  local status=0
  "$bin_dir/$name" -max_total_time="$seconds" -runs="$runs" -max_len="$(max_len "$name")" \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$dir/" \
    "$dir/corpus" "$here/corpus/${name#fuzz_}" > "$dir/log" 2>&1 || status=$?
  echo "$status" > "$dir/status"
}

mkdir -p "$work_dir"
for name in "${targets[@]}"; do
  if [ "$parallel" -eq 1 ]; then run_one "$name" & else run_one "$name"; fi
done
wait

failed=0 total=0
printf '%-22s %14s %10s  %s\n' target executions exec/s result
for name in "${targets[@]}"; do
  dir="$work_dir/$name"
  status="$(cat "$dir/status")"
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)"
  rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/log" | tail -1)"
  artifacts="$(find "$dir" -maxdepth 1 -name 'crash-*' -o -maxdepth 1 -name 'leak-*' \
    -o -maxdepth 1 -name 'timeout-*' -o -maxdepth 1 -name 'oom-*' | head -1)"
  result=ok
  if [ "$status" != 0 ] || [ -n "$artifacts" ]; then
    result="FAILED (exit $status) ${artifacts:-see $dir/log}"
    failed=1
    grep -E 'ERROR|runtime error|invariant failed|SUMMARY' "$dir/log" | head -5 >&2 || true
  fi
  total=$((total + ${execs:-0}))
  printf '%-22s %14s %10s  %s\n' "$name" "${execs:-?}" "${rate:-?}" "$result"
done
printf '%-22s %14s\n' total "$total"
exit "$failed"
