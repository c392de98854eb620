#!/usr/bin/env bash
# The operator demo: builds the host programs if needed (every trueaxis-*, so that
# the commands of README.md and docs/GUIDE.md work after it), starts trueaxis-sim
# on a free port with a temporary NV file, runs trueaxis-level (probe, level,
# verify), stops the sim and exits with the client's code (0 when the true
# residual tilt after leveling is within 3 sigma of the module's uncertainty).
#
# usage: methods/level/demo.sh [--bin-dir DIR] [-- extra trueaxis-sim options]
#   --bin-dir DIR  use the programs in DIR and build nothing (ctest does this)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin_dir=""
sim_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin-dir) bin_dir="$2"; shift 2 ;;
    --) shift; sim_args=("$@"); break ;;
    *) echo "usage: $0 [--bin-dir DIR] [-- trueaxis-sim options]" >&2; exit 2 ;;
  esac
done

if [ -z "$bin_dir" ]; then
  bash "$root/toolchain/setup.sh"
  cmake -S "$root" -B "$root/build/host" -G Ninja >/dev/null
  cmake --build "$root/build/host" --target trueaxis-programs
  bin_dir="$root/build/host/bin"
fi

source "$root/toolchain/sim_session.sh"
start_sim "$bin_dir" "${sim_args[@]}"
echo "demo: trueaxis-sim (pid $sim_pid) $sim_line"

set +e
"$bin_dir/trueaxis-level" --port "$port"
code=$?
set -e
exit "$code"
