#!/bin/bash
# povray.sh - end-to-end test of the POV-Ray export (issue 5): a scene
# written by sea_pov_write (exporters/povray.h) is rendered by the real
# povray (+FE, half floats) and compared with seabake's own render.
#
# tests/pov_driver exports scenes of uniform radiance (tests/scenes/
# pov_*.ini: every sea pixel emits B(T)) with markers (single texels of
# distinct values) in the finest level's map and the sky at half its value,
# then checks POV-Ray's image: every other pixel within half-float precision
# (4.9e-4 relative) of seabake render (so no gap or seam between rings, and
# sea and sky where seabake has them), every marker within 1 px of
# sea_camera_project's position.
# Skips (exit 77) only when povray is not installed.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=povray
. "$(dirname "$0")/lib.sh"

: "${top_srcdir:?top_srcdir must name the source directory}"
# The driver is a check program built next to the program's directory.
POV_DRIVER=${POV_DRIVER:-$(dirname "$SEABAKE")/../tests/pov_driver}

if ! have povray povray; then
    # Under scripts/test an absent povray has failed a check: finish says so.
    [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ] && finish
    exit 77 # (have printed the SKIP line)
fi
if [ ! -x "$POV_DRIVER" ]; then
    echo "povray: $POV_DRIVER is missing (make check builds it)" >&2
    exit 99
fi

# POV-Ray complains, harmlessly, when it has no user configuration file.
export HOME="$SB_TMP/home"
mkdir -p "$HOME/.povray/3.7"
: >"$HOME/.povray/3.7/povray.conf"

# povray_render NAME DIR: renders DIR/scene.ini with the real povray into
# DIR/scene.exr, checks it ran, prints its time.
povray_render() {
    local name=$1 dir=$2 start end
    SB_CMD="(cd $dir && povray scene.ini)"
    start=$(date +%s.%N)
    (cd "$dir" && povray scene.ini) >"$SB_TMP/pov.out" 2>&1
    SB_RC=$?
    end=$(date +%s.%N)
    SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
    check_rc "$name.povray.rc" 0
    check "$name.povray.output" test -s "$dir/scene.exr"
    echo "$name: povray render took $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }') s"
}

# pov_run NAME: exports tests/scenes/pov_NAME.ini, renders it, compares.
# The largest relative difference over the whole image in a compare report.
image_max() {
    sed -n 's/^  the whole image: [0-9]* pixels, relative RMS [0-9.e+-]*, max \([0-9.e+-]*\)$/\1/p' \
        "$1"
}

pov_run() {
    local name=$1 scene="$top_srcdir/tests/scenes/pov_$1.ini" dir="$SB_TMP/$1" rc f
    mkdir -p "$dir"
    SB_CMD="pov_driver export $scene $dir"
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$POV_DRIVER" export "$scene" "$dir" >"$SB_TMP/export.out" 2>"$SB_TMP/export.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/export.err")
    check_rc "$name.export.rc" 0
    for f in scene.pov sea.inc scene.ini seabake.inc level_0.exr; do
        check "$name.export.$f" test -s "$dir/$f"
    done
    check_eq "$name.export.no_temp" "$(find "$dir" -name '*.tmp.*' | wc -l)" 0
    check "$name.export.inc_copy" cmp -s "$dir/seabake.inc" "$top_srcdir/exporters/povray/seabake.inc"
    check_match "$name.export.scale" "$(cat "$dir/sea.inc")" \
        '^#declare Seabake_Radiance_Scale = [0-9.e+-]+;'
    check_match "$name.export.ini" "$(cat "$dir/scene.ini")" '^Output_File_Type=E'

    povray_render "$name" "$dir"

    SB_CMD="pov_driver check $scene $dir"
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$POV_DRIVER" check "$scene" "$dir" >"$SB_TMP/check.out" 2>"$SB_TMP/check.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/check.err")
    sed "s/^/$name: /" "$SB_TMP/check.out"
    check_rc "$name.compare" 0
}

