"""The trueaxis module as LinuxCNC's remap sees it: variables over Modbus TCP or
RTU (python3-pymodbus), the handshake, the macro interface, and the register
map for names and texts. No LinuxCNC import: the G65 remap (trueaxis_g65.py)
and tests both use it.

Conventions (docs/INTERFACE.md):
1. #N is the holding registers 4N..4N+3, an IEEE-754 binary64, most
   significant word first ("Encoding").
2. One Module is one Modbus client: over TCP one connection, which the module
   treats as one client of its macro interface ("One client at a time"). The
   remap keeps one Module for the whole program; `take()` holds the interface
   for a session (G65 P1), `release()` gives it back (G65 P0).
3. Every failure raises TrueaxisError with one line a person reads, naming the
   likely cause (no module at the address, a busy controller, a refused
   write); nothing here retries a write the module refused, except the first
   write of a call (`write(..., wait=True)`), refused because another client
   holds the interface, which waits up to `wait_s` for it. A later write of
   the same call refused that way means another client took the interface in
   the middle of the call: it raises, as it would otherwise run the macro on
   inputs that other client may have changed.
4. Blocking: every call returns within its timeouts (`timeout_s` a Modbus
   request, `macro_timeout_s` a macro to done, `wait_s` a busy interface).
5. Every number comes from macros/register_map.json (RegisterMap): the
   handshake's variables by name, the G65 letters' argument variables (the
   rows arg_a .. arg_z), the work offsets (the persistent rows) with their
   units, the request sizes, the status values, the gates' and the errors'
   codes and texts. Nothing here repeats a number the map has.
"""
import json
import re
import struct
import time

EXCEPTION_BUSY = 6  # Modbus exception 06, SERVER DEVICE BUSY (the protocol's, not the map's)

# The handshake's variables, by their names in the register map (docs/INTERFACE.md
# "The handshake"); their numbers come from the map (convention 5).
HANDSHAKE = ("cmd", "status", "error", "done_count", "unlock", "access_fault", "interface",
             "gate_item", "gate_value", "gate_limit", "log_time")

# Why the module refused a register access: #9007's codes (the JSON map's
# access_faults), by name, for the remap's messages.
ACCESS_FAULTS = {}

class TrueaxisError(Exception):
    """A failure to report as one line."""


class ModuleError(TrueaxisError):
    """A macro that ended with status 3: its code, name, text and gate figures."""

    def __init__(self, macro, code, name, text, gate=None):
        self.macro, self.code, self.name, self.text, self.gate = macro, code, name, text, gate
        line = f"macro {macro} failed: error {code} {name}: {text}"
        if gate is not None:
            item, value, limit = gate
            line += f" (gate_item {item:g}, gate_value {value:.6g}, gate_limit {limit:.6g})"
        super().__init__(line)


def read_ini(path):
    """{SECTION: {KEY: [values, in file order]}} of a LinuxCNC ini (upper-case
    names; `#` and `;` lines are comments)."""
    sections, section = {}, None
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line or line[0] in "#;":
                continue
            if line.startswith("[") and line.endswith("]"):
                section = sections.setdefault(line[1:-1].strip().upper(), {})
            elif section is not None and "=" in line:
                key, value = line.split("=", 1)
                section.setdefault(key.strip().upper(), []).append(value.strip())
    return sections


