"""The trueaxis module as LinuxCNC's remap sees it: variables over Modbus TCP or
RTU (python3-pymodbus), the handshake, the macro interface, and the register
map for names and texts. No LinuxCNC import: the G65 remap (trueaxis_g65.py)
and tests both use it.

Conventions (docs/INTERFACE.md):
1. #N is the holding registers 4N..4N+3, an IEEE-754 binary64, most
   significant word first ("Encoding").
2. One Module is one Modbus client: over TCP one connection, which the module
   treats as one client of its macro interface ("One client at a time"). The
   remap keeps one Module for the whole program, so a session (clear, add, ...,
   build) is one client's from its first write to its `release()`.
3. Every failure raises TrueaxisError with one line a person reads, naming the
   likely cause (no module at the address, a busy controller, a refused
   write); nothing here retries a write the module refused, except a write
   refused because another client holds the interface, which waits up to
   `wait_s` for it.
4. Blocking: every call returns within its timeouts (`timeout_s` a Modbus
   request, `macro_timeout_s` a macro to done, `wait_s` a busy interface).
"""
import json
import struct
import time

# Handshake and status variables (docs/INTERFACE.md "The handshake").
CMD, STATUS, ERROR, DONE_COUNT, UNLOCK = 9000, 9001, 9002, 9003, 9004
ACCESS_FAULT, INTERFACE = 9007, 9009
GATE_ITEM, GATE_VALUE, GATE_LIMIT = 9012, 9013, 9014
LOG_TIME = 9015  # the measuring log's time of the macro about to run (Unix seconds)
STATUS_DONE, STATUS_ERROR = 2, 3
EXCEPTION_BUSY = 6
VARS_PER_REQUEST = 31  # 124 registers a read, within function 3's 125
WRITE_VARS_PER_REQUEST = 30  # 120 registers a write, within function 16's 123

# Why the module refused a register access: #9007's codes (the JSON map's
# access_faults), by name, for the remap's messages.
ACCESS_FAULTS = {}

# The G65 letters and the argument variable each fills (docs/INTERFACE.md "Variable ranges").
LETTER_VARIABLE = {
    "a": 1, "b": 2, "c": 3, "i": 4, "j": 5, "k": 6, "d": 7, "e": 8, "f": 9, "h": 11, "m": 13,
    "q": 17, "r": 18, "s": 19, "t": 20, "u": 21, "v": 22, "w": 23, "x": 24, "y": 25, "z": 26,
}


class TrueaxisError(Exception):
    """A failure to report as one line."""


class ModuleError(TrueaxisError):
    """A macro that ended with status 3: its code, name, text and gate figures."""

    def __init__(self, macro, code, name, text, gate=None):
        self.macro, self.code, self.name, self.text, self.gate = macro, code, name, text, gate
        line = f"macro {macro} failed: error {code} {name}: {text}"
        if gate is not None:
            item, value, limit = gate
            line += f" (#9012 item {item:g}, #9013 value {value:.6g}, #9014 limit {limit:.6g})"
        super().__init__(line)


def encode(value):
    """The four registers of one variable."""
    return list(struct.unpack(">4H", struct.pack(">d", float(value))))


def decode(registers):
    """The variables in a list of registers (a multiple of four)."""
    return [struct.unpack(">d", struct.pack(">4H", *registers[i:i + 4]))[0] for i in range(0, len(registers), 4)]


class RegisterMap:
    """What the remap needs of macros/register_map.json: error names and texts,
    each macro's work-offset inputs, and the macros the measuring log records
    (each method's compute and check macro, for methods with a "log")."""

    def __init__(self, path):
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
            self.errors = {e["code"]: (e["name"], e["message"]) for e in data["errors"]}
            for fault in data.get("access_faults", []):
                ACCESS_FAULTS[int(fault["code"])] = fault["name"]
            self.work_offsets = {}
            for macro in data["macros"]:
                ranges = [(i["number"], i.get("count", 1)) for i in macro["inputs"]
                          if 5221 <= i["number"] <= 5326]
                self.work_offsets[macro["number"]] = ranges
            self.logged = set()
            for method in data.get("methods", []):
                if "log" in method:
                    self.logged.add(method.get("session", {}).get("compute"))
                    self.logged.add(method.get("check", {}).get("macro"))
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise TrueaxisError(f"cannot read the register map {path}: {e} "
                                "([TRUEAXIS] MAP names macros/register_map.json)") from e

    def error(self, code):
        return self.errors.get(code, ("unknown_error", "an error code this register map does not list"))


