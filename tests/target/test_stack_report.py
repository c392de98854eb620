#!/usr/bin/env python3
"""Self-test of tools/stack_report.py on handcrafted call graphs (gcc 12's
-fcallgraph-info=su VCG format): the worst case of a chain and of a diamond,
an indirect call resolved to two targets, and every error the tool must raise
(an unresolved indirect call, a recursion, a dynamic frame, a function without
stack information, a stale or missing .ci); the tables' allowances (LIBRARY,
DYNAMIC_FRAMES, RECURSIONS); gcc's unit-local and weak names; the command
line (--bound, --json, exit status); the disassembly reader on canned objdump
output; CALL_BOUNDS (a library call bounded through a chain of callers: context
sensitivity, partial chains, the entries a root relies on, stale entries, the
check against a disassembly with `skip` cut off). Python 3 standard library
only; ctest runs it as stack_report_selftest.

    python3 tests/target/test_stack_report.py
"""
import contextlib
import io
import json
import os
import sys
import tempfile
import textwrap
import time
import unittest
from unittest import mock

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import stack_report as sr  # noqa: E402

Root, Rule, CallBound = sr.Root, sr.Rule, sr.CallBound


def vcg(source, nodes, edges):
    """A .ci file's text. nodes: (title, label, frame, qualifier) defined here,
    or (title, label) for a callee only declared; edges: (source, target[, site])."""
    out = [f'graph: {{ title: "{source}"']
    for n in nodes:
        if len(n) == 4:
            title, label, frame, qual = n
            out.append(f'node: {{ title: "{title}" label: "{label}\\n{source}:1:1\\n{frame} bytes ({qual})" }}')
        else:
            title, label = n
            out.append(f'node: {{ title: "{title}" label: "{label}\\n<built-in>" shape : ellipse }}')
    for e in edges:
        site = f' label: "{e[2]}"' if len(e) > 2 else ""
        out.append(f'edge: {{ sourcename: "{e[0]}" targetname: "{e[1]}"{site} }}')
    out.append("}")
    return "\n".join(out) + "\n"


INDIRECT = ("__indirect_call", "Indirect Call Placeholder")


