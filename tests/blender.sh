#!/bin/bash
# blender.sh - end-to-end test of the Blender import (issue 5): seabake bake
# --blender, then the real Blender 3.4 (headless) runs the script the bake
# wrote beside its manifest.
#
#   - three bakes: a nadir scene with the sun in the glint (float), an oblique
#     view with six rings and the horizon (float), the nadir scene again with
#     --format half; files there, nothing temporary left, the script named
#     in the manifest;
#   - the import's own command line: --save writes a .blend, --render a
#     Cycles EXR; bad manifests fail with exit status 1 naming the file;
#   - tests/blender_check.py inside Blender: every map listed in the
#     manifest loaded as Non-Color with image.pixels equal to seabake's EXR
#     reader (row-flipped; exact for float and half files, see there), the
#     half maps within half rounding of the float ones, marker texels within
#     1 px of the sensor's projection (camera and UV orientation), the
#     normal maps in the encoding of Blender's Normal Map node;
#   - Cycles' render of the nadir import against seabake render of the same
#     scene: relative RMS over the sea pixels below 2 % (emission maps
#     interpolated bilinearly by Cycles against per-pixel optics).
# Blender itself does not run under $SEABAKE_WRAPPER (only seabake does).
# Skips (exit 77) only when blender is not installed.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=blender
. "$(dirname "$0")/lib.sh"

: "${top_srcdir:?top_srcdir must name the source directory}"
POV_DRIVER=${POV_DRIVER:-$(dirname "$SEABAKE")/../tests/pov_driver}
CHECK_PY="$top_srcdir/tests/blender_check.py"

if ! have blender blender; then
    # Under scripts/test an absent blender has failed a check: finish says so.
    [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ] && finish
    exit 77 # (have printed the SKIP line)
fi
if [ ! -x "$POV_DRIVER" ]; then
    echo "blender: $POV_DRIVER is missing (make check builds it)" >&2
    exit 99
fi
# Blender writes its user configuration under $HOME; keep it in the scratch.
export HOME="$SB_TMP/home"
mkdir -p "$HOME"
start_all=$(date +%s.%N)

# run_blender NAME ARGS...: headless Blender with the factory settings; an
# uncaught Python error is exit status 1 too.
run_blender() {
    local name=$1
    shift
    SB_CMD="blender -b --factory-startup --python-exit-code 1 --python $*"
    blender -b --factory-startup --python-exit-code 1 --python "$@" >"$SB_TMP/$name.out" 2>&1
    SB_RC=$?
    SB_ERR=$(grep -E 'FAIL|rror' "$SB_TMP/$name.out" | head -n 5)
}

# bake NAME SCENE ARGS...: seabake bake SCENE -o $SB_TMP/NAME --blender ARGS.
bake() {
    local name=$1 scene="$top_srcdir/tests/scenes/$2.ini" dir="$SB_TMP/$1" f
    shift 2
    SB_CMD="seabake bake $scene -o $dir --blender $*"
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" bake "$scene" -o "$dir" --blender --quiet "$@" 2>"$SB_TMP/err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/err")
    check_rc "$name.bake.rc" 0
    for f in manifest.json seabake_import.py emission_0.exr emission_0.png normal_0.exr \
        roughness_0.exr; do
        check "$name.bake.$f" test -s "$dir/$f"
    done
    check_eq "$name.bake.no_temp" "$(find "$SB_TMP" -maxdepth 2 -name '*.tmp.*' | wc -l)" 0
    check "$name.bake.script_copy" cmp -s "$dir/seabake_import.py" \
        "$top_srcdir/exporters/blender/seabake_import.py"
    check_match "$name.bake.manifest_script" "$(cat "$dir/manifest.json")" \
        '"script":[[:space:]]*"seabake_import.py"'
}

# check_in_blender NAME DIR ARGS...: tests/blender_check.py on DIR's bake.
check_in_blender() {
    local name=$1 dir=$2
    shift 2
    mkdir -p "$SB_TMP/work_$name"
    run_blender "check_$name" "$CHECK_PY" -- "$dir/manifest.json" "$POV_DRIVER" \
        "$SB_TMP/work_$name" "$@"
    grep -E '^(ok|FAIL|maps|half|markers|normal|waves|blender_check):' "$SB_TMP/check_$name.out" |
        grep -vE '^ok: .*(colour space|alpha mode|image.pixels|half against)' |
        sed "s/^/$name: /"
    check_rc "$name.blender_check" 0
}