class Module:
    """One Modbus client of the module (convention 2)."""

    def __init__(self, host=None, port=502, serial=None, baud=19200, parity="N", unit=1,
                 timeout_s=1.0, macro_timeout_s=30.0, wait_s=10.0):
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
            n = min(count, VARS_PER_REQUEST)
            reply = self._request(self.client.read_holding_registers, 4 * first, 4 * n)
            if reply.isError():
                raise TrueaxisError(f"reading #{first}..#{first + n - 1} was refused with Modbus exception "
                                    f"{reply.exception_code:02d}")
            values += decode(reply.registers)
            first, count = first + n, count - n
        return values

    def write(self, first, values):
        """#first.. = values; waits while another client holds the interface
        (convention 3); any other refusal raises with the module's reason."""
        values = list(values)
        while values:
            n = min(len(values), WRITE_VARS_PER_REQUEST)
            words = [w for v in values[:n] for w in encode(v)]
            deadline = time.monotonic() + self.wait_s
            while True:
                reply = self._request(self.client.write_registers, 4 * first, words)
                if not reply.isError():
                    break
                code = reply.exception_code
                if code == EXCEPTION_BUSY and self.read(INTERFACE, 1)[0] == 2:
                    if time.monotonic() > deadline:
                        raise TrueaxisError(f"controller busy: another client holds the macro interface "
                                            f"(waited {self.wait_s:g} s; [TRUEAXIS] WAIT)")
                    time.sleep(0.1)
                    continue
                fault = int(self.read(ACCESS_FAULT, 1)[0])
                why = f"#9007 access fault {fault} {ACCESS_FAULTS.get(fault, '')}".rstrip()
                raise TrueaxisError(f"writing #{first}..#{first + n - 1} was refused with Modbus exception "
                                    f"{code:02d} ({why})")
            first, values = first + n, values[n:]

    # ----- the macro interface -------------------------------------------

    def take(self):
        """Takes the macro interface (#9009 = 1), waiting for another holder."""
        self.write(INTERFACE, [1])

    def release(self):
        """Gives the macro interface back (#9009 = 0) when this client holds it."""
        if self.connected and self.read(INTERFACE, 1)[0] == 1:
            self.write(INTERFACE, [0])

    def run(self, macro, register_map):
        """Runs `macro` to its end; raises ModuleError on status 3. A macro the
        measuring log records is handed the controller's wall clock (#9015)."""
        before = self.read(DONE_COUNT, 1)[0]
        if macro in register_map.logged:
            self.write(LOG_TIME, [float(int(time.time()))])
        self.write(CMD, [macro])
        deadline = time.monotonic() + self.macro_timeout_s
        pause = 0.001
        while self.read(DONE_COUNT, 1)[0] == before:
            if time.monotonic() > deadline:
                raise TrueaxisError(f"macro {macro} did not finish within {self.macro_timeout_s:g} s "
                                    "([TRUEAXIS] TIMEOUT; is the controller calling the module's step()?)")
            time.sleep(pause)
            pause = min(2 * pause, 0.02)
        status, code = self.read(STATUS, 2)
        if status == STATUS_DONE:
            return
        code = int(code)
        name, text = register_map.error(code)
        gate = tuple(self.read(GATE_ITEM, 3)) if code in (500, 501) or code >= 1000 else None
        raise ModuleError(macro, code, name, text, gate)

    def close(self):
        try:
            self.client.close()
        finally:
            self.connected = False
