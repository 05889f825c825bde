#!/bin/bash
# example_bake.sh - runs examples/bake.c, the library's bake example, and
# checks that the directory it writes through sea_bake_write is that of
# `seabake bake SCENE -o DIR --pov --blender`, byte for byte (diff -r: every
# map, preview, POV-Ray file, the Blender script and manifest.json), on
# examples/tiny.ini named by the same path; that it replaces its own bake;
# and that it refuses, untouched, a directory that is not a bake.
#
# make check runs the example built against the uninstalled shared library
# (through libtool); make installcheck runs the copies it compiled against
# the installed library (pkg-config), with the installed program.
#
# Environment, besides lib.sh's: BAKE_EXAMPLE, the example program; LIBTOOL,
# the build's libtool (empty for an installed, non-libtool program).
# $(SHELL) may be a plain POSIX sh: these scripts need bash.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=${TEST_NAME:-example_bake}
. "$(dirname "$0")/lib.sh"

: "${BAKE_EXAMPLE:?BAKE_EXAMPLE must name the built examples/bake}"
: "${top_srcdir:?top_srcdir must name the source directory}"
LIBTOOL=${LIBTOOL-}

# ex_run ARGS...: the example, under the wrapper (words split on purpose).
ex_run() {
    SB_CMD="bake (examples/bake.c) $*"
    # shellcheck disable=SC2086
    ${LIBTOOL:+$LIBTOOL --mode=execute} $SEABAKE_WRAPPER "$BAKE_EXAMPLE" "$@" \
        >"$SB_TMP/out" 2>"$SB_TMP/err"
    SB_RC=$?
    SB_OUT=$(cat "$SB_TMP/out")
    SB_ERR=$(cat "$SB_TMP/err")
}

# Both read the scene by the same name: the manifest records it.
cp "$top_srcdir/examples/tiny.ini" "$SB_TMP/tiny.ini"
cd "$SB_TMP" || exit 99

ex_run tiny.ini lib
check_rc example.rc 0
check_eq example.stderr "$SB_ERR" ""
check_match example.summary "$SB_OUT" "^lib: [0-9]+ texels, "
sb_run bake tiny.ini -o prog --pov --blender --quiet
check_rc program.rc 0
if diff -r lib prog >"$SB_TMP/diff" 2>&1; then
    pass
else
    fail example.same_as_program "$(head -n 5 "$SB_TMP/diff")"
fi
check example.files test "$(find lib -type f | grep -c '')" -gt 20
check example.pov test -s lib/scene.pov
check example.blender cmp -s lib/seabake_import.py "$top_srcdir/exporters/blender/seabake_import.py"

# It replaces its own bake (and the program's), leaving nothing beside it.
ex_run tiny.ini prog
check_rc example.rebake 0
check example.rebake_same diff -r lib prog
check_eq example.rebake_leftovers "$(find . -maxdepth 1 -name 'prog.*' | grep -c '')" 0

# A directory that is not a bake is refused before any work, untouched.
mkdir mine && echo notes >mine/notes.txt
ex_run tiny.ini mine
check_rc example.refused 1
check_match example.refused_message "$SB_ERR" \
    "^bake: mine: 'mine' is not a bake that seabake wrote \(it has no manifest.json and holds 'notes.txt'\); seabake replaces only its own bakes: choose another directory, or move or remove 'mine' yourself \(value out of range\)$"
check_eq example.refused_untouched "$(ls mine)" notes.txt
check_eq example.refused_leftovers "$(find . -maxdepth 1 -name 'mine.*' | grep -c '')" 0

finish
