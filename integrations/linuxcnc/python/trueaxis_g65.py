"""G65 P<macro> <letters> in LinuxCNC: a Fanuc-style call of a trueaxis module
macro (integrations/linuxcnc/README.md; docs/INTERFACE.md "Additions").

The remap (trueaxis.ini: REMAP=G65 ... python=g65):
1. waits for the motion queue to empty (the call is a queue buster, as a Fanuc
   macro call that reads system variables is), so the module acts in program
   order;
2. in LinuxCNC's preview interpreters (self.task 0) does no device I/O and
   leaves #100..#199 as they are, unless [TRUEAXIS] PREVIEW = 1;
3. writes the module's argument variables (#1..#26 of the 21 G65 letters)
   from the call's letters (letters not given: 0),
   and, for a macro whose map entry reads work offsets, LinuxCNC's own values
   of those offsets (#5221..#5326: lengths converted from machine units to mm,
   angles in degrees as they are; RegisterMap.work_offsets_of) where they
   differ from the module's;
4. runs the macro to its end and copies the module's #100..#199 into
   LinuxCNC's #100..#199, bit for bit; on a module error aborts the program
   with the module's code, name and text (and a gate's #9012..#9014).

Letters. LinuxCNC executes F, S, T and M in any block, and B, U, V, W are axis
words only on machines with those axes, so those eight letters never go on
the G65 line: set #<_ta_b>, #<_ta_f>, #<_ta_m>, #<_ta_s>, #<_ta_t>, #<_ta_u>,
#<_ta_v>, #<_ta_w> before the call (`#<_ta_s> = 30` then `G65 P9843 Z100`).
The call reads them and sets them back to 0, as the module clears its #1..#26
after every macro. A G65 block holding one of them is refused before anything
is written. Every value is in mm and degrees: the call is refused under G20
(G65 P0 excepted).

A macro that stores a table (9832, 9823, 9842 with R = 1) needs the module
unlocked: `#<_ta_unlock> = CODE` before the call writes CODE to #9004 just
before the macro and 0 just after it, whatever its end; the code is never
kept.

The macro interface (docs/INTERFACE.md "One client at a time"). The remap
keeps one connection to the module for the LinuxCNC session. A call takes the
module's macro interface with its arguments and keeps it for its macro and
2 s after (the module's rule), so an HMI beside LinuxCNC is never locked out
for longer. `G65 P1` takes it for a session (#9009 = 1: the module keeps it
up to its idle limit #903, default 30 s, after each call, while the program
probes between two adds); `G65 P0` gives it back (#9009 = 0). The operator
programs that run a session wrap it in P1 .. P0; a call that fails gives the
interface back too.
"""
import os

from interpreter import INTERP_ERROR, INTERP_EXECUTE_FINISH, INTERP_OK

from trueaxis_module import Module, RegisterMap, TrueaxisError, home_identity, read_ini

LINE_LETTERS = "acdehijkqrxyz"  # the G65 line's letters besides P (trueaxis.ini argspec)
NAMED_LETTERS = tuple("bfmstuvw")  # as #<_ta_LETTER>
RESULTS_FIRST, RESULTS_COUNT = 100, 100  # #100..#199, the results (docs/INTERFACE.md, the fixed part)
RELEASE, HOLD = 0, 1  # G65 P0, G65 P1: the macro interface given back, taken for a session
HERE = os.path.dirname(os.path.abspath(__file__))


def _ini_path():
    """The machine's ini: $INI_FILE_NAME (set by `linuxcnc`), else the standalone
    interpreter's `rs274 -i FILE`."""
    path = os.environ.get("INI_FILE_NAME")
    if path:
        return path
    try:
        with open("/proc/self/cmdline", "rb") as f:
            argv = f.read().decode("utf-8", "replace").split("\0")
        return argv[argv.index("-i") + 1]
    except (OSError, ValueError, IndexError):
        return None


