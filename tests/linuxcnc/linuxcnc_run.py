"""Running the simulated machine (integrations/linuxcnc/sim) headless, for the
scenario tests and the demo: trueaxis-sim on 127.0.0.1 port 0, LinuxCNC with
tests/linuxcnc/scenario_display.py as its display, as a non-root user.

Machine(bin_dir, errors, folder).run(commands) -> the display's result dict.
The simulator and LinuxCNC run in the real-time class SCHED_RR where the
caller may give it (root), so that a build beside them cannot stall them
(_real_time_class).
LinuxCNC refuses to run as root: as root the run is `runuser -u trueaxis-ci`
(the user toolchain/setup.sh creates), otherwise as the calling user. What
LinuxCNC reads, and trueaxis-var (which the display runs), is copied into
`folder` in the repository's layout (so the machine ini's relative paths hold
and the user can read it wherever the clone is) and handed to that user.

One LinuxCNC on a host at a time: two share its shared-memory keys, and its
start and stop kill the other's processes by name. Machine.run holds the
host-wide lock host_lock() (an flock on LOCK_FILE) for the whole run, so two
test runs, or a demo beside a test, wait for each other rather than collide;
test_scenarios.py holds it for a whole scenario. By hand, anything else that
starts LinuxCNC takes the same lock: `flock /tmp/trueaxis-linuxcnc.lock CMD`.
"""
import contextlib
import fcntl
import json
import os
import pwd
import re
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
CI_USER = "trueaxis-ci"
LOCK_FILE = "/tmp/trueaxis-linuxcnc.lock"
_lock = {"depth": 0, "fd": None}


@contextlib.contextmanager
def host_lock(what="LinuxCNC"):
    """Holds LOCK_FILE's exclusive flock for the block (re-entrant within the
    process), waiting for it with one line on stderr when another process
    holds it, and one when it is ours."""
    if _lock["depth"] == 0:
        try:
            fd = os.open(LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o666)
        except PermissionError:  # another user's file: a read-only descriptor locks as well
            fd = os.open(LOCK_FILE, os.O_RDONLY)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            try:
                holder = os.pread(fd, 200, 0).decode("utf-8", "replace").strip() or "a process that names none"
            except OSError:
                holder = "a process that names none"
            print(f"linuxcnc_run: waiting for {LOCK_FILE}: another LinuxCNC run on this host holds it ({holder}); "
                  f"{what} starts when it ends", file=sys.stderr, flush=True)
            started = time.monotonic()
            fcntl.flock(fd, fcntl.LOCK_EX)
            print(f"linuxcnc_run: {LOCK_FILE} is ours after {time.monotonic() - started:.0f} s", file=sys.stderr,
                  flush=True)
        try:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"pid {os.getpid()}: {what}\n".encode(), 0)
        except OSError:
            pass  # read-only: the lock holds all the same
        _lock["fd"] = fd
    _lock["depth"] += 1
    try:
        yield
    finally:
        _lock["depth"] -= 1
        if _lock["depth"] == 0:
            fd, _lock["fd"] = _lock["fd"], None
            os.close(fd)  # releases the flock


def _real_time_class():
    """In the child, before it runs LinuxCNC or trueaxis-sim: the simulated
    machine in the round-robin real-time class, ahead of every ordinary
    process. LinuxCNC's own real time (rtapi_app's SCHED_FIFO) needs root that
    may raise RLIMIT_RTPRIO (CAP_SYS_RESOURCE, which a virtual machine's or a
    container's root may lack: "Note: Using POSIX non-realtime" in its log);
    without it its task is an ordinary process that a parallel build on two
    cores stalls for over a second, past its 1 s wait for the motion
    controller ([EMCMOT] COMM_TIMEOUT), and the task aborts the program
    (tests/linuxcnc/README.md). Without the right (not root) nothing changes."""
    try:
        os.sched_setscheduler(0, os.SCHED_RR, os.sched_param(1))
    except OSError:
        pass


def _kill_run(plan):
    """Kills every process of the LinuxCNC run whose plan is `plan`: those
    that inherited TRUEAXIS_SCENARIO=plan (rtapi_app too, which starts a
    session of its own), and nothing else (another user's LinuxCNC)."""
    mark = f"TRUEAXIS_SCENARIO={plan}".encode()
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/environ", "rb") as f:
                if mark in f.read().split(b"\0"):
                    os.kill(int(pid), signal.SIGKILL)
        except OSError:
            continue


# The simulated machine's probe (integrations/linuxcnc/sim: trueaxis_sim.tbl's
# T1 and [TRUEAXIS_SIM] PROBE_LENGTH): its tip this far below the gauge line,
# and what every run does after homing.
PROBE_LENGTH_MM = 100.0
PROBE_SETUP = ("T1 M6", "G43")


