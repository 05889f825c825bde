#!/bin/bash
# layers.sh - the library's layers (README, Architecture): each object file
# of libseabake and of exporters/ calls only functions defined in its own
# layer or a lower one, besides the exceptions listed here with their
# reasons.  Read from the built objects' symbols (nm): a call is an
# undefined symbol of one object defined by another.  The program
# (src/cli/) is the top layer; no library object may call it.
#
# Layers, lowest first (the number orders them):
#   0 base       status textfile tempfile gridtable geometry
#  10 physics    water water_data planck spectrum shadow
#  20 optics     optics twoscale model polar
#  30 sea        waves multires sensor
#  35 exporters  exr preview arrays povray povray_inc blender blender_py
#  40 view       scene render imager
#  50 bake       bake bakemaps bakedir manifest horizon atomicdir
#
# Under make installcheck (an installed program, no objects) it skips.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=layers
. "$(dirname "$0")/lib.sh"

: "${SEABAKE:?SEABAKE must name the built program}"
src=$(dirname "$SEABAKE")
exp=$src/../exporters
# libtool's objects: the shared library's (.libs/), else the static ones
[ -f "$src/.libs/render.o" ] && src=$src/.libs
if [ ! -f "$src/render.o" ] || [ ! -f "$exp/exr.o" ]; then
    skip "no object files beside $SEABAKE (an installed program): the layers are checked in the build tree"
    exit 77
fi
if ! have nm binutils; then
    [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ] && finish
    exit 77
fi

declare -A layer=(
    [status]=0 [textfile]=0 [tempfile]=0 [gridtable]=0 [geometry]=0
    [water]=10 [water_data]=10 [planck]=10 [spectrum]=10 [shadow]=10
    [optics]=20 [twoscale]=20 [model]=20 [polar]=20
    [waves]=30 [multires]=30 [sensor]=30
    [exr]=35 [preview]=35 [arrays]=35 [povray]=35 [povray_inc]=35 [blender]=35 [blender_py]=35
    [scene]=40 [render]=40 [imager]=40
    [bake]=50 [bakemaps]=50 [bakedir]=50 [manifest]=50 [horizon]=50 [atomicdir]=50
)
# The calls upward, each with its reason.
declare -A allowed=(
    # the sea's spectrum from the scene's [sea] keys (wind, fetch, swell)
    ["multires sea_scene_spectrum"]=1
    # a camera's MTF table is read, and checked, when the scene file is
    ["scene sea_imager_mtf_load"]=1
    ["scene sea_imager_mtf_free"]=1
)

objs=()
for o in "$src"/*.o "$exp"/*.o; do
    n=$(basename "$o" .o)
    if [ -z "${layer[$n]+x}" ]; then
        # a new file must be given a layer here and in the README
        fail "layers.unknown_$n" "$o has no layer (tests/layers.sh and README, Architecture)"
        continue
    fi
    objs+=("$o")
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
    check "layers.exception_${n}_$sym" bash -c "nm -u '$src/$n.o' | grep -qw '$sym'"
done
finish
