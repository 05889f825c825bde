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
#   - the add-on (issue 45): make's seabake-blender.zip (its files, bl_info,
#     blender_manifest.toml, rebuilt byte for byte), installed, enabled and
#     run from File > Import by tests/blender_addon.py in a scratch user
#     directory: its render against seabake render (0.3 %) and equal to the
#     script's, and each option's effect (projection off, one frame against
#     all, levels up to 0, the visible material, a frame not baked refused).
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
# The import's choices: --single-frame (frame 1's files alone, the scene's
# range that frame), --max-level 0 (the finest ring alone, no horizon mesh)
# and --no-projection (the sensor's image not projected), in the summary.
run_blender frames_one "$fdir/seabake_import.py" -- "$fdir/manifest.json" --frame 1 \
    --single-frame --max-level 0 --no-projection
check_rc frames.choices.rc 0
check_match frames.choices.summary "$(cat "$SB_TMP/frames_one.out")" \
    '^seabake_import: 1 ring \(1 with waves\) of 2 levels, frame 1, material emission,'
run_blender frames_level "$fdir/seabake_import.py" -- "$fdir/manifest.json" --max-level -1
check_rc frames.bad_level.rc 1
check_match frames.bad_level.msg "$(cat "$SB_TMP/frames_level.out")" \
    'seabake_import: error: .*manifest.json: no level of index -1 or finer \(levels \[0, 7\]\)'

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

# The add-on (issue 45): make's seabake-blender.zip holds seabake/ with
# __init__.py (bl_info, Blender 3.4), the import script byte for byte and
# blender_manifest.toml (Blender 4.2+), and is reproducible (rebuilt from
# copies of the sources dated otherwise, under another umask: the same
# bytes).
: "${BLENDER_ADDON:?BLENDER_ADDON must name the built seabake-blender.zip}"
PY=${PYTHON3:-python3}
ADDON_PY="$top_srcdir/tests/blender_addon.py"
check addon.zip test -s "$BLENDER_ADDON"
SB_CMD="$PY zipfile $BLENDER_ADDON"
SB_ERR=
check_eq addon.zip.names "$("$PY" -c 'import sys, zipfile
print(" ".join(zipfile.ZipFile(sys.argv[1]).namelist()))' "$BLENDER_ADDON")" \
    "seabake/__init__.py seabake/seabake_import.py seabake/blender_manifest.toml"
"$PY" -c 'import sys, zipfile
sys.stdout.buffer.write(zipfile.ZipFile(sys.argv[1]).read("seabake/seabake_import.py"))' \
    "$BLENDER_ADDON" >"$SB_TMP/zip_import.py"
check addon.zip.script cmp -s "$SB_TMP/zip_import.py" \
    "$top_srcdir/exporters/blender/seabake_import.py"