sys.path.insert(0, os.path.join(ROOT, "integrations", "linuxcnc", "python"))
import trueaxis_module  # noqa: E402  (no LinuxCNC import: the ini reader and the home identity)

SIM_INI = os.path.join(ROOT, "integrations", "linuxcnc", "sim", "trueaxis_sim.ini")


def _sim_machine():
    """The simulated machine's nominal pivot and home, from its ini (the one
    place they are stated): the [TRUEAXIS] PIVOT_* and A_OFFSET_* strings (the
    first of each, as LinuxCNC reads them) and the home identity."""
    sections = trueaxis_module.read_ini(SIM_INI)
    keys = ("PIVOT_X", "PIVOT_Y", "PIVOT_Z", "A_OFFSET_Y", "A_OFFSET_Z")
    missing = [k for k in keys if k not in sections.get("TRUEAXIS", {})]
    if missing:
        raise RuntimeError(f"{SIM_INI}: [TRUEAXIS] has no {', '.join(missing)}")
    text = [sections["TRUEAXIS"][k][0] for k in keys]
    return text, trueaxis_module.home_identity(sections)


_PIVOT_TEXT, HOME_IDENTITY = _sim_machine()
PIVOT_MM = tuple(float(v) for v in _PIVOT_TEXT[:3])
A_OFFSET_MM = tuple(float(v) for v in _PIVOT_TEXT[3:])
# trueaxis_kins' parameters for that machine (its [KINS] line on the simulated
# machine): the pivot as the ini writes it, the home identity.
KINS_PIVOT = f"pivot={','.join(_PIVOT_TEXT[:3])} a_offset={','.join(_PIVOT_TEXT[3:])} home={HOME_IDENTITY}"
# trueaxis-sim's calibration ball on the table (sim_ball_x, _y, _z's defaults)
# and so its centre at A = 0, C = 0 in machine coordinates, nominally.
BALL_TABLE_MM = (200.0, 0.0, 50.0)
BALL_MM = tuple(b + r for b, r in zip(BALL_TABLE_MM, PIVOT_MM))


def on_table(x, y):
    """A point X, Y from the table's centre (the C axis at A = 0) in machine coordinates."""
    return (PIVOT_MM[0] + x, PIVOT_MM[1] + y)


