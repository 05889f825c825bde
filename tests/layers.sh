#!/bin/bash
# layers.sh - the library's layers (README, Architecture): each object file
# of libseabake and of exporters/ calls only functions defined in its own
# layer or a lower one, besides the exceptions listed here with their
# reasons.  Read from the built objects' symbols (nm): a call is an
# undefined symbol of one object defined by another.  The program
# (src/cli/) is the top layer; no library object may call it.
#
# Layers, lowest first (the number orders them), one folder each:
#   0 base       src/base/      status textfile tempfile gridtable geometry
#  10 physics    src/physics/   water water_data planck spectrum shadow
#  20 optics     src/optics/    optics twoscale model polar
#  30 sea        src/sea/       waves multires camera
#  35 exporters  exporters/     exr preview arrays povray blender (+ generated)
#  40 view       src/view/      scene view radiometry imager
#  50 bake       src/bake/      bake bakemaps bakedir manifest horizon atomicdir
# An object's layer is its folder's, so a new file joins the layer of the
# folder it is put in.
#
# Under make installcheck (an installed program, no objects) it skips.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=layers
. "$(dirname "$0")/lib.sh"

: "${SEABAKE:?SEABAKE must name the built program}"
src=$(dirname "$SEABAKE")
exp=$src/../exporters
declare -A folder_layer=(
    [base]=0 [physics]=10 [optics]=20 [sea]=30 [exporters]=35 [view]=40 [bake]=50
)
# libtool's objects: the shared library's (.libs/), else the static ones
objdir() {
    if [ -d "$1/.libs" ] && compgen -G "$1/.libs/*.o" >/dev/null; then
        echo "$1/.libs"
    else
        echo "$1"
    fi
}
if ! compgen -G "$(objdir "$src/view")/*.o" >/dev/null || ! compgen -G "$(objdir "$exp")/*.o" >/dev/null; then
    skip "no object files beside $SEABAKE (an installed program): the layers are checked in the build tree"
    exit 77
fi
if ! have nm binutils; then
    [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ] && finish
    exit 77
fi

# Every object of the library, its layer from its folder.  Nothing of the
# library may lie outside the layer folders (a file in src/ itself would).
declare -A layer=() path=()
for f in "${!folder_layer[@]}"; do
    if [ "$f" = exporters ]; then d=$exp; else d=$src/$f; fi
    for o in "$(objdir "$d")"/*.o; do
        [ -f "$o" ] || continue
        n=$(basename "$o" .o)
        layer[$n]=${folder_layer[$f]}
        path[$n]=$o
    done
done
# (an object in src/ whose source is no longer there is a build tree's
# leftover from before the folders, not part of the library)
for o in "$(objdir "$src")"/*.o; do
    [ -f "$o" ] || continue
    n=$(basename "$o" .o)
    [ -f "${top_srcdir:-.}/src/$n.c" ] || continue
    fail "layers.unplaced_$n" "$o is in src/ itself: put it in the folder of its layer (tests/layers.sh, README Architecture)"
done
check layers.folders test "${#layer[@]}" -ge 30

# The calls upward, each with its reason.
declare -A allowed=(
    # the sea's spectrum from the scene's [sea] keys (wind, fetch, swell)
    ["multires sea_scene_spectrum"]=1
    # a camera's MTF table is read, and checked, when the scene file is
    ["scene sea_imager_mtf_load"]=1
    ["scene sea_imager_mtf_free"]=1
)

objs=()
for n in "${!path[@]}"; do
    objs+=("${path[$n]}")
done

# Who defines each global symbol.
declare -A owner=()
for o in "${objs[@]}"; do
    n=$(basename "$o" .o)
    while read -r sym; do
        owner[$sym]=$n
    done < <(nm --defined-only -g "$o" | awk '{ print $3 }')
done
check layers.symbols test "${#owner[@]}" -gt 200

edges=0
for o in "${objs[@]}"; do
    n=$(basename "$o" .o)
    while read -r sym; do
        case $sym in
        sea_cli_*)
            fail "layers.cli_$n" "$n calls $sym: the library never calls the program"
            continue
            ;;
        esac
        d=${owner[$sym]-}
        [ -n "$d" ] && [ "$d" != "$n" ] || continue
        edges=$((edges + 1))
        if [ "${layer[$d]}" -gt "${layer[$n]}" ] && [ -z "${allowed["$n $sym"]+x}" ]; then
            fail "layers.up_${n}_$d" "$n (layer ${layer[$n]}) calls $sym of $d (layer ${layer[$d]})"
        fi
    done < <(nm -u "$o" | awk '{ print $2 }')
done
echo "measured: layers: ${#objs[@]} objects, ${#owner[@]} global symbols, $edges calls between objects"
check layers.edges test "$edges" -gt 100
# every allowed exception is still a real call (an entry nobody needs goes)
for e in "${!allowed[@]}"; do
    n=${e% *} sym=${e#* }
    check "layers.exception_${n}_$sym" bash -c "nm -u '${path[$n]}' | grep -qw '$sym'"
done
finish
