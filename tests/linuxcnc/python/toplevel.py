"""The tests' [PYTHON] TOPLEVEL: trueaxis's remap, and oword.py's test helpers."""
import oword
import remap

__all__ = ["oword", "remap"]
