#!/usr/bin/python3
"""G65 through LinuxCNC's standalone interpreter: the remap of
integrations/linuxcnc against trueaxis-sim, its golden outputs and its errors.

usage: test_g65_rs274.py BIN_DIR [--regenerate]

Each case starts nothing but `rs274 -i INI -n 2 -g PROGRAM` against one
trueaxis-sim on 127.0.0.1 port 0 (its own --nv file in a temporary folder),
with an ini made from integrations/linuxcnc/trueaxis.ini (paths made absolute,
PORT the simulator's, PREVIEW = 1 unless a case says) plus the tests' own
[PYTHON] TOPLEVEL (python/: oword.py's o<dump_results>).

Golden cases (rs274/NAME.ngc, output compared line by line with
rs274/NAME.expected; --regenerate writes the .expected files):
  level_3pt  G65 P9810 on three offsets in G57..G59 (the remap converts them
             from the interpreter's machine units, inches in rs274, to mm);
             LinuxCNC's #100..#199 afterwards (o<dump_results>, repr) equal
             the module's read by trueaxis-var (17 digits), bit for bit
  preview    PREVIEW = 0 in a preview interpreter: no device I/O (#9003 and
             #100 as they were)
  level_flow o<trueaxis_level> in rs274, a preview interpreter whose probe
             never trips: every move, each touch taken at its target (a
             level face at Z 20), 9810 once, the interface given back
  rigidity_flow  o<trueaxis_rigidity> likewise: every pose and touch, 9815
             finding the nominal centres, 9831 twelve times, 9832 building
             an ideal cradle's table; again about a pivot off the origin
             ([TRUEAXIS] PIVOT_*: 9832's A axis there), without PIVOT_X (a
             stop naming it), and beside a trueaxis_kins [KINS] line with
             another pivot (the remap's stop)
Error cases: each program must stop (exit 1) with the module's code, name and
text from the register map on one line, or the remap's own sentence; under
G20 only G65 P1 and P0 pass (o<interface_seen>: #9009 1, then 0).
The work offsets' conversion (RegisterMap.work_offsets_of) on a small map
whose macro reads G54 X..C: lengths from inches, angles as they are.
Exit 0 when every check holds, 1 when one fails.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
RS274 = "/usr/bin/rs274"


class Sim:
    """trueaxis-sim on 127.0.0.1 port 0."""

    def __init__(self, bin_dir, folder):
        self.process = subprocess.Popen([os.path.join(bin_dir, "trueaxis-sim"), "--port", "0",
                                         "--nv", os.path.join(folder, "sim.nv")],
                                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        line = self.process.stdout.readline()
        found = re.search(r"listening on [0-9.]+:(\d+)", line)
        if not found:
            self.process.kill()
            sys.exit(f"test_g65_rs274: trueaxis-sim said {line!r}")
        self.port = int(found.group(1))
        self.var = [os.path.join(bin_dir, "trueaxis-var"), "--port", str(self.port)]

    def get(self, *numbers):
        done = subprocess.run(self.var + ["get"] + [str(n) for n in numbers], capture_output=True, text=True,
                              check=True)
        return {int(m.group(1)): float(m.group(2)) for m in re.finditer(r"#(\d+) = (\S+)", done.stdout)}

    def set(self, **values):
        subprocess.run(self.var + ["set"] + [f"{k[1:]}={v}" for k, v in values.items()], capture_output=True,
                       text=True, check=True)

    def stop(self):
        self.process.terminate()
        self.process.wait(timeout=10)


def make_ini(folder, port, preview=1, extra=None):
    """The shipped trueaxis.ini with absolute paths, the tests' TOPLEVEL and the
    simulator's port."""
    text = open(os.path.join(ROOT, "integrations", "linuxcnc", "trueaxis.ini"), encoding="utf-8").read()
    settings = {"PORT": str(port), "PREVIEW": str(preview), **(extra or {})}
    out = []
    for line in text.splitlines():
        key = line.split("=", 1)[0].strip()
        if key in ("SUBROUTINE_PATH", "PATH_APPEND", "MAP"):
            line = f"{key} = {os.path.join(ROOT, line.split('=', 1)[1].strip())}"
        elif key == "TOPLEVEL":
            line = f"TOPLEVEL = {os.path.join(HERE, 'python', 'toplevel.py')}"
        elif key in settings:
            line = f"{key} = {settings.pop(key)}"
        out.append(line)
        if line.strip() == "[RS274NGC]":
            out.append(f"PARAMETER_FILE = {os.path.join(folder, 'rs274.var')}")
        if line.startswith("PATH_APPEND"):
            out.append(f"PATH_APPEND = {os.path.join(HERE, 'python')}")
        if line.strip() == "[TRUEAXIS]":
            out += [f"{k} = {v}" for k, v in settings.items()]
    make_ini.count = getattr(make_ini, "count", 0) + 1
    path = os.path.join(folder, f"test{make_ini.count}.ini")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
    return path


