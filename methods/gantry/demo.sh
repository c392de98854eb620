#!/usr/bin/env bash
# The M2 demo: the integrator's gantry flow on the virtual gantry (realistic
# errors: squareness, A-to-C offsets and angles, a bowed gantry, four
# sub-machines), and the controller's point conversion on what it stored:
#   1. measure the gantry with the virtual laser tracker (trueaxis-measure-gantry,
#      with the ground truth beside the samples);
#   2. compute and store the frames in the module (trueaxis-calibrate gantry
#      --store), with the JSON and the report page;
#   3. check each sub-machine's origin against the truth, in mm and in units of
#      its own origin_sigma_mm;
#   4. convert one workpiece point (global frame) into every sub-machine's program
#      coordinates through macro 9825 over Modbus (mbpoll) and hold it against
#      the truth's global_T_sub.
# Exit 0 when every origin is within 3 sigma of the truth and every converted
# point within 3 of its sigma; 1 otherwise.
#
# The converted point's sigma is first order and radial, like origin_sigma_mm:
# sqrt(origin_sigma^2 + sx^2 (qy^2 + qz^2) + sy^2 (qx^2 + qz^2) + sz^2 (qx^2 + qy^2)),
# q the point in the sub-machine's frame and sx, sy, sz the frame's angle sigmas
# (radians) about its own axes, from the report's module_figures.json (the
# origin-rotation correlation is left out).
#
# usage: methods/gantry/demo.sh [--bin-dir DIR] [--keep DIR] [--seed N]
#   --bin-dir DIR  use the programs in DIR and build nothing (ctest does this)
#   --keep DIR     write the samples, the truth, the JSON and the report into DIR and keep them
#   --seed N       the tracker's noise seed (default 1)
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$root/toolchain/sim_session.sh"
demo_start "$@"

echo
echo "== 1. measure the virtual gantry with the laser tracker"
"$bin_dir/trueaxis-measure-gantry" --out "$out_dir/samples.csv" --machine "$out_dir/machine.csv" \
  --truth "$out_dir/truth.json" --seed "$seed"

echo
echo "== 2. compute and store the frames (trueaxis-calibrate gantry --store)"
"$bin_dir/trueaxis-calibrate" gantry --in "$out_dir/samples.csv" --machine "$out_dir/machine.csv" \
  --json "$out_dir/gantry.json" --report "$out_dir/report" --store --port "$port"
if [ -n "$keep" ]; then echo "  report: $out_dir/report/index.html"; fi

echo
echo "== 3-4. origins against the truth; a workpiece point through macro 9825"
/usr/bin/python3 - "$port" "$out_dir/gantry.json" "$out_dir/report/module_figures.json" "$out_dir/truth.json" \
  "$root/toolchain" <<'PY'
import json, math, sys

port, out_path, figures_path, truth_path = sys.argv[1:5]
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, sys.argv[5])
from mbpoll_vars import Vars  # noqa: E402

out = json.load(open(out_path))
figures = {f["id"]: f for f in json.load(open(figures_path))["sub_machine_figures"]}
truth = {s["id"]: s for s in json.load(open(truth_path))["sub_machines"]}
ARCSEC = math.pi / (180.0 * 3600.0)
module = Vars(port)  # variables over Modbus with mbpoll
write, read, run_macro = module.write, module.read, module.run_macro


def to_sub(t, p):
    """A global point into a sub-machine's frame through global_T_sub (row-major)."""
    d = [p[i] - t[4 * i + 3] for i in range(3)]
    return [sum(t[4 * i + j] * d[i] for i in range(3)) for j in range(3)]


point = [400.0, 1100.0, 150.0]  # a workpiece point on the bed, global frame (mm)
print(f"  workpiece point {', '.join(f'{v:.1f}' for v in point)} mm (global frame)")
print("  sub   origin error (mm)   origin    point error (mm)   point     converted by 9825 (mm)")
print("        (sigma, mm)         /sigma    (sigma, mm)        /sigma")
worst_origin = worst_point = 0.0
for s in out["sub_machines"]:
    n = s["id"]
    true = truth[n]
    origin_err = math.dist(s["origin_mm"], true["origin_mm"])
    origin_k = origin_err / s["origin_sigma_mm"]
    write(20, [n])                      # T
    write(24, point)                    # X, Y, Z
    code = run_macro(9825)
    if code != 0:
        sys.exit(f"demo: 9825 for sub-machine {n} failed with module error {code}")
    got = read(100, 3)
    want = to_sub(true["global_T_sub"], point)
    q = to_sub(s["global_T_sub"], point)
    sx, sy, sz = (a * ARCSEC for a in figures[n]["angle_sigma_arcsec"])
    sigma = math.sqrt(s["origin_sigma_mm"] ** 2 + sx * sx * (q[1] ** 2 + q[2] ** 2)
                      + sy * sy * (q[0] ** 2 + q[2] ** 2) + sz * sz * (q[0] ** 2 + q[1] ** 2))
    point_err = math.dist(got, want)
    point_k = point_err / sigma
    worst_origin = max(worst_origin, origin_k)
    worst_point = max(worst_point, point_k)
    print(f"  sp{n}   {origin_err:.4f} ({s['origin_sigma_mm']:.4f})    {origin_k:5.2f}     "
          f"{point_err:.4f} ({sigma:.4f})    {point_k:5.2f}     {', '.join(f'{v:.4f}' for v in got)}")
    if math.dist(got, q) > 1e-6:
        sys.exit(f"demo: 9825 for sub-machine {n} disagrees with OUT.json's global_T_sub")

print(f"  worst: origin {worst_origin:.2f} sigma, converted point {worst_point:.2f} sigma")
if worst_origin > 3.0 or worst_point > 3.0:
    print("demo: FAIL: an origin or a converted point is off by more than 3 sigma", file=sys.stderr)
    sys.exit(1)
PY

echo
echo "demo: PASS: every origin and every converted point within 3 sigma of the truth"