def read_settings(path):
    """[TRUEAXIS] of the ini at `path` as a dict of upper-case keys (the first
    value of a repeated key, as LinuxCNC's own ini reader and #<_ini[..]>
    take it; trueaxis_module.read_ini); paths in it are relative to the ini's
    folder. "_KINEMATICS" is [KINS] KINEMATICS, "_SECTIONS" the whole ini."""
    sections = read_ini(path)
    settings = {key: values[0] for key, values in sections.get("TRUEAXIS", {}).items()}
    kinematics = sections.get("KINS", {}).get("KINEMATICS")
    if kinematics:
        settings["_KINEMATICS"] = kinematics[0]
    settings["_DIR"] = os.path.dirname(os.path.abspath(path))
    settings["_SECTIONS"] = sections
    return settings


def trueaxis_kins_parameters(settings):
    """The name=value words of a [KINS] KINEMATICS = trueaxis_kins line as a
    dict, or None when the machine's kinematics are another module's."""
    words = settings.get("_KINEMATICS", "").split()
    if not words or words[0] != "trueaxis_kins":
        return None
    return dict(w.split("=", 1) for w in words[1:] if "=" in w)


PIVOT_KEYS = ("PIVOT_X", "PIVOT_Y", "PIVOT_Z", "A_OFFSET_Y", "A_OFFSET_Z")


def home_mismatch(settings, home):
    """None, or the sentence why a [KINS] KINEMATICS = trueaxis_kins line's
    home= (absent 0) is not this machine's home identity `home`."""
    kins = trueaxis_kins_parameters(settings)
    if kins is None or kins.get("home", "0") in (str(home), ""):
        return None
    return (f"[KINS] trueaxis_kins home={kins.get('home', '0')} is not this machine's home identity {home} "
            "([TRUEAXIS] HOME_ID and the joints' HOME, HOME_OFFSET; trueaxis_home.py prints it): the kinematics "
            "would check their table against another home")


INCH_NAMES = ("inch", "in", "imperial")  # trueaxis_kins' linear_units= for an inch machine


def pivot_mismatch(settings):
    """None, or the sentence why [TRUEAXIS] PIVOT_X .. A_OFFSET_Z (what the
    programs aim with, mm, absent 0) are not the pivot= and a_offset= of a
    [KINS] KINEMATICS = trueaxis_kins line without table= (the machine's
    units, absent 0): two pivots on one machine. With table= the kinematics
    turn about the table's measured axes, not the nominal pivot."""
    kins = trueaxis_kins_parameters(settings)
    if kins is None or kins.get("table"):
        return None
    mm = 25.4 if kins.get("linear_units", "mm") in INCH_NAMES else 1.0
    try:
        theirs = [mm * float(v) for v in (kins.get("pivot") or "0,0,0").split(",")] + \
                 [mm * float(v) for v in (kins.get("a_offset") or "0,0").split(",")]
        ours = [float(settings.get(k, "0")) for k in PIVOT_KEYS]
    except ValueError:
        return "[KINS] KINEMATICS or [TRUEAXIS] PIVOT_* holds a pivot that is not numbers"
    if len(theirs) != 5 or any(abs(a - b) > 1e-9 for a, b in zip(theirs, ours)):
        return (f"[TRUEAXIS] PIVOT_X..A_OFFSET_Z {ours} are not [KINS] trueaxis_kins' pivot= and a_offset= "
                f"{theirs}: the programs would aim at a pivot the kinematics do not turn about")
    return None