bake glint pov_glint
# Markers need texels that span pixels: one emission texel per facet, and
# the maps alone (--emission-space map), as the sensor's image would cover
# them in the sensor's view.
bake glint_k1 pov_glint --emission-texels 1 --emission-space map
bake oblique pov_oblique --emission-texels 1 --emission-space map
bake half pov_glint --format half
check_match half.bake.pixel_type "$(cat "$SB_TMP/half/manifest.json")" \
    '"pixel_type":[[:space:]]*"half"'

# The import's command line, as a user runs it: save and render.
dir="$SB_TMP/glint"
run_blender import "$dir/seabake_import.py" -- "$dir/manifest.json" --save "$SB_TMP/glint.blend" \
    --render "$SB_TMP/glint_cycles.exr"
check_rc glint.import.rc 0
check glint.import.blend test -s "$SB_TMP/glint.blend"
check glint.import.render test -s "$SB_TMP/glint_cycles.exr"

# Cycles against seabake render of the same scene, the sensor's image
# projected: the issue's nadir bound, 0.3 % (0.04 % measured: Cycles' pixel
# filter of 0.01 px still moves each lookup a little off the texel centre).
SB_CMD="seabake render $top_srcdir/tests/scenes/pov_glint.ini"
$SEABAKE_WRAPPER "$SEABAKE" render "$top_srcdir/tests/scenes/pov_glint.ini" -o "$SB_TMP/ref.exr" \
    --aov level --png none --quiet 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc glint.render.rc 0
scale=$(sed -n 's/^[[:space:]]*"emission_scale":[[:space:]]*\([0-9.eE+-]*\),*$/\1/p' \
    "$dir/manifest.json")
check_match glint.scale "$scale" '^[0-9.eE+-]+$'
SB_CMD="pov_driver compare ... Cycles"
"$POV_DRIVER" compare "$SB_TMP/ref.exr" "$SB_TMP/ref.level.exr" "$SB_TMP/glint_cycles.exr" \
    "$scale" 0.003 Cycles >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/cmp.err")
sed "s/^/glint: /" "$SB_TMP/cmp.out"
check_rc glint.compare 0

# Inside Blender: maps, markers, normal maps, half rounding.
check_in_blender glint "$SB_TMP/glint" --normal-map --waves
check_in_blender glint_k1 "$SB_TMP/glint_k1" --markers
check_in_blender oblique "$SB_TMP/oblique" --markers
check_in_blender half "$SB_TMP/half" --half-of "$SB_TMP/glint/manifest.json" --normal-map

# Errors: exit status 1 and a message naming the file.
run_blender missing "$dir/seabake_import.py" -- "$SB_TMP/no-such/manifest.json"
check_rc import.missing.rc 1
check_match import.missing.msg "$(cat "$SB_TMP/missing.out")" \
    'seabake_import: error: .*no-such/manifest.json: cannot read'
sed 's/"version":[[:space:]]*1,/"version": 99,/' "$dir/manifest.json" >"$dir/v99.json"
check_match import.version.edit "$(cat "$dir/v99.json")" '"version": 99,'
run_blender version "$dir/seabake_import.py" -- "$dir/v99.json"
check_rc import.version.rc 1
check_match import.version.msg "$(cat "$SB_TMP/version.out")" \
    'seabake_import: error: .*v99.json: manifest version 99'
printf '{"format": "something-else", "version": 1}\n' >"$dir/other.json"
run_blender format "$dir/seabake_import.py" -- "$dir/other.json"
check_rc import.format.rc 1
check_match import.format.msg "$(cat "$SB_TMP/format.out")" \
    'seabake_import: error: .*other.json: not a seabake bake manifest'
mv "$dir/normal_0.exr" "$dir/moved.exr"
run_blender no_map "$dir/seabake_import.py" -- "$dir/manifest.json"
check_rc import.no_map.rc 1
check_match import.no_map.msg "$(cat "$SB_TMP/no_map.out")" \
    'seabake_import: error: .*normal_0.exr: map not found'
