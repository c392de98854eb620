#!/usr/bin/env python3
"""Worst-case stack of the firmware's entry points, from gcc's call graph.

    python3 tools/stack_report.py build/target [--elf IMAGE ...] [--bound ROOT=BYTES ...] [--json]

The cross build writes, beside every object of the firmware libraries, gcc's
call graph with each function's frame (-fcallgraph-info=su, a VCG file *.ci;
option TRUEAXIS_STACK_INFO, cmake/trueaxis.cmake). This script reads every .ci
under the build directory, joins them into one call graph, and reports for each
root (ROOTS below: Module::step(), the register read/write, the protocol core,
the RTU framer, each per-cycle query) the worst-case stack in bytes and the call
path that reaches it, and the largest frames (the targets for cutting).
Python 3 standard library (and objdump for --elf); a run takes a second or two.

Conventions
 1. A function's frame is gcc's "static" stack usage of it (-fstack-usage): on
    the Cortex-M7 everything its prologue reserves: the registers it pushes (LR
    among them), the VFP registers it saves, its locals and spills and the
    outgoing arguments. A call (bl) pushes nothing more. With --elf, a function
    linked in an image takes the larger of gcc's figure and its disassembly's:
    gcc leaves out the argument registers a function pushes for an argument
    passed partly in registers (ARM's "pretend args"; apply_disassembly()).
    A root's figure is its own frame plus the worst of its callees',
    recursively: the stack the call needs below the caller's stack pointer.
    Interrupts are not included: an exception taken during the call adds the
    hardware frame (32 bytes, 104 with the FP context) and the handler's stack.
 2. Functions are the nodes gcc names in the .ci files. A function with
    internal linkage (anonymous namespace, static, a .isra/.constprop/.part
    clone; is_internal()) is its unit's own; any other name (a strong symbol, or the weak
    copies of an inline or template function, one per unit) is one node whose
    frame is the largest of its copies and whose callees are all of theirs.
    A call to a complete-object constructor or destructor (C1, D1) reaches the
    base-object one (C2, D2) that gcc defined it as an alias of.
 3. A frame gcc calls "dynamic" (alloca, a variable-length array) is an error
    unless DYNAMIC_FRAMES states a bound for it; "dynamic,bounded" is taken at
    gcc's figure, which bounds it. A recursion is an error unless RECURSIONS
    states the depth of a function calling itself: its frame counts that many
    times.
 4. Indirect calls (gcc's __indirect_call: virtual calls, function pointers)
    are resolved by INDIRECT_CALLS, an ordered table of rules: the first rule
    whose caller pattern matches the calling function and whose site pattern
    matches the call's source location (file:line:column, of the inlined
    wrapper when the virtual call is inlined: e.g. hal/clock.hpp for
    Clock::now_us()) gives the call's possible targets: every analysed function
    matching one of the rule's target patterns. The call costs the worst of
    them. Patterns are Python regular expressions searched in gcc's name of a
    function, its declaration as gcc prints it: return type, qualified name,
    parameter types and, for a template, " [with T = ...]"; e.g.
        trueaxis::macros::MacroStep trueaxis::macros::gantry::run_build(trueaxis::macros::MacroContext&)
    With --elf, the function pointers held by a rule's tables (the macro
    table) in the linked image must all be among its targets.
 5. A call to a function the build did not compile (newlib, libgcc) costs the
    bound LIBRARY states for it: its own frame and everything it calls, read
    from the disassembly of the linked image. --elf IMAGE checks every stated
    bound a root relies on against that image's disassembly (conventions of
    the disassembly: see the comment above Disassembly).
 6. A library function's bound may depend on its arguments (libm's sin and cos
    need 744 B only to reduce |x| >= 2^20 pi/2). CALL_BOUNDS states a smaller
    bound for the calls made through a chain of callers (patterns of
    consecutive functions on the call path, the last one the library
    function's caller) whose code guarantees the arguments for every input,
    the reason in the entry; the analysis is context-sensitive for them (a
    function reached through the chain and otherwise is two cases), and a
    root's report lists the entries its figure relies on. With --elf, each
    entry a root relies on is checked: its bound is at least the
    disassembly's with the entry's `skip` functions cut off, and each of them
    is on the library function's path there.
 7. Errors, never counted as zero, in what a root reaches: an indirect call no
    rule resolves, a rule whose targets match no function, a table entry no
    rule target covers, a recursion not in RECURSIONS, a call to a function
    with no stack information and no LIBRARY entry, a dynamic frame not in
    DYNAMIC_FRAMES, a library bound below its disassembly, a CALL_BOUNDS
    bound below its disassembly or cutting off a function its library
    function does not call, a root pattern that matches no function or
    several, a --bound naming no root. Also a rule, table, RECURSIONS or
    CALL_BOUNDS entry that nothing matches any more (stale: for CALL_BOUNDS,
    one no root relies on), an object of an analysed library without its .ci
    or with a .ci older than it (a build without TRUEAXIS_STACK_INFO, or a
    ccache hit, which restores no .ci). Problems in code no root reaches are
    not errors.

Exit status: 0 when every root is analysed and within its bound; 1 when a root
exceeds its --bound (its path is printed); 2 on an analysis error (printed).
"""

import argparse
import bisect
import fnmatch
import json
import os
import re
import shutil
import subprocess
import sys
from collections import namedtuple

# ---------------------------------------------------------------------------
# Configuration. Patterns: Python regexes searched in gcc's function names
# (convention 4). Keep them to names an integrator would recognise; a renamed
# function that a pattern no longer matches is an error, never a silent zero.

Root = namedtuple("Root", "name pattern note")

# The entry points an integrator sizes his tasks for. Names are grouped by a
# prefix so that --bound takes globs ('query:*=1024').
ROOTS = [
    Root("step", r"\btrueaxis::macros::Module::step\(\)",
         "Module::step(): one bounded piece of the running macro (background task)"),
    Root("access:read", r"\btrueaxis::macros::Module::do_read\(",
         "a register read: VariableAccess::read (inline) into Module::do_read"),
    Root("access:write", r"\btrueaxis::macros::Module::do_write\(",
         "a register write: VariableAccess::write (inline) into Module::do_write"),
    Root("protocol:respond", r"\btrueaxis::modbus::ModbusCore::respond\(",
         "the protocol core: one Modbus request, PDU in, response out"),
    Root("protocol:rtu_receive", r"\btrueaxis::modbus::ModbusRtu::receive\(",
         "the RTU framer fed one byte (may end a frame and answer it)"),
    Root("protocol:rtu_poll", r"\btrueaxis::modbus::ModbusRtu::poll\(",
         "the RTU framer's poll (ends a frame after the silence and answers it)"),
    Root("query:compensation_rad", r"\btrueaxis::macros::rigidity::compensation_rad\(",
         "M3's per-cycle query (real-time task)"),
    Root("query:sub_point_mm", r"\btrueaxis::macros::gantry::sub_point_mm\(",
         "M2's per-cycle query (real-time task)"),
    Root("query:tool_tip_correction", r"\btrueaxis::macros::spindle::tool_tip_correction\(",
         "M4's per-cycle query (real-time task)"),
    Root("boot:start", r"\btrueaxis::macros::Module::start\(\)",
         "Module::start(): once, at boot"),
]