class Remap:
    """The remap's state over a LinuxCNC session: settings, map, one client."""

    def __init__(self, settings):
        def number(key, default, kind=float):
            try:
                return kind(settings.get(key, default))
            except ValueError:
                raise TrueaxisError(f"[TRUEAXIS] {key} = {settings[key]!r} is not a number")

        mismatch = pivot_mismatch(settings)
        if mismatch:
            raise TrueaxisError(mismatch)
        # The machine's home identity (trueaxis_module.home_identity), which the
        # module's #904 and the kinematics' home= must be.
        self.home = home_identity(settings.get("_SECTIONS", {}))
        mismatch = home_mismatch(settings, self.home)
        if mismatch:
            raise TrueaxisError(mismatch)
        where = settings.get("_DIR", HERE)
        map_path = settings.get("MAP", os.path.join(HERE, "..", "..", "..", "macros", "register_map.json"))
        self.map = RegisterMap(os.path.join(where, map_path))
        self.preview = number("PREVIEW", 0, int) == 1
        self.session_count = None  # #9003 after this client's last macro, in a G65 P1 session
        self.module = Module(self.map, host=settings.get("HOST", "127.0.0.1"), port=number("PORT", 502, int),
                             serial=settings.get("SERIAL"), baud=number("BAUD", 19200, int),
                             parity=settings.get("PARITY", "N"), unit=number("UNIT", 1, int),
                             timeout_s=number("REQUEST_TIMEOUT", 1.0), macro_timeout_s=number("TIMEOUT", 30.0),
                             wait_s=number("WAIT", 10.0))

    def call(self, macro, arguments, offsets, unlock=0.0):
        """Runs `macro` with the arguments {number: value} (every G65 letter's
        variable) and the work offsets {number: mm or deg}; returns the
        module's #100..#199. P0 and P1 give the macro interface back and take
        it for a session; they return None."""
        module = self.module
        if macro == RELEASE:
            self.session_count = None
            module.release()
            return None
        if macro == HOLD:
            module.take()
            self.session_count = module.done_count()
            return None
        # The module's home is this machine's (docs/INTERFACE.md "The home"):
        # else its tables hold axes whose zeros moved, or #904 was never set.
        if module.map.home_var is not None:
            theirs = module.read(module.map.home_var, 1)[0]
            if theirs != self.home:
                raise TrueaxisError(
                    f"the module's home identity #{module.map.home_var} is {theirs:g}, this machine's {self.home} "
                    "([TRUEAXIS] HOME_ID and the joints' HOME, HOME_OFFSET): an axis' zero moved since the module "
                    f"was told, or it never was. Once the axes are homed where its tables were measured, set "
                    f"#{module.map.home_var} = {self.home} (unlocked: trueaxis-var set {module.var['unlock']}=CODE "
                    f"{module.map.home_var}={self.home} {module.var['unlock']}=0); else measure M3 again")
        # The arguments first: they take the interface (waiting for it), so no
        # other client's write comes between them and the macro; a later write
        # refused means another client took it meanwhile (trueaxis_module.py
        # convention 3). In a session (P1) no other client's macro may have
        # run since this client's last one.
        first = True
        for start, values in _runs(arguments):
            module.write(start, values, wait=first)
            first = False
        if self.session_count is not None and module.done_count() != self.session_count:
            raise TrueaxisError("another client ran a macro on the module during this program's session "
                                "(G65 P1; its hold ends #903 s after a call): the session may be mixed, "
                                "run the program again")
        for start, values in _runs(offsets):
            present = module.read(start, len(values))
            if present != values:
                module.write(start, values)
        unlock_var = module.var["unlock"]
        if unlock:
            module.write(unlock_var, [unlock])
        try:
            module.run(macro)
        finally:
            if self.session_count is not None:
                self.session_count = module.done_count()
            if unlock:
                try:
                    module.write(unlock_var, [0])
                except TrueaxisError:
                    module.close()  # the module locks a closed connection's unlock
                    raise
        return module.read(RESULTS_FIRST, RESULTS_COUNT)

    def release_after_failure(self):
        """A program that stops gives the macro interface back at once, so
        another client need not wait for it; quietly, as the stop has its message."""
        self.session_count = None
        try:
            self.module.release()
        except Exception:
            self.module.close()


