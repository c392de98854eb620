"""Test-only O-word subroutines in Python (o<dump_results> call): LinuxCNC's own
#100..#199 as they are in its parameter store, repr()'d one a line (exact
binary64) into $TRUEAXIS_DUMP, for a test to compare with the module's."""
import os


def dump_results(self, *args):
    with open(os.environ["TRUEAXIS_DUMP"], "w", encoding="utf-8") as f:
        for n in range(100, 200):
            f.write(f"#{n} = {float(self.params[n])!r}\n")