# bl_info as Blender reads it (a literal) and the manifest as TOML.
meta=$("$PY" -c 'import ast, sys, tomllib, zipfile
z = zipfile.ZipFile(sys.argv[1])
tree = ast.parse(z.read("seabake/__init__.py"))
info = next(ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
            and getattr(n.targets[0], "id", "") == "bl_info")
t = tomllib.loads(z.read("seabake/blender_manifest.toml").decode())
print("bl_info %s %s %s %s %s %s" % (".".join(map(str, info["version"])),
      ".".join(map(str, info["blender"])), info["author"], info["location"],
      info["category"], info["name"]))
print("toml %s %s %s %s %s %s %s [%s]" % (t["schema_version"], t["id"], t["version"], t["type"],
      t["blender_version_min"], t["maintainer"], " ".join(t["license"]), t["permissions"]["files"]))
' "$BLENDER_ADDON" 2>&1)
echo "$meta" | sed 's/^/addon: /'
check_match addon.bl_info "$meta" \
    "^bl_info $PACKAGE_VERSION 3\.4\.0 seabake File > Import Import-Export seabake"
check_match addon.toml "$meta" \
    "^toml 1\.0\.0 seabake $PACKAGE_VERSION add-on 4\.2\.0 seabake SPDX:$ADDON_LICENSE \[reads seabake bake directories\]$"
mkdir -p "$SB_TMP/addon_src/addon"
cp "$top_srcdir/exporters/blender/seabake_import.py" "$SB_TMP/addon_src/"
cp "$top_srcdir/exporters/blender/addon/__init__.py.in" \
    "$top_srcdir/exporters/blender/addon/blender_manifest.toml.in" "$SB_TMP/addon_src/addon/"
touch -d '2001-02-03 04:05:06' "$SB_TMP"/addon_src/*.py "$SB_TMP"/addon_src/addon/*
SB_CMD="make_addon.py (again)"
(umask 077 && "$PY" "$top_srcdir/exporters/blender/make_addon.py" "$SB_TMP/again.zip" \
    "$PACKAGE_VERSION" "$ADDON_LICENSE" "$SB_TMP/addon_src") 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc addon.zip.again 0
check addon.zip.reproducible cmp -s "$SB_TMP/again.zip" "$BLENDER_ADDON"

# run_addon NAME MANIFEST ARGS...: tests/blender_addon.py in headless Blender
# with a user configuration and scripts directory of its own (never
# ~/.config): installs and enables the zip, runs File > Import > seabake bake
# on MANIFEST with the operator options ARGS (and --render OUT.exr), disables.
run_addon() {
    local name=$1 user="$SB_TMP/bl_$1"
    shift
    mkdir -p "$user"
    SB_CMD="blender -b --factory-startup --python blender_addon.py -- $BLENDER_ADDON $*"
    BLENDER_USER_CONFIG="$user/config" BLENDER_USER_SCRIPTS="$user/scripts" \
        blender -b --factory-startup --python-exit-code 1 --python "$ADDON_PY" -- \
        "$BLENDER_ADDON" "$@" >"$SB_TMP/$name.out" 2>&1
    SB_RC=$?
    SB_ERR=$(grep -E 'FAIL|rror' "$SB_TMP/$name.out" | head -n 5)
    grep -E '^(FAIL|scene|images|objects|materials|projection|blender_addon):' \
        "$SB_TMP/$name.out" | sed "s/^/$name: /"
}
# addon_compare NAME IMAGE REF LEVELS SCALE MAX: pov_driver compare.
addon_compare() {
    SB_CMD="pov_driver compare $2 against $3, max $6"
    "$POV_DRIVER" compare "$3" "$4" "$2" "$5" "$6" Cycles >"$SB_TMP/cmp.out" \
        2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed -n "1s/^/$1: /p" "$SB_TMP/cmp.out"
}

# The default options on the nadir bake: installed, enabled, in File >
# Import, imported into a new scene (the startup scene keeps its cube), the
# script's own summary, and Cycles' render against seabake render within the
# script's bound (0.3 %); its pixels are those of the script's --render
# above, exactly: the operator runs the same code.
run_addon addon "$dir/manifest.json" --render "$SB_TMP/addon_cycles.exr"
check_rc addon.rc 0
check_match addon.summary "$(cat "$SB_TMP/addon.out")" \
    '^seabake_import: 1 ring \(1 with waves\) and the horizon mesh \([0-9]+ x [0-9]+ nodes\) of 2 levels, the sensor.s image projected where it sees, frame 0, material emission, emission scale [0-9.e+-]+$'
check_match addon.new_scene "$(cat "$SB_TMP/addon.out")" \
    '^ok: imported into a new scene, glint, shown in the window$'
check_match addon.projected "$(cat "$SB_TMP/addon.out")" '^projection: 2 of 2 emission materials$'
check_eq addon.no_home_config "$(find "$HOME" -name 'seabake*' | wc -l)" 0
addon_compare addon.compare "$SB_TMP/addon_cycles.exr" "$SB_TMP/ref.exr" \
    "$SB_TMP/ref.level.exr" "$scale" 0.003
check_rc addon.compare 0
"$POV_DRIVER" dump "$SB_TMP/addon_cycles.exr" "$SB_TMP/addon_cycles.raw" >/dev/null 2>&1
"$POV_DRIVER" dump "$SB_TMP/glint_cycles.exr" "$SB_TMP/glint_cycles.raw" >/dev/null 2>&1
check addon.same_pixels_as_script cmp -s "$SB_TMP/addon_cycles.raw" "$SB_TMP/glint_cycles.raw"

# Sensor projection off: no emission material projects the sensor's image,
# and the render is the emission maps alone on the waves: the sea still
# (within 5 %, tests/povray.sh's bound for the maps alone over an image;
# 2.4 % measured) but outside the projection's 0.3 % (0.037 % projected).
run_addon addon_noproj "$dir/manifest.json" projection=0 --render "$SB_TMP/noproj.exr"
check_rc addon_noproj.rc 0
check_match addon_noproj.materials "$(cat "$SB_TMP/addon_noproj.out")" \
    '^projection: 0 of 2 emission materials$'
check_no_match addon_noproj.summary "$(cat "$SB_TMP/addon_noproj.out")" 'projected'
addon_compare addon_noproj.compare "$SB_TMP/noproj.exr" "$SB_TMP/ref.exr" \
    "$SB_TMP/ref.level.exr" "$scale" 0.05
check_rc addon_noproj.compare 0
addon_compare addon_noproj.not_projected "$SB_TMP/noproj.exr" "$SB_TMP/ref.exr" \
    "$SB_TMP/ref.level.exr" "$scale" 0.003
check_rc addon_noproj.not_projected 1

# Frames: All loads the 8-frame bake as image sequences over the baked
# range; One (frame ONE) that frame's files alone as still images, the
# scene's range that frame, and its render is seabake render's frame ONE
# within the frames' 1 %, and not frame 0's.
ONE=$((LAST - 1))
run_addon addon_all "$fdir/manifest.json"
check_rc addon_all.rc 0
check_match addon_all.scene "$(cat "$SB_TMP/addon_all.out")" "^scene: frames, frames 0 to $LAST, current 0$"
check_match addon_all.sequences "$(cat "$SB_TMP/addon_all.out")" '^images: ([0-9]+), \1 sequences$'
run_addon addon_one "$fdir/manifest.json" frames=ONE frame=$ONE --render "$SB_TMP/one.exr"
check_rc addon_one.rc 0
check_match addon_one.scene "$(cat "$SB_TMP/addon_one.out")" "^scene: frames, frames $ONE to $ONE, current $ONE$"
check_match addon_one.stills "$(cat "$SB_TMP/addon_one.out")" '^images: [1-9][0-9]*, 0 sequences$'
cycles_frame addon_one.compare "$SB_TMP/one.exr" "$ONE"
check_rc addon_one.compare 0
cycles_frame addon_one.against_0 "$SB_TMP/one.exr" 0
check_rc addon_one.against_0.differs 1
run_addon addon_bad "$fdir/manifest.json" frames=ONE frame=9 \
    --expect-error 'seabake_import: error: .*manifest.json: frame 9 was not baked'
check_rc addon_bad.rc 0

# Levels up to 0: the finest ring alone, no horizon mesh; the visible
# material: the Visible materials active.
run_addon addon_levels "$dir/manifest.json" levels=UP_TO max_level=0
check_rc addon_levels.rc 0
check_match addon_levels.objects "$(cat "$SB_TMP/addon_levels.out")" '^objects: seabake_level_0$'
check_match addon_levels.summary "$(cat "$SB_TMP/addon_levels.out")" \
    '^seabake_import: 1 ring \(1 with waves\) of 2 levels,'
run_addon addon_visible "$dir/manifest.json" material=visible
check_rc addon_visible.rc 0
check_match addon_visible.materials "$(cat "$SB_TMP/addon_visible.out")" \
    '^materials: seabake_visible_7 seabake_visible_0$'

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