def _crc16(data):
    """CRC-16/CCITT-FALSE (polynomial 0x1021, initial 0xFFFF)."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def home_identity(sections):
    """The machine's home identity, the module's #904 (docs/INTERFACE.md
    "The home"), from an ini read by read_ini: 0 without [TRUEAXIS] HOME_ID
    (the home is not checked); with it, a number 1..65535 of HOME_ID and every
    [JOINT_n]'s HOME and HOME_OFFSET (the first of each, as LinuxCNC reads
    them), so that a home offset changed in the ini changes it, and HOME_ID
    (the integrator's, changed when a home switch moves) too. Raises
    TrueaxisError for a HOME_ID, HOME or HOME_OFFSET that is not a number."""
    trueaxis = sections.get("TRUEAXIS", {})
    if "HOME_ID" not in trueaxis:
        return 0

    def number(where, key, text):
        try:
            return repr(float(text))
        except ValueError:
            raise TrueaxisError(f"[{where}] {key} = {text!r} is not a number (the home identity reads it)")

    text = "HOME_ID=" + number("TRUEAXIS", "HOME_ID", trueaxis["HOME_ID"][0])
    joints = sorted((int(name[6:]), name) for name in sections if re.fullmatch(r"JOINT_\d+", name))
    for n, name in joints:
        joint = sections[name]
        home = [number(name, key, joint[key][0]) if key in joint else "-" for key in ("HOME", "HOME_OFFSET")]
        text += f";{n}:{home[0]},{home[1]}"
    return _crc16(text.encode("ascii")) or 1


def encode(value):
    """The four registers of one variable."""
    return list(struct.unpack(">4H", struct.pack(">d", float(value))))


def decode(registers):
    """The variables in a list of registers (a multiple of four)."""
    return [struct.unpack(">d", struct.pack(">4H", *registers[i:i + 4]))[0] for i in range(0, len(registers), 4)]


class RegisterMap:
    """What the remap needs of macros/register_map.json (convention 5): the
    handshake's numbers (`var["cmd"]` ...), the G65 letters' variables
    (`letters["x"]` = 24), the largest read and write, the status values, the
    error names and texts, the work offsets' units (`offset_units[5281]` =
    "mm") and each macro's work-offset inputs, and the macros the measuring
    log records (each method's compute and check macro, for methods with a
    "log")."""

    def __init__(self, path):
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
            numbers = {v["name"]: v["number"] for v in data["variables"]}
            missing = [name for name in HANDSHAKE if name not in numbers]
            if missing:
                raise KeyError(f"no variable named {', '.join(missing)}")
            self.var = {name: numbers[name] for name in HANDSHAKE}
            self.home_var = numbers.get("home_identity")  # #904 (a map before it: None, not checked)
            self.letters = {name[4:]: number for name, number in numbers.items() if re.fullmatch(r"arg_[a-z]", name)}
            self.read_max = int(data["encoding"]["max_variables_per_read"])
            self.write_max = int(data["encoding"]["max_variables_per_write"])
            status = {name: int(code) for code, name in data["macro_status"].items()}
            self.status_done, self.status_error = status["done"], status["error"]
            self.errors = {e["code"]: (e["name"], e["message"]) for e in data["errors"]}
            for fault in data.get("access_faults", []):
                ACCESS_FAULTS[int(fault["code"])] = fault["name"]
            # The work offsets (the map's persistent rows) and their units, and
            # the ones each macro reads.
            self.offset_units = {v["number"] + k: v["unit"] for v in data["variables"]
                                 if v["access"] == "persistent" for k in range(v.get("count", 1))}
            self.work_offsets = {}
            for macro in data["macros"]:
                ranges = [(i["number"], i.get("count", 1)) for i in macro["inputs"]
                          if i["number"] in self.offset_units]
                self.work_offsets[macro["number"]] = ranges
            self.logged = set()
            self.gate_errors = set()  # the codes of a gate's refusal, which #9012..#9014 explain
            for method in data.get("methods", []):
                self.gate_errors.update(gate["error"] for gate in method.get("gates", []))
                if "log" in method:
                    self.logged.add(method.get("session", {}).get("compute"))
                    self.logged.add(method.get("check", {}).get("macro"))
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise TrueaxisError(f"cannot read the register map {path}: {e} "
                                "([TRUEAXIS] MAP names macros/register_map.json)") from e

    def error(self, code):
        return self.errors.get(code, ("unknown_error", "an error code this register map does not list"))

    def work_offsets_of(self, macro, value_of, machine_units_per_mm):
        """The work offsets `macro` reads, {number: value} in the module's
        units, from value_of(number) in LinuxCNC's: a length (unit "mm") from
        machine units, an angle ("deg") as it is (LinuxCNC keeps angles in
        degrees whatever G20 or G21). Any other unit in the map is an error."""
        offsets = {}
        for first, count in self.work_offsets.get(macro, []):
            for number in range(first, first + count):
                unit = self.offset_units[number]
                value = float(value_of(number))
                if unit == "mm":
                    offsets[number] = value / machine_units_per_mm
                elif unit == "deg":
                    offsets[number] = value
                else:
                    raise TrueaxisError(f"the register map gives work offset #{number} the unit {unit!r}: "
                                        "the remap converts mm and deg")
        return offsets


class Module:
    """One Modbus client of the module (convention 2)."""

    def __init__(self, register_map, host=None, port=502, serial=None, baud=19200, parity="N", unit=1,
                 timeout_s=1.0, macro_timeout_s=30.0, wait_s=10.0):
        self.map = register_map
        self.var = register_map.var
        self.unit = unit
        self.macro_timeout_s = macro_timeout_s
        self.wait_s = wait_s
        if serial:
            from pymodbus.client import ModbusSerialClient
            self.where = f"{serial} (RTU {baud} baud)"
            self.client = ModbusSerialClient(port=serial, baudrate=baud, parity=parity, timeout=timeout_s)
        else:
            from pymodbus.client import ModbusTcpClient
            self.where = f"{host}:{port}"
            self.client = ModbusTcpClient(host, port=port, timeout=timeout_s)
        self.connected = False

    # ----- registers -----------------------------------------------------

    def _connect(self):
        if not self.connected:
            if not self.client.connect():
                raise TrueaxisError(f"no module answers at {self.where} ([TRUEAXIS] HOST/PORT or SERIAL; "
                                    "is the controller's module, or trueaxis-sim, running?)")
            self.connected = True

    def _request(self, call, *args):
        self._connect()
        try:
            reply = call(*args, slave=self.unit)
        except Exception as e:  # pymodbus raises its own ConnectionException, IOError, ...
            self.close()
            raise TrueaxisError(f"the module at {self.where} stopped answering: {e}") from e
        if reply is None:
            self.close()
            raise TrueaxisError(f"the module at {self.where} did not answer")
        if not reply.isError():
            return reply
        code = getattr(reply, "exception_code", None)
        if code is None:  # a transport failure reported as a response object
            self.close()
            raise TrueaxisError(f"the module at {self.where} stopped answering: {reply}")
        return reply

    def read(self, first, count):
        """#first .. #first+count-1 as floats."""
        values = []
        while count > 0:
            n = min(count, self.map.read_max)
            reply = self._request(self.client.read_holding_registers, 4 * first, 4 * n)
            if reply.isError():
                raise TrueaxisError(f"reading #{first}..#{first + n - 1} was refused with Modbus exception "
                                    f"{reply.exception_code:02d}")
            values += decode(reply.registers)
            first, count = first + n, count - n
        return values

    def write(self, first, values, wait=False):
        """#first.. = values. With `wait`, a write refused because another
        client holds the interface is tried again for up to `wait_s`
        (convention 3); any other refusal raises with the module's reason."""
        values = list(values)
        while values:
            n = min(len(values), self.map.write_max)
            words = [w for v in values[:n] for w in encode(v)]
            deadline = time.monotonic() + self.wait_s
            while True:
                reply = self._request(self.client.write_registers, 4 * first, words)
                if not reply.isError():
                    break
                code = reply.exception_code
                if code == EXCEPTION_BUSY and self.read(self.var["interface"], 1)[0] == 2:
                    if not wait:
                        raise TrueaxisError("another client took the macro interface during this call (the "
                                            "module's hold ended: 2 s after a macro, #903 s in a session); "
                                            "nothing of it was run")
                    if time.monotonic() > deadline:
                        raise TrueaxisError(f"controller busy: another client holds the macro interface "
                                            f"(waited {self.wait_s:g} s; [TRUEAXIS] WAIT)")
                    time.sleep(0.1)
                    continue
                fault = int(self.read(self.var["access_fault"], 1)[0])
                why = f"#{self.var['access_fault']} access fault {fault} {ACCESS_FAULTS.get(fault, '')}".rstrip()
                raise TrueaxisError(f"writing #{first}..#{first + n - 1} was refused with Modbus exception "
                                    f"{code:02d} ({why})")
            first, values, wait = first + n, values[n:], False

    # ----- the macro interface -------------------------------------------

    def take(self):
        """Takes the macro interface for a session (#9009 = 1: held up to the
        module's idle limit #903 after each call), waiting for another
        holder."""
        self.write(self.var["interface"], [1], wait=True)

    def release(self):
        """Gives the macro interface back (#9009 = 0) when this client holds
        it: one write, no waiting (a refusal means another client holds it,
        so this one does not)."""
        if not self.connected:
            return
        self._request(self.client.write_registers, 4 * self.var["interface"], encode(0))

    def done_count(self):
        """#9003: the macros finished since the module started."""
        return self.read(self.var["done_count"], 1)[0]

    def run(self, macro):
        """Runs `macro` to its end; raises ModuleError on its error status. A
        macro the measuring log records is handed the controller's wall clock
        (#9015)."""
        var = self.var
        before = self.read(var["done_count"], 1)[0]
        if macro in self.map.logged:
            self.write(var["log_time"], [float(int(time.time()))])
        self.write(var["cmd"], [macro])
        deadline = time.monotonic() + self.macro_timeout_s
        pause = 0.001
        while self.read(var["done_count"], 1)[0] == before:
            if time.monotonic() > deadline:
                raise TrueaxisError(f"macro {macro} did not finish within {self.macro_timeout_s:g} s "
                                    "([TRUEAXIS] TIMEOUT; is the controller calling the module's step()?)")
            time.sleep(pause)
            pause = min(2 * pause, 0.02)
        status, code = self.read(var["status"], 2)
        if status == self.map.status_done:
            return
        code = int(code)
        name, text = self.map.error(code)
        gate = tuple(self.read(var["gate_item"], 3)) if code in self.map.gate_errors else None
        raise ModuleError(macro, code, name, text, gate)

    def close(self):
        try:
            self.client.close()
        finally:
            self.connected = False