def _runs(offsets):
    """{number: value} as runs of consecutive numbers: [(first, [values])]."""
    runs = []
    for number in sorted(offsets):
        if runs and runs[-1][0] + len(runs[-1][1]) == number:
            runs[-1][1].append(offsets[number])
        else:
            runs.append((number, [offsets[number]]))
    return runs


_remap = None


def _state():
    global _remap
    if _remap is None:
        path = _ini_path()
        if path is None or not os.path.isfile(path):
            raise TrueaxisError("no ini file to read [TRUEAXIS] from (INI_FILE_NAME or rs274 -i)")
        _remap = Remap(read_settings(path))
    return _remap


def _refused_letters(block):
    """The letters of NAMED_LETTERS present in the G65 block."""
    found = [c.upper() for c in "bfstuvw" if getattr(block, c + "_flag", False)]
    if any(m != -1 for m in block.m_modes):
        found.append("M")
    return found


def _named_arguments(params):
    """{letter: value} of the #<_ta_LETTER> that exist, and "unlock" for
    #<_ta_unlock>; each set back to 0."""
    values = {}
    for letter in NAMED_LETTERS + ("unlock",):
        name = "_ta_" + letter
        try:
            values[letter] = float(params[name])
        except (KeyError, NameError, TypeError, RuntimeError):
            continue
        params[name] = 0.0
    return values


def g65(self, **words):
    """The G65 remap handler (a generator: it waits for motion with
    INTERP_EXECUTE_FINISH)."""
    try:
        block = self.blocks[self.remap_level]
        refused = _refused_letters(block)
        if refused:
            letters = ", ".join(refused)
            raise TrueaxisError(f"{letters} on a G65 line: LinuxCNC acts on {letters} in any block; set "
                                + ", ".join(f"#<_ta_{c.lower()}>" for c in refused) + " before the call instead")
        macro = words.get("p")
        if macro is None or macro != int(macro) or not 0 <= macro <= 9999:
            raise TrueaxisError(f"P must be a macro number 0..9999 (got {macro})")
        macro = int(macro)
        named = _named_arguments(self.params)
        remap = _state()
        if self.task == 0 and not remap.preview:
            yield INTERP_OK
            return
    except TrueaxisError as e:
        self.set_errormsg(f"trueaxis G65: {e}")
        yield INTERP_ERROR
        return
    except Exception as e:  # anything else still stops the program with one line
        self.set_errormsg(f"trueaxis G65: {type(e).__name__}: {e}")
        yield INTERP_ERROR
        return

    if macro != RELEASE:
        # P0 moves nothing and needs no motion finished: in LinuxCNC's on_abort
        # a suspended call would only resume with the next program. P1 waits,
        # so that its hold starts where the program's session does.
        yield INTERP_EXECUTE_FINISH

    try:
        if macro not in (RELEASE, HOLD) and int(self.params["_metric"]) != 1:
            raise TrueaxisError("G20 is active: the module takes mm (program G21 before the call)")
        letters = remap.map.letters
        arguments = {number: 0.0 for number in letters.values()}
        unlock = named.pop("unlock", 0.0)
        for letter, value in list(words.items()) + list(named.items()):
            if letter != "p":
                arguments[letters[letter]] = float(value)
        import emccanon  # LinuxCNC's canon: machine units per mm
        # LinuxCNC's own #5221.. are the module's numbers.
        offsets = remap.map.work_offsets_of(macro, lambda number: self.params[number],
                                            emccanon.GET_EXTERNAL_LENGTH_UNITS())
        results = remap.call(macro, arguments, offsets, unlock)
    except Exception as e:  # TrueaxisError, or anything else: one line
        text = str(e) if isinstance(e, TrueaxisError) else f"{type(e).__name__}: {e}"
        remap.release_after_failure()
        self.set_errormsg(f"trueaxis G65 P{macro}: {text}")
        yield INTERP_ERROR
        return
    if results is not None:
        for i, value in enumerate(results):
            self.params[RESULTS_FIRST + i] = value
    yield INTERP_OK