# A nadir view: one high-resolution ring and the low-resolution one.
pov_run nadir
# An oblique view with roll: six high-resolution rings (windows not nested),
# the horizon and sky pixels.
pov_run oblique

# The real export: seabake bake --pov of a scene rendered by POV-Ray against
# seabake render of the same scene.  By default the sea shows the sensor's
# image projected from the sensor where it sees (sensor.exr), so the view
# from Seabake_Camera is the render's.  With --emission-space map the rings
# show their emission maps alone: what the sensor sees (what seabake render
# shows along the ray through each point) on 3 x 3 texels per facet; what is
# left is POV-Ray's bilinear lookup of a radiance that varies within a facet
# (the waves' slope under each ray), and at the oblique view its flat rings
# against the waves seabake render meets (0.75 % nadir, 1.7 % oblique when
# measured; 0.23 % and 0.61 % when seabake read the moments under the
# mean-surface point).
# bake_run NAME SCENE MAX [BAKE OPTIONS]: relative RMS below MAX over the
# sea and over the whole image.  With the sensor's image projected (the
# default, --emission-space sensor) every pixel is the render's value
# through two half-float roundings (POV-Ray's map and its +FE output):
# within 1e-3 (4.9e-4 each), checked on the largest difference.
# The reference render is made once per scene (the runs of one scene
# follow each other).
ref_scene=""
bake_run() {
    local name=$1 scene=$2 max=$3 dir="$SB_TMP/bake_$1" scale
    shift 3
    if [ "$scene" != "$ref_scene" ]; then
        sb_run render "$scene" -o "$SB_TMP/ref.exr" --aov level --png none --quiet
        check_rc "$name.render.rc" 0
        ref_scene=$scene
    fi
    sb_run bake "$scene" -o "$dir" --pov --quiet "$@"
    check_rc "$name.bake.rc" 0
    for f in scene.pov sea.inc scene.ini seabake.inc manifest.json emission_0.exr; do
        check "$name.bake.$f" test -s "$dir/$f"
    done
    povray_render "$name" "$dir"
    scale=$(sed -n 's/^#declare Seabake_Radiance_Scale = \(.*\);/\1/p' "$dir/sea.inc")
    SB_CMD="pov_driver compare"
    "$POV_DRIVER" compare "$SB_TMP/ref.exr" "$SB_TMP/ref.level.exr" "$dir/scene.exr" "$scale" "$max" \
        >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed "s/^/$name: /" "$SB_TMP/cmp.out"
    check_rc "$name.compare" 0
    case " $* " in
    *" --emission-space map "*) ;;
    *)
        local mx
        mx=$(image_max "$SB_TMP/cmp.out")
        num_check "$name.every_pixel" 'r < 1e-3' "r=${mx:-nan}"
        ;;
    esac
}

# Nadir, the sun (30 deg) in the glint, a 250 K sky: one ring and the
# low-resolution one.  The issue's bound 0.3 % with the sensor's image; the
# maps alone within 2 %.
bake_run bake_nadir "$top_srcdir/tests/scenes/pov_glint.ini" 0.003
bake_run bake_nadir_maps "$top_srcdir/tests/scenes/pov_glint.ini" 0.02 --emission-space map
# 70 deg from nadir toward the sun (40 deg): three high-resolution rings
# whose windows overlap rather than nest, so a point inside a finer ring is
# read by seabake render at a coarser level.  The issue's bound 0.7 % with
# the sensor's image; the maps alone within 2 %.
bake_run bake_slant "$top_srcdir/tests/scenes/pov_slant.ini" 0.007
bake_run bake_slant_maps "$top_srcdir/tests/scenes/pov_slant.ini" 0.02 --emission-space map