def rs274(ini, program, folder, timeout=60):
    """(exit code, output) of the standalone interpreter on `program` (a path
    or G-code text)."""
    if "\n" in program:
        path = os.path.join(folder, "case.ngc")
        with open(path, "w", encoding="utf-8") as f:
            f.write(program)
        program = path
    # INI_FILE_NAME as `linuxcnc` sets it: the interpreter reads #<_ini[..]..> from it.
    env = dict(os.environ, TRUEAXIS_DUMP=os.path.join(folder, "dump.txt"), PYTHONDONTWRITEBYTECODE="1",
               INI_FILE_NAME=ini)
    done = subprocess.run([RS274, "-i", ini, "-n", "2", "-g", program], capture_output=True, text=True,
                          cwd=folder, env=env, timeout=timeout)
    return done.returncode, done.stdout + done.stderr


class Checks:
    def __init__(self):
        self.failures = 0

    def check(self, ok, what, detail=""):
        print(f"{'ok  ' if ok else 'FAIL'} {what}" + (f"\n     {detail}" if not ok and detail else ""))
        self.failures += 0 if ok else 1


def golden(checks, name, code, output, regenerate, expected_code=0):
    path = os.path.join(HERE, "rs274", name + ".expected")
    if regenerate:
        with open(path, "w", encoding="utf-8") as f:
            f.write(output)
    expected = open(path, encoding="utf-8").read()
    checks.check(code == expected_code and output == expected, f"{name}: exit {expected_code} and the golden output",
                 f"exit {code}; output:\n{output}")


def main(argv):
    if len(argv) < 2 or not os.path.isdir(argv[1]):
        print("usage: test_g65_rs274.py BIN_DIR [--regenerate]", file=sys.stderr)
        return 2
    regenerate = "--regenerate" in argv
    if not os.access(RS274, os.X_OK):
        print("test_g65_rs274: no /usr/bin/rs274: LinuxCNC is not installed (bash toolchain/setup.sh)",
              file=sys.stderr)
        return 1
    errors = {e["code"]: e for e in json.load(open(os.path.join(ROOT, "macros", "register_map.json")))["errors"]}
    checks = Checks()
    folder = tempfile.mkdtemp(prefix="trueaxis-rs274-")
    sim = Sim(argv[1], folder)
    try:
        run_cases(checks, sim, folder, errors, regenerate)
    finally:
        sim.stop()
        shutil.rmtree(folder, ignore_errors=True)
    print(f"test_g65_rs274: {checks.failures} failure(s)")
    return 1 if checks.failures else 0


def module_error(code, errors):
    return f"error {code} {errors[code]['name']}: {errors[code]['message']}"


# A rigidity session through G-code loops: 3 A poses of c_count C positions,
# a ball 100 mm off the C axis and 50 mm above the table, turning with C
# and A (an ideal cradle: Rx(A) Rz(C)).
RIGIDITY = """G21
G65 P9830
#<pose> = 0
o100 while [#<pose> LT 3]
  #<k> = 0
  o101 while [#<k> LT {c_count}]
    #<c> = [90 * #<k>]
    #<a> = [{first_a} + 20 * #<pose>]
    G65 P9831 A#<a> C#<c> X[100 * COS[#<c>]] Y[100 * SIN[#<c>] * COS[#<a>] - 50 * SIN[#<a>]] Z[100 * SIN[#<c>] * SIN[#<a>] + 50 * COS[#<a>]]
    #<k> = [#<k> + 1]
  o101 endwhile
  #<pose> = [#<pose> + 1]
o100 endwhile
{build}
M2
"""


