"""Running the simulated machine (integrations/linuxcnc/sim) headless, for the
scenario tests and the demo: trueaxis-sim on 127.0.0.1 port 0, LinuxCNC with
tests/linuxcnc/scenario_display.py as its display, as a non-root user.

Machine(bin_dir, errors, folder).run(commands) -> the display's result dict.
LinuxCNC refuses to run as root: as root the run is `runuser -u trueaxis-ci`
(the user toolchain/setup.sh creates), otherwise as the calling user. What
LinuxCNC reads is copied into `folder` in the repository's layout (so the
machine ini's relative paths hold and the user can read it wherever the clone
is) and handed to that user.
"""
import json
import os
import pwd
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
CI_USER = "trueaxis-ci"


class Machine:
    def __init__(self, bin_dir, folder, errors="ideal", face_tilt=None):
        self.bin_dir = bin_dir = os.path.abspath(bin_dir)
        self.folder = folder
        os.chmod(folder, 0o755)
        argv = [os.path.join(bin_dir, "trueaxis-sim"), "--port", "0", "--nv", os.path.join(folder, "sim.nv"),
                "--errors", errors]
        if face_tilt is not None:
            argv += ["--face-tilt", str(face_tilt)]
        self.sim = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        line = self.sim.stdout.readline()
        found = re.search(r"listening on [0-9.]+:(\d+)", line)
        if not found:
            self.sim.kill()
            raise RuntimeError(f"trueaxis-sim said {line!r}")
        self.port = int(found.group(1))
        self.var = [os.path.join(bin_dir, "trueaxis-var"), "--port", str(self.port)]
        self._copy()

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

    def run(self, commands, timeout_s=300, name="run", show=None):
        """Starts LinuxCNC, runs the MDI commands, stops it: the display's result,
        with "log" (LinuxCNC's output) and "seconds" added."""
        plan = os.path.join(self.folder, f"{name}.plan.json")
        out = os.path.join(self.folder, f"{name}.out.json")
        with open(plan, "w", encoding="utf-8") as f:
            json.dump({"commands": commands, "timeout": timeout_s, "out": out, "show": show}, f)
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
        started = time.monotonic()
        try:
            done = subprocess.run(argv, cwd=self.machine_dir, env=env, capture_output=True, text=True,
                                  timeout=timeout_s + 60)
            log = done.stdout + done.stderr
        except subprocess.TimeoutExpired as e:
            log = f"linuxcnc timed out after {timeout_s + 60} s\n{e.stdout or ''}{e.stderr or ''}"
            subprocess.run(["pkill", "-9", "-u", CI_USER], check=False)
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
