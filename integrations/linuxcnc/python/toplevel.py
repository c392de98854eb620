"""LinuxCNC's [PYTHON] TOPLEVEL for trueaxis: imports the remap module. A machine
that has a toplevel.py of its own keeps it; its `import remap` finds ours when
python/ is on [PYTHON] PATH_APPEND and its remap.py imports trueaxis_g65."""
import remap

__all__ = ["remap"]