class Machine:
    def __init__(self, bin_dir, folder, errors="ideal", face_tilt=None):
        self.bin_dir = bin_dir = os.path.abspath(bin_dir)
        self.folder = folder
        os.chmod(folder, 0o755)
        argv = [os.path.join(bin_dir, "trueaxis-sim"), "--port", "0", "--nv", os.path.join(folder, "sim.nv"),
                "--errors", errors, "--pivot", ",".join(repr(v) for v in PIVOT_MM),
                "--a-offset", ",".join(repr(v) for v in A_OFFSET_MM)]
        if face_tilt is not None:
            argv += ["--face-tilt", str(face_tilt)]
        self.sim = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                    preexec_fn=_real_time_class)
        line = self.sim.stdout.readline()
        found = re.search(r"listening on [0-9.]+:(\d+)", line)
        if not found:
            self.sim.kill()
            raise RuntimeError(f"trueaxis-sim said {line!r}")
        self.port = int(found.group(1))
        self._copy()
        # Commissioning: the module told the machine's home identity (#904),
        # as the remap checks before every G65.
        subprocess.run([os.path.join(bin_dir, "trueaxis-var"), "--port", str(self.port), "set", "9004=2718",
                        f"904={HOME_IDENTITY}", "9004=0"], check=True, capture_output=True)
        # trueaxis-var from the machine's folder, not the build: the display runs
        # it as the LinuxCNC user, who may not reach a clone under a 0700
        # folder (mktemp -d).
        os.makedirs(os.path.join(folder, "bin"))
        var = shutil.copy(os.path.join(bin_dir, "trueaxis-var"), os.path.join(folder, "bin"))
        self.var = [var, "--port", str(self.port)]

    # ----- the module and the simulator's truth, over trueaxis-var -----------

    def get(self, *numbers):
        done = subprocess.run(self.var + ["get"] + [str(n) for n in numbers], capture_output=True, text=True,
                              check=True)
        return {int(m.group(1)): float(m.group(2)) for m in re.finditer(r"#(\d+) = (\S+)", done.stdout)}

    def set(self, *assignments):
        subprocess.run(self.var + ["set"] + list(assignments), capture_output=True, text=True, check=True)

    def query(self, macro, *arguments):
        """trueaxis-var run MACRO ARGS: its output, or None when the macro failed."""
        done = subprocess.run(self.var + ["run", str(macro)] + list(arguments), capture_output=True, text=True)
        return done.stdout if done.returncode == 0 else None

    # ----- LinuxCNC ----------------------------------------------------------

    def _copy(self):
        for part in ("python", "nc_subroutines", "sim"):
            shutil.copytree(os.path.join(ROOT, "integrations", "linuxcnc", part),
                            os.path.join(self.folder, "integrations", "linuxcnc", part),
                            ignore=shutil.ignore_patterns("__pycache__"))
        os.makedirs(os.path.join(self.folder, "macros"))
        shutil.copy(os.path.join(ROOT, "macros", "register_map.json"), os.path.join(self.folder, "macros"))
        shutil.copy(os.path.join(HERE, "scenario_display.py"), self.folder)
        self.machine_dir = os.path.join(self.folder, "integrations", "linuxcnc", "sim")
        self.ini = os.path.join(self.machine_dir, "trueaxis_sim.ini")
        text = open(self.ini, encoding="utf-8").read()
        text = re.sub(r"(?m)^PORT = .*$", f"PORT = {self.port}", text)
        text = re.sub(r"(?m)^DISPLAY = .*$", f"DISPLAY = {os.path.join(self.folder, 'scenario_display.py')}", text)
        with open(self.ini, "w", encoding="utf-8") as f:
            f.write(text)

    def add_ini_lines(self, section, lines):
        """Adds lines at the top of [section] of the machine's ini (the copy)."""
        text = open(self.ini, encoding="utf-8").read()
        head = f"[{section}]\n"
        if head not in text:
            raise ValueError(f"no [{section}] in {self.ini}")
        text = text.replace(head, head + "".join(line + "\n" for line in lines), 1)
        with open(self.ini, "w", encoding="utf-8") as f:
            f.write(text)

    def run(self, commands, timeout_s=300, name="run", show=None, setup=PROBE_SETUP):
        """Starts LinuxCNC, runs the MDI commands, stops it: the display's result,
        with "log" (LinuxCNC's output) and "seconds" added. `setup` runs first,
        after homing: the probe (T1, PROBE_LENGTH_MM long) in the spindle with
        its length offset on, as an operator probes."""
        plan = os.path.join(self.folder, f"{name}.plan.json")
        out = os.path.join(self.folder, f"{name}.out.json")
        with open(plan, "w", encoding="utf-8") as f:
            json.dump({"commands": commands, "setup": list(setup), "timeout": timeout_s, "out": out, "show": show}, f)
        argv = ["linuxcnc", "-r", self.ini]
        env = {"TRUEAXIS_SCENARIO": plan, "PATH": "/usr/bin:/bin:/usr/sbin:/sbin", "PYTHONDONTWRITEBYTECODE": "1"}
        if os.getuid() == 0:
            user = pwd.getpwnam(CI_USER)
            subprocess.run(["chown", "-R", f"{user.pw_uid}:{user.pw_gid}", self.folder], check=True)
            env["HOME"] = user.pw_dir
            argv = ["runuser", "-u", CI_USER, "--", "env"] + [f"{k}={v}" for k, v in env.items()] + argv
            env = None
        else:
            env = dict(os.environ, **env)
        with host_lock(f"linuxcnc_run {name} in {self.folder}"):
            started = time.monotonic()
            run = subprocess.Popen(argv, cwd=self.machine_dir, env=env, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True, preexec_fn=_real_time_class)
            try:
                log, _ = run.communicate(timeout=timeout_s + 60)
            except subprocess.TimeoutExpired:
                _kill_run(plan)
                try:
                    log, _ = run.communicate(timeout=30)
                except subprocess.TimeoutExpired:
                    log = ""
                log = f"linuxcnc timed out after {timeout_s + 60} s\n{log or ''}"
        result = {"steps": [], "homed": False, "error": "the display wrote nothing"}
        if os.path.exists(out):
            result = json.load(open(out, encoding="utf-8"))
        result["log"] = log if isinstance(log, str) else log.decode("utf-8", "replace")
        result["seconds"] = round(time.monotonic() - started, 1)
        return result

    def stop(self):
        self.sim.terminate()
        self.sim.wait(timeout=10)


def main(argv):
    """By hand: linuxcnc_run.py BIN_DIR MDI... runs the commands and prints the result."""
    import tempfile
    folder = tempfile.mkdtemp(prefix="trueaxis-lcnc-")
    machine = Machine(argv[1], folder)
    try:
        result = machine.run(argv[2:], show=os.environ.get("SHOW", "").split() or None)
        print(json.dumps({k: v for k, v in result.items() if k != "log"}, indent=1))
        print(result["log"][-3000:])
    finally:
        machine.stop()
    print(f"folder: {folder}")


if __name__ == "__main__":
    main(sys.argv)
