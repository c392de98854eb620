#!/usr/bin/env bash
# The spindle method's demo is methods/spindle/demo.sh (its folder); this name, which the
# README gave before, runs it with the same arguments.
exec bash "$(dirname "${BASH_SOURCE[0]}")/../methods/spindle/demo.sh" "$@"
