"""The tests' [PYTHON] TOPLEVEL: trueaxis's remap, and oword.py's test helpers."""
import remap  # noqa: F401
import oword  # noqa: F401