# The waves of the default export (the oblique bake above): each level's
# height field (height_<l>.png, 4 samples per facet side) against the
# surface seabake render marches, probed by POV-Ray's trace straight down
# (pov_driver heights): at the samples within 1e-4 m (the PNG's 16 bits
# over the level's range of about 3 m: 2.5e-5 m; 5.3e-5 measured), between
# them within 2 cm (the height field's triangles against the render's
# bicubic patches a quarter facet apart: 6.9 mm measured on 1 m facets).
sdir="$SB_TMP/bake_bake_slant"
sscene="$top_srcdir/tests/scenes/pov_slant.ini"
check_match slant.waves "$(cat "$sdir/sea.inc")" '#declare Seabake_Height_0 = height_field'
check slant.waves.png test -s "$sdir/height_0.png"
SB_CMD="pov_driver heights $sscene $sdir 4"
SB_ERR=$("$POV_DRIVER" heights "$sscene" "$sdir" 4 2>&1)
SB_RC=$?
check_rc slant.heights.probe 0
SB_CMD="(cd $sdir && povray +Iprobe.pov -D +W1 +H1)"
(cd "$sdir" && povray +Iprobe.pov -D +W1 +H1) >"$SB_TMP/pov.out" 2>&1
SB_RC=$?
SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
check_rc slant.heights.povray 0
hline=$(grep '^heights:' "$SB_TMP/pov.out")
echo "slant: $hline"
set -- $(echo "$hline" | sed -n 's/^heights: nodes \([0-9.e+-]*\) m, points \([0-9.e+-]*\) m, misses \([0-9]*\)$/\1 \2 \3/p')
num_check slant.heights.nodes 'r < 1e-4' "r=${1:-nan}"
num_check slant.heights.points 'r < 0.02' "r=${2:-nan}"
check_eq slant.heights.misses "${3:-none}" 0
# The finest level's map on its waves, seen straight down by an orthographic
# camera with a pixel on every emission texel and the sensor's image off
# (Seabake_Use_Sensor): the map itself (Seabake_Emission_Plane's planar
# projection, north up), within one half-float rounding.
set -- $(sed -n 's|^// level 0: facets of [0-9.e+-]* m, rectangle \[\([0-9.e+-]*\), \([0-9.e+-]*\)\] x \[\([0-9.e+-]*\), \([0-9.e+-]*\)\].*|\1 \2 \3 \4|p' "$sdir/sea.inc")
printf '%s\n' '#version 3.7;' 'global_settings { assumed_gamma 1.0 }' \
    '#declare Seabake_Use_Sensor = off;' '#include "sea.inc"' \
    "camera { orthographic location <($1 + $2) / 2, 1e4, ($3 + $4) / 2> direction <0, -1, 0>" \
    "         right <$2 - ($1), 0, 0> up <0, 0, $4 - ($3)> }" 'object { Seabake_Sea }' \
    >"$sdir/ortho.pov"
msize=$("$POV_DRIVER" dump "$sdir/emission_0.exr" "$SB_TMP/e0.raw" 2>/dev/null)
check_match slant.ortho.size "$msize" '^[0-9]+ [0-9]+ 1$'
set -- $msize
SB_CMD="(cd $sdir && povray scene.ini +Iortho.pov +Oortho.exr +W$1 +H$2)"
(cd "$sdir" && povray scene.ini +Iortho.pov +Oortho.exr "+W$1" "+H$2") >"$SB_TMP/pov.out" 2>&1
SB_RC=$?
SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
check_rc slant.ortho.rc 0
SB_CMD="pov_driver same ortho.exr emission_0.exr 1e-3"
SB_ERR=$("$POV_DRIVER" same "$sdir/ortho.exr" "$sdir/emission_0.exr" 1e-3 2>&1)
SB_RC=$?
echo "slant: ortho: $SB_ERR"
check_rc slant.ortho.same 0

