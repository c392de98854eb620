#!/usr/bin/env bash
# The LinuxCNC demo: an operator levels a workpiece face from LinuxCNC.
# LinuxCNC (headless, `linuxcnc -r`, as the user toolchain/setup.sh creates) runs
# the simulated cradle machine of integrations/linuxcnc/sim, whose probe trips on
# trueaxis-sim's face (tilted 12.5 deg); the operator's program
#   o<trueaxis_level> call [-30] [-30] [30] [-30] [-30] [30] [100] [60] [10] [100] [2] [0.003] [3]
# probes three points with G38.2, runs macro 9810 in the module through G65,
# turns the table to the answer and probes again. Prints the operator's view (the
# table's pose, the tilt left as the module measured it with its 1 sigma, the
# measuring log) and the simulator's truth; exit 0 when the tilt left is within
# 3 sigma (tests/linuxcnc/test_scenarios.py leveling, ctest
# linuxcnc_scenario_leveling).
#
# usage: toolchain/demo_linuxcnc.sh [--bin-dir DIR] [--keep]
#   --bin-dir DIR  use the programs in DIR and build nothing
#   --keep         keep LinuxCNC's folder (its ini, HAL file, log, var file)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin_dir=""
keep=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin-dir) bin_dir="$2"; shift 2 ;;
    --keep) keep=(--keep); shift ;;
    *) echo "usage: $0 [--bin-dir DIR] [--keep]" >&2; exit 2 ;;
  esac
done

if [ -z "$bin_dir" ]; then
  bash "$root/toolchain/setup.sh"
  cmake -S "$root" -B "$root/build/host" -G Ninja >/dev/null
  cmake --build "$root/build/host" --target trueaxis-programs
  bin_dir="$root/build/host/bin"
fi

exec /usr/bin/python3 "$root/tests/linuxcnc/test_scenarios.py" "$bin_dir" leveling "${keep[@]}"
