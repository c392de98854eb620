#!/usr/bin/python3
"""Prints a LinuxCNC machine's home identity, the number the module's #904 and
trueaxis_kins' home= take (trueaxis_module.home_identity: [TRUEAXIS] HOME_ID
and every [JOINT_n]'s HOME and HOME_OFFSET; 0 without HOME_ID).

usage: trueaxis_home.py INI
Exit 0 with the number on stdout; 1 with one line on stderr (a value that is
not a number, a file that cannot be read); 2 on bad usage."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trueaxis_module import TrueaxisError, home_identity, read_ini  # noqa: E402


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr if len(argv) != 2 else sys.stdout)
        return 0 if len(argv) == 2 else 2
    try:
        print(home_identity(read_ini(argv[1])))
    except (OSError, TrueaxisError) as e:
        print(f"trueaxis_home: {argv[1]}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