mv "$dir/moved.exr" "$dir/normal_0.exr"
for f in sensor.exr height_0.exr; do
    mv "$dir/$f" "$dir/moved.exr"
    run_blender "no_$f" "$dir/seabake_import.py" -- "$dir/manifest.json"
    check_rc "import.no_$f.rc" 1
    check_match "import.no_$f.msg" "$(cat "$SB_TMP/no_$f.out")" \
        "seabake_import: error: .*$f: map not found"
    mv "$dir/moved.exr" "$dir/$f"
done

# A map outside the manifest's directory (issue 40, item 7): a name with
# ../, an absolute path elsewhere and a link inside the directory that
# points out of it are refused, though the file exists and is a good map.
cp "$dir/normal_0.exr" "$SB_TMP/outside.exr"
ln -s "$SB_TMP/outside.exr" "$dir/link.exr"
n=0
for name in ../outside.exr "$SB_TMP/outside.exr" link.exr; do
    n=$((n + 1))
    sed "s#\"normal_0.exr\"#\"$name\"#" "$dir/manifest.json" >"$dir/outside_$n.json"
    run_blender "outside_$n" "$dir/seabake_import.py" -- "$dir/outside_$n.json"
    check_rc "import.outside_$n.rc" 1
    check_match "import.outside_$n.msg" "$(cat "$SB_TMP/outside_$n.out")" \
        "seabake_import: error: .*outside_$n.json: map '.*$(basename "$name")' lies outside the manifest's directory"
    rm -f "$dir/outside_$n.json"
done
rm -f "$dir/link.exr" "$SB_TMP/outside.exr"

# The import's one-line summary.
check_match import.summary "$(cat "$SB_TMP/import.out")" \
    '^seabake_import: 1 ring \(1 with waves\) and the horizon mesh \([0-9]+ x [0-9]+ nodes\) of 2 levels, the sensor.s image projected where it sees, frame 0, material emission, emission scale [0-9.e+-]+$'

# An animation: bake --frames 0:7 --blender at 2 frames per second, imported
# as image sequences (the scene's frame range 0..7 at 2 fps), every frame
# rendered by Cycles after frame_set (--render-frames) and compared with
# seabake render of that frame: relative RMS below 1 % (the issue's bound;
# 0.04 % measured with each frame's sensor image, 0.70-0.75 % with the maps
# alone).  A frame against another frame's
# render must fail that bound (0.23 measured), or the check could not tell
# frames apart.  --frame 9 (not baked) is an error naming the range.
# Under valgrind (seabake's runs only) three frames, 0:2.
fscene="$top_srcdir/tests/scenes/pov_glint.ini"
fdir="$SB_TMP/frames"
LAST=7
[ -n "$SEABAKE_WRAPPER" ] && LAST=2
SB_CMD="seabake render $fscene --frames 0:$LAST --frame-rate 2"
$SEABAKE_WRAPPER "$SEABAKE" render "$fscene" -o "$SB_TMP/fref.exr" --aov level --png none \
    --frames 0:$LAST --frame-rate 2 --quiet 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc frames.render.rc 0
SB_CMD="seabake bake $fscene --blender --frames 0:$LAST --frame-rate 2"
$SEABAKE_WRAPPER "$SEABAKE" bake "$fscene" -o "$fdir" --blender --frames 0:$LAST --frame-rate 2 \
    --quiet 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc frames.bake.rc 0
run_blender frames "$fdir/seabake_import.py" -- "$fdir/manifest.json" \
    --render-frames "$SB_TMP/cy_####.exr" --save "$SB_TMP/frames.blend"
check_rc frames.import.rc 0
check_match frames.summary "$(cat "$SB_TMP/frames.out")" \
    "^seabake_import: .*, frames 0 to $LAST at 2 Hz \\(now 0\\), material emission,"
fscale=$(sed -n 's/^[[:space:]]*"emission_scale":[[:space:]]*\([0-9.eE+-]*\),*$/\1/p' \
    "$fdir/manifest.json")
