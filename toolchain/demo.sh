#!/usr/bin/env bash
# The level method's demo is methods/level/demo.sh (its folder); this name, which the
# README gave before, runs it with the same arguments.
exec bash "$(dirname "${BASH_SOURCE[0]}")/../methods/level/demo.sh" "$@"