# A mast view of a round Earth (tests/scenes/pov_horizon.ini: 20 m, 88 deg,
# a low sun ahead): the low-resolution sea is the horizon mesh, on the
# sphere out to the horizon, its map the radiance a low-resolution pixel
# has at each node.  Under valgrind the horizon is refined to 1e-2 instead
# of 1e-3, to keep the run short.
hscene="$top_srcdir/tests/scenes/pov_horizon.ini"
htol=()
[ -n "$SEABAKE_WRAPPER" ] && htol=(--set model.tolerance=1e-2)
sb_run render "$hscene" -o "$SB_TMP/href.exr" --aov level --png none --quiet "${htol[@]}"
check_rc horizon.render.rc 0
# horizon_run NAME MAX MAX_BELOW_HORIZON [BAKE OPTIONS]
horizon_run() {
    local name=$1 max=$2 hmax=$3 hdir="$SB_TMP/$1" hscale
    shift 3
    sb_run bake "$hscene" -o "$hdir" --pov --quiet "${htol[@]}" "$@"
    check_rc "$name.bake.rc" 0
    check "$name.map" test -s "$hdir/horizon.exr"
    check_match "$name.mesh" "$(cat "$hdir/sea.inc")" '#declare Seabake_Horizon = mesh2'
    povray_render "$name" "$hdir"
    hscale=$(sed -n 's/^#declare Seabake_Radiance_Scale = \(.*\);/\1/p' "$hdir/sea.inc")
    SB_CMD="pov_driver compare ($name)"
    "$POV_DRIVER" compare "$SB_TMP/href.exr" "$SB_TMP/href.level.exr" "$hdir/scene.exr" \
        "$hscale" "$max" POV-Ray "$hmax" >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed "s/^/$name: /" "$SB_TMP/cmp.out"
    check_rc "$name.compare" 0
}
# The default export (the sensor's image projected where the sensor sees):
# the issue's bounds, 1 % over the image and 2 % over the 10 sea rows below
# the horizon (2.0e-4 and 1.9e-4 measured), and every pixel within two
# half-float roundings.
horizon_run horizon 0.01 0.02
mx=$(image_max "$SB_TMP/cmp.out")
num_check horizon.every_pixel 'r < 1e-3' "r=${mx:-nan}"
check_match horizon.sensor_map "$(cat "$SB_TMP/horizon/sea.inc")" 'exr "sensor.exr"'
# The maps alone: the low-resolution pixels within 2 % RMS of seabake
# render (0.99 % measured, 0.09 % away from the high-resolution windows'
# edge; the one constant ring it replaces was 59.5 % off on
# examples/mast.ini), the 10 sea rows below the horizon within 2 % (1.63 %
# measured, mostly the high-resolution rings' flat geometry against the
# waves seabake render meets), the whole image within 5 % (3.3 % measured,
# the same cause).
horizon_run horizon_maps 0.05 0.02 --emission-space map
# the coarsest level in the report is the low-resolution one
lr_rms=$(sed -n 's/^  pixels of the .* m level: [0-9]*, relative RMS \([0-9.e+-]*\),.*/\1/p' \
    "$SB_TMP/cmp.out" | tail -n 1)
num_check horizon.low_res 'r < 0.02' "r=${lr_rms:-nan}"
check_no_match horizon_maps.no_sensor "$(cat "$SB_TMP/horizon_maps/sea.inc")" 'Seabake_Sensor'
# The default export seen by a camera of twice the sensor's field (its
# position and axes, half the focal length, as many pixels), with the
# sensor's image and without it (Seabake_Use_Sensor off: the maps alone, on
# the same waves): inside the sensor's view the projection (the 2 x 2 mean
# of sensor.exr at each pixel), outside it the maps, the same pixel for
# pixel (pov_driver wide).
hdir="$SB_TMP/horizon"
sed -n '/^#declare Seabake_Camera = camera {/,/^}/p' "$hdir/sea.inc" |
    sed 's/^#declare Seabake_Camera = camera {/camera {/; s/^  direction </  direction 0.5 * </' \
        >"$hdir/wide_camera.inc"
