#!/usr/bin/python3
"""The display of a headless LinuxCNC run (linuxcnc -r, [DISPLAY] DISPLAY): runs
the MDI commands of a scenario and writes what happened, then exits, which
ends LinuxCNC.

usage (by linuxcnc): scenario_display.py -ini INI
Environment: TRUEAXIS_SCENARIO, a JSON file {"commands": [MDI lines...],
"setup": [MDI lines run after homing, before the commands, not steps: the
probe's tool loaded and its length offset on], "timeout": seconds each, "out":
result file}. A command is an MDI line, or
{"mdi": line, "may_fail": true} (a step whose error does not stop the run),
or {"run": [argv]} (a program run while LinuxCNC is up, its output in the
step's "stdout"). The result file: {"steps": [{"command", "ok", "errors":
[texts], "seconds", "position": [x, y, z, a, c], "joints": [the five joints]}],
"homed": bool, "error":
text of a failure outside the steps or null}. Stops at the first command that
fails (unless it may).

A command has ended when LinuxCNC's task answers it done (wait_complete) and
the interpreter is idle with nothing queued. It has failed when the task
reports an error message, or answers it with RCS_ERROR without one: the task
then aborted it (a program stopped half-way looks idle too), as it does when
it gives up waiting for the motion controller ("USRMOT: ERROR: command
timeout" in LinuxCNC's log, [EMCMOT] COMM_TIMEOUT).
"""
import json
import os
import time

import linuxcnc


def wait_for(predicate, stat, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            stat.poll()
        except SystemError:  # the task's status buffer not there yet
            time.sleep(0.2)
            continue
        if predicate(stat):
            return
        time.sleep(0.05)
    raise TimeoutError(f"timed out after {timeout} s waiting for {what}")


def drain(errors):
    texts = []
    while True:
        e = errors.poll()
        if not e:
            return texts
        kind, text = e
        texts.append((kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR), text))


def main():
    plan = json.load(open(os.environ["TRUEAXIS_SCENARIO"]))
    out = {"steps": [], "homed": False, "error": None}
    c, s, errors = linuxcnc.command(), linuxcnc.stat(), linuxcnc.error_channel()
    try:
        wait_for(lambda st: True, s, 30, "the task")
        c.state(linuxcnc.STATE_ESTOP_RESET)
        c.state(linuxcnc.STATE_ON)
        wait_for(lambda st: st.task_state == linuxcnc.STATE_ON, s, 30, "machine on")
        c.mode(linuxcnc.MODE_MANUAL)
        c.wait_complete()
        c.home(-1)
        wait_for(lambda st: all(st.homed[i] for i in range(5)), s, 60, "homing")
        out["homed"] = True
        c.mode(linuxcnc.MODE_MDI)
        c.wait_complete()
        drain(errors)
        for command in plan.get("setup", []):
            c.mdi(command)
            answer = c.wait_complete(60)
            wait_for(lambda st: st.interp_state == linuxcnc.INTERP_IDLE and st.queue == 0, s, 60, f"'{command}'")
            texts = [t for error, t in drain(errors) if error]
            if texts or answer in (-1, linuxcnc.RCS_ERROR):
                raise RuntimeError(f"the setup command '{command}' failed: {texts or answer}")
        for item in plan["commands"]:
            started = time.monotonic()
            if isinstance(item, dict) and "run" in item:
                import subprocess
                done = subprocess.run(item["run"], capture_output=True, text=True, timeout=60)
                out["steps"].append({"command": item["run"], "ok": done.returncode == 0, "errors": [],
                                     "stdout": done.stdout + done.stderr,
                                     "seconds": round(time.monotonic() - started, 3)})
                continue
            command = item["mdi"] if isinstance(item, dict) else item
            may_fail = isinstance(item, dict) and item.get("may_fail", False)
            c.mdi(command)
            answer = c.wait_complete(plan.get("timeout", 300))
            wait_for(lambda st: st.interp_state == linuxcnc.INTERP_IDLE and st.queue == 0 and not getattr(st, "queued_mdi_commands", 0),
                     s, plan.get("timeout", 300), f"'{command}'")
            time.sleep(0.1)
            drained = drain(errors)
            texts = [t for error, t in drained if error]
            if answer == linuxcnc.RCS_ERROR and not texts:
                texts.append("LinuxCNC's task aborted the command without a message (RCS_ERROR): its log says why, "
                             "e.g. 'USRMOT: ERROR: command timeout'")
            elif answer == -1 and not texts:
                texts.append(f"LinuxCNC's task did not answer the command within {plan.get('timeout', 300)} s")
            s.poll()
            step = {"command": command, "ok": not texts, "errors": texts,
                    "messages": [t for error, t in drained if not error],
                    "probed": list(s.probed_position)[:6], "probe_tripped": bool(s.probe_tripped),
                    "seconds": round(time.monotonic() - started, 3),
                    "position": [s.actual_position[i] for i in (0, 1, 2, 3, 5)],
                    "joints": list(s.joint_actual_position[:5])}
            if plan.get("show"):  # diagnosis: HAL pins after each step
                import subprocess
                step["hal"] = subprocess.run(["halcmd", "show", "pin"] + plan["show"], capture_output=True,
                                             text=True).stdout
            out["steps"].append(step)
            if texts and not may_fail:
                break
    except Exception as e:  # reported to the test, which fails on it
        out["error"] = f"{type(e).__name__}: {e}"
    with open(plan["out"], "w", encoding="utf-8") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
