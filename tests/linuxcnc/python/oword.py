"""Test-only O-word subroutines in Python (o<dump_results> call): LinuxCNC's own
#100..#199 as they are in its parameter store, repr()'d one a line (exact
binary64) into $TRUEAXIS_DUMP, for a test to compare with the module's; and
o<interface_seen> call: the macro interface as the remap's connection sees it."""
import os


def dump_results(self, *args):
    with open(os.environ["TRUEAXIS_DUMP"], "w", encoding="utf-8") as f:
        for n in range(100, 200):
            f.write(f"#{n} = {float(self.params[n])!r}\n")


def interface_seen(self, *args):
    """#9009 as the remap's own connection reads it (1: it holds the macro
    interface, 0: free), appended to $TRUEAXIS_DUMP as `#9009 = VALUE`."""
    import trueaxis_g65
    remap = trueaxis_g65._state()
    value = remap.module.read(remap.map.var["interface"], 1)[0]
    with open(os.environ["TRUEAXIS_DUMP"], "a", encoding="utf-8") as f:
        f.write(f"#9009 = {value!r}\n")