for mode in on off; do
    printf '%s\n' '#version 3.7;' 'global_settings { assumed_gamma 1.0 }' \
        "#declare Seabake_Use_Sensor = $mode;" '#include "sea.inc"' '#include "wide_camera.inc"' \
        'Seabake_Sky(Seabake_Sky_Radiance)' 'object { Seabake_Sea }' >"$hdir/wide_$mode.pov"
    SB_CMD="(cd $hdir && povray scene.ini +Iwide_$mode.pov +Owide_$mode.exr)"
    (cd "$hdir" && povray scene.ini "+Iwide_$mode.pov" "+Owide_$mode.exr") >"$SB_TMP/pov.out" 2>&1
    SB_RC=$?
    SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
    check_rc "horizon.wide_$mode.rc" 0
done
SB_CMD="pov_driver wide"
"$POV_DRIVER" wide "$hdir/sensor.exr" "$SB_TMP/href.level.exr" "$hdir/wide_on.exr" \
    "$hdir/wide_off.exr" >"$SB_TMP/cmp.out" 2>&1
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/cmp.out")
sed "s/^/horizon.wide: /" "$SB_TMP/cmp.out"
check_rc horizon.wide 0

# The sky and the air (issue 45): tests/scenes/pov_horizon_sky.ini, a small
# examples/horizon.ini (a clear sky of zenith emissivity 0.3, 0.5/km of air
# at 280 K over a 295 K sea, a 60 deg field reaching 14 deg above the
# horizon), baked with --pov --blender.  The sky is a sky_sphere by
# direction (sea.inc's color_map by s = sqrt(max(y, 0))), and the sea's
# emission maps and horizon map carry the air along each point's range to
# the sensor.  The issue's bounds, 1 % over the image and 2 % over the 10
# sea rows below the horizon, with the sensor's image projected (1.9e-4 and
# 1.8e-4 measured) and with the maps alone (2.7e-4 and 3.2e-4); the sky's
# pixels within two half-float roundings, 1e-3 (4.5e-4 measured), of a sky
# whose radiance spreads 29 % over them (more than 5 % required, or one
# radiance everywhere would pass).  The render of the same scene without
# the air (atmosphere.extinction = 0) must fail the maps' bounds (2.2 %
# over the sea, 4.6 % below the horizon measured), or the check could not
# tell the air from none.
# sky_check NAME: the sky's pixels in the last compare report.
sky_check() {
    local name=$1 line
    line=$(sed -n 's/^  the sky: [0-9]* pixels, relative RMS \([0-9.e+-]*\), max \([0-9.e+-]*\), spread \([0-9.e+-]*\)$/\1 \2 \3/p' \
        "$SB_TMP/cmp.out")
    set -- $line
    num_check "$name.sky_max" 'r < 1e-3' "r=${2:-nan}"
    num_check "$name.sky_spread" 's > 0.05' "s=${3:-0}"
}
hscene="$top_srcdir/tests/scenes/pov_horizon_sky.ini"
sb_run render "$hscene" -o "$SB_TMP/href.exr" --aov level --png none --quiet "${htol[@]}"
check_rc sky.render.rc 0
horizon_run sky 0.01 0.02 --blender
sky_check sky
check_match sky.sky_sphere "$(cat "$SB_TMP/sky/scene.pov")" \
    '^Seabake_Sky_Sphere\(Seabake_Sky_Pigment\)$'
check_match sky.manifest_table "$(cat "$SB_TMP/sky/manifest.json")" '"sky_table":'
horizon_run sky_maps 0.01 0.02 --emission-space map
sky_check sky_maps
sb_run render "$hscene" -o "$SB_TMP/noair.exr" --aov level --png none --quiet "${htol[@]}" \
    --set atmosphere.extinction=0
check_rc sky.noair.render.rc 0
SB_CMD="pov_driver compare (sky_maps against no air)"
"$POV_DRIVER" compare "$SB_TMP/noair.exr" "$SB_TMP/noair.level.exr" "$SB_TMP/sky_maps/scene.exr" \
    "$(sed -n 's/^#declare Seabake_Radiance_Scale = \(.*\);/\1/p' "$SB_TMP/sky_maps/sea.inc")" \
    0.01 POV-Ray 0.02 >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/cmp.err")