Rule = namedtuple("Rule", "caller site targets why tables layout", defaults=(None, None))

# Ordered: the first rule matching (caller, site) resolves an indirect call.
# caller/site None: any. Every target pattern of a rule that fires must match
# at least one function. tables (optional): a pattern of the symbol names of
# the data objects the calls take their pointers from; with --elf, every
# function pointer those objects hold in the image must be among the rule's
# targets (so a table entry the patterns miss is an error, not an underestimate).
# layout (optional): (stride, offsets) when the tables are arrays of structs
# of `stride` bytes holding pointers only at those byte offsets: the other
# words are data (a macro number, 9841 = 0x2671, is a Thumb address when a
# function starts at 0x2670), and a table whose size is no multiple of the
# stride is an error (the struct changed).
INDIRECT_CALLS = [
    Rule(None, r"/hal/clock\.hpp:",
         [r"::do_now_us\(\)"],
         "hal::Clock::now_us(): every Clock implementation analysed (the board's SysTickClock)"),
    Rule(None, r"/hal/nv_storage\.hpp:",
         [r"::do_size_bytes\(\) const", r"::do_read\(std::size_t, uint8_t\*, std::size_t\)",
          r"::do_write\(std::size_t, const uint8_t\*, std::size_t\)"],
         "hal::NvStorage's read/write/size: every NvStorage implementation analysed (RamNvStorage)"),
    Rule(None, r"/variable_access\.hpp:",
         [r"::do_read\(uint16_t, uint16_t, double\*, (trueaxis::macros::)?ClientId\)",
          r"::do_write\(uint16_t, uint16_t, const double\*, (trueaxis::macros::)?ClientId\)",
          r"::do_note_fault\(trueaxis::macros::AccessFault\)"],
         "VariableAccess's read/write/note_fault: every implementation analysed (Module)"),
    # The macro table (each method descriptor's kMacros, MacroInfo::run): by
    # type, every function of MacroThunk's type, MacroStep(MacroCall&): the
    # thunk of each handler (gcc names a template's parameters unqualified:
    # "MacroStep trueaxis::macros::thunk(MacroCall&) [with auto Handler = ...]"),
    # and any captureless lambda standing in for one. An integrator's extra
    # macros (Module's extra_macros) are his code: add their worst to step()'s figure.
    Rule(r"\btrueaxis::macros::Module::", None,
         [r"^(static )?(constexpr )?(trueaxis::macros::)?MacroStep .*\((trueaxis::macros::)?MacroCall&\)"
          r"( \[with .*\])?$"],
         "a macro handler through the macro table (MacroThunk): every function of that type",
         r"^_ZN8trueaxis6macros.*kMacros",
         (32, (4,))),  # MacroInfo on the Cortex-M7: number, run, ... (macro_info.hpp asserts it)
]

# Functions the build does not compile: bound in bytes of the function and
# everything it calls (convention 5), from the disassembly of the linked image
# (arm-none-eabi-gcc 12.2, newlib-nano's libc, newlib's libm, libgcc; --elf
# checks them). Only what the firmware calls is listed.
LIBRARY = {
    "memcpy": (0, "newlib-nano; no frame"),
    "memset": (12, "newlib-nano"),
    "memmove": (16, "newlib-nano"),
    "sqrt": (24, "libm; called only for a negative argument (errno)"),
    "sin": (744, "libm: sin 24 + __ieee754_rem_pio2 48 + __kernel_rem_pio2 656 + floor 16 (the reduction of |x| >= 2^20 pi/2)"),
    "cos": (744, "libm: as sin"),
    "atan": (64, "libm"),
    "atan2": (96, "libm: __ieee754_atan2 32 + atan 64"),
    "hypot": (56, "libm: hypot 32 + __ieee754_hypot 24"),
    "fmod": (64, "libm: fmod 24 + __ieee754_fmod 40"),
    "remainder": (104, "libm: remainder 24 + __ieee754_remainder 40 + __ieee754_fmod 40"),
    "exp": (56, "libm: exp 32 + __math_uflow 0 + xflow 8 + with_errno 16 (form_noise.cpp, M2's noise floors)"),
    "expm1": (56, "libm: expm1 32 + __math_oflow 0 + xflow 8 + with_errno 16"),
    "log1p": (56, "libm: log1p 32 + __math_divzero 8 + with_errno 16"),
    "erfc": (104, "libm: erfc 48 + exp 56"),
    "pow": (144, "libm: pow 120 + __math_uflow 0 + xflow 8 + with_errno 16"),
    "__aeabi_uldivmod": (48, "libgcc: 16 + __udivmoddi4 32"),
    "__aeabi_ldivmod": (48, "libgcc: 16 + __udivmoddi4 32 (from libgcc.a: not linked in the images)"),
    "__aeabi_ul2d": (36, "libgcc: 12 + __aeabi_l2d 12 + __adddf3 12"),
    "__aeabi_l2d": (24, "libgcc: 12 + __adddf3 12"),
    "__aeabi_d2lz": (8, "libgcc"),
    "__aeabi_d2ulz": (0, "libgcc; no frame"),
}

# Library calls bounded by their callers (convention 6): a call of one of
# `functions` by a function matching the last pattern of `chain`, called by one
# matching the pattern before it, and so on up to the first, costs `bytes`
# instead of its LIBRARY bound. `why` states what those callers guarantee for
# every input (any finite double from the controller, any table a record
# decodes to) and why the library's deeper path, `skip`, is then never taken;
# --elf checks `bytes` against the disassembly with `skip` cut off.
CallBound = namedtuple("CallBound", "chain functions bytes skip why")

# newlib's sin and cos (libm/math/s_sin.c, s_cos.c, e_rem_pio2.c): |x| <= pi/4
# goes to __kernel_sin/cos directly; otherwise __ieee754_rem_pio2 reduces x,
# and calls __kernel_rem_pio2 (656 B, the multi-precision reduction) only when
# x's high word is above 0x413921fb, |x| >= 2^20 pi/2 = 1,647,099 (NaN and
# infinity return before it): the literal and the branch are in the image's
# __ieee754_rem_pio2 (cmp with 0x413921fb, bls to the medium reduction).
_SMALL_TRIG = ("newlib: below 2^20 pi/2 the reduction is __ieee754_rem_pio2's own (no __kernel_rem_pio2): "
               "sin or cos 24 + __ieee754_rem_pio2 48")

