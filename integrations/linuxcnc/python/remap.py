"""LinuxCNC's remap module for trueaxis (trueaxis.ini: REMAP=G65 ... python=g65).
A machine that has a remap.py of its own adds the import below to it instead."""
from trueaxis_g65 import g65

__all__ = ["g65"]  # LinuxCNC looks the handler up by name here
