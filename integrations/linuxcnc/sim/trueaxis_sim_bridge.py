#!/usr/bin/python3
"""The simulated machine's link to trueaxis-sim: a userspace HAL component that
places the virtual probe's face and ball (trueaxis_sim.hal) where trueaxis-sim's
own cradle model puts them, with its true geometric errors (one model of the
machine: no second copy of its geometry here).

usage: trueaxis_sim_bridge.py HOST PORT BALL_RADIUS_MM [PROBE_LENGTH_MM [ORIENT_ERROR_DEG]]

Pins (component trueaxis-sim-bridge):
  a, c (float in)                  the table's commanded A and C, deg (joints 3, 4)
  face-enable, ball-enable (bit in) which of the two the probe trips on (the
                                   HAL file nets them to M64/M65 P0, P1); a
                                   disabled one never trips
  face-nx, face-ny, face-nz, face-d (float out)  the face's outward unit normal
                                   and n . p on it, machine frame
  ball-x, ball-y, ball-z, ball-r2 (float out)    the ball's centre, machine frame,
                                   and the square of BALL_RADIUS_MM (the ball's
                                   plus the stylus tip's radius)
  pose-a, pose-c (float out)       the pose the outputs are for
  The probe's tip is PROBE_LENGTH_MM (default 0) below the joints' X, Y, Z
  (the gauge line): the face and the ball are given shifted up by it, where
  the joints meet them.
  spindle-angle (float in)         the angle M19 commands (deg; the HAL file nets
                                   it to spindle.0.orient-angle)
  spindle-encoder (float out)      the angle the spindle stands at, as its
                                   encoder reads it: the command plus
                                   ORIENT_ERROR_DEG (default 0), as a real
                                   orient stops within its tolerance, not on
                                   the command. The probe's tip is the joints'
                                   X, Y, Z plus the spindle's tool tip error
                                   at that angle (#12060..#12062, 0 unless the
                                   simulator's sim_spindle is 1), so the face
                                   and the ball are given shifted back by it
Every 5 ms: when A, C, the spindle angle or an enable has changed, it writes
A and C to the simulator (#12000, #12001: sim variables, outside the module's
macro interface) and the angle (#12058) and reads #12048..#12054 and
#12060..#12062 back. Exit when the HAL component is
asked to (SIGTERM) or the simulator stops answering.
"""
import math
import os
import signal
import sys
import time

import hal
from pymodbus.client import ModbusTcpClient

# The variables' encoding is the remap's (docs/INTERFACE.md "Encoding"): one copy.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from trueaxis_module import decode, encode  # noqa: E402

NEVER = -1.0e9


def main(argv):
    host, port, radius = argv[1], int(argv[2]), float(argv[3])
    length = float(argv[4]) if len(argv) > 4 else 0.0
    orient_error = float(argv[5]) if len(argv) > 5 else 0.0
    client = ModbusTcpClient(host, port=port, timeout=2)
    if not client.connect():
        sys.exit(f"trueaxis_sim_bridge: no trueaxis-sim at {host}:{port}")
    h = hal.component("trueaxis-sim-bridge")
    for name in ("a", "c", "spindle-angle"):
        h.newpin(name, hal.HAL_FLOAT, hal.HAL_IN)
    for name in ("face-enable", "ball-enable"):
        h.newpin(name, hal.HAL_BIT, hal.HAL_IN)
    for name in ("face-nx", "face-ny", "face-nz", "face-d", "ball-x", "ball-y", "ball-z", "ball-r2",
                 "pose-a", "pose-c", "spindle-encoder"):
        h.newpin(name, hal.HAL_FLOAT, hal.HAL_OUT)
    h["face-d"] = NEVER   # nothing trips before the first answer
    h["ball-r2"] = -1.0
    h.ready()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))

    def write(first, values):
        words = [w for v in values for w in encode(v)]
        reply = client.write_registers(4 * first, words, slave=1)
        if reply.isError():
            sys.exit(f"trueaxis_sim_bridge: writing #{first} refused: {reply}")

    def read(first, count):
        reply = client.read_holding_registers(4 * first, 4 * count, slave=1)
        if reply.isError():
            sys.exit(f"trueaxis_sim_bridge: reading #{first} refused: {reply}")
        return decode(reply.registers)

    last = None
    try:
        while True:
            now = (h["a"], h["c"], h["face-enable"], h["ball-enable"], h["spindle-angle"])
            if now != last:
                write(12000, [now[0], now[1]])
                actual = math.fmod(now[4] + orient_error, 360.0) if math.isfinite(now[4]) else 0.0
                actual = actual + 360.0 if actual < 0.0 else actual  # within the map's range
                write(12058, [actual])
                h["spindle-encoder"] = actual
                nx, ny, nz, d, bx, by, bz = read(12048, 7)
                ex, ey, ez = read(12060, 3)
                ez -= length  # the tip below the joints: they meet the face and the ball that much higher
                h["face-nx"], h["face-ny"], h["face-nz"] = nx, ny, nz
                h["face-d"] = d - (nx * ex + ny * ey + nz * ez) if now[2] else NEVER
                h["ball-x"], h["ball-y"], h["ball-z"] = bx - ex, by - ey, bz - ez
                h["ball-r2"] = radius * radius if now[3] else -1.0
                h["pose-a"], h["pose-c"] = now[0], now[1]
                last = now
            time.sleep(0.005)
    except KeyboardInterrupt:
        pass
    finally:
        client.close()


if __name__ == "__main__":
    main(sys.argv)
