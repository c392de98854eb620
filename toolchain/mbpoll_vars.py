"""trueaxis variables over Modbus with mbpoll, for the demo scripts.

docs/INTERFACE.md "Encoding": #N is the holding registers 4N..4N+3, an IEEE-754
binary64 with the most significant word first. A failure ends the demo with
one line (sys.exit).

usage: Vars(port).write(first, values), .read(first, count), .run_macro(number)
"""
import struct
import subprocess
import sys


class Vars:
    def __init__(self, port, host="127.0.0.1"):
        self.port = str(port)
        self.host = host

    def _mbpoll(self, first, words=None, count=None):
        argv = ["mbpoll", "-m", "tcp", "-p", self.port, "-0", "-q", "-t", "4:hex", "-r", str(4 * first)]
        if words is None:
            argv += ["-c", str(count * 4), "-1", self.host]
        else:
            argv += [self.host] + [f"0x{w:04X}" for w in words]
        done = subprocess.run(argv, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"demo: mbpoll failed: {' '.join(argv)}: {done.stdout.strip()} {done.stderr.strip()}")
        return done.stdout

    def write(self, first, values):
        words = []
        for v in values:
            words += struct.unpack(">4H", struct.pack(">d", v))
        self._mbpoll(first, words=words)

    def read(self, first, count):
        out = self._mbpoll(first, count=count)
        words = [int(line.split()[1], 16) for line in out.splitlines() if line.startswith("[")]
        if len(words) != 4 * count:
            sys.exit(f"demo: mbpoll read #{first}: {len(words)} registers")
        return [struct.unpack(">d", struct.pack(">4H", *words[4 * k:4 * k + 4]))[0] for k in range(count)]

    def run_macro(self, number):
        """Runs a macro; 0 when it succeeded, else the module's error code."""
        self.write(9000, [number])
        for _ in range(50):
            status, error = self.read(9001, 2)
            if status >= 2:
                return int(error) if status == 3 else 0
        sys.exit(f"demo: macro {number} did not finish")
