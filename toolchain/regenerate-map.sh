#!/usr/bin/env bash
# Rewrites macros/register_map.json and macros/REGISTER_MAP.md from the code's
# tables (after a change to register_map.hpp, sim_map.hpp, the macro or status tables).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build/host -G Ninja >/dev/null
cmake --build build/host --target trueaxis-map
build/host/bin/trueaxis-map --json > macros/register_map.json
build/host/bin/trueaxis-map --markdown > macros/REGISTER_MAP.md
echo "register map regenerated"
