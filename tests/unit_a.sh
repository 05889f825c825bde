#!/bin/sh
# tests/unit_a.sh - half a of the unit suites (tests/unit_half.sh)
HALF=a
. "$top_srcdir/tests/unit_half.sh"
