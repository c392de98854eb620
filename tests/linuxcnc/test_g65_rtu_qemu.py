#!/usr/bin/python3
"""G65 over Modbus RTU: LinuxCNC's standalone interpreter rs274, the remap of
integrations/linuxcnc with [TRUEAXIS] SERIAL, against the firmware image under
QEMU (rtu_server_qemu_target, UART0 on a pseudo-terminal; the QEMU start and
the held terminal as tests/protocol/test_var_rtu_qemu.py does them).

usage: test_g65_rtu_qemu.py HOST_BIN_DIR IMAGE

The program writes G57, G58, G59 of a face tilted 30 deg, runs G65 P9810 A0 C0
and writes out LinuxCNC's #100..#199 (o<dump_results>); then trueaxis-var
reads the module's over the same line. Checks: exit 0, #107 = 30 deg, and
LinuxCNC's #100..#199 equal the module's bit for bit. Exit 0 when every check
holds, 1 when one fails, 77 (ctest's skip) when the image or a host program is
missing.
"""
import os
import re
import subprocess
import sys
import tempfile
import termios
import time
import tty

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "protocol"))
from test_g65_rs274 import make_ini, rs274  # noqa: E402
from test_var_rtu_qemu import start_qemu  # noqa: E402

PROGRAM = """G21
G10 L2 P4 X0 Y0 Z0
G10 L2 P5 X100 Y0 Z0
G10 L2 P6 X0 Y86.602540378443865 Z50
G65 P9810 A0 C0
(DEBUG, tilt=#107)
o<dump_results> call
G65 P0
M2
"""


def main(argv):
    if len(argv) != 3:
        print("usage: test_g65_rtu_qemu.py HOST_BIN_DIR IMAGE", file=sys.stderr)
        return 2
    var, image = os.path.join(argv[1], "trueaxis-var"), argv[2]
    for path in (var, image, "/usr/bin/rs274"):
        if not os.path.exists(path):
            print(f"test_g65_rtu_qemu: no {path} (build or install it first); skipped", file=sys.stderr)
            return 77
    started = time.monotonic()
    qemu, pts, baud = start_qemu(image)
    if pts is None:
        qemu.kill()
        return 1
    held = os.open(pts, os.O_RDWR | os.O_NOCTTY)
    failures = 0
    with tempfile.TemporaryDirectory(prefix="trueaxis-rtu-") as folder:
        try:
            tty.setraw(held, termios.TCSANOW)
            # The firmware answers once it has booted: on a loaded machine that
            # takes longer than any fixed wait, so ask it (#9006) until it does.
            ready = False
            for _ in range(30):
                probe = subprocess.run([var, "--rtu", pts, "--baud", str(baud), "--timeout", "1000", "get", "9006"],
                                       stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
                if probe.returncode == 0:
                    ready = True
                    break
                time.sleep(0.5)
            if not ready:
                print(f"test_g65_rtu_qemu: the firmware did not answer on {pts}: {probe.stderr.strip()}")
                return 1
            ini = make_ini(folder, 0, extra={"SERIAL": pts, "BAUD": str(baud), "REQUEST_TIMEOUT": "3"})
            code, output = rs274(ini, PROGRAM, folder, timeout=120)
            print(f"rs274: exit {code}, {time.monotonic() - started:.1f} s")
            dumped = {}
            dump = os.path.join(folder, "dump.txt")
            if os.path.exists(dump):
                for line in open(dump, encoding="utf-8"):
                    number, value = line.split(" = ")
                    dumped[int(number[1:])] = float(value)
            done = subprocess.run([var, "--rtu", pts, "--baud", str(baud), "get", "100..199"],
                                  stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
            module = {int(m.group(1)): float(m.group(2)) for m in re.finditer(r"#(\d+) = (\S+)", done.stdout)}
            checks = [
                ("rs274 exits 0 and prints the tilt", code == 0 and "tilt=30.000000" in output),
                ("#107 = 30 deg", abs(dumped.get(107, 0.0) - 30.0) < 1e-9),
                ("LinuxCNC's #100..#199 equal the module's, bit for bit",
                 len(module) == 100 and all(dumped.get(n) == module[n] for n in range(100, 200))),
            ]
            for what, ok in checks:
                print(f"{'ok  ' if ok else 'FAIL'} {what}")
                failures += 0 if ok else 1
            if failures:
                print(output[-1500:])
        finally:
            os.close(held)
            qemu.terminate()
            qemu.wait(10)
    print(f"test_g65_rtu_qemu: {failures} failure(s) in {time.monotonic() - started:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