def level_3pt(checks, sim, ini, folder, regenerate, label):
    """rs274/level_3pt.ngc: its golden output, and LinuxCNC's #100..#199 equal
    the module's, bit for bit."""
    dump = os.path.join(folder, "dump.txt")
    if os.path.exists(dump):
        os.remove(dump)
    code, output = rs274(ini, os.path.join(HERE, "rs274", "level_3pt.ngc"), folder)
    golden(checks, "level_3pt", code, output, regenerate)
    module = sim.get("100..199")
    dumped = {}
    if os.path.exists(dump):
        for line in open(dump, encoding="utf-8"):
            number, value = line.split(" = ")
            dumped[int(number[1:])] = float(value)
    same = len(dumped) == 100 and all(dumped[n] == module[n] for n in range(100, 200))
    differ = [n for n in range(100, 200) if dumped.get(n) != module.get(n)]
    checks.check(same, f"{label}: LinuxCNC's #100..#199 equal the module's, bit for bit",
                 f"differ at {differ[:5]}: {[(dumped.get(n), module.get(n)) for n in differ[:3]]}")
    import math
    p2 = sim.get("5301..5303")
    checks.check(abs(module[107] - 12.5) < 1e-9 and abs(p2[5301] - 50) < 1e-9
                 and abs(p2[5303] - (40 - 50 * math.tan(math.radians(12.5)))) < 1e-9,
                 f"{label}: the module got G58 in mm (rs274 keeps offsets in inches) and a tilt of 12.5 deg",
                 f"#107 = {module[107]!r}, G58 = {p2}")
    checks.check(sim.get(9009)[9009] == 0, f"{label}: G65 P0 gave the macro interface back")


