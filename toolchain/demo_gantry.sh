#!/usr/bin/env bash
# The gantry method's demo is methods/gantry/demo.sh (its folder); this name, which the
# README gave before, runs it with the same arguments.
exec bash "$(dirname "${BASH_SOURCE[0]}")/../methods/gantry/demo.sh" "$@"
