# The stack bounds CI holds: ctest stack_bounds fails when a root of
# tools/stack_report.py needs more than its bound here (bytes: its own frame and
# the worst of everything it calls, interrupts not included; docs/FIGURES.md "Stack").
#
# step() and every per-cycle query (query:*) hold the targets of the issue ("A
# method is one type", item 2): 4 KiB and 1 KiB. The large scratch of the fits
# lives in the builders (the module's work arena), and libm's sin and cos are
# bounded by their callers' argument ranges (CALL_BOUNDS in
# tools/stack_report.py, checked against the disassembly). The other bounds sit
# just above today's figure (in the comment), so that nothing grows unnoticed.
# ROOT=BYTES; ROOT may be a glob over the roots' names (query:*=1024).
set(TRUEAXIS_STACK_BOUNDS
  step=4096                         # 3,848: 9810's plane fit on the calibrated table
  access:read=256                   # 112
  access:write=256                  # 232
  protocol:respond=1280             # 1,104
  protocol:rtu_receive=1280         # 1,144
  protocol:rtu_poll=1280            # 1,136
  query:*=1024                      # compensation_rad 896, sub_point_mm 72, tool_tip_correction 944
  boot:start=4096)                  # 4,000: once, at boot (a stored M3 table's splines)
