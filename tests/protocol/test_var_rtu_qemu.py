#!/usr/bin/env python3
"""trueaxis-var over Modbus RTU against the firmware image under QEMU: the
operator's command, not a test client, through the RTU framer of the image
(tests/target/rtu_server_main.cpp) on a pseudo-terminal.

usage: test_var_rtu_qemu.py TRUEAXIS_VAR IMAGE

Starts IMAGE (rtu_server_qemu_target: 2400 baud, see docs/GUIDE.md "Modbus RTU
on the firmware image") with UART0 on a pseudo-terminal, and holds the terminal
open itself for the whole run: QEMU reads a terminal only while one is open,
and notices a newly opened one only on its next check (once a second), so
each trueaxis-var run then finds it listening. Then, with
`trueaxis-var --rtu PTS --baud B`:
  get 9006                  the interface version, 1
  set 1=2.5 + get 1         a decimal written and read back
  set G57, G58, G59 + run 9810 A=0 C=0
                            a face tilted 30 deg: done, #107 level_tilt = 30
  set 100=1                 refused: exit 1, one line naming #100, read_only
                            and Modbus exception 02
Every run must finish within 20 s. Exit 0 when every check holds, 1 when one
fails, 77 (ctest's SKIP_RETURN_CODE) when TRUEAXIS_VAR or IMAGE is missing.
"""
import os
import re
import select
import subprocess
import sys
import termios
import time
import tty

BANNER = re.compile(r"rtu_server: slave (\d+), (\d+) baud")


def start_qemu(image):
    """QEMU with UART0 on a new pseudo-terminal: (process, pts, baud) once the
    image has said it is ready, or (process, None, None)."""
    qemu = subprocess.Popen(["qemu-system-arm", "-M", "mps2-an500", "-nographic", "-monitor", "none",
                             "-semihosting", "-serial", "pty", "-no-reboot", "-kernel", image],
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    text = ""
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        ready, _, _ = select.select([qemu.stdout], [], [], 0.2)
        if not ready:
            continue
        chunk = os.read(qemu.stdout.fileno(), 4096).decode("utf-8", "replace")
        if not chunk:
            break
        text += chunk
        pts = re.search(r"/dev/pts/\d+", text)
        banner = BANNER.search(text)
        if pts and banner and text.endswith("\n"):
            return qemu, pts.group(0), int(banner.group(2))
    print(f"test_var_rtu_qemu: QEMU said:\n{text}", file=sys.stderr)
    return qemu, None, None


class Checks:
    def __init__(self, var, pts, baud):
        self.base = [var, "--rtu", pts, "--baud", str(baud)]
        self.failures = 0

    def run(self, *args):
        started = time.monotonic()
        done = subprocess.run(self.base + list(args), stdin=subprocess.DEVNULL, capture_output=True, text=True,
                              timeout=20)
        print(f"trueaxis-var {' '.join(args)}: exit {done.returncode}, {time.monotonic() - started:.1f} s")
        for line in (done.stdout + done.stderr).splitlines():
            print(f"  {line}")
        return done

    def check(self, what, ok):
        if not ok:
            print(f"test_var_rtu_qemu: FAILED: {what}", file=sys.stderr)
            self.failures += 1


def value_of(stdout, number):
    """The value of '#N = V ...' in stdout, or None."""
    match = re.search(rf"^#{number} = (\S+)", stdout, re.MULTILINE)
    return float(match.group(1)) if match else None


def main(argv):
    if len(argv) != 3:
        print("usage: test_var_rtu_qemu.py TRUEAXIS_VAR IMAGE", file=sys.stderr)
        return 2
    var, image = argv[1], argv[2]
    for path in (var, image):
        if not os.path.exists(path):
            print(f"test_var_rtu_qemu: no {path} (build it first); skipped", file=sys.stderr)
            return 77
    started = time.monotonic()
    qemu, pts, baud = start_qemu(image)
    if pts is None:
        qemu.kill()
        return 1
    held = os.open(pts, os.O_RDWR | os.O_NOCTTY)
    t = Checks(var, pts, baud)
    try:
        tty.setraw(held, termios.TCSANOW)  # what trueaxis-var's runs restore on leaving
        time.sleep(1.5)

        r = t.run("get", "9006")
        t.check("get 9006 is '#9006 = 1'", r.returncode == 0 and r.stdout == "#9006 = 1\n")

        r = t.run("set", "1=2.5")
        t.check("set 1=2.5 succeeds, silently", r.returncode == 0 and r.stdout == "" and r.stderr == "")
        r = t.run("get", "1")
        t.check("get 1 reads 2.5 back", r.returncode == 0 and r.stdout == "#1 = 2.5\n")

        r = t.run("set", "5281=0", "5282=0", "5283=0", "5301=100", "5302=0", "5303=0",
                  "5321=0", "5322=86.602540378443865", "5323=50")
        t.check("set G57, G58, G59 succeeds", r.returncode == 0)
        r = t.run("run", "9810", "A=0", "C=0")
        t.check("run 9810 is done", r.returncode == 0 and r.stdout.startswith("9810 level_3pt: done, error 0 ok, "))
        tilt = value_of(r.stdout, 107)
        t.check("#107 level_tilt is 30 deg", tilt is not None and abs(tilt - 30.0) < 1e-9
                and "#107 = " in r.stdout and "(level_tilt, deg)" in r.stdout)

        r = t.run("set", "100=1")
        t.check("set 100=1 is refused in one line",
                r.returncode == 1 and r.stdout == "" and r.stderr.count("\n") == 1
                and r.stderr.startswith("trueaxis-var: #100: read_only (Modbus 02 illegal data address: "))
    finally:
        os.close(held)
        qemu.terminate()
        qemu.wait(10)
    result = "all checks hold" if t.failures == 0 else f"{t.failures} checks FAILED"
    print(f"test_var_rtu_qemu: {result} in {time.monotonic() - started:.1f} s")
    return 0 if t.failures == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
