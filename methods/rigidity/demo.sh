#!/usr/bin/env bash
# The M3 demo: the integrator's rigidity flow and the operator's leveling on the
# calibrated machine, against trueaxis-sim with its realistic errors (A and C
# location errors, an A positioning error, a tilt-dependent deflection of the C
# table):
#   1. measure the calibration ball at 7 A poses x 36 C positions (trueaxis-measure-ball);
#   2. build the rigidity table in the module and store it (trueaxis-calibrate
#      rigidity --store), with the JSON and the report page;
#   3. level an inclined face on the ideal axes (before) and on the calibrated
#      axes (after), each from the table at zero, each checked against the
#      simulator's ground truth.
# Exit 0 when the calibrated leveling is within 3 sigma of the truth and the
# ideal one is not (the machine's errors are real and the table removes them).
#
# usage: methods/rigidity/demo.sh [--bin-dir DIR] [--keep DIR]
#   --bin-dir DIR  use the programs in DIR and build nothing (ctest does this)
#   --keep DIR     write the samples, the JSON and the report into DIR and keep them
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin_dir=""
keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --bin-dir) bin_dir="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) echo "usage: $0 [--bin-dir DIR] [--keep DIR]" >&2; exit 2 ;;
  esac
done

if [ -z "$bin_dir" ]; then
  bash "$root/toolchain/setup.sh"
  cmake -S "$root" -B "$root/build/host" -G Ninja >/dev/null
  cmake --build "$root/build/host" --target trueaxis-programs
  bin_dir="$root/build/host/bin"
fi

source "$root/toolchain/sim_session.sh"
start_sim "$bin_dir" --errors realistic --face-tilt 40 --face-azimuth 30
out_dir="${keep:-$work}"
mkdir -p "$out_dir"
echo "demo: trueaxis-sim (pid $sim_pid, realistic errors) $sim_line"

echo
echo "== 1. measure the calibration ball"
"$bin_dir/trueaxis-measure-ball" --port "$port" --out "$out_dir/samples.csv"

echo
echo "== 2. build and store the rigidity table (trueaxis-calibrate rigidity --store)"
"$bin_dir/trueaxis-calibrate" rigidity --in "$out_dir/samples.csv" --json "$out_dir/rigidity.json" \
  --report "$out_dir/report" --store --port "$port"
/usr/bin/python3 - "$out_dir/rigidity.json" "$out_dir/report/module_figures.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.update(json.load(open(sys.argv[2])))
print(f"  A axis point {', '.join(f'{v:.4f}' for v in d['a_axis']['point_mm'])} mm, "
      f"C-to-A offset {d['c_to_a_offset_mm'] * 1000:.1f} um, squareness {d['c_to_a_squareness_arcsec']:.1f}\"")
print("  A (deg)   rigidity (arcsec)   A positioning error (arcsec)")
for p in d["poses"]:
    print(f"  {p['a_deg']:7.1f}   {p['rigidity_arcsec']:6.2f} +- {p['rigidity_sigma_arcsec']:4.2f}"
          f"        {p['a_positioning_error_arcsec']:7.2f}")
PY
if [ -n "$keep" ]; then echo "  report: $out_dir/report/index.html"; fi

echo
echo "== 3a. level the face on the ideal axes (before)"
set +e
"$bin_dir/trueaxis-level" --port "$port" --axes ideal --home 1
ideal=$?
echo
echo "== 3b. level the face on the calibrated axes (after)"
"$bin_dir/trueaxis-level" --port "$port" --axes calibrated --home 1
calibrated=$?
set -e

echo
if [ "$calibrated" -eq 0 ] && [ "$ideal" -eq 1 ]; then
  echo "demo: PASS: the ideal axes leave the face tilted beyond 3 sigma, the calibrated axes level it within 3 sigma"
  exit 0
fi
echo "demo: FAIL: ideal-axis leveling exit $ideal (expected 1), calibrated exit $calibrated (expected 0)" >&2
exit 1