class Build:
    """A temporary build directory of .ci files (and, on request, objects)."""

    def __init__(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.dir = self._tmp.name

    def add(self, name, text, obj=False):
        d = os.path.join(self.dir, "lib.dir")
        os.makedirs(d, exist_ok=True)
        path = os.path.join(d, name + ".ci")
        with open(path, "w") as f:
            f.write(text)
        if obj:
            with open(os.path.join(d, name + ".obj"), "w") as f:
                f.write("")
        return path

    def analysis(self, roots, rules=(), library=None, dynamic=(), recursions=(), call_bounds=None):
        paths, problems = sr.find_units(self.dir)
        g = sr.Graph([sr.parse_ci(p) for p in paths])
        kw = {} if call_bounds is None else {"call_bounds": list(call_bounds)}
        an = sr.Analysis(g, roots=list(roots), rules=list(rules), library=library or {}, dynamic=list(dynamic),
                         recursions=list(recursions), **kw)
        return an, problems

    def result(self, root_pattern, **kw):
        an, _ = self.analysis([Root("r", root_pattern, "")], **kw)
        return an.root_result(an.roots[0])

    def cli(self, *args):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = sr.main([self.dir, *args])
        return rc, out.getvalue(), err.getvalue()

    def close(self):
        self._tmp.cleanup()


def chain_unit():
    return vcg("a.cpp", [("_Z1av", "void a()", 16, "static"), ("_Z1bv", "void b()", 32, "static"),
                         ("_Z1cv", "void c()", 8, "static")],
               [("_Z1av", "_Z1bv", "a.cpp:2:3"), ("_Z1bv", "_Z1cv", "a.cpp:3:3")])


class WorstCase(unittest.TestCase):
    def setUp(self):
        self.b = Build()

    def tearDown(self):
        self.b.close()

    def test_chain(self):
        self.b.add("a", chain_unit())
        r = self.b.result(r"\ba\(\)")
        self.assertEqual(r["errors"], [])
        self.assertEqual(r["bytes"], 56)
        self.assertEqual([(p["function"], p["frame"], p["cumulative"]) for p in r["path"]],
                         [("a()", 16, 16), ("b()", 32, 48), ("c()", 8, 56)])

    def test_diamond_takes_the_larger_branch(self):
        # a -> b -> d, a -> c -> d: the path through b (100) beats c (20).
        self.b.add("d", vcg("d.cpp", [("a", "void a()", 8, "static"), ("b", "void b()", 100, "static"),
                                      ("c", "void c()", 20, "static"), ("d", "void d()", 4, "static")],
                            [("a", "b"), ("a", "c"), ("b", "d"), ("c", "d")]))
        r = self.b.result(r"\ba\(\)")
        self.assertEqual(r["bytes"], 112)
        self.assertEqual([p["function"] for p in r["path"]], ["a()", "b()", "d()"])
        self.assertEqual(r["functions"], 4)

    def test_calls_across_units(self):
        self.b.add("x", vcg("x.cpp", [("_Z1xv", "void x()", 24, "static"), ("_Z1yv", "void y()")],
                            [("_Z1xv", "_Z1yv")]))
        self.b.add("y", vcg("y.cpp", [("_Z1yv", "void y()", 40, "static")], []))
        self.assertEqual(self.b.result(r"\bx\(\)")["bytes"], 64)

    def test_indirect_call_resolved_to_two_targets(self):
        self.b.add("i", vcg("i.cpp", [("caller", "void caller()", 8, "static"), INDIRECT,
                                      ("t1", "int impl_one::run(int)", 40, "static"),
                                      ("t2", "int impl_two::run(int)", 64, "static"),
                                      ("t3", "int other(int)", 500, "static")],
                            [("caller", "__indirect_call", "/src/hal/iface.hpp:12:3")]))
        rules = [Rule(None, r"/iface\.hpp:", [r"::run\(int\)"], "the interface")]
        an, _ = self.b.analysis([Root("r", r"\bcaller\(\)", "")], rules=rules)
        r = an.root_result(an.roots[0])
        self.assertEqual(r["errors"], [])
        self.assertEqual(r["bytes"], 72)  # 8 + the larger of 40 and 64, not other()'s 500
        self.assertEqual(r["path"][-1]["function"], "impl_two::run(int)")
        self.assertEqual(an.rule_hits, [1])

    def test_first_matching_rule_wins(self):
        self.b.add("i", vcg("i.cpp", [("caller", "void caller()", 8, "static"), INDIRECT,
                                      ("small", "void small()", 4, "static"), ("big", "void big()", 400, "static")],
                            [("caller", "__indirect_call", "/src/clock.hpp:1:1")]))
        rules = [Rule(None, r"/clock\.hpp:", [r"\bsmall\("], "clock"),
                 Rule(r"\bcaller\(", None, [r"\bbig\("], "table")]
        self.assertEqual(self.b.result(r"\bcaller\(\)", rules=rules)["bytes"], 12)

    def test_library_function_costs_its_stated_bound(self):
        self.b.add("l", vcg("l.cpp", [("f", "void f()", 16, "static"), ("memcpy", "void* memcpy(void*, const void*, size_t)")],
                            [("f", "memcpy")]))
        r = self.b.result(r"\bf\(\)", library={"memcpy": (24, "test")})
        self.assertEqual(r["errors"], [])
        self.assertEqual(r["bytes"], 40)
        self.assertEqual(r["path"][-1], {"function": "memcpy", "frame": 24, "cumulative": 40, "library": True})

    def test_bounded_recursion(self):
        self.b.add("s", vcg("s.cpp", [("top", "void top()", 8, "static"), ("sort", "void sort_loop(int*)", 24, "static"),
                                      ("leaf", "void leaf()", 4, "static")],
                            [("top", "sort"), ("sort", "sort"), ("sort", "leaf")]))
        r = self.b.result(r"\btop\(\)", recursions=[(r"\bsort_loop\(", 5, "test")])
        self.assertEqual(r["errors"], [])
        self.assertEqual(r["bytes"], 8 + 5 * 24 + 4)

    def test_accepted_dynamic_frame(self):
        self.b.add("v", vcg("v.cpp", [("f", "void f(int)", 16, "dynamic")], []))
        r = self.b.result(r"\bf\(int\)", dynamic=[(r"\bf\(int\)", 128, "test")])
        self.assertEqual(r["errors"], [])
        self.assertEqual(r["bytes"], 128)

    def test_dynamic_bounded_is_taken_at_gccs_figure(self):
        self.b.add("v", vcg("v.cpp", [("f", "void f(int)", 48, "dynamic,bounded")], []))
        r = self.b.result(r"\bf\(int\)")
        self.assertEqual((r["errors"], r["bytes"]), ([], 48))


class Names(unittest.TestCase):
    """gcc prefixes a unit-local or weak name with its unit's source file."""

    def setUp(self):
        self.b = Build()

    def tearDown(self):
        self.b.close()

    def test_internal_functions_are_their_units_own(self):
        # The same anonymous-namespace helper in two units: each caller gets its own.
        helper = "_ZN12_GLOBAL__N_16helperEv"
        for src, frame in (("p.cpp", 10), ("q.cpp", 300)):
            stem = src[0]
            self.b.add(stem, vcg(src, [(f"_Z1{stem}v", f"void {stem}()", 8, "static"),
                                       (f"{src}:{helper}", "void {anonymous}::helper()", frame, "static")],
                                 [(f"_Z1{stem}v", f"{src}:{helper}")]))
        self.assertEqual(self.b.result(r"\bp\(\)")["bytes"], 18)
        self.assertEqual(self.b.result(r"\bq\(\)")["bytes"], 308)

    def test_weak_copies_are_one_function_at_the_larger_frame(self):
        inline = "_ZN1S6inlineEv"
        for src, frame in (("p.cpp", 10), ("q.cpp", 30)):
            stem = src[0]
            self.b.add(stem, vcg(src, [(f"_Z1{stem}v", f"void {stem}()", 8, "static"),
                                       (f"{src}:{inline}", "void S::inline()", frame, "static")],
                                 [(f"_Z1{stem}v", f"{src}:{inline}")]))
        # The linker keeps one copy, either: both callers get the larger.
        self.assertEqual(self.b.result(r"\bp\(\)")["bytes"], 38)

    def test_constructor_alias(self):
        # Defined as the base-object constructor (C2), called as the complete one (C1).
        self.b.add("c", vcg("c.cpp", [("_ZN1TC2Ev", "T::T()", 20, "static")], []))
        self.b.add("u", vcg("u.cpp", [("_Z1uv", "void u()", 8, "static"), ("_ZN1TC1Ev", "T::T()")],
                            [("_Z1uv", "_ZN1TC1Ev")]))
        r = self.b.result(r"\bu\(\)")
        self.assertEqual((r["errors"], r["bytes"]), ([], 28))

    def test_short_name_drops_the_return_type(self):
        self.assertEqual(sr.short_name("trueaxis::core::Result<Eigen::Matrix<double, 3, 1> > ns::f(const S&, int)"),
                         "ns::f(const S&, int)")
        self.assertEqual(sr.short_name("decltype (f(declval<const T&>())) ns::read_or(const L<T>&, F) [with T = int]"),
                         "ns::read_or(const L<T>&, F) [with T = int]")
        self.assertEqual(sr.short_name("void f()"), "f()")

    def test_macro_table_rule_matches_handlers_and_thunks(self):
        # gcc 12's names of the thunks of MacroThunk's type, MacroStep(MacroCall&)
        # (taken from the Cortex-M7 build), and of a captureless lambda of that
        # type, and of functions that are not of that type (the handlers
        # themselves take their context and state).
        (pattern,) = next(r for r in sr.INDIRECT_CALLS if r.tables).targets
        of_type = [
            "trueaxis::macros::MacroStep trueaxis::macros::thunk(MacroCall&) [with auto Handler = rigidity::run_build]",
            "trueaxis::macros::MacroStep trueaxis::macros::thunk(trueaxis::macros::MacroCall&) "
            "[with auto Handler = level::run_level_3pt]",
            "static constexpr trueaxis::macros::MacroStep trueaxis::macros::<lambda(trueaxis::macros::MacroCall&)>"
            "::_FUN(trueaxis::macros::MacroCall&)"]
        not_of_type = [
            "trueaxis::macros::MacroStep trueaxis::macros::rigidity::run_build(Context&, State&)",
            "trueaxis::macros::MacroStep trueaxis::macros::call(int, MacroCall&)",
            "trueaxis::macros::MacroStep trueaxis::macros::<lambda(trueaxis::macros::MacroCall&)>::operator()"
            "(trueaxis::macros::MacroCall&) const"]
        for label in of_type:
            self.assertRegex(label, pattern)
        for label in not_of_type:
            self.assertNotRegex(label, pattern)

    def test_internal_names(self):
        for name in ("_ZL3loci", "_ZN12_GLOBAL__N_14anonEi", "_ZN1SIiE1hEi.isra.0"):
            self.assertTrue(sr.is_internal(name), name)
        # A static in a named namespace (_ZN2nsL3nslEi) is merged with its
        # namesakes (conservative); so is anything else.
        for name in ("_Z1gi", "_ZN5Eigen6MatrixIdLi3ELi1ELi0ELi3ELi1EEC2Ev", "_ZN8trueaxis6macros6Module4stepEv",
                     "_ZN2nsL3nslEi", "_ZN2ns6L2NormC2Ev"):
            self.assertFalse(sr.is_internal(name), name)


class Errors(unittest.TestCase):
    """What the tool must refuse: never a silent zero."""

    def setUp(self):
        self.b = Build()

    def tearDown(self):
        self.b.close()

    def assertError(self, result, fragment):
        self.assertTrue(any(fragment in e for e in result.get("errors", [])),
                        f"no error containing {fragment!r} in {result.get('errors')}")

    def test_unresolved_indirect_call(self):
        self.b.add("i", vcg("i.cpp", [("caller", "void caller()", 8, "static"), INDIRECT],
                            [("caller", "__indirect_call", "i.cpp:4:5")]))
        r = self.b.result(r"\bcaller\(\)", rules=[Rule(None, r"/other\.hpp:", [r"x"], "unrelated")])
        self.assertError(r, "indirect call at i.cpp:4:5 resolved by no rule")

    def test_rule_whose_targets_match_nothing(self):
        self.b.add("i", vcg("i.cpp", [("caller", "void caller()", 8, "static"), INDIRECT],
                            [("caller", "__indirect_call", "i.cpp:4:5")]))
        r = self.b.result(r"\bcaller\(\)", rules=[Rule(None, None, [r"renamed_handler"], "handlers")])
        self.assertError(r, "target pattern 'renamed_handler' matches no function")

    def test_recursion(self):
        self.b.add("r", vcg("r.cpp", [("a", "void a()", 8, "static"), ("b", "void b()", 8, "static")],
                            [("a", "b"), ("b", "a")]))
        r = self.b.result(r"\ba\(\)")
        self.assertError(r, "recursion: a() -> b() -> a()")

    def test_self_recursion_not_listed(self):
        self.b.add("r", vcg("r.cpp", [("a", "void a()", 8, "static")], [("a", "a")]))
        self.assertError(self.b.result(r"\ba\(\)"), "recursion: a() -> a()")

    def test_dynamic_frame(self):
        self.b.add("v", vcg("v.cpp", [("f", "void f(int)", 16, "static"), ("g", "void g(int)", 16, "dynamic")],
                            [("f", "g")]))
        self.assertError(self.b.result(r"\bf\(int\)"), "frame is dynamic")

    def test_no_stack_information(self):
        self.b.add("l", vcg("l.cpp", [("f", "void f()", 16, "static"), ("strtod", "double strtod(const char*, char**)")],
                            [("f", "strtod")]))
        self.assertError(self.b.result(r"\bf\(\)"), "calls strtod, which has no stack information")

    def test_root_matching_nothing_or_several(self):
        self.b.add("a", chain_unit())
        self.assertError(self.b.result(r"\bzzz\("), "matches no function")
        self.assertError(self.b.result(r"\b[ab]\(\)"), "matches 2 functions")

    def test_problems_outside_the_roots_reach_are_not_errors(self):
        self.b.add("a", chain_unit())
        self.b.add("z", vcg("z.cpp", [("z", "void z()", 8, "dynamic"), INDIRECT], [("z", "__indirect_call", "z:1")]))
        self.assertEqual(self.b.result(r"\ba\(\)")["errors"], [])

    def test_missing_and_stale_call_graphs(self):
        self.b.add("a", chain_unit(), obj=True)
        d = os.path.join(self.b.dir, "lib.dir")
        with open(os.path.join(d, "orphan.cpp.obj"), "w") as f:
            f.write("")
        _, problems = sr.find_units(self.b.dir)
        self.assertEqual(len(problems), 1)
        self.assertIn("orphan.cpp.obj: no call graph beside it", problems[0])
        old = time.time() - 3600
        os.utime(os.path.join(d, "a.ci"), (old, old))
        _, problems = sr.find_units(self.b.dir)
        self.assertTrue(any("a.ci: older than its object" in p for p in problems), problems)

    def test_no_call_graph_at_all(self):
        with self.assertRaises(sr.AnalysisError):
            sr.find_units(self.b.dir)


class CommandLine(unittest.TestCase):
    def setUp(self):
        self.b = Build()
        self.b.add("a", chain_unit())

    def tearDown(self):
        self.b.close()

    def test_within_bound(self):
        rc, out, _ = self.b.cli("--root", r"chain=\ba\(\)", "--bound", "chain=56")
        self.assertEqual(rc, 0, out)
        self.assertIn("chain: 56 bytes", out)

    def test_over_bound_exits_1_with_the_path(self):
        rc, out, _ = self.b.cli("--root", r"chain=\ba\(\)", "--root", r"leaf=\bc\(\)", "--bound", "chain=55",
                                "--bound", "leaf=1000")
        self.assertEqual(rc, 1, out)
        self.assertIn("OVER BOUND: chain needs 56 bytes, bound 55: a() (16) -> b() (32) -> c() (8)", out)
        self.assertNotIn("OVER BOUND: leaf", out)

    def test_bound_globs_and_a_bound_for_no_root(self):
        rc, out, _ = self.b.cli("--root", r"query:a=\ba\(\)", "--root", r"query:b=\bb\(\)", "--bound", "query:*=40")
        self.assertEqual(rc, 1)
        self.assertIn("OVER BOUND: query:a", out)
        self.assertNotIn("OVER BOUND: query:b", out)
        rc, out, _ = self.b.cli("--root", r"chain=\ba\(\)", "--bound", "renamed=100")
        self.assertEqual(rc, 2)
        self.assertIn("--bound renamed: no root of that name", out)

    def test_json(self):
        rc, out, _ = self.b.cli("--root", r"chain=\ba\(\)", "--bound", "chain=100", "--json")
        self.assertEqual(rc, 0)
        doc = json.loads(out)
        (root,) = doc["roots"]
        self.assertEqual((root["root"], root["bytes"], root["bound"]), ("chain", 56, 100))
        self.assertEqual([p["cumulative"] for p in root["path"]], [16, 48, 56])
        self.assertEqual([t["frame"] for t in doc["top_frames"]], [32, 16, 8])
        self.assertEqual(doc["errors"], [])

    def test_error_exits_2(self):
        self.b.add("r", vcg("r.cpp", [("_Z1rv", "void r()", 8, "static")], [("_Z1rv", "_Z1rv")]))
        rc, out, err = self.b.cli("--root", r"r=\br\(\)")
        self.assertEqual(rc, 2)
        self.assertIn("recursion", out)
        self.assertIn("not bounds", err)


CANNED_OBJDUMP = textwrap.dedent("""\
    #!/bin/sh
    if [ "$1" = "-t" ]; then cat <<'EOF'
    00001000 g     F .text\t00000020 lib_top
    00001020 g     F .text\t00000010 lib_leaf
    00001030 g     F .text\t00000010 lib_alloca
    00001040 g     F .text\t00000010 _Z8own_funcv
    00002000 g     O .rodata\t0000000c kTable
    EOF
    elif [ "$1" = "-s" ]; then cat <<'EOF'

    image.elf:     file format elf32-littlearm

    Contents of section .rodata:
     2000 01100000 00300000 41100000           .....0..A...
    EOF
    else cat <<'EOF'
    00001000 <lib_top>:
        1000:\tstmdb\tsp!, {r4, r5, r6, r7, r8, r9, sl, fp, lr}
        1004:\tvpush\t{d8-d11}
        1008:\tsub.w\tsp, sp, #588\t@ 0x24c
        100c:\tbls.n\t1010 <lib_top+0x10>
        100e:\tbl\t1020 <lib_leaf>
        1010:\tldr\tr2, [pc, #8]\t@ (1040 <_Z8own_func>)
        1012:\tb.w\t1020 <lib_leaf>

    00001020 <lib_leaf>:
        1020:\tstrd\tip, lr, [sp, #-16]!
        1024:\tpush\t{r4, lr}
        1026:\tbx\tlr

    00001030 <lib_alloca>:
        1030:\tsub.w\tsp, sp, r3
        1034:\tblx\tr3

    00001040 <_Z8own_funcv>:
        1040:\tsub\tsp, #8
        1042:\tpush\t{r4, lr}
        1044:\tbx\tlr
    EOF
    fi
    """)


class DisassemblyReader(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.objdump = os.path.join(self.tmp.name, "objdump")
        with open(self.objdump, "w") as f:
            f.write(CANNED_OBJDUMP)
        os.chmod(self.objdump, 0o755)
        self.dis = sr.Disassembly("image.elf", self.objdump)

    def tearDown(self):
        self.tmp.cleanup()

    def test_frames_and_calls(self):
        b, problems, path = self.dis.bound("lib_top")
        # 9 registers + 4 doubles + 588; then lib_leaf (16 + 8). bls.n is no call,
        # the literal's annotation no reference.
        self.assertEqual(b, 36 + 32 + 588 + 24)
        self.assertEqual(problems, [])
        self.assertEqual(path, ["lib_top (656)", "lib_leaf (24)"])

    def test_dynamic_and_indirect(self):
        _, problems, _ = self.dis.bound("lib_alloca")
        self.assertEqual(len(problems), 2)
        self.assertTrue(any("dynamic" in p for p in problems))
        self.assertTrue(any("indirect branch" in p for p in problems))
        self.assertIsNone(self.dis.bound("absent"))

    def test_gcc_frame_raised_to_the_disassembly(self):
        # gcc's -fstack-usage leaves out pushed argument registers (sub sp, #8 here).
        b = Build()
        try:
            b.add("o", vcg("o.cpp", [("_Z8own_funcv", "void own_func()", 8, "static")], []))
            paths, _ = sr.find_units(b.dir)
            g = sr.Graph([sr.parse_ci(p) for p in paths])
            raised, compared = sr.apply_disassembly(g, [self.dis])
            self.assertEqual((compared, raised), ({"_Z8own_funcv"}, [("own_func()", 8, 16)]))
            self.assertEqual(g.functions["_Z8own_funcv"].frame, 16)
        finally:
            b.close()

    def test_function_pointers_of_a_table(self):
        # 0x1001: lib_top (Thumb bit set); 0x3000 no function; 0x1041 _Z8own_funcv.
        self.assertEqual(self.dis.function_pointers(r"^kTable$"), {"kTable": ["lib_top", "_Z8own_funcv"]})
        self.assertEqual(self.dis.function_pointers(r"^kOther$"), {})
        # With a layout only the fields named are pointers: 0x1041 is then data.
        self.assertEqual(self.dis.function_pointers(r"^kTable$", (12, (0,))), {"kTable": ["lib_top"]})
        self.assertEqual(self.dis.function_pointers(r"^kTable$", (4, (0,))), {"kTable": ["lib_top", "_Z8own_funcv"]})
        with self.assertRaises(sr.AnalysisError):
            self.dis.function_pointers(r"^kTable$", (8, (0,)))  # 12 bytes: no whole entries

    def test_table_entry_the_rule_misses(self):
        b = Build()
        try:
            b.add("t", vcg("t.cpp", [("caller", "void caller()", 8, "static"), INDIRECT,
                                     ("lib_top", "void lib_top()", 4, "static"),
                                     ("_Z8own_funcv", "void own_func()", 4, "static")],
                           [("caller", "__indirect_call", "t.cpp:1:1")]))
            rule = Rule(None, None, [r"\blib_top\("], "the table", r"^kTable$")
            an, _ = b.analysis([Root("r", r"\bcaller\(", "")], rules=[rule])
            errors, _ = sr.check_tables(an, [self.dis])
            self.assertEqual(len(errors), 1)
            self.assertIn("kTable in image.elf holds _Z8own_funcv, which rule 'the table' does not resolve to", errors[0])
            an, _ = b.analysis([Root("r", r"\bcaller\(", "")],
                               rules=[rule._replace(targets=[r"\blib_top\(", r"\bown_func\("])])
            self.assertEqual(sr.check_tables(an, [self.dis])[0], [])
        finally:
            b.close()

    def test_instruction_decrements(self):
        cases = {("push", "{r4, r5, r6, lr}"): 16, ("push.w", "{r4, lr}"): 8, ("vpush", "{d8}"): 8,
                 ("vpush", "{d8-d15}"): 64, ("sub", "sp, #20"): 20, ("subw", "sp, sp, #1036\t@ 0x40c"): 1036,
                 ("str.w", "lr, [sp, #-4]!"): 4, ("sub", "sp, r3"): -1, ("add", "sp, #20"): None,
                 ("sub", "r3, sp, #8"): None, ("stmdb", "sp!, {r4, r5, lr}"): 12, ("ldr", "r2, [sp, #4]"): None}
        for (mn, ops), want in cases.items():
            self.assertEqual(sr._insn_decrement(mn, ops), want, f"{mn} {ops}")


# CALL_BOUNDS (convention 6). fa -> fb -> sin is the bounded chain; fc -> fb is
# another way to the same fb; both() reaches fb both ways.
TRIG_LIBRARY = {"sin": (744, "test: the large reduction"), "cos": (744, "test: as sin")}
SIN = ("sin", "double sin(double)")
FA, FB = r"\bfa\(", r"\bfb\("


def trig_unit(extra_nodes=(), extra_edges=()):
    return vcg("t.cpp", [("fa", "void fa()", 16, "static"), ("fb", "void fb()", 32, "static"),
                         ("fc", "void fc()", 24, "static"), ("both", "void both()", 4, "static"), SIN,
                         *extra_nodes],
               [("both", "fa"), ("both", "fc"), ("fa", "fb"), ("fc", "fb"), ("fb", "sin"), *extra_edges])


def small_sin(chain=(FA, FB), functions=("sin",), nbytes=72, skip=("__kernel_rem_pio2",)):
    return CallBound(list(chain), functions, nbytes, skip, "test: the callers keep |x| small")


class CallBounds(unittest.TestCase):
    def setUp(self):
        self.b = Build()

    def tearDown(self):
        self.b.close()

    def results(self, roots, call_bounds, library=TRIG_LIBRARY):
        """{root name: result} of roots (name, pattern) analysed together (one Analysis:
        its memo must keep the contexts apart)."""
        an, _ = self.b.analysis([Root(n, p, "") for n, p in roots], library=library, call_bounds=call_bounds)
        return {r.name: an.root_result(r) for r in an.roots}, an

    def test_chain_bounds_the_call_and_only_through_it(self):
        self.b.add("t", trig_unit())
        res, an = self.results([("a", r"\bfa\(\)"), ("c", r"\bfc\(\)"), ("both", r"\bboth\(\)"),
                                ("b", r"\bfb\(\)")], [small_sin()])
        for r in res.values():
            self.assertEqual(r["errors"], [])
        # Through fa: the chain fa -> fb holds, sin costs 72.
        self.assertEqual(res["a"]["bytes"], 16 + 32 + 72)
        self.assertEqual(res["a"]["path"][-1],
                         {"function": "sin", "frame": 72, "cumulative": 120, "library": True, "call_bound": 0})
        # The same fb through fc (not in the chain), or as a root: LIBRARY's 744.
        self.assertEqual(res["c"]["bytes"], 24 + 32 + 744)
        self.assertEqual(res["c"]["path"][-1], {"function": "sin", "frame": 744, "cumulative": 800, "library": True})
        self.assertEqual(res["b"]["bytes"], 32 + 744)
        # Both ways from one root: the worst (through fc), though fa's way is analysed first.
        self.assertEqual(res["both"]["bytes"], 4 + 24 + 32 + 744)
        self.assertEqual([p["function"] for p in res["both"]["path"]], ["both()", "fc()", "fb()", "sin"])

    def test_context_is_kept_whichever_root_comes_first(self):
        self.b.add("t", trig_unit())
        res, _ = self.results([("c", r"\bfc\(\)"), ("b", r"\bfb\(\)"), ("a", r"\bfa\(\)")], [small_sin()])
        self.assertEqual((res["c"]["bytes"], res["b"]["bytes"], res["a"]["bytes"]), (800, 776, 120))

    def test_chain_starting_above_the_root(self):
        # The root fb is called by fa elsewhere; analysed on its own, nothing guarantees its argument.
        self.b.add("t", trig_unit())
        res, _ = self.results([("b", r"\bfb\(\)")], [small_sin()])
        self.assertEqual((res["b"]["bytes"], res["b"]["call_bounds"]), (776, []))

    def test_partial_chains_do_not_count(self):
        # fa calls sin itself (only the chain's first pattern matched); fb calls it
        # through fd (the chain's last pattern is not sin's caller); fa -> fx -> fb
        # (not consecutive); fb alone (the chain's first pattern missing: fc -> fb).
        nodes = [("fd", "void fd()", 8, "static"), ("fx", "void fx()", 8, "static"),
                 ("top_direct", "void top_direct()", 4, "static"), ("top_gap", "void top_gap()", 4, "static"),
                 ("top_deeper", "void top_deeper()", 4, "static")]
        self.b.add("t", trig_unit(nodes, [("fa", "sin")]))
        self.b.add("u", vcg("u.cpp", [("fd", "void fd()", 8, "static"), ("fb2", "void fb_deep()", 32, "static"),
                                      ("fa2", "void fa_deep()", 16, "static"), ("fx", "void fx()", 8, "static"),
                                      ("fb", "void fb()"), ("fa3", "void fa_gap()", 16, "static"), SIN],
                            [("fa2", "fb2"), ("fb2", "fd"), ("fd", "sin"), ("fa3", "fx"), ("fx", "fb")]))
        chains = [small_sin(), small_sin(chain=(r"\bfa_deep\(", r"\bfb_deep\(")),
                  small_sin(chain=(r"\bfa_gap\(", FB))]
        res, _ = self.results([("direct", r"\bfa\(\)"), ("deeper", r"\bfa_deep\(\)"), ("gap", r"\bfa_gap\(\)"),
                               ("c", r"\bfc\(\)")], chains)
        # fa: its own sin call costs 744 (the chain fa -> fb is not complete at fa); fb's costs 72.
        self.assertEqual(res["direct"]["bytes"], 16 + 744)
        self.assertEqual(res["direct"]["path"][-1], {"function": "sin", "frame": 744, "cumulative": 760,
                                                     "library": True})
        self.assertEqual(res["deeper"]["bytes"], 16 + 32 + 8 + 744)
        self.assertEqual(res["gap"]["bytes"], 16 + 8 + 32 + 744)
        self.assertEqual(res["c"]["bytes"], 24 + 32 + 744)
        for r in res.values():
            self.assertEqual(r["errors"], [], r["root"])
        # fa's figure relies on entry 0 all the same: through fb, sin would cost 16 + 32 + 744 without it.
        self.assertEqual([res[n]["call_bounds"] for n in ("direct", "deeper", "gap", "c")], [[0], [], [], []])

    def test_only_the_functions_named(self):
        # The chain holds, but the entry bounds sin, not cos.
        self.b.add("t", vcg("t.cpp", [("fa", "void fa()", 16, "static"), ("fb", "void fb()", 32, "static"),
                                      ("cos", "double cos(double)")], [("fa", "fb"), ("fb", "cos")]))
        res, _ = self.results([("a", r"\bfa\(\)")], [small_sin()])
        self.assertEqual((res["a"]["bytes"], res["a"]["path"][-1]["function"]), (16 + 32 + 744, "cos"))
        self.assertEqual(res["a"]["call_bounds"], [])
        res, _ = self.results([("a", r"\bfa\(\)")], [small_sin(functions=("sin", "cos"))])
        self.assertEqual((res["a"]["bytes"], res["a"]["call_bounds"]), (16 + 32 + 72, [0]))

    def test_roots_list_the_entries_they_rely_on(self):
        self.b.add("t", trig_unit())
        # Entry 1 is the same chain but no smaller than LIBRARY: never relied on.
        # Entry 2 bounds fc's way, entry 3 a chain the graph does not have.
        entries = [small_sin(), small_sin(nbytes=744), small_sin(chain=(r"\bfc\(", FB), nbytes=100),
                   small_sin(chain=(r"\bgone\(", FB))]
        res, an = self.results([("a", r"\bfa\(\)"), ("c", r"\bfc\(\)"), ("both", r"\bboth\(\)"),
                                ("b", r"\bfb\(\)")], entries)
        self.assertEqual(res["a"]["call_bounds"], [0])
        self.assertEqual(res["c"]["call_bounds"], [2])
        self.assertEqual(res["b"]["call_bounds"], [])
        # both(): its worst path is fc's, but fa's way would be the worse without entry 0.
        self.assertEqual(res["both"]["bytes"], 4 + 24 + 32 + 100)
        self.assertEqual(res["both"]["call_bounds"], [0, 2])
        self.assertEqual(an.call_bound_hits, [2, 0, 2, 0])

    def test_relied_on_though_off_the_worst_path(self):
        # fb's worst is fe (200), not sin (72); without the entry sin (744) would be.
        self.b.add("t", trig_unit([("fe", "void fe()", 200, "static")], [("fb", "fe")]))
        res, _ = self.results([("a", r"\bfa\(\)")], [small_sin()])
        self.assertEqual(res["a"]["bytes"], 16 + 32 + 200)
        self.assertEqual(res["a"]["path"][-1]["function"], "fe()")
        self.assertEqual(res["a"]["call_bounds"], [0])


@contextlib.contextmanager
def configured(roots, call_bounds):
    """main() with these ROOTS and CALL_BOUNDS, and no INDIRECT_CALLS or RECURSIONS
    (whose stale entries main() reports too). Analysis takes CALL_BOUNDS as a
    default argument: the list is replaced in place, and restored."""
    saved = sr.CALL_BOUNDS[:]
    sr.CALL_BOUNDS[:] = call_bounds
    try:
        with mock.patch.object(sr, "ROOTS", roots), mock.patch.object(sr, "INDIRECT_CALLS", []), \
                mock.patch.object(sr, "RECURSIONS", []):
            yield
    finally:
        sr.CALL_BOUNDS[:] = saved


class CallBoundsCommandLine(unittest.TestCase):
    """main() with the module's tables (LIBRARY's sin: 744 B)."""

    def setUp(self):
        self.b = Build()
        self.b.add("t", trig_unit())
        self.entries = [small_sin(), small_sin(chain=(r"\bfc\(", FB))]

    def tearDown(self):
        self.b.close()

    def test_entry_no_root_relies_on_is_stale(self):
        with configured([Root("a", r"\bfa\(\)", "")], self.entries):
            rc, out, _ = self.b.cli()
        self.assertEqual(rc, 2, out)
        self.assertIn(r"error: CALL_BOUNDS[1] (\bfc\( -> \bfb\( -> sin) bounds no call a root makes: stale", out)
        self.assertNotIn("CALL_BOUNDS[0] (", out)
        self.assertIn("relies on CALL_BOUNDS [0]", out)

    def test_every_entry_relied_on(self):
        with configured([Root("a", r"\bfa\(\)", ""), Root("c", r"\bfc\(\)", "")], self.entries):
            rc, out, _ = self.b.cli("--bound", "a=120", "--bound", "c=128")
        self.assertEqual(rc, 0, out)
        self.assertNotIn("error", out)

    def test_not_stale_with_root(self):
        # --root analyses a few roots only: an entry they do not use is no error.
        with configured([], self.entries):
            rc, out, _ = self.b.cli("--root", r"a=\bfa\(\)", "--json")
        self.assertEqual(rc, 0, out)
        doc = json.loads(out)
        self.assertEqual(doc["errors"], [])
        (root,) = doc["roots"]
        self.assertEqual((root["bytes"], root["call_bounds"]), (120, [0]))
        self.assertEqual(doc["call_bounds"], [{"index": 0, "chain": [FA, FB], "function": "sin", "stated": 72,
                                               "disassembly": None, "image": None, "path": []}])


# newlib's sin and cos as linked: sin 24 + __ieee754_rem_pio2 48 +
# __kernel_rem_pio2 656 + floor 16 = 744; without __kernel_rem_pio2, 72.
TRIG_OBJDUMP = textwrap.dedent("""\
    #!/bin/sh
    if [ "$1" = "-t" ]; then cat <<'EOF'
    00003000 g     F .text\t00000010 sin
    00003010 g     F .text\t00000010 cos
    00003020 g     F .text\t00000020 __ieee754_rem_pio2
    00003040 g     F .text\t00000010 __kernel_rem_pio2
    00003050 g     F .text\t00000004 floor
    00003060 g     F .text\t00000004 __kernel_sin
    00003064 g     F .text\t00000004 __kernel_cos
    EOF
    else cat <<'EOF'
    00003000 <sin>:
        3000:\tpush\t{r4, lr}
        3002:\tsub\tsp, #16
        3004:\tbl\t3020 <__ieee754_rem_pio2>
        3008:\tbl\t3060 <__kernel_sin>
        300c:\tadd\tsp, #16
        300e:\tpop\t{r4, pc}

    00003010 <cos>:
        3010:\tpush\t{r4, lr}
        3012:\tsub\tsp, #16
        3014:\tbl\t3020 <__ieee754_rem_pio2>
        3018:\tbl\t3064 <__kernel_cos>
        301c:\tadd\tsp, #16
        301e:\tpop\t{r4, pc}

    00003020 <__ieee754_rem_pio2>:
        3020:\tstmdb\tsp!, {r4, r5, r6, r7, r8, lr}
        3024:\tsub\tsp, #24
        3026:\tldr\tr3, [pc, #20]\t@ (303c <__ieee754_rem_pio2+0x1c>)
        3028:\tcmp\tr4, r3
        302a:\tbls.n\t3032 <__ieee754_rem_pio2+0x12>
        302c:\tbl\t3040 <__kernel_rem_pio2>
        3030:\tb.n\t3036 <__ieee754_rem_pio2+0x16>
        3032:\tvmov\td0, r0, r1
        3036:\tadd\tsp, #24
        3038:\tldmia.w\tsp!, {r4, r5, r6, r7, r8, pc}
        303c:\t.word\t0x413921fb

    00003040 <__kernel_rem_pio2>:
        3040:\tstmdb\tsp!, {r4, r5, r6, r7, r8, r9, sl, fp, lr}
        3044:\tvpush\t{d8-d15}
        3048:\tsub.w\tsp, sp, #556\t@ 0x22c
        304c:\tbl\t3050 <floor>

    00003050 <floor>:
        3050:\tpush\t{r4, r5, r6, lr}
        3052:\tpop\t{r4, r5, r6, pc}

    00003060 <__kernel_sin>:
        3060:\tvmov\td0, r0, r1
        3062:\tbx\tlr

    00003064 <__kernel_cos>:
        3064:\tvmov\td0, r0, r1
        3066:\tbx\tlr
    EOF
    fi
    """)


class CallBoundsDisassembly(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.objdump = os.path.join(self.tmp.name, "objdump")
        with open(self.objdump, "w") as f:
            f.write(TRIG_OBJDUMP)
        os.chmod(self.objdump, 0o755)
        self.dis = sr.Disassembly("image.elf", self.objdump)
        self.b = Build()
        self.b.add("t", trig_unit([("cos", "double cos(double)")], [("fb", "cos")]))

    def tearDown(self):
        self.b.close()
        self.tmp.cleanup()

    def check(self, entry):
        an, _ = self.b.analysis([Root("a", r"\bfa\(\)", "")], library=TRIG_LIBRARY, call_bounds=[entry])
        r = an.root_result(an.roots[0])
        self.assertEqual((r["errors"], r["call_bounds"]), ([], [0]))
        return sr.check_call_bounds(an, [self.dis], set(r["call_bounds"]))

    def test_bound_with_skip(self):
        self.assertEqual(self.dis.bound("sin"), (744, [], ["sin (24)", "__ieee754_rem_pio2 (48)",
                                                         "__kernel_rem_pio2 (656)", "floor (16)"]))
        self.assertEqual(self.dis.bound("sin", ("__kernel_rem_pio2",)),
                         (72, [], ["sin (24)", "__ieee754_rem_pio2 (48)"]))
        self.assertEqual(self.dis.skipped, {"__kernel_rem_pio2"})
        self.dis.bound("sin", ("__kernel_cos",))
        self.assertEqual(self.dis.skipped, set())

    def test_correct_entry_passes(self):
        for nbytes in (72, 100):
            rows, errors, notes = self.check(small_sin(functions=("sin", "cos"), nbytes=nbytes))
            self.assertEqual((errors, notes), ([], []))
            self.assertEqual(rows, [(0, "sin", nbytes, 72, "image.elf", ["sin (24)", "__ieee754_rem_pio2 (48)"]),
                                    (0, "cos", nbytes, 72, "image.elf", ["cos (24)", "__ieee754_rem_pio2 (48)"])])

    def test_bound_below_the_disassembly(self):
        _, errors, _ = self.check(small_sin(nbytes=71))
        self.assertEqual(len(errors), 1, errors)
        self.assertIn("CALL_BOUNDS[0] sin: the disassembly of image.elf needs 72 B without __kernel_rem_pio2, "
                      "over the stated 71 B: sin (24) -> __ieee754_rem_pio2 (48)", errors[0])
        # Cutting off nothing: the whole 744.
        _, errors, _ = self.check(small_sin(skip=()))
        self.assertEqual(len(errors), 1, errors)
        self.assertIn("needs 744 B", errors[0])

    def test_skip_on_no_path(self):
        _, errors, _ = self.check(small_sin(skip=("__kernel_rem_pio2", "__kernel_cos")))
        self.assertEqual(errors, ["CALL_BOUNDS[0] sin: __kernel_cos is on no path of sin in the images: the entry "
                                  "cuts off nothing there (stale?)"])
        # Checked for each function: cos's path has __kernel_cos, not __kernel_sin.
        _, errors, _ = self.check(small_sin(functions=("sin", "cos"), skip=("__kernel_rem_pio2", "__kernel_sin")))
        self.assertEqual(len(errors), 1, errors)
        self.assertIn("CALL_BOUNDS[0] cos: __kernel_sin is on no path of cos", errors[0])

    def test_unlinked_function_is_a_note(self):
        self.b.add("t", trig_unit([("tan", "double tan(double)")], [("fb", "tan")]))
        an, _ = self.b.analysis([Root("a", r"\bfa\(\)", "")], library=dict(TRIG_LIBRARY, tan=(744, "test")),
                                call_bounds=[small_sin(functions=("tan",))])
        r = an.root_result(an.roots[0])
        self.assertEqual(r["call_bounds"], [0])
        rows, errors, notes = sr.check_call_bounds(an, [self.dis], {0})
        self.assertEqual((rows, errors), ([(0, "tan", 72, None, None, [])], []))
        self.assertIn("CALL_BOUNDS[0] tan: linked in no image given with --elf", notes[0])

    def test_command_line_checks_the_entries_relied_on(self):
        entries = [small_sin(nbytes=71), small_sin(chain=(r"\bgone\(", FB), nbytes=1)]
        with configured([], entries):
            rc, out, _ = self.b.cli("--root", r"a=\bfa\(\)", "--elf", "image.elf", "--objdump", self.objdump)
        self.assertEqual(rc, 2, out)
        self.assertIn("error: CALL_BOUNDS[0] sin: the disassembly of image.elf needs 72 B", out)
        self.assertNotIn("CALL_BOUNDS[1]", out)  # relied on by no root: not checked
        with configured([], [small_sin(nbytes=72)]):
            rc, out, _ = self.b.cli("--root", r"a=\bfa\(\)", "--elf", "image.elf", "--objdump", self.objdump)
        self.assertEqual(rc, 0, out)
        self.assertIn("[0] sin       72 B  via \\bfa\\( -> \\bfb\\(  disassembly 72 B (image.elf): "
                      "sin (24) -> __ieee754_rem_pio2 (48)", out)


if __name__ == "__main__":
    unittest.main(verbosity=1)