sed "s/^/sky_maps against no air: /" "$SB_TMP/cmp.out"
check_rc sky.noair.fails 1

# The same view with tables: a [sky] table (the clear model of zenith
# emissivity 0.25 at 282 K every degree, at 9.95 and 10.05 um) and an
# [atmosphere] table of a shape Beer-Lambert cannot give (tau = 1 / (1 +
# d / 2 km), path (1 - tau) B(280 K), every 100 m to 30 km), the maps
# alone: the same bounds (2.7e-4 over the image, 3.5e-4 below the horizon,
# the sky within 4.7e-4 measured; the sky's table in sea.inc within 4.4e-5
# of the zenith table's linear interpolation, whose kinks every degree it
# rounds).  B(l, T): Planck's radiance per um (l in m), the SI 2019 constants.
awk 'function B(l, T) { return 2 * 6.62607015e-34 * 299792458^2 / l^5 / (exp(6.62607015e-34 * 299792458 / (l * 1.380649e-23 * T)) - 1) * 1e-6 }
     BEGIN { print "zenith_deg,wavelength_um,radiance"
             for (w = 0; w < 2; w++) { l = w ? 10.05 : 9.95
                 for (z = 0; z <= 90; z++) { c = cos(z * 3.141592653589793 / 180)
                     printf "%d,%.6f,%.9g\n", z, l,
                         (z < 90 ? 1 - exp(log(0.75) / c) : 1) * B(l * 1e-6, 282) } } }' \
    >"$SB_TMP/tsky.csv"
awk 'function B(l, T) { return 2 * 6.62607015e-34 * 299792458^2 / l^5 / (exp(6.62607015e-34 * 299792458 / (l * 1.380649e-23 * T)) - 1) * 1e-6 }
     BEGIN { print "range_m,wavelength_um,transmittance,path_radiance"
             for (q = 0; q <= 300; q++) for (w = 0; w < 2; w++) {
                 l = w ? 10.05 : 9.95; d = 100 * q; tau = 1 / (1 + d / 2000)
                 printf "%d,%.6f,%.9g,%.9g\n", d, l, tau, (1 - tau) * B(l * 1e-6, 280) } }' \
    >"$SB_TMP/tatm.csv"
sed -e "s|^model = clear|model = table\ntable = $SB_TMP/tsky.csv|" -e '/^zenith_emissivity/d' \
    -e '/^air_temperature/d' -e "s|^extinction = .*|table = $SB_TMP/tatm.csv|" "$hscene" \
    >"$SB_TMP/tables.ini"
hscene="$SB_TMP/tables.ini"
sb_run render "$hscene" -o "$SB_TMP/href.exr" --aov level --png none --quiet "${htol[@]}"
check_rc sky_tables.render.rc 0
horizon_run sky_tables 0.01 0.02 --emission-space map
sky_check sky_tables

# An animation: bake --frames 0:7 --pov at 2 frames per second (the waves
# move 3.5 s over the sequence), rendered by POV-Ray as scene.ini says (all
# eight frames in one run, scene0.exr ... scene7.exr, each reading its own
# maps through frame_number), each frame against seabake render of that
# frame: relative RMS below 1 % (the issue's bound; 2.0e-4 measured with
# each frame's sensor image, 0.70-0.75 % with the maps alone).  A frame compared
# with another frame's render must fail that bound (0.23 measured), or the
# check could not tell the frames apart.  One frame alone: +SF5 +EF5 (a
# subset of scene.ini's frames) and +KFI6 +KFF6 give the animation's image
# of that frame, pixel for pixel.
# Under valgrind three frames (0:2), the single frames and the user's scene
# at frame 2.
fscene="$top_srcdir/tests/scenes/pov_glint.ini"
fdir="$SB_TMP/frames"
LAST=7 SF=5 KF=6 MF=3
[ -n "$SEABAKE_WRAPPER" ] && LAST=2 SF=2 KF=2 MF=2
SB_CMD="seabake render $fscene --frames 0:$LAST --frame-rate 2"
$SEABAKE_WRAPPER "$SEABAKE" render "$fscene" -o "$SB_TMP/fref.exr" --aov level --png none \
    --frames 0:$LAST --frame-rate 2 --quiet 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc frames.render.rc 0