# cycles_frame NAME FRAME_IMAGE FRAME: pov_driver compare against render frame FRAME.
cycles_frame() {
    SB_CMD="pov_driver compare $2 (render frame $3) Cycles"
    "$POV_DRIVER" compare "$SB_TMP/fref_000$3.exr" "$SB_TMP/fref_000$3.level.exr" "$2" \
        "$fscale" 0.01 Cycles >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed -n "1s/^/$1: /p" "$SB_TMP/cmp.out"
}
for f in $(seq 0 "$LAST"); do
    cycles_frame "frames.$f" "$SB_TMP/cy_000$f.exr" "$f"
    check_rc "frames.$f.compare" 0
done
cycles_frame frames.last_against_0 "$SB_TMP/cy_000$LAST.exr" 0
check_rc frames.last_against_0.differs 1
# Each frame's waves: the import's meshes after frame_set against that
# frame's height samples (the Displace modifier reads the sequence).
check_in_blender frames "$fdir" --waves
run_blender frames_bad "$fdir/seabake_import.py" -- "$fdir/manifest.json" --frame 9
check_rc frames.bad_frame.rc 1
check_match frames.bad_frame.msg "$(cat "$SB_TMP/frames_bad.out")" \
    "seabake_import: error: .*manifest.json: frame 9 was not baked \\(frames 0 to $LAST\\)"

# The visible material: a Sun lamp where [sun] is (30 deg from the zenith,
# azimuth 200 deg: its glint lies in this nadir view), a sky and 64 samples.
# Seabake's glint at 4 um covers hundreds of pixels here; Cycles' glint of
# the lamp on the GGX roughness must too: over 100 pixels above 3 times the
# median (the sky alone, reflected at about 2 % by water near nadir, is
# uniform within far less; measured: median 0.029, 1 % of the pixels above
# 0.16, peak 0.23), and the sea elsewhere is lit by the sky (median above
# 0.005).
run_blender visible "$SB_TMP/glint_k1/seabake_import.py" -- "$SB_TMP/glint_k1/manifest.json" \
    --material visible --render "$SB_TMP/visible.exr"
check_rc visible.rc 0
check_match visible.summary "$(cat "$SB_TMP/visible.out")" \
    '^seabake_import: .*material visible, sun at 30\.0 deg from zenith,'
