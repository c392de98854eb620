#!/usr/bin/env python3
"""The JSON map of a module with the canary (tests/canary/run_canary.cmake):
the canary's row, macros, method entry (blocks, status block, session), record
and status code are all there, and the four methods' entries are unchanged
against the repository's own map.

usage: check_canary_map.py CANARY_MAP.json REPOSITORY_MAP.json   (exit 0 when it holds)
"""
import json
import sys


def main():
    canary, base = (json.load(open(p)) for p in sys.argv[1:3])
    problems = []

    def need(ok, what):
        if not ok:
            problems.append(what)

    variables = {v["number"]: v for v in canary["variables"]}
    need(950 in variables and variables[950]["name"] == "canary_gain" and variables[950]["access"] == "config",
         "variable #950 canary_gain (config)")
    macros = {m["number"]: m for m in canary["macros"]}
    need(all(n in macros and macros[n]["method"] == "canary" for n in range(9850, 9855)), "macros 9850..9854")
    methods = {m["name"]: m for m in canary["methods"]}
    c = methods.get("canary", {})
    need(c.get("config_block") == [950, 959] and c.get("status_block") == [1900, 1999], "the canary's blocks")
    need(c.get("session", {}).get("capacity") == 4 and c.get("session", {}).get("add") == 9852, "the canary's session")
    records = canary["records"]
    need(records[-2]["key"] == 6 and records[-2]["name"] == "canary_sum", "record key 6 after the tables")
    need(records[-1]["name"] == "measuring_log", "the measuring log last (its place moves with the tables)")
    errors = {e["code"]: e for e in canary["errors"]}
    need(errors.get(1901, {}).get("name") == "canary_empty", "error 1901 canary_empty")
    # Everything the repository's map publishes is there as it was: a new method only adds.
    for v in base["variables"]:
        need(variables.get(v["number"]) == v, f"variable #{v['number']} unchanged")
    for m in base["macros"]:
        need(macros.get(m["number"]) == m, f"macro {m['number']} unchanged")
    for m in base["methods"]:
        need(methods.get(m["name"]) == m, f"method {m['name']} unchanged")
    tables = [r for r in base["records"] if r["name"] != "measuring_log"]
    need(records[:len(tables)] == tables, "the records before the canary's unchanged")
    for e in base["errors"]:
        need(errors.get(e["code"]) == e, f"error {e['code']} unchanged")
    for p in problems:
        print(f"canary map: missing or changed: {p}")
    print("canary map: the canary is in the map, the rest as it was" if not problems else
          f"canary map: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
