#!/usr/bin/env python3
"""The published register map may only grow: every key, variable, macro and
error of interface version 1 (register_map_v1.json, frozen) is still in the
current map with the same values; new entries and new keys are allowed.

usage: check_map_grows.py OLD.json NEW.json   (exit 0 when it only grew)
"""
import json
import sys

# Lists whose entries are matched by a key, not by position.
KEYED = {"variables": "number", "macros": "number", "errors": "code", "access_faults": "code"}


def grows(old, new, path):
    if isinstance(old, dict):
        if not isinstance(new, dict):
            return [f"{path}: was an object"]
        problems = []
        for key, value in old.items():
            if key not in new:
                problems.append(f"{path}/{key}: removed")
            else:
                problems += grows(value, new[key], f"{path}/{key}")
        return problems
    if isinstance(old, list):
        name = path.rsplit("/", 1)[-1]
        if name in KEYED:
            key = KEYED[name]
            by_key = {entry[key]: entry for entry in new}
            problems = []
            for entry in old:
                if entry[key] not in by_key:
                    problems.append(f"{path}[{entry[key]}]: removed")
                else:
                    problems += grows(entry, by_key[entry[key]], f"{path}[{entry[key]}]")
            return problems
        return [] if old == new else [f"{path}: changed from {old} to {new}"]
    return [] if old == new else [f"{path}: changed from {old!r} to {new!r}"]


def main():
    old, new = (json.load(open(p)) for p in sys.argv[1:3])
    problems = grows(old, new, "")
    for p in problems:
        print(p)
    print("the map only grew" if not problems else f"{len(problems)} change(s) to the published map")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