"$POV_DRIVER" dump "$SB_TMP/visible.exr" "$SB_TMP/visible.raw" >/dev/null 2>&1
check visible.dump test -s "$SB_TMP/visible.raw"
SB_CMD="visible render: glint pixels and median"
SB_ERR=$(od -An -v -f -w16 "$SB_TMP/visible.raw" | awk '{ print $2 }' | sort -g |
    awk '{ v[NR] = $1 }
        END { med = v[int(NR / 2)]
              for (i = 1; i <= NR; i++) if (v[i] > 3 * med) hi++
              printf "%d of %d pixels above 3 x the median %.4f, max %.4f", hi, NR, med, v[NR]
              exit !(hi > 100 && med > 0.005) }')
SB_RC=$?
echo "visible: $SB_ERR"
check_rc visible.lit 0

# The round-Earth mast view in Blender (tests/scenes/pov_horizon.ini, as
# tests/povray.sh): Cycles against seabake render.  Under valgrind the
# horizon is refined to 1e-2.
hscene="$top_srcdir/tests/scenes/pov_horizon.ini"
htol=()
[ -n "$SEABAKE_WRAPPER" ] && htol=(--set model.tolerance=1e-2)
sb_run render "$hscene" -o "$SB_TMP/href.exr" --aov level --png none --quiet "${htol[@]}"
check_rc horizon.render.rc 0
# horizon_run NAME MAX MAX_BELOW_HORIZON [BAKE OPTIONS]
horizon_run() {
    local name=$1 max=$2 hmax=$3 hdir="$SB_TMP/$1" hscale
    shift 3
    sb_run bake "$hscene" -o "$hdir" --blender --quiet "${htol[@]}" "$@"
    check_rc "$name.bake.rc" 0
    check_match "$name.manifest" "$(cat "$hdir/manifest.json")" '"horizon":'
    run_blender "$name" "$hdir/seabake_import.py" -- "$hdir/manifest.json" \
        --render "$SB_TMP/${name}_cycles.exr"
    check_rc "$name.import.rc" 0
    check_match "$name.summary" "$(cat "$SB_TMP/$name.out")" \
        '^seabake_import: [0-9]+ rings( \([0-9]+ with waves\))? and the horizon mesh \([0-9]+ x [0-9]+ nodes\)'
    check_no_match "$name.no_flat_warning" "$(cat "$SB_TMP/$name.out")" 'this import is flat'
    hscale=$(sed -n 's/^[[:space:]]*"emission_scale":[[:space:]]*\([0-9.eE+-]*\),*$/\1/p' \
        "$hdir/manifest.json")
    SB_CMD="pov_driver compare ($name) Cycles"
    "$POV_DRIVER" compare "$SB_TMP/href.exr" "$SB_TMP/href.level.exr" \
        "$SB_TMP/${name}_cycles.exr" "$hscale" "$max" Cycles "$hmax" >"$SB_TMP/cmp.out" \
        2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed "s/^/$name: /" "$SB_TMP/cmp.out"
    check_rc "$name.compare" 0
}
# The default import (the sensor's image projected where the sensor sees):
# the issue's bounds, 1 % over the image and 2 % over the 10 sea rows below
# the horizon (0.09 % and 0.04 % measured).
horizon_run horizon 0.01 0.02
check_match horizon.projected "$(cat "$SB_TMP/horizon.out")" \
    "^seabake_import: .* the sensor's image projected where it sees,"
# Six levels of waves, the finer ones cut out, skirts at every edge.
check_in_blender horizon "$SB_TMP/horizon" --waves
# The maps alone: the horizon mesh (on the sphere, the map of low-resolution
# radiances) with the bounds of tests/povray.sh (low-resolution pixels 2 %,
# the 10 rows below the horizon 2 %, the image 5 %; measured as POV-Ray's,
# 0.99 %, 1.63 %, 3.3 %).
horizon_run horizon_maps 0.05 0.02 --emission-space map
lr_rms=$(sed -n 's/^  pixels of the .* m level: [0-9]*, relative RMS \([0-9.e+-]*\),.*/\1/p' \
    "$SB_TMP/cmp.out" | tail -n 1)
num_check horizon.low_res 'r < 0.02' "r=${lr_rms:-nan}"
check_no_match horizon_maps.not_projected "$(cat "$SB_TMP/horizon_maps.out")" 'projected'

# The sky and the air (issue 45; tests/scenes/pov_horizon_sky.ini, as
# tests/povray.sh): the World's sky by the ray's zenith cosine (an image of
# the manifest's blender.sky_table), the emission maps and the horizon map
# with the air along each point's range.  The issue's bounds, 1 % over the
# image and 2 % over the 10 sea rows below the horizon, with the sensor's
# image projected (2.5e-5 and 3.0e-5 measured) and with the maps alone
# (1.6e-4 and 2.3e-4); the sky's pixels within 1e-3 RMS (3.2e-5 measured;
# its largest, 1.4e-3, is a horizon pixel whose samples also meet the
# sea) of a sky whose radiance spreads 29 % over them (more than 5 %
# required, or one value everywhere would pass).
hscene="$top_srcdir/tests/scenes/pov_horizon_sky.ini"
sb_run render "$hscene" -o "$SB_TMP/href.exr" --aov level --png none --quiet "${htol[@]}"
check_rc sky.render.rc 0
for name in sky sky_maps; do
    if [ "$name" = sky ]; then
        horizon_run sky 0.01 0.02
    else
        horizon_run sky_maps 0.01 0.02 --emission-space map
    fi
    line=$(sed -n 's/^  the sky: [0-9]* pixels, relative RMS \([0-9.e+-]*\), max [0-9.e+-]*, spread \([0-9.e+-]*\)$/\1 \2/p' \
        "$SB_TMP/cmp.out")
    set -- $line
    num_check "$name.sky_rms" 'r < 1e-3' "r=${1:-nan}"
    num_check "$name.sky_spread" 's > 0.05' "s=${2:-0}"
done
check_match sky.manifest_table "$(cat "$SB_TMP/sky/manifest.json")" '"sky_table":'

end_all=$(date +%s.%N)
secs=$(awk -v a="$start_all" -v b="$end_all" 'BEGIN { printf "%.1f", b - a }')
echo "blender: whole test took $secs s"
finish