SB_CMD="seabake bake $fscene --pov --frames 0:$LAST --frame-rate 2"
$SEABAKE_WRAPPER "$SEABAKE" bake "$fscene" -o "$fdir" --pov --frames 0:$LAST --frame-rate 2 \
    --quiet 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
check_rc frames.bake.rc 0
check_match frames.ini "$(cat "$fdir/scene.ini")" "Initial_Frame=0"$'\n'"Final_Frame=$LAST"
# POV-Ray's clock is the frame's time in seconds (2 frames per second from 0)
check_match frames.clock "$(cat "$fdir/scene.ini")" \
    "Initial_Clock=0"$'\n'"Final_Clock=$(awk -v l="$LAST" 'BEGIN { print l / 2 }')"$'\n'
# sea.inc follows the POV-Ray library's conventions: an include guard and
# the includer's #version restored at its end
check_match frames.guard "$(head -c 4000 "$fdir/sea.inc")" \
    '#ifndef \(Seabake_Sea_Inc_Temp\)'$'\n''#declare Seabake_Sea_Inc_Temp = version;'$'\n''#version 3.7;'
check_match frames.guard_end "$(tail -n 2 "$fdir/sea.inc")" '^#version Seabake_Sea_Inc_Temp;'$'\n''#end$'
SB_CMD="(cd $fdir && povray scene.ini)"
(cd "$fdir" && povray scene.ini) >"$SB_TMP/pov.out" 2>&1
SB_RC=$?
SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
check_rc frames.povray.rc 0
fscale=$(sed -n 's/^#declare Seabake_Radiance_Scale = \(.*\);/\1/p' "$fdir/sea.inc")
check_match frames.scale "$fscale" '^[0-9.eE+-]+$'
# pov_frame NAME POV_IMAGE FRAME TOL: pov_driver compare against render frame FRAME.
pov_frame() {
    SB_CMD="pov_driver compare $2 (render frame $3)"
    "$POV_DRIVER" compare "$SB_TMP/fref_000$3.exr" "$SB_TMP/fref_000$3.level.exr" "$2" \
        "$fscale" "$4" >"$SB_TMP/cmp.out" 2>"$SB_TMP/cmp.err"
    SB_RC=$?
    SB_ERR=$(cat "$SB_TMP/cmp.err")
    sed -n "1s/^/$1: /p" "$SB_TMP/cmp.out"
}
for f in $(seq 0 "$LAST"); do
    pov_frame "frames.$f" "$fdir/scene$f.exr" "$f" 0.01
    check_rc "frames.$f.compare" 0
done
pov_frame frames.last_against_0 "$fdir/scene$LAST.exr" 0 0.01
check_rc frames.last_against_0.differs 1
for sub in "$SF +SF$SF +EF$SF" "$KF +KFI$KF +KFF$KF"; do
    # shellcheck disable=SC2086
    set -- $sub
    f=$1
    shift
    # POV-Ray numbers an animation's image: +Oone.exr writes one<frame>.exr
    rm -f "$fdir/one$f.exr"
    SB_CMD="(cd $fdir && povray scene.ini $* +Oone.exr)"
    (cd "$fdir" && povray scene.ini "$@" +Oone.exr) >"$SB_TMP/pov.out" 2>&1
    SB_RC=$?
    SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
    check_rc "frames.one$f.rc" 0
    "$POV_DRIVER" dump "$fdir/one$f.exr" "$SB_TMP/one.raw" >/dev/null 2>&1 &&
        "$POV_DRIVER" dump "$fdir/scene$f.exr" "$SB_TMP/all.raw" >/dev/null 2>&1
    check "frames.one$f.same_image" cmp -s "$SB_TMP/one.raw" "$SB_TMP/all.raw"
done

