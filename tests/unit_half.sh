# tests/unit_half.sh - sourced by tests/unit_a.sh and tests/unit_b.sh with
# HALF set: the unit suites under valgrind (check-valgrind, Makefile.am) in
# two processes side by side (valgrind runs a program on one core).  Half a
# runs the suites named in A_SUITES, half b every other one but those of
# VALGRIND_SKIP (SEA_UNIT_SKIP), so a new suite is never left out.  Each
# half's log ends in its own "unit: N passed, M failed" line.
#
# VALGRIND_SKIP: the suites whose cost is arithmetic over large arrays, not
# memory ownership: render (5.98 s native at SEA_UNIT_QUICK, one thread),
# bake (6.52 s), swell (7.07 s), multires (4.59 s), stability (0.61 s) and
# the Monte Carlo suites.  Under valgrind (about 50 times slower) they took
# the CI past its 45 minutes; ASan, UBSan and LeakSanitizer run them whole
# (scripts/test), and the bake directory's writer (bakedir), the image files
# (exr, preview) and the loaders stay here.
A_SUITES="optics,shadow,waves,scene,water,spectrum,sensor,preview,arrays"
VALGRIND_SKIP="render,bake,swell,multires,stability,mc oracle"
unit="${SEABAKE%/src/seabake}/tests/unit"
case ${HALF:?} in
a) SEA_UNIT_SUITES=$A_SUITES exec ${SEABAKE_WRAPPER:-} "$unit" ;;
b) SEA_UNIT_SKIP=$A_SUITES,$VALGRIND_SKIP exec ${SEABAKE_WRAPPER:-} "$unit" ;;
*) echo "unit_half.sh: HALF must be a or b" >&2; exit 2 ;;
esac