CALL_BOUNDS = [
    CallBound([r"\bcore::\{anonymous\}::blend_rotvec\(", r"\bcore::so3_exp\("], ("sin",), 72, ("__kernel_rem_pio2",),
              "so3_exp(w) takes sin(theta) and sin(theta / 2), theta = |w|. blend_rotvec (rigidity_compensation.cpp, "
              "the geodesic blend) calls it only with w = b.w * geodesic_step_rad[k]: b.w in [0, 1] (find_bracket: "
              "A_k <= A < A_k+1 for any finite A, clamped or refused outside the table), and geodesic_step_rad is "
              "so3_log(R_k^T R_k+1) as prepare_rigidity_table computes it for every table, built or decoded "
              "(rigidity_table.hpp convention 8: never stored), of norm 2 atan(x) or 2 atan2(|q_v|, q_w >= 0): at "
              "most pi up to rounding, or NaN. So theta <= 3.15 or NaN: never the large reduction. " + _SMALL_TRIG),
    CallBound([r"\bmacros::spindle::tool_tip_correction\(", r"\bcore::spindle_correction\("], ("sin", "cos"), 72,
              ("__kernel_rem_pio2",),
              "spindle_correction takes cos(phi) and sin(phi) of its angle. tool_tip_correction (spindle_macros.cpp) "
              "refuses a phi_deg that is not finite and passes phi = deg_to_rad(fmod(phi_deg, 360)): fmod is exact "
              "and below 360 in magnitude, so |phi| < 2 pi (1 + 2^-52). " + _SMALL_TRIG),
    CallBound([r"\bcore::decode_rigidity_table\(", r"\bcore::prepare_rigidity_table\(RigidityTable&\)",
               r"\bcore::prepare_rigidity_table\(RigidityTable&, RigiditySplineWork&\)", r"\bcore::so3_exp\("],
              ("sin",), 72, ("__kernel_rem_pio2",),
              "prepare_rigidity_table calls so3_exp(rotvec_rad) of each pose and nothing else of so3_exp; "
              "decode_rigidity_table (rigidity_codec.cpp) refuses a record with a pose whose |rotvec_rad| is not "
              "<= pi (the same norm so3_exp takes) before it prepares the table. " + _SMALL_TRIG),
]

# Dynamic frames accepted, with the bound that holds for them: (pattern, bytes, why).
DYNAMIC_FRAMES = []

# Recursions accepted: a function calling itself, at most `depth` frames deep
# (the first call included): (pattern, depth, why). Any other cycle is an error.
RECURSIONS = [
    (r"\bstd::__introsort_loop\(", 17,
     "std::sort (circle_fit.cpp arc_span_deg, rigidity_table.cpp step_fit) of at most kMaxCirclePoints = 360 "
     "elements: libstdc++'s introsort recurses with a depth limit of 2*floor(log2(n)) = 16, so at most 17 "
     "frames (holds for n < 512)"),
]

# ---------------------------------------------------------------------------
# Reading gcc's call graph (VCG, gcc 12 -fcallgraph-info=su).

_STRING = r'"((?:[^"\\]|\\.)*)"'
_NODE = re.compile(r"^node: \{ title: " + _STRING + r" label: " + _STRING + r"(.*)\}\s*$")
_EDGE = re.compile(r"^edge: \{ sourcename: " + _STRING + r" targetname: " + _STRING +
                   r"(?: label: " + _STRING + r")?\s*\}\s*$")
_FRAME = re.compile(r"^(\d+) bytes \(([a-z,]+)\)$")
INDIRECT = "__indirect_call"


class AnalysisError(Exception):
    pass


def _unescape(s):
    return s.replace("\\n", "\n").replace('\\"', '"').replace("\\\\", "\\")


Unit = namedtuple("Unit", "path source nodes edges")
# nodes: title -> (label, location, frame or None, qualifier or None); frame None: not defined here.
# edges: [(source title, target title, site)]