# The sea in a scene of one's own: sea.inc included by a user's file that
# adds a sphere at 300 K (Seabake_Blackbody) above the sea, rendered at
# frame 3 (mine3.exr).  Seabake_Blackbody of the sky's temperature is the
# exported sky radiance (to its 9 printed digits); Seabake_Time is frame 3's, 1.5 s; the
# sphere's pixels hold the scaled Planck radiance at 4 um and 300 K that awk
# computes here (within half-float precision, 4.9e-4 relative); every other
# pixel is scene3.exr's, exactly.  The user's file is in a directory of its
# own and finds sea.inc, seabake.inc and the maps through POV-Ray's
# Library_Path (+L), includes sea.inc twice (the guard) and keeps its own
# #version (3.6 before and after the include).
udir="$SB_TMP/user"
mkdir -p "$udir"
cat >"$udir/mine.pov" <<'EOF'
#version 3.6;
global_settings { assumed_gamma 1.0 }
#include "sea.inc"
#include "sea.inc"
#debug concat("version after ", str(version, 0, 1), "\n")
#version 3.7;
#debug concat("blackbody/sky ", str(Seabake_Blackbody(250) / Seabake_Sky_Radiance, 0, 12), "\n")
#debug concat("time ", str(Seabake_Time, 0, 6), "\n")
camera { Seabake_Camera }
Seabake_Sky(Seabake_Sky_Radiance)
object { Seabake_Sea }
sphere { <0, 30, 0>, 6 Seabake_Emission_Constant(Seabake_Blackbody(300)) }
EOF
SB_CMD="(cd $udir && povray $fdir/scene.ini +Imine.pov +Omine.exr +L$fdir +SF$MF +EF$MF)"
(cd "$udir" && povray "$fdir/scene.ini" +Imine.pov +Omine.exr "+L$fdir" "+SF$MF" "+EF$MF") \
    >"$SB_TMP/pov.out" 2>&1
SB_RC=$?
SB_ERR=$(grep -A3 -E 'Error|error' "$SB_TMP/pov.out" | head -n 5)
check_rc include.rc 0
check_match include.version_kept "$(cat "$SB_TMP/pov.out")" "version after 3.6"
check_eq include.no_copy "$(find "$udir" -name '*.inc' -o -name 'level_*' | wc -l)" 0
ratio=$(sed -n 's/^blackbody\/sky //p' "$SB_TMP/pov.out")
num_check include.blackbody_is_sky 'r > 1 - 1e-8 && r < 1 + 1e-8' "r=${ratio:-nan}"
check_match include.time "$(cat "$SB_TMP/pov.out")" "time $(awk -v f="$MF" 'BEGIN { printf "%.6f", f / 2 }')"
"$POV_DRIVER" dump "$udir/mine$MF.exr" "$SB_TMP/mine.raw" >/dev/null 2>&1 &&
    "$POV_DRIVER" dump "$fdir/scene$MF.exr" "$SB_TMP/s3.raw" >/dev/null 2>&1
check include.dump test -s "$SB_TMP/mine.raw"
SB_CMD="sphere pixels of mine$MF.exr against Planck(4 um, 300 K) x $fscale"
SB_ERR=$(paste <(od -An -v -f -w16 "$SB_TMP/mine.raw") <(od -An -v -f -w16 "$SB_TMP/s3.raw") |
    awk -v s="$fscale" 'BEGIN {
            h = 6.62607015e-34; c = 299792458; k = 1.380649e-23; l = 4e-6
            want = s * 1e-6 * 2 * h * c * c / l^5 / (exp(h * c / (l * k * 300)) - 1)
        }
        { if ($1 != $5) { n++; d = $1 / want - 1; if (d < 0) d = -d; if (d > 4.9e-4) bad++ }
          else same++ }
        END { printf "%d sphere pixels (%d off %.6g), %d unchanged", n, bad, want, same
              exit !(n > 100 && bad == 0 && same > 10000) }')
SB_RC=$?
echo "include: $SB_ERR"
check_rc include.sphere 0

finish
