#!/bin/sh
# tests/unit_b.sh - half b of the unit suites (tests/unit_half.sh)
HALF=b
. "$top_srcdir/tests/unit_half.sh"
