# tests/unit_half.sh - sourced by tests/unit_a.sh and tests/unit_b.sh with
# HALF set: the unit suites in two processes, for check-valgrind (Makefile.am),
# where tests/unit was one 680 s process (valgrind runs a program on one
# core); its halves take 289 and 343 s side by side.  Half a runs the suites
# named below, half b
# every other one (SEA_UNIT_SKIP), so a new suite is never left out.  Each
# half's log ends in its own "unit: N passed, M failed" line.
# Split by their time (SEA_UNIT_QUICK, native): optics 2.7 s, render 2.2 s
# and the small ones here; bake 2.0, mc oracle 2.2, multires 1.0,
# stability 0.5, exr 0.4 in half b.
A_SUITES="optics,render,shadow,waves,scene,water,spectrum,sensor,preview"
unit="${SEABAKE%/src/seabake}/tests/unit"
case ${HALF:?} in
a) SEA_UNIT_SUITES=$A_SUITES exec ${SEABAKE_WRAPPER:-} "$unit" ;;
b) SEA_UNIT_SKIP=$A_SUITES exec ${SEABAKE_WRAPPER:-} "$unit" ;;
*) echo "unit_half.sh: HALF must be a or b" >&2; exit 2 ;;
esac
