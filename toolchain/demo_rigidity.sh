#!/usr/bin/env bash
# The rigidity method's demo is methods/rigidity/demo.sh (its folder); this name, which the
# README gave before, runs it with the same arguments.
exec bash "$(dirname "${BASH_SOURCE[0]}")/../methods/rigidity/demo.sh" "$@"