def parse_ci(path):
    nodes, edges, source = {}, [], None
    with open(path, encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if line.startswith("graph: { title:"):
                m = re.search(_STRING, line)
                source = _unescape(m.group(1)) if m else None
            elif line.startswith("node:"):
                m = _NODE.match(line)
                if not m:
                    raise AnalysisError(f"{path}:{n}: unreadable node: {line}")
                title = _unescape(m.group(1))
                parts = _unescape(m.group(2)).split("\n")
                frame = qual = None
                if len(parts) >= 3:
                    fm = _FRAME.match(parts[2])
                    if fm:
                        frame, qual = int(fm.group(1)), fm.group(2)
                nodes[title] = (parts[0], parts[1] if len(parts) > 1 else "", frame, qual)
            elif line.startswith("edge:"):
                m = _EDGE.match(line)
                if not m:
                    raise AnalysisError(f"{path}:{n}: unreadable edge: {line}")
                edges.append((_unescape(m.group(1)), _unescape(m.group(2)),
                              _unescape(m.group(3)) if m.group(3) is not None else ""))
    if source is None:
        raise AnalysisError(f"{path}: not a gcc call graph (no 'graph: {{ title:' line)")
    return Unit(path, source, nodes, edges)


def find_units(build_dir):
    """Every .ci under build_dir, and the freshness problems of the analysed objects."""
    cis, problems = [], []
    for dirpath, dirnames, filenames in os.walk(build_dir):
        dirnames.sort()
        cis.extend(os.path.join(dirpath, f) for f in sorted(filenames) if f.endswith(".ci"))
    if not cis:
        raise AnalysisError(f"no .ci file under {build_dir}: configure the cross build with "
                            "TRUEAXIS_STACK_INFO=ON (the default) and build the firmware libraries")
    # An analysed library: the CMake target directory (*.dir) holding a .ci. Each
    # of its objects must have a .ci written with it.
    lib_dirs = set()
    for ci in cis:
        d = os.path.dirname(ci)
        while d.startswith(build_dir) and not d.endswith(".dir") and d != build_dir:
            d = os.path.dirname(d)
        lib_dirs.add(d if d.endswith(".dir") else os.path.dirname(ci))
    ci_set = set(cis)
    for lib in sorted(lib_dirs):
        for dirpath, dirnames, filenames in os.walk(lib):
            dirnames.sort()
            for f in sorted(filenames):
                if not f.endswith((".o", ".obj")):
                    continue
                obj = os.path.join(dirpath, f)
                ci = os.path.splitext(obj)[0] + ".ci"
                if ci not in ci_set:
                    problems.append(f"{obj}: no call graph beside it ({os.path.basename(ci)}); "
                                    "rebuild the library with TRUEAXIS_STACK_INFO=ON and without ccache")
                elif os.path.getmtime(obj) > os.path.getmtime(ci) + 30:
                    problems.append(f"{ci}: older than its object: stale (the object was rebuilt "
                                    "without -fcallgraph-info or restored by ccache); rebuild it")
    return cis, problems


# ---------------------------------------------------------------------------
# The call graph.

_INTERNAL = re.compile(r"_GLOBAL__N_|^_ZL|\.(?:isra|constprop|part|cold|lto_priv)")


def is_internal(name):
    """True for an assembler name surely of internal linkage: in an anonymous
    namespace, a static at namespace scope (_ZL), or a compiler's clone. Other
    internal names (a static in a named namespace) are merged with any
    namesake of another unit: conservative, the larger frame counts."""
    return bool(_INTERNAL.search(name))


def short_name(label):
    """gcc's name without the return type (for display)."""
    head = label.split(" [with ")[0]
    depth = 0
    for i, c in enumerate(head):
        if c in "<(":
            if c == "(" and depth == 0 and i > 0 and (head[i - 1].isalnum() or head[i - 1] in "_>"):
                if head[:i].endswith("operator") and head[i:i + 2] == "()":
                    continue
                j = i - 1
                d2 = 0
                while j >= 0:
                    cj = head[j]
                    if cj in ">)":
                        d2 += 1
                    elif cj in "<(":
                        d2 -= 1
                    elif cj == " " and d2 == 0:
                        break
                    j -= 1
                return label[j + 1:]
            depth += 1
        elif c in ">)":
            depth = max(0, depth - 1)
    return label


class Function:
    __slots__ = ("key", "label", "mangled", "location", "frame", "qualifier", "units", "callees",
                 "indirect", "externals")

    def __init__(self, key, label, mangled, location):
        self.key, self.label, self.mangled, self.location = key, label, mangled, location
        self.frame, self.qualifier, self.units = 0, "static", []
        self.callees = set()   # keys of called functions
        self.indirect = []     # sites of indirect calls
        self.externals = set()  # names of called functions not compiled here

    @property
    def name(self):
        return short_name(self.label)


_QUAL_RANK = {"static": 0, "dynamic,bounded": 1, "dynamic": 2}


class Graph:
    def __init__(self, units):
        self.functions = {}
        self.units = units
        for u in units:
            for title, (label, loc, frame, qual) in u.nodes.items():
                if frame is None:
                    continue
                key = self._key(u, title)
                f = self.functions.get(key)
                if f is None:
                    f = self.functions[key] = Function(key, label, self._name(u, title), loc)
                    f.frame, f.qualifier = frame, qual
                else:
                    f.frame = max(f.frame, frame)
                    if _QUAL_RANK.get(qual, 2) > _QUAL_RANK.get(f.qualifier, 2):
                        f.qualifier = qual
                f.units.append(u.path)
        for u in units:
            for src, dst, site in u.edges:
                caller = self.functions.get(self._key(u, src))
                if caller is None:
                    continue  # gcc lists only calls of functions it compiled
                if dst == INDIRECT:
                    caller.indirect.append(site)
                    continue
                key = self._key(u, dst)
                if key not in self.functions:
                    key = self._alias(key)
                if key in self.functions:
                    caller.callees.add(key)
                else:
                    caller.externals.add(self._name(u, dst))

    @staticmethod
    def _name(unit, title):
        prefix = unit.source + ":"
        return title[len(prefix):] if title.startswith(prefix) else title

    def _key(self, unit, title):
        # gcc prefixes a name that is not unique to its unit (internal or weak);
        # an unprefixed one is a strong or an external symbol.
        name = self._name(unit, title)
        return (unit.path, name) if name != title and is_internal(name) else name

    def _alias(self, key):
        """gcc defines a complete-object constructor or destructor (C1, D1) as an
        alias of the base-object one (C2, D2) when they are the same code: its
        graph holds the definition under one name and calls under the other."""
        if isinstance(key, tuple):
            return key
        m = re.match(r"^(_ZN.*[CD])([12])(E.*)$", key)
        if m:
            other = m.group(1) + ("2" if m.group(2) == "1" else "1") + m.group(3)
            if other in self.functions:
                return other
        return key

    def matching(self, pattern):
        rx = re.compile(pattern)
        return [f for f in self.functions.values() if rx.search(f.label)]


# ---------------------------------------------------------------------------
# Analysis.

class Analysis:
    def __init__(self, graph, roots=ROOTS, rules=INDIRECT_CALLS, library=LIBRARY, dynamic=DYNAMIC_FRAMES,
                 recursions=RECURSIONS, call_bounds=CALL_BOUNDS):
        self.g, self.roots, self.rules, self.library, self.dynamic = graph, roots, rules, library, dynamic
        self.call_bounds = call_bounds
        self.call_bound_hits = [0] * len(call_bounds)
        self._chain_rx = [[re.compile(p) for p in cb.chain] for cb in call_bounds]
        self._applied = {}     # node -> indices of CALL_BOUNDS applied to its own library calls
        self.rule_hits = [0] * len(rules)
        # Accepted self-recursions: key -> depth; their self edge is not a cycle.
        self.repeat = {}
        self.recursion_hits = [0] * len(recursions)
        for i, (pattern, depth, _) in enumerate(recursions):
            for f in graph.matching(pattern):
                if f.key in f.callees:
                    self.repeat[f.key] = depth
                    self.recursion_hits[i] += 1
        self._targets = {}
        self._worst = {}       # node (key, context) -> (bytes, next hop: node | ('lib', name, entry) | None)
        self._errors = {}      # key -> [messages] of the function itself
        self._state = {}
        self.cycles = []
        self._resolve_all()

    # Indirect calls ---------------------------------------------------------
    def _rule_targets(self, i):
        if i not in self._targets:
            keys, missing = set(), []
            for p in self.rules[i].targets:
                found = self.g.matching(p)
                if not found:
                    missing.append(p)
                keys.update(f.key for f in found)
            self._targets[i] = (keys, missing)
        return self._targets[i]

    def _resolve_all(self):
        self.resolved = {}  # key -> set of keys reached through indirect calls
        for f in self.g.functions.values():
            errs = []
            targets = set()
            for site in f.indirect:
                for i, r in enumerate(self.rules):
                    if r.caller is not None and not re.search(r.caller, f.label):
                        continue
                    if r.site is not None and not re.search(r.site, site):
                        continue
                    self.rule_hits[i] += 1
                    keys, missing = self._rule_targets(i)
                    for p in missing:
                        errs.append(f"indirect call at {site}: rule '{r.why}': target pattern {p!r} "
                                    "matches no function")
                    targets |= keys
                    break
                else:
                    errs.append(f"indirect call at {site} resolved by no rule of INDIRECT_CALLS "
                                f"(caller {f.name})")
            for name in sorted(f.externals):
                if name not in self.library:
                    errs.append(f"calls {name}, which has no stack information (not compiled by the "
                                "build, not in LIBRARY)")
            if f.qualifier != "static" and f.qualifier != "dynamic,bounded":
                allowed = [d for d in self.dynamic if re.search(d[0], f.label)]
                if allowed:
                    f.frame = max(f.frame, allowed[0][1])
                else:
                    errs.append(f"frame is {f.qualifier} ({f.frame} bytes + a runtime amount) and not "
                                "in DYNAMIC_FRAMES")
            self.resolved[f.key] = targets
            if errs:
                self._errors[f.key] = errs

    def callees(self, f):
        c = f.callees | self.resolved[f.key]
        return c - {f.key} if f.key in self.repeat else c

    def frame(self, key):
        return self.g.functions[key].frame * self.repeat.get(key, 1)

    # Call bounds (convention 6) ---------------------------------------------
    def _enter(self, ctx, key):
        """The context of function `key` called from a function in context ctx:
        the (entry, depth) pairs whose chain's first `depth` patterns match the
        call path ending at key."""
        label = self.g.functions[key].label
        out = {(e, 1) for e, rxs in enumerate(self._chain_rx) if rxs[0].search(label)}
        for e, d in ctx:
            rxs = self._chain_rx[e]
            if d < len(rxs) and rxs[d].search(label):
                out.add((e, d + 1))
        return frozenset(out)

    def library_bound(self, ctx, name):
        """(bytes, index of the CALL_BOUNDS entry that gives them or None) of a
        call of library function `name` by a function in context ctx."""
        best, which = self.library.get(name, (0, ""))[0], None
        for e, d in sorted(ctx):
            cb = self.call_bounds[e]
            if d == len(cb.chain) and name in cb.functions and cb.bytes < best:
                best, which = cb.bytes, e
        return best, which

    def node(self, key):
        """A root's node: the function in the context of its own name."""
        return (key, self._enter(frozenset(), key))

    def _children(self, node):
        key, ctx = node
        return [(c, self._enter(ctx, c)) for c in sorted(self.callees(self.g.functions[key]), key=str)]

    # Worst case -------------------------------------------------------------
    def worst(self, node):
        """(bytes, next hop) of the worst path from node (function key, context);
        cycles are recorded. A hop is a node or ('lib', name, CALL_BOUNDS index or None)."""
        if node in self._worst:
            return self._worst[node]
        # Iterative depth-first search (no recursion limit on deep graphs).
        stack = [(node, None)]
        while stack:
            n, it = stack[-1]
            k = n[0]
            f = self.g.functions[k]
            if it is None:
                self._state[n] = "open"
                it = iter(self._children(n))
                stack[-1] = (n, it)
            advanced = False
            for c in it:
                st = self._state.get(c)
                if st == "open":
                    path = [s[0][0] for s in stack]
                    cyc = path[path.index(c[0]):] + [c[0]]
                    self.cycles.append(cyc)
                    for m in cyc:
                        self._errors.setdefault(m, []).append(
                            "recursion: " + " -> ".join(self.g.functions[x].name for x in cyc))
                    continue
                if st is None:
                    stack.append((c, None))
                    advanced = True
                    break
            if advanced:
                continue
            best, hop = 0, None
            for c in self._children(n):
                if self._state.get(c) == "done" and self._worst[c][0] > best:
                    best, hop = self._worst[c][0], c
            for name in sorted(f.externals):
                b, which = self.library_bound(n[1], name)
                if which is not None:
                    self._applied.setdefault(n, set()).add(which)
                if b > best:
                    best, hop = b, ("lib", name, which)
            self._worst[n] = (self.frame(k) + best, hop)
            self._state[n] = "done"
            stack.pop()
        return self._worst[node]

    def path(self, node):
        out, cum = [], 0
        while node is not None:
            if node[0] == "lib":
                _, name, which = node
                b, _ = (self.call_bounds[which].bytes, None) if which is not None else (self.library[name][0], None)
                step = {"function": name, "frame": b, "cumulative": cum + b, "library": True}
                if which is not None:
                    step["call_bound"] = which
                out.append(step)
                break
            key = node[0]
            f = self.g.functions[key]
            cum += self.frame(key)
            out.append({"function": f.name, "frame": self.frame(key), "cumulative": cum,
                        "qualifier": f.qualifier, "repeat": self.repeat.get(key, 1)})
            node = self._worst[node][1]
        return out

    def applied(self, node):
        """The CALL_BOUNDS entries the figure of node relies on (anywhere below it)."""
        seen, todo, used = set(), [node], set()
        while todo:
            n = todo.pop()
            if n in seen:
                continue
            seen.add(n)
            used |= self._applied.get(n, set())
            todo.extend(self._children(n))
        return used

    def reach(self, key):
        seen, todo = set(), [key]
        while todo:
            k = todo.pop()
            if k in seen:
                continue
            seen.add(k)
            todo.extend(self.callees(self.g.functions[k]))
        return seen

    def root_result(self, root):
        found = self.g.matching(root.pattern)
        res = {"root": root.name, "pattern": root.pattern, "note": root.note}
        if len(found) != 1:
            res["errors"] = [f"root pattern {root.pattern!r} matches "
                             + ("no function" if not found else
                                f"{len(found)} functions: " + "; ".join(sorted(f.name for f in found)))]
            return res
        f = found[0]
        start = self.node(f.key)
        b, _ = self.worst(start)
        reach = self.reach(f.key)
        errs = []
        for k in sorted(reach, key=str):
            for e in self._errors.get(k, []):
                errs.append(f"{self.g.functions[k].name}: {e}")
        libs = sorted({n for k in reach for n in self.g.functions[k].externals})
        used = sorted(self.applied(start))
        for e in used:
            self.call_bound_hits[e] += 1
        res.update({"function": f.name, "bytes": b, "path": self.path(start), "functions": len(reach),
                    "library": libs, "call_bounds": used, "errors": sorted(set(errs))})
        return res


# ---------------------------------------------------------------------------
# The disassembly: library bounds (convention 5), frames checked (convention 1).
#
# A function's frame is the sum of every stack decrement in its body (push,
# stmdb sp!, vpush, vstmdb sp!, sub sp, str/strd with sp pre-decrement): an
# upper bound as long as it pushes nothing in a loop without popping it. A
# decrement by a register (alloca) is an error. Its calls are its bl/blx to a
# symbol and its branches (b, b<cond>, cbz, cbnz) to another function (tail
# calls); a call or branch through a register (blx rN, bx rN, rN not lr) is an
# error. The bound is the frame plus the worst bound of the calls.

_DIS_FUNC = re.compile(r"^([0-9a-f]+) <(.+)>:$")
_DIS_INSN = re.compile(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$")
_BRANCH = re.compile(r"^(bl|blx|b|b(?:eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)|cbz|cbnz)(?:\.[nw])?$")
_SYM = re.compile(r"^([0-9a-f]+) (.{7}) (\S+)\s+[0-9a-f]+ (?:\.hidden )?(\S+)$")
_TARGET = re.compile(r"([0-9a-f]+) <([^>+]+)(\+0x[0-9a-f]+)?>")


def _reg_count(lst):
    n = 0
    for r in lst.strip("{} ").split(","):
        r = r.strip()
        m = re.match(r"^([a-z]+)(\d+)-[a-z]+(\d+)$", r)
        n += int(m.group(3)) - int(m.group(2)) + 1 if m else (1 if r else 0)
    return n


def _insn_decrement(mn, ops):
    """Bytes an instruction moves sp down by; None if none; -1 if by a register."""
    base = mn.split(".")[0]
    if base == "push":
        return 4 * _reg_count(ops)
    if base == "vpush":
        size = 8 if "d" in ops else 4
        return size * _reg_count(ops)
    if base in ("stmdb", "stmfd") and ops.startswith("sp!"):
        return 4 * _reg_count(ops.split(",", 1)[1])
    if base == "vstmdb" and ops.startswith("sp!"):
        rl = ops.split(",", 1)[1]
        return (8 if "d" in rl else 4) * _reg_count(rl)
    if base in ("sub", "subw", "subs"):
        parts = [p.strip() for p in ops.split("@")[0].split(",")]
        if parts and parts[0] == "sp":
            src = parts[-1]
            if src.startswith("#"):
                return int(src[1:], 0)
            return -1
    if base in ("str", "strd", "vstr") and "[sp, #-" in ops and ops.rstrip().endswith("!"):
        return int(re.search(r"\[sp, #-(\d+)\]!", ops).group(1))
    return None


class Disassembly:
    def __init__(self, image, objdump):
        try:
            out = subprocess.run([objdump, "-d", "--no-show-raw-insn", image], check=True,
                                 capture_output=True, text=True).stdout
            syms = subprocess.run([objdump, "-t", image], check=True, capture_output=True, text=True).stdout
        except (OSError, subprocess.CalledProcessError) as e:
            raise AnalysisError(f"cannot disassemble {image} with {objdump}: {e}")
        self.image = image
        self.funcs = {}  # start address -> [name, frame, dynamic, calls set of addresses, indirect list]
        cur = None
        for line in out.splitlines():
            m = _DIS_FUNC.match(line)
            if m:
                cur = int(m.group(1), 16)
                self.funcs[cur] = [m.group(2), 0, False, set(), []]
                continue
            m = _DIS_INSN.match(line)
            if not m or cur is None:
                continue
            mn, ops = m.group(2), m.group(3)
            if mn.startswith("."):
                continue
            d = _insn_decrement(mn, ops)
            if d == -1:
                self.funcs[cur][2] = True
            elif d:
                self.funcs[cur][1] += d
            base = mn.split(".")[0]
            if _BRANCH.match(mn):
                t = _TARGET.search(ops)
                if t:
                    addr = int(t.group(1), 16)
                    if base in ("bl", "blx") or t.group(2) != self.funcs[cur][0]:
                        self.funcs[cur][3].add(addr)
                elif base == "blx":
                    self.funcs[cur][4].append(f"{m.group(1)}: {mn} {ops}")
            elif base == "bx" and not ops.startswith("lr"):
                self.funcs[cur][4].append(f"{m.group(1)}: {mn} {ops}")
        self.starts = sorted(self.funcs)
        self.by_name = {}
        self.ambiguous = set()  # local names defined more than once (one per object)
        self.objects = {}  # data object name -> (address, size)
        self.objdump = objdump
        for line in syms.splitlines():
            m = _SYM.match(line)
            if m and "O" in m.group(2):
                size = int(line[m.end(3):].split()[0], 16)
                self.objects[m.group(4)] = (int(m.group(1), 16), size, m.group(3))
            if m and "F" in m.group(2):
                name, addr = m.group(4), int(m.group(1), 16) & ~1
                if self.by_name.get(name, addr) != addr:
                    self.ambiguous.add(name)
                self.by_name[name] = addr
        for a, f in self.funcs.items():
            self.by_name.setdefault(f[0], a)

    def function_pointers(self, pattern, layout=None):
        """{object name: [function names]}: the Thumb function addresses held in the
        words of the image's data objects whose symbol matches pattern (with a
        layout (stride, offsets), only the words at those offsets of each entry)."""
        out = {}
        for name, (addr, size, section) in sorted(self.objects.items()):
            if not re.search(pattern, name) or size == 0:
                continue
            try:
                dump = subprocess.run([self.objdump, "-s", "-j", section, f"--start-address={addr:#x}",
                                       f"--stop-address={addr + size:#x}", self.image],
                                      check=True, capture_output=True, text=True).stdout
            except (OSError, subprocess.CalledProcessError) as e:
                raise AnalysisError(f"cannot dump {name} of {self.image}: {e}")
            data = bytearray()
            for line in dump.splitlines():
                m = re.match(r"^ ([0-9a-f]+) ((?:[0-9a-f]{2,8} ?){1,4})", line)
                if m:
                    data += bytes.fromhex(m.group(2).replace(" ", ""))
            ptrs = []
            offsets = range(0, len(data) - 3, 4)
            if layout is not None:
                stride, fields = layout
                if len(data) % stride != 0:
                    raise AnalysisError(f"{name} of {self.image}: {len(data)} bytes, no multiple of its "
                                        f"entries' {stride}: the table's layout changed")
                offsets = [e + f for e in range(0, len(data), stride) for f in fields]
            for i in offsets:
                w = int.from_bytes(data[i:i + 4], "little")
                if w & 1 and (w & ~1) in self.funcs:
                    ptrs.append(self.funcs[w & ~1][0])
            out[name] = ptrs
        return out

    def _containing(self, addr):
        i = bisect.bisect_right(self.starts, addr) - 1
        return self.starts[i] if i >= 0 else None

    def bound(self, name, skip=()):
        """(bytes, [problems], [path names]) of a function of the image, or None if
        absent; the functions named in `skip` are cut off (CALL_BOUNDS):
        self.skipped tells which of them the walk met."""
        self.skipped = set()
        if name not in self.by_name:
            return None
        memo, problems = {}, []

        def visit(a, trail):
            if a in memo:
                return memo[a]
            f = self.funcs[a]
            if a in trail:
                problems.append("recursion: " + " -> ".join(self.funcs[x][0] for x in trail + [a]))
                return (0, [])
            if f[2]:
                problems.append(f"{f[0]}: stack moved by a register (dynamic)")
            for s in f[4]:
                problems.append(f"{f[0]}: indirect branch {s}")
            best = (0, [])
            for t in sorted(f[3]):
                c = self._containing(t)
                if c is None:
                    problems.append(f"{f[0]}: branch to {t:#x} outside every function")
                    continue
                if self.funcs[c][0] in skip:
                    self.skipped.add(self.funcs[c][0])
                    continue
                r = visit(c, trail + [a])
                if r[0] > best[0]:
                    best = r
            memo[a] = (f[1] + best[0], [f"{f[0]} ({f[1]})"] + best[1])
            return memo[a]

        b, p = visit(self._containing(self.by_name[name]), [])
        return b, sorted(set(problems)), p


def apply_disassembly(graph, dis):
    """Each analysed function linked in an image takes the larger of gcc's frame
    and its disassembly's: gcc's -fstack-usage leaves out the argument registers
    a function pushes for an argument passed partly on the stack (ARM's
    "pretend args", e.g. a small struct or lambda by value after three int
    arguments). Returns [(name, gcc, disassembly)] of the functions raised, and
    the keys of the functions compared."""
    raised, compared = [], set()
    for f in graph.functions.values():
        best = None
        for d in dis:
            a = d.by_name.get(f.mangled)
            if a is None or a not in d.funcs or f.mangled in d.ambiguous:
                continue
            best = max(best or 0, d.funcs[a][1])
        if best is None:
            continue
        compared.add(f.key)
        if best > f.frame:
            raised.append((f.name, f.frame, best))
            f.frame = best
    return sorted(raised), compared


def check_tables(analysis, dis):
    """Errors and notes: every function pointer of a rule's tables is one of its targets."""
    errors, notes = [], []
    for i, r in enumerate(analysis.rules):
        if not r.tables or analysis.rule_hits[i] == 0:
            continue
        keys, _ = analysis._rule_targets(i)
        names = {analysis.g.functions[k].mangled for k in keys}
        seen, objects = set(), set()
        for d in dis:
            for obj, ptrs in d.function_pointers(r.tables, r.layout).items():
                objects.add(obj)
                for p in ptrs:
                    seen.add(p)
                    if p not in names:
                        errors.append(f"{obj} in {os.path.basename(d.image)} holds {p}, which rule '{r.why}' "
                                      "does not resolve to: its target patterns miss it")
        if not seen:
            errors.append(f"rule '{r.why}': no function pointer in any object matching {r.tables!r} of the "
                          "--elf images: stale table pattern?")
        else:
            notes.append(f"rule '{r.why}': the {len(seen)} functions {len(objects)} tables point to are all "
                         f"among its {len(names)} targets")
    return sorted(set(errors)), notes


def check_library(analysis, dis, needed):
    """Errors, notes and a table of (name, stated, disassembled, image, path) for the library functions used."""
    rows, errors, notes = [], [], []
    for name in sorted(needed):
        stated = analysis.library[name][0]
        found = [(d.bound(name), d.image) for d in dis]
        found = [(r, img) for r, img in found if r is not None]
        if not found:
            notes.append(f"library function {name}: linked in no image given with --elf (gcc's graph lists "
                         f"a call the linked code does not make); its stated bound ({stated} B) is unchecked")
            rows.append((name, stated, None, None, []))
            continue
        (b, probs, path), img = max(found, key=lambda x: x[0][0])
        for p in probs:
            errors.append(f"library function {name} ({os.path.basename(img)}): {p}")
        if b > stated:
            errors.append(f"library function {name}: the disassembly of {os.path.basename(img)} needs {b} B, "
                          f"over the bound LIBRARY states ({stated} B): "
                          + " -> ".join(path))
        rows.append((name, stated, b, img, path))
    return rows, errors, notes


def check_call_bounds(analysis, dis, used):
    """Errors, notes and rows (index, function, stated, disassembly, image, path) of
    the CALL_BOUNDS entries the roots rely on: each bound at least the
    disassembly's with its `skip` cut off, each skipped function really on the
    library function's path (else the entry states nothing)."""
    rows, errors, notes = [], [], []
    for e in sorted(used):
        cb = analysis.call_bounds[e]
        for name in cb.functions:
            found = []
            for d in dis:
                r = d.bound(name, cb.skip)
                if r is not None:
                    found.append((r, d.image, set(d.skipped)))
            if not found:
                notes.append(f"CALL_BOUNDS[{e}] {name}: linked in no image given with --elf; its bound "
                             f"({cb.bytes} B) is unchecked")
                rows.append((e, name, cb.bytes, None, None, []))
                continue
            (b, probs, path), img, skipped = max(found, key=lambda x: x[0][0])
            for p in probs:
                errors.append(f"CALL_BOUNDS[{e}] {name} ({os.path.basename(img)}): {p}")
            missing = set(cb.skip) - set().union(*(x[2] for x in found))
            for m in sorted(missing):
                errors.append(f"CALL_BOUNDS[{e}] {name}: {m} is on no path of {name} in the images: the entry "
                              "cuts off nothing there (stale?)")
            if b > cb.bytes:
                errors.append(f"CALL_BOUNDS[{e}] {name}: the disassembly of {os.path.basename(img)} needs {b} B "
                              f"without {', '.join(cb.skip)}, over the stated {cb.bytes} B: " + " -> ".join(path))
            rows.append((e, name, cb.bytes, b, img, path))
    return rows, errors, notes


# ---------------------------------------------------------------------------
# Report.

def parse_bound(text):
    pat, sep, val = text.rpartition("=")
    if not sep or not pat or not val.isdigit():
        raise argparse.ArgumentTypeError(f"--bound wants ROOT_PATTERN=BYTES, not {text!r}")
    return pat, int(val)


def _fit(s, width):
    return s if len(s) <= width else s[:width - 3] + "..."


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build_dir", help="the cross build directory (its .ci files are read)")
    ap.add_argument("--bound", action="append", type=parse_bound, default=[], metavar="ROOT_PATTERN=BYTES",
                    help="fail (exit 1) when a root whose name matches the glob exceeds BYTES; repeatable")
    ap.add_argument("--root", action="append", default=[], metavar="NAME=REGEX",
                    help="analyse this root instead of the configured ones; repeatable")
    ap.add_argument("--elf", action="append", default=[], metavar="IMAGE",
                    help="check LIBRARY's bounds against this linked image's disassembly; repeatable")
    ap.add_argument("--objdump", default=os.environ.get("OBJDUMP") or shutil.which("arm-none-eabi-objdump")
                    or "arm-none-eabi-objdump")
    ap.add_argument("--top", type=int, default=15, help="how many of the largest frames to list (15)")
    ap.add_argument("--json", action="store_true", help="machine-readable output")
    args = ap.parse_args(argv)

    roots = ROOTS
    if args.root:
        roots = []
        for r in args.root:
            name, sep, rx = r.partition("=")
            if not sep:
                ap.error(f"--root wants NAME=REGEX, not {r!r}")
            roots.append(Root(name, rx, "given on the command line"))

    build_dir = os.path.abspath(args.build_dir)
    try:
        paths, freshness = find_units(build_dir)
        graph = Graph([parse_ci(p) for p in paths])
    except AnalysisError as e:
        print(f"stack_report: error: {e}", file=sys.stderr)
        return 2
    dis, raised, compared = [], [], set()
    if args.elf:
        try:
            dis = [Disassembly(i, args.objdump) for i in args.elf]
        except AnalysisError as e:
            print(f"stack_report: error: {e}", file=sys.stderr)
            return 2
        raised, compared = apply_disassembly(graph, dis)
    an = Analysis(graph, roots=roots)
    results = [an.root_result(r) for r in roots]

    errors = list(freshness)
    for pat, _ in args.bound:
        if not any(fnmatch.fnmatchcase(r.name, pat) for r in roots):
            errors.append(f"--bound {pat}: no root of that name ({', '.join(r.name for r in roots)})")
    for res in results:
        res["bound"] = None
        for pat, b in args.bound:
            if fnmatch.fnmatchcase(res["root"], pat):
                res["bound"] = b if res["bound"] is None else min(res["bound"], b)
        errors.extend(f"{res['root']}: {e}" for e in res.get("errors", []))

    reach_of = {}
    for res in results:
        if "bytes" in res:
            reach_of[res["root"]] = an.reach(graph.matching(res["pattern"])[0].key)
    reached = set().union(*reach_of.values())
    needed = {n for k in reached for n in graph.functions[k].externals if n in LIBRARY}
    used_bounds = set().union(*(set(r.get("call_bounds", [])) for r in results))
    lib_rows, notes, bound_rows = [], [], []
    if dis:
        lib_rows, lib_errors, notes = check_library(an, dis, needed)
        errors.extend(lib_errors)
        bound_rows, bound_errors, bound_notes = check_call_bounds(an, dis, used_bounds)
        errors.extend(bound_errors)
        notes.extend(bound_notes)
        try:
            table_errors, table_notes = check_tables(an, dis)
        except AnalysisError as e:
            print(f"stack_report: error: {e}", file=sys.stderr)
            return 2
        errors.extend(table_errors)
        notes.extend(table_notes)
        unlinked = len(reached - compared)
        notes.append(f"frames compared with the disassembly of {', '.join(os.path.basename(i) for i in args.elf)}: "
                     f"{len(compared)} functions ({len(reached) - unlinked} of the {len(reached)} the roots reach), "
                     f"{len(raised)} raised to it"
                     + "".join(f"\n    {n}: gcc {a} B, disassembly {b} B" for n, a, b in raised))
    else:
        notes.append("no --elf image: library bounds and gcc's frames are not checked against a disassembly")
        lib_rows = [(n, LIBRARY[n][0], None, None, []) for n in sorted(needed)]
        bound_rows = [(e, n, an.call_bounds[e].bytes, None, None, []) for e in sorted(used_bounds)
                      for n in an.call_bounds[e].functions]
    if not args.root:
        for i, r in enumerate(INDIRECT_CALLS):
            if an.rule_hits[i] == 0:
                errors.append(f"INDIRECT_CALLS rule '{r.why}' resolves no call of the build: stale pattern?")
        for i, r in enumerate(RECURSIONS):
            if an.recursion_hits[i] == 0:
                errors.append(f"RECURSIONS entry {r[0]!r} matches no recursive function: stale pattern?")
        for i, cb in enumerate(an.call_bounds):
            if an.call_bound_hits[i] == 0:
                errors.append(f"CALL_BOUNDS[{i}] ({' -> '.join(cb.chain)} -> {'/'.join(cb.functions)}) bounds no "
                              "call a root makes: stale pattern?")

    over = [r for r in results if r.get("bytes") is not None and r["bound"] is not None and r["bytes"] > r["bound"]]
    top = sorted((graph.functions[k] for k in reached), key=lambda f: (-f.frame, f.name))[:args.top]
    top_rows = []
    for f in top:
        by = [name for name, reach in reach_of.items() if f.key in reach]
        top_rows.append({"function": f.name, "frame": f.frame, "qualifier": f.qualifier, "location": f.location,
                         "roots": by})

    if args.json:
        json.dump({"build_dir": build_dir, "units": len(paths), "functions": len(graph.functions),
                   "roots": results, "top_frames": top_rows,
                   "library": [{"function": n, "stated": s, "disassembly": d, "image": img, "path": p}
                               for n, s, d, img, p in lib_rows],
                   "call_bounds": [{"index": e, "chain": an.call_bounds[e].chain,
                                    "function": n, "stated": b, "disassembly": d, "image": img, "path": p}
                                   for e, n, b, d, img, p in bound_rows],
                   "cycles": [[graph.functions[k].name for k in c] for c in an.cycles],
                   "notes": notes, "errors": errors, "over_bound": [r["root"] for r in over]}, sys.stdout, indent=2)
        print()
    else:
        print(f"Worst-case stack (gcc -fcallgraph-info=su of {len(paths)} units, {len(graph.functions)} "
              f"functions; tools/stack_report.py convention 1: interrupts not included)\n")
        print(f"  {'root':28} {'bytes':>7} {'bound':>7}  function")
        for r in results:
            b = r.get("bytes")
            flag = "  OVER" if r in over else ("  ERROR" if r.get("errors") else "")
            print(f"  {r['root']:28} {b if b is not None else '?':>7} "
                  f"{r['bound'] if r['bound'] is not None else '-':>7}  {_fit(r.get('function', r['pattern']), 80)}{flag}")
        for r in results:
            if "path" not in r:
                continue
            print(f"\n{r['root']}: {r['bytes']} bytes, worst path ({r['functions']} functions reached"
                  + (f"; library: {', '.join(r['library'])}" if r["library"] else "") + ")")
            print(f"  {'frame':>6} {'cumul':>6}  function")
            if r.get("call_bounds"):
                print("  relies on CALL_BOUNDS " + ", ".join(f"[{e}]" for e in r["call_bounds"])
                      + " (library calls bounded by their callers)")
            for p in r["path"]:
                q = " (library)" if p.get("library") else ("" if p.get("qualifier") == "static" else f" ({p.get('qualifier')})")
                if "call_bound" in p:
                    q = f" (library; CALL_BOUNDS[{p['call_bound']}], LIBRARY {LIBRARY.get(p['function'], ('?',))[0]})"
                if p.get("repeat", 1) > 1:
                    q += f" (recursion: {p['repeat']} x {p['frame'] // p['repeat']} bytes)"
                print(f"  {p['frame']:>6} {p['cumulative']:>6}  {_fit(p['function'], 110)}{q}")
        print("\nLargest frames reached from the roots (the targets for cutting):")
        print(f"  {'frame':>6}  function  [roots]")
        for t in top_rows:
            print(f"  {t['frame']:>6}  {_fit(t['function'], 100)}  [{', '.join(t['roots'])}]")
        if lib_rows:
            print("\nLibrary functions called (LIBRARY bound"
                  + (", disassembly" if args.elf else "; --elf checks them") + "):")
            for n, s, d, img, p in lib_rows:
                extra = f"  disassembly {d} B ({os.path.basename(img)}): {' -> '.join(p)}" if d is not None else ""
                print(f"  {n:18} {s:>5} B{extra}")
        if bound_rows:
            print("\nLibrary calls bounded by their callers (CALL_BOUNDS"
                  + (", disassembly with the skipped functions cut off" if args.elf else "; --elf checks them") + "):")
            for e, n, b, d, img, p in bound_rows:
                chain = " -> ".join(an.call_bounds[e].chain)
                extra = f"  disassembly {d} B ({os.path.basename(img)}): {' -> '.join(p)}" if d is not None else ""
                print(f"  [{e}] {n:6} {b:>5} B  via {chain}{extra}")
        if notes:
            print()
            for n in notes:
                print(f"note: {n}")
        if over:
            print()
            for r in over:
                print(f"OVER BOUND: {r['root']} needs {r['bytes']} bytes, bound {r['bound']}: "
                      + " -> ".join(f"{p['function']} ({p['frame']})" for p in r["path"]))
        if errors:
            print()
            for e in errors:
                print(f"error: {e}")
    if errors:
        if not args.json:
            print(f"\nstack_report: {len(errors)} error(s): the figures above are not bounds", file=sys.stderr)
        return 2
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