def run_cases(checks, sim, folder, errors, regenerate):
    ini = make_ini(folder, sim.port)

    # 1. G65 P9810: golden, and LinuxCNC's #100..#199 equal the module's bit for bit.
    level_3pt(checks, sim, ini, folder, regenerate, "level_3pt")

    # 1b. ... while another client keeps an open connection on which it wrote
    # arguments and points moments before (an HMI beside LinuxCNC): the remap
    # waits out its 2 s hold (module.hpp contract 8), and its 9810 runs on its
    # own inputs: that client's K = -1 (not on the G65 line) does not reach it
    # (the module clears it when the interface changes hands, and the remap
    # writes every letter).
    from pymodbus.client import ModbusTcpClient
    import struct
    other = ModbusTcpClient("127.0.0.1", port=sim.port)
    other.connect()
    words = lambda *values: [w for v in values for w in struct.unpack(">4H", struct.pack(">d", v))]
    other.write_registers(4 * 6, words(-1.0), slave=1)  # K = -1 (facing down): an argument takes it
    other.write_registers(4 * 5281, words(1.0, 2.0, 3.0), slave=1)
    time.sleep(0.5)
    held = sim.get(9009)[9009]
    started = time.monotonic()
    level_3pt(checks, sim, ini, folder, False, "level_3pt beside a client that wrote 1 s before")
    checks.check(held == 2 and time.monotonic() - started < 8, "level_3pt beside that client: it held the interface "
                 "then; the program waited out its 2 s and completed", f"#9009 {held}")
    other.close()

    # 2. A preview interpreter (PREVIEW = 0) does no device I/O.
    before = sim.get(9003)[9003]
    code, output = rs274(make_ini(folder, sim.port, preview=0), os.path.join(HERE, "rs274", "preview.ngc"), folder)
    golden(checks, "preview", code, output, regenerate)
    checks.check(sim.get(9003)[9003] == before, "preview: no macro ran in the module")

    # 3. The operator programs run through in a preview interpreter (the probe
    # never trips; each touch is taken at its target), G65 talking (PREVIEW = 1).
    before = sim.get(9003)[9003]
    code, output = rs274(ini, os.path.join(HERE, "rs274", "level_flow.ngc"), folder)
    golden(checks, "level_flow", code, output, regenerate)
    after = sim.get(9003, 107, 5283, 5303, 5323)
    checks.check(after[9003] == before + 1 and after[107] == 0.0 and after[5283] == after[5303] == after[5323] == 20.0,
                 "level_flow: one 9810, on the three touches at Z 20 (a level face)", str(after))
    code, output = rs274(ini, os.path.join(HERE, "rs274", "rigidity_flow.ngc"), folder)
    golden(checks, "rigidity_flow", code, output, regenerate)
    built = sim.get(100, 101, 109)
    checks.check(built[100] == 3.0 and built[101] < 1e-6 and built[109] < 1e-9,
                 "rigidity_flow: 9832 built 3 poses of an ideal cradle from the fitted centres", str(built))

    # 3b. ... on a cradle whose pivot is off the origin ([TRUEAXIS] PIVOT_*,
    # A_OFFSET_*): the program aims at the ball turned about it, so the
    # centres 9815 finds are the nominal cradle's and 9832's A axis lies at
    # r + d, d_y across the C axis.
    pivot = {"PIVOT_X": "35", "PIVOT_Y": "-25", "PIVOT_Z": "0", "A_OFFSET_Y": "4", "A_OFFSET_Z": "-80"}
    code, output = rs274(make_ini(folder, sim.port, extra=pivot), os.path.join(HERE, "rs274", "rigidity_flow.ngc"),
                         folder)
    built = sim.get(100, 101, 103, 104, 105, 109)
    checks.check(code == 0 and built[100] == 3.0 and built[101] < 1e-6 and abs(built[103] - 35) < 1e-6
                 and abs(built[104] - (-25 + 4)) < 1e-6
                 and abs(built[105] - (0 - 80)) < 1e-6 and abs(built[109] - 4) < 1e-6,
                 "rigidity_flow about the pivot (35, -25, 0) + (0, 4, -80): 9832's A axis through X 35, Y -21, "
                 "Z -80, 4 mm across C", f"exit {code}; {built}\n{output[-600:]}")
    # ... and a program that cannot know the pivot, or whose pivot is not the
    # kinematics', stops with the sentence.
    no_pivot = make_ini(folder, sim.port)
    text = open(no_pivot, encoding="utf-8").read()
    with open(no_pivot, "w", encoding="utf-8") as f:
        f.write(re.sub(r"(?m)^PIVOT_X = .*\n", "", text))
    code, output = rs274(no_pivot, os.path.join(HERE, "rs274", "rigidity_flow.ngc"), folder)
    checks.check(code == 1 and "pivot_x" in output.lower(),
                 "rigidity_flow without [TRUEAXIS] PIVOT_X: stops, naming it", f"exit {code}; {output[-400:]}")
    mismatch = make_ini(folder, sim.port, extra=pivot)
    with open(mismatch, "a", encoding="utf-8") as f:
        f.write("[KINS]\nKINEMATICS = trueaxis_kins pivot=35,-25,0 a_offset=0,-80\n")
    code, output = rs274(mismatch, "G21\nG65 P9830\nM2\n", folder)
    checks.check(code == 1 and "are not [KINS] trueaxis_kins' pivot=" in output,
                 "a [TRUEAXIS] pivot that is not trueaxis_kins' (A offset Y 4 against 0): G65 stops with the sentence",
                 f"exit {code}; {output[-400:]}")
    same = make_ini(folder, sim.port, extra=pivot)
    with open(same, "a", encoding="utf-8") as f:
        f.write("[KINS]\nKINEMATICS = trueaxis_kins pivot=35,-25,0 a_offset=4,-80\n")
    code, output = rs274(same, "G21\nG65 P9830\nM2\n", folder)
    checks.check(code == 0, "the same pivot in both: G65 runs", f"exit {code}; {output[-400:]}")
    # An inch machine's trueaxis_kins takes the pivot in inches; with table= the
    # kinematics turn about the table's axes and take none.
    for kins in ("trueaxis_kins linear_units=inch pivot=1.3779527559055118,-0.984251968503937,0 "
                 "a_offset=0.15748031496062992,-3.1496062992125986", "trueaxis_kins table=/some/m3.table"):
        path = make_ini(folder, sim.port, extra=pivot)
        with open(path, "a", encoding="utf-8") as f:
            f.write(f"[KINS]\nKINEMATICS = {kins}\n")
        code, output = rs274(path, "G21\nG65 P9830\nM2\n", folder)
        checks.check(code == 0, f"[KINS] {kins}: the same pivot, G65 runs", f"exit {code}; {output[-400:]}")

    # 3c. The home (docs/INTERFACE.md "The home"): with [TRUEAXIS] HOME_ID the
    # machine's home identity (of HOME_ID and the joints' HOME, HOME_OFFSET)
    # must be the module's #904 and trueaxis_kins' home=, or G65 stops.
    sys.path.insert(0, os.path.join(ROOT, "integrations", "linuxcnc", "python"))
    import trueaxis_module

    def homed(offset, kins=None):
        path = make_ini(folder, sim.port, extra={"HOME_ID": "5"})
        with open(path, "a", encoding="utf-8") as f:
            f.write(f"[JOINT_3]\nHOME = 0\nHOME_OFFSET = {offset}\n" + (f"[KINS]\nKINEMATICS = {kins}\n" if kins else ""))
        return path, trueaxis_module.home_identity(trueaxis_module.read_ini(path))

    ini_home, home = homed("10")
    level = "G21\nG10 L2 P4 X0 Y0 Z40\nG10 L2 P5 X50 Y0 Z40\nG10 L2 P6 X0 Y50 Z40\nG65 P9810 A0 C0\nM2\n"
    code, output = rs274(ini_home, level, folder)
    checks.check(code == 1 and f"home identity #904 is 0, this machine's {home}" in output,
                 f"HOME_ID set, the module's #904 still 0: G65 stops, naming the machine's identity ({home})",
                 f"exit {code}; {output[-500:]}")
    sim.set(_9004=2718, _904=home)
    sim.set(_9004=0)
    code, output = rs274(ini_home, level, folder)
    checks.check(code == 0, "#904 set to it: G65 runs", f"exit {code}; {output[-400:]}")
    moved, moved_home = homed("10.5")
    code, output = rs274(moved, level, folder)
    checks.check(moved_home not in (0, home) and code == 1 and f"this machine's {moved_home}" in output,
                 "a HOME_OFFSET changed in the ini: another identity, G65 stops", f"exit {code}; {output[-400:]}")
    for kins, runs in ((f"trueaxis_kins home={home + 1}", False), (f"trueaxis_kins home={home}", True)):
        path, _ = homed("10", kins)
        code, output = rs274(path, level, folder)
        checks.check((code == 0) == runs and (runs or "is not this machine's home identity" in output),
                     f"[KINS] {kins}: G65 {'runs' if runs else 'stops with the sentence'}", f"exit {code}; {output[-400:]}")
    sim.set(_9004=2718, _904=0)
    sim.set(_9004=0)
    no_id = make_ini(folder, sim.port)
    checks.check(trueaxis_module.home_identity(trueaxis_module.read_ini(no_id)) == 0,
                 "without HOME_ID the identity is 0 (the shipped trueaxis.ini): not checked beyond #904 = 0")

    # 4. The module's errors abort the program with its code, name and text.
    points = "G21\nG10 L2 P4 X0 Y0 Z40\nG10 L2 P5 X{} Y0 Z{}\nG10 L2 P6 X{} Y{} Z40\n"
    cases = [
        (200, points.format(0, 40, 0, 0) + "G65 P9810 A0 C0\nM2\n"),         # P1 = P2 = P3
        (201, points.format(50, 40, 100, 0) + "G65 P9810 A0 C0\nM2\n"),      # on one line
        (204, points.format(50, 30, 0, 50) + "G65 P9810 A0 C0 K-1\nM2\n"),   # facing down: 169 deg
        (104, "G21\nG65 P9812\nG65 P9813 X0 Y0 Z40\nG65 P9814\nM2\n"),
        (400, "G21\nG65 P9899\nM2\n"),
        (209, RIGIDITY.format(first_a=10, c_count=4, build="G65 P9832")),  # no pose at A = 0
        (210, RIGIDITY.format(first_a=0, c_count=3, build="G65 P9832")),   # 3 C positions a pose
        (403, RIGIDITY.format(first_a=0, c_count=4, build="G65 P9832 R1")),  # a store, locked
        (208, "G21\nG65 P9830\nG65 P9831 A0 C0 X1 Y0 Z0\nG65 P9831 A0 C90 X0 Y1 Z0\nG65 P9832\nM2\n"),
    ]
    for expected, program in cases:
        code, output = rs274(ini, program, folder)
        text = module_error(expected, errors)
        checks.check(code == 1 and text in output, f"error {expected} {errors[expected]['name']}: the program stops "
                     "with the module's code, name and text", f"exit {code}; output:\n{output[-600:]}")

    # ... and every 2xx code the map lists reaches the program as "error N name:
    # text" (the remap's lookup in the map, without a module to raise each).
    sys.path.insert(0, os.path.join(ROOT, "integrations", "linuxcnc", "python"))
    from trueaxis_module import ModuleError, RegisterMap, TrueaxisError
    register_map = RegisterMap(os.path.join(ROOT, "macros", "register_map.json"))
    codes = [c for c in errors if 200 <= c < 300]
    lines = {c: str(ModuleError(9810, c, *register_map.error(c))) for c in codes}
    checks.check(len(codes) >= 23 and all(module_error(c, errors) in lines[c] for c in codes),
                 f"each of the map's {len(codes)} 2xx codes is named in the stop's line with its text",
                 str([c for c in codes if module_error(c, errors) not in lines[c]]))

    # 4b. The work offsets a macro reads reach the module in its units
    # (RegisterMap.work_offsets_of): lengths from machine units to mm, angles
    # in degrees as they are; no macro of the map reads an angle yet, so a
    # small map (the real one with one macro more) reads G54's X..C.
    with open(os.path.join(ROOT, "macros", "register_map.json"), encoding="utf-8") as f:
        data = json.load(f)
    data["variables"].append({"number": 5230, "count": 1, "name": "test_offset_in", "access": "persistent",
                              "kind": "real", "unit": "in"})
    data["macros"].append({"number": 9998, "name": "test_g54", "inputs": [{"number": 5221, "count": 6}]})
    data["macros"].append({"number": 9997, "name": "test_inches", "inputs": [{"number": 5230}]})
    fake = os.path.join(folder, "fake_map.json")
    with open(fake, "w", encoding="utf-8") as f:
        json.dump(data, f)
    small = RegisterMap(fake)
    g54 = {5221: 1.0, 5222: -2.5, 5223: 0.125, 5224: 30.0, 5225: -45.5, 5226: 400.0}
    per_mm = 1.0 / 25.4  # an inch machine: LinuxCNC's machine units per mm
    got = small.work_offsets_of(9998, g54.get, per_mm)
    want = {n: g54[n] / per_mm if n <= 5223 else g54[n] for n in g54}
    checks.check(got == want, "a macro reading G54 X..C: X, Y, Z from inches to mm, A, B, C in degrees as they are",
                 f"{got}")
    checks.check(small.work_offsets_of(9998, g54.get, 1.0) == g54, "... and on a mm machine every offset as it is",
                 str(small.work_offsets_of(9998, g54.get, 1.0)))
    try:
        small.work_offsets_of(9997, lambda n: 1.0, per_mm)
        refused = ""
    except TrueaxisError as e:
        refused = str(e)
    checks.check("work offset #5230 the unit 'in'" in refused, "a work offset of another unit is refused, named",
                 refused)
    units = {register_map.offset_units[n] for first, count in register_map.work_offsets[9810]
             for n in range(first, first + count)}
    checks.check(units == {"mm"}, "the real map: 9810 reads lengths only", str(units))

    # 4c. G65 P1 and G65 P0 move nothing and take no length: they pass under
    # G20 (an inch program's session, on_abort's P0 after it), P1 taking the
    # macro interface for the remap's connection and P0 giving it back.
    dump = os.path.join(folder, "dump.txt")
    if os.path.exists(dump):
        os.remove(dump)
    code, output = rs274(ini, "G20\nG65 P1\no<interface_seen> call\nG65 P0\no<interface_seen> call\nM2\n", folder)
    seen = open(dump, encoding="utf-8").read() if os.path.exists(dump) else ""
    checks.check(code == 0 and "G20 is active" not in output and seen == "#9009 = 1.0\n#9009 = 0.0\n",
                 "G20: G65 P1 takes the interface and G65 P0 gives it back", f"exit {code}; {seen!r}; {output[-600:]}")

    # 5. #<_ta_unlock> stores a table: unlocked for that macro alone.
    # The same program stores again without the code: the module must be locked
    # again (403) while the remap's connection is still open.
    code, output = rs274(ini, RIGIDITY.format(first_a=0, c_count=4, build="#<_ta_unlock> = 2718\nG65 P9832 R1\n"
                                              "(DEBUG, unlock after: #<_ta_unlock>)\nG65 P9833 A20 Q0 R0\n"
                                              "(DEBUG, stored: #103)\nG65 P9832 R1"), folder)
    checks.check(code == 1 and "unlock after: 0.000000" in output and "stored: 0.000000" in output
                 and module_error(403, errors) in output,
                 "#<_ta_unlock> = 2718 stores the rigidity table, and the module is locked again after it (403)",
                 f"exit {code}; output:\n{output[-600:]}")

    # 6. Letters LinuxCNC acts on are refused on the G65 line, before anything is written.
    for letter, word in (("S", "S30"), ("T", "T1"), ("F", "F100"), ("M", "M5")):
        before = sim.get(9003)[9003]
        code, output = rs274(ini, f"G21\nG65 P9843 Z100 {word}\nM2\n", folder)
        checks.check(code == 1 and f"set #<_ta_{letter.lower()}> before the call instead" in output
                     and sim.get(9003)[9003] == before, f"{letter} on the G65 line: refused, naming #<_ta_{letter.lower()}>",
                     f"exit {code}; output:\n{output[-600:]}")

    # 7. ... and arrive as #<_ta_s>, #<_ta_t>: the simulator holds the macro (sim_hold)
    # so its arguments stay to be read; the remap's time-out names [TRUEAXIS] TIMEOUT.
    sim.set(_12009=1)
    held = make_ini(folder, sim.port, extra={"TIMEOUT": "1"})
    code, output = rs274(held, "G21\n#<_ta_s> = 30.25\n#<_ta_t> = 2\nG65 P9843 Z100\nM2\n", folder)
    args = sim.get(19, 20, 26)
    sim.set(_12009=0)
    checks.check(code == 1 and "did not finish within 1 s ([TRUEAXIS] TIMEOUT" in output,
                 "a macro that does not finish: the program stops naming [TRUEAXIS] TIMEOUT", output[-600:])
    checks.check(args == {19: 30.25, 20: 2.0, 26: 100.0}, "#<_ta_s>, #<_ta_t> and Z arrive as #19, #20, #26",
                 f"{args}")
    time.sleep(0.2)
    code, output = rs274(ini, "G21\n#<_ta_s> = 30\nG65 P9812\n(DEBUG, after: #<_ta_s>)\nM2\n", folder)
    checks.check(code == 0 and "after: 0.000000" in output, "a call sets #<_ta_s> back to 0", output[-600:])

    # 8. Inches are refused; a busy controller is named.
    code, output = rs274(ini, "G20\nG65 P9812\nM2\n", folder)
    checks.check(code == 1 and "G20 is active: the module takes mm" in output, "G20: refused", output[-600:])
    from pymodbus.client import ModbusTcpClient
    other = ModbusTcpClient("127.0.0.1", port=sim.port)
    other.connect()
    other.write_registers(4 * 9009, [0x3FF0, 0, 0, 0], slave=1)  # #9009 = 1: another client holds it
    code, output = rs274(make_ini(folder, sim.port, extra={"WAIT": "0.5"}), "G21\nG65 P9812\nM2\n", folder)
    other.close()
    checks.check(code == 1 and "controller busy: another client holds the macro interface" in output,
                 "another client holds the interface: the program stops naming it", output[-600:])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
