#!/bin/bash
# hostile.sh - hostile input on the command line of every subcommand
# (issue "Hostile input"): numbers that are not numbers (NaN, infinities,
# overflow, denormals, empty and 100 kB strings, hexadecimal, garbage),
# huge lists, options without values, unknown options, duplicated options,
# stray arguments, odd file names (quotes, newlines, spaces, unicode) for
# -o and for scene files, a directory or a missing file where a file is
# read.  The cases are generated: loops over the subcommands, their options
# and the values below.
#
# The failure contract, for an input that must fail: exit 2 (usage: any
# malformed or out-of-range value, unknown option, option without value,
# stray argument) or 3 (input/output: a missing or unreadable file, a
# directory where a file is read, an output in a missing directory or
# under a regular file), exactly one "seabake: error:" line on stderr,
# nothing on stdout, and nothing written: the scratch directory (the
# working directory of every run, where each -o points) lists the same
# files before and after, hidden temporaries (*.tmp.*) included.  An input
# that may be valid (-0, 4.9e-324, 1e308, inf where a range is closed at
# infinity, a duplicated option whose last value is valid) must either
# succeed with finite output (no nan or inf in stdout) or fail by the
# contract.
#
# Under SEABAKE_WRAPPER (valgrind) only a core of the cases runs: the first
# values of each class on the first option of each subcommand.
# $(SHELL) may be a plain POSIX sh: this script needs bash.
if [ -z "${BASH_VERSION:-}" ]; then exec bash "$0" "$@"; fi
TEST_NAME=hostile
# shellcheck source=tests/lib.sh
. "${top_srcdir:-.}/tests/lib.sh"
shopt -s dotglob nullglob globstar

QUICK=
[ -n "$SEABAKE_WRAPPER" ] && QUICK=1
# shellcheck disable=SC2206
WRAP=($SEABAKE_WRAPPER)

W=$SB_TMP/w     # scratch: the working directory of every run
FIX=$SB_TMP/fix # fixtures, outside the scratch directory
OK=$SB_TMP/ok   # where runs that may succeed write
mkdir -p "$W" "$FIX" "$OK" || exit 99
cd "$W" || exit 99
CASES=0

cat >"$FIX/tiny.ini" <<'EOF'
[sea]
wind_speed = 8
[sensor]
altitude = 50
look_zenith = 60
hfov = 40
width = 4
height = 3
wavelength = 4
[model]
emissivity = fast
EOF
printf 'wavelength_um,n,k\n2,1.3,0.01\n16,1.2,0.4\n' >"$FIX/water.csv"

# ------------------------------------------------------------ the runner

# run ARGS...: runs seabake in $W; sets RC, OUT, ERR (no fork beyond the
# program itself: thousands of cases).
run() {
    CASES=$((CASES + 1))
    SB_CMD="seabake $(printf '%q ' "$@" | head -c 400)"
    "${WRAP[@]}" "$SEABAKE" "$@" >"$SB_TMP/out" 2>"$SB_TMP/err"
    RC=$?
    OUT= ERR=
    IFS= read -r -d '' OUT <"$SB_TMP/out"
    IFS= read -r -d '' ERR <"$SB_TMP/err"
    SB_RC=$RC SB_ERR=$ERR
}

# The files under the scratch directory, hidden ones included.
listing() {
    local f=("$W"/**)
    LISTING="${f[*]}"
}

# failing NAME WANT_RC ARGS...: the failure contract.
failing() {
    local name=$1 want=$2 before
    shift 2
    listing
    before=$LISTING
    run "$@"
    listing
    local nl=${ERR//[^$'\n']/}
    if [ "$RC" -ne "$want" ]; then
        fail "$name" "exit code $RC, expected $want"
    elif [ -n "$OUT" ]; then
        fail "$name" "unexpected stdout: ${OUT:0:200}"
    elif [ "${#nl}" -ne 1 ] || [[ $ERR != "seabake: error: "* ]]; then
        fail "$name" "stderr is not one 'seabake: error:' line: ${ERR:0:300}"
    elif [ "$LISTING" != "$before" ]; then
        fail "$name" "files written: ${LISTING#"$before"}"
    else
        pass
    fi
}

# maybe NAME ARGS...: succeeds with finite output, or fails by the contract
# (exit 1 or 2).  Whatever a success wrote goes to $OK, emptied after.
maybe() {
    local name=$1
    shift
    run "$@"
    if [ "$RC" -eq 0 ]; then
        if [[ ${OUT,,} =~ (^|[^a-z])(nan|inf|infinity)([^a-z]|$) ]]; then
            fail "$name" "non-finite output: ${OUT:0:200}"
        else
            pass
        fi
    else
        local nl=${ERR//[^$'\n']/}
        if [ "$RC" -ne 1 ] && [ "$RC" -ne 2 ]; then
            fail "$name" "exit code $RC, expected 0, or 1 or 2 by the failure contract"
        elif [ -n "$OUT" ]; then
            fail "$name" "failed (exit $RC) after printing: ${OUT:0:200}"
        elif [ "${#nl}" -ne 1 ] || [[ $ERR != "seabake: error: "* ]]; then
            fail "$name" "stderr is not one 'seabake: error:' line: ${ERR:0:300}"
        else
            pass
        fi
    fi
    rm -rf "${OK:?}"/* && rm -f "$W"/*.exr "$W"/*.png
}

# ------------------------------------------------------------ the inputs

LONG=1$(printf '%0100000d' 0)         # 100 kB of digits (too large for any integer)
LONGX=$(printf '%0100000d' 0 | tr 0 x) # 100 kB of letters
# Never a number: NaN in its spellings, minus infinity (no range has it),
# overflow, empty, blank, garbage, hexadecimal, trailing text, 100 kB.
BAD_NUMBERS=(nan NaN -nan +NAN -inf -Infinity 1e309 -1e309 1e99999 '' ' ' abc 0x10 0x1p3 1e
    '1 2' 1.5.2 '--' '-' '+' 1e308x '4.9e-324e' $'1\n2' 'ñ' "$LONG" "$LONGX")
# Lists that must fail: too many values (1e6, 1e10), backwards, a zero,
# negative or NaN step, a NaN or empty element, a 1e6-element list.
BAD_LISTS=('0:89:1e-9' '0:1:1e-10' '-89:89:1e-6' '1:0:1' '0:1:0' '0:1:-1' '0:1:nan' '0:1:inf'
    'nan:1:1' '0:nan:1' '0,nan' '0,,1' ',' '0,' ':' '::' '0:1' '0:1:1:1' '0:1,2:1')
# Values a range may accept.
MAYBE_NUMBERS=(-0 0 4.9e-324 -4.9e-324 2.2250738585072014e-308 1e308 -1e308 inf +inf 1e-300)
if [ -n "$QUICK" ]; then
    BAD_NUMBERS=(nan 1e309 "$LONG")
    BAD_LISTS=('0:89:1e-9')
    MAYBE_NUMBERS=(4.9e-324)
fi

# Each subcommand: its base arguments (valid and quick), then its options
# by kind: numbers (N), lists (L), pairs and triples (T2, T3), integers (I).
# An option in the base is replaced; others are added.
base_of() {
    case $1 in
    spectrum) BASE=(--wind 8) ;;
    emissivity | energy) BASE=(--wavelength 4 --wind 8 --theta 10) ;;
    reflectivity) BASE=(--wavelength 4 --wind 8 --inc 30,0 --theta 10) ;;
    slopes) BASE=(--wind 8 --facet 1 --size 2,2 --quiet) ;;
    convergence) BASE=(--wavelength 4 --wind 8 --theta 30 --facets 1 --sizes 1:1 -o "$OK"
        --quiet) ;;
    bench) BASE=(--quick -o "$OK") ;;
    render) BASE=("$FIX/tiny.ini" -o "$OK/out.exr" --quiet) ;;
    bake) BASE=("$FIX/tiny.ini" -o "$OK/maps" --quiet) ;;
    esac
}
opts_of() {
    case $1 in
    spectrum) OPTS="N:wind N:fetch N:wind-dir L:facet" ;;
    emissivity)
        OPTS="N:wavelength N:wind N:fetch N:wind-dir N:facet N:salinity L:theta L:phi T2:mean
              T2:index T3:cov I:reflections" ;;
    energy)
        OPTS="N:wavelength N:wind N:fetch N:wind-dir N:facet N:salinity L:theta L:phi T2:mean
              T2:index T3:cov" ;;
    reflectivity)
        OPTS="N:wavelength N:wind N:fetch N:wind-dir N:facet N:salinity L:theta L:phi T2:mean
              T2:index T3:cov T2:inc T2:obs" ;;
    slopes)
        OPTS="N:wind N:fetch N:wind-dir N:facet T2:size I:n I:seed N:time N:finest
              N:loop-period" ;;
    convergence)
        OPTS="N:theta N:phi T2:inc L:wind N:fetch N:wind-dir I:seed I:n I:facets N:tolerance
              N:wavelength N:salinity" ;;
    bench) OPTS="I:threads" ;;
    render) OPTS="N:frame-rate I:png-depth I:threads N:tolerance I:reflections" ;;
    bake) OPTS="N:frame-rate I:emission-texels N:tolerance I:reflections" ;;
    esac
    [ -z "$QUICK" ] || OPTS=${OPTS%% *}
}
COMMANDS=(spectrum emissivity reflectivity energy slopes convergence bench render bake)

# with OPT VALUE: the base with --OPT VALUE (replacing the base's), and
# what the option needs beside it (--n: its method; --index: no table;
# --cov: no sea state).
with() {
    local opt=$1 val=$2 i skip=
    ARGS=()
    for ((i = 0; i < ${#BASE[@]}; i++)); do
        if [ -n "$skip" ]; then skip=; continue; fi
        case ${BASE[i]} in
        --"$opt") skip=1; continue ;;
        --wind | --fetch | --wind-dir | --facet)
            if [ "$opt" = cov ]; then skip=1; continue; fi ;;
        --theta)
            if [ "$opt" = obs ]; then skip=1; continue; fi ;;
        esac
        ARGS+=("${BASE[i]}")
    done
    [ "$opt" = n ] && ARGS+=(--method variable-step-2n)
    ARGS+=(--"$opt" "$val")
}

# ------------------------------------------------------- values x options

for cmd in "${COMMANDS[@]}"; do
    base_of "$cmd"
    opts_of "$cmd"
    for spec in $OPTS; do
        kind=${spec%%:*} opt=${spec#*:}
        for v in "${BAD_NUMBERS[@]}"; do
            case $kind in
            N | L | I) vals=("$v") ;;
            T2) vals=("$v,0" "0,$v") ;;
            T3) vals=("$v,0,0" "0,0,$v") ;;
            esac
            for x in "${vals[@]}"; do
                with "$opt" "$x"
                failing "$cmd --$opt ${x:0:20}" 2 "$cmd" "${ARGS[@]}"
            done
        done
        if [ "$kind" = L ]; then
            for v in "${BAD_LISTS[@]}"; do
                with "$opt" "$v"
                failing "$cmd --$opt $v" 2 "$cmd" "${ARGS[@]}"
            done
        fi
        # --opt=VALUE, and --opt with no value at the end.
        with "$opt" x
        failing "$cmd --$opt=nan" 2 "$cmd" "${ARGS[@]:0:${#ARGS[@]}-2}" "--$opt=nan"
        failing "$cmd --$opt=" 2 "$cmd" "${ARGS[@]:0:${#ARGS[@]}-2}" "--$opt="
        failing "$cmd --$opt (no value)" 2 "$cmd" "${ARGS[@]:0:${#ARGS[@]}-2}" "--$opt"
        [ "$cmd" = bench ] && continue # a success runs for minutes
        for v in "${MAYBE_NUMBERS[@]}"; do
            case $kind in
            N | L | I) vals=("$v") ;;
            T2) vals=("$v,0" "0,$v") ;;
            T3) vals=("$v,0,0" "0,0,$v") ;;
            esac
            for x in "${vals[@]}"; do
                with "$opt" "$x"
                maybe "$cmd --$opt $x" "$cmd" "${ARGS[@]}"
            done
        done
        # Duplicated: the last value is taken, so a bad one after the
        # base's valid one fails.
        [ -n "$QUICK" ] && continue
        with "$opt" nan
        failing "$cmd --$opt nan after the base" 2 "$cmd" "${BASE[@]}" "${ARGS[@]: -2}"
    done
done

# ------------------------------------------------ options, arguments, names

UNKNOWN=(--nope -x --WIND ---wind --wind_speed '--' '--=' '--=8' -- --help=1 -h=1 -oo
    '--wínd' $'--wind\n' '--ünknown' "--$LONGX")
BAD_FRAMES=(0:999999 0:100000 -1:2 1.5:2 2:1 nan:1 1:inf 1 1:2:3 : '' 1e6:1e6 0x1:2)
[ -n "$QUICK" ] && UNKNOWN=("--$LONGX") && BAD_FRAMES=(0:999999)
for cmd in "${COMMANDS[@]}"; do
    base_of "$cmd"
    for u in "${UNKNOWN[@]}"; do
        failing "$cmd unknown ${u:0:20}" 2 "$cmd" "${BASE[@]}" "$u"
        failing "$cmd unknown ${u:0:20} first" 2 "$cmd" "$u" "${BASE[@]}"
    done
    # A flag given a value.
    case $cmd in
    slopes | convergence | render | bake)
        failing "$cmd --quiet=1" 2 "$cmd" "${BASE[@]}" --quiet=1
        failing "$cmd --quiet=" 2 "$cmd" "${BASE[@]}" --quiet= ;;
    bench) failing "bench --quick=1" 2 bench --quick=1 -o "$OK" ;;
    esac
    # --frames A:B of render and bake.
    case $cmd in
    render | bake)
        for f in "${BAD_FRAMES[@]}"; do
            failing "$cmd --frames $f" 2 "$cmd" "${BASE[@]}" --frames "$f"
        done
        failing "$cmd --frame-rate without --frames" 2 "$cmd" "${BASE[@]}" --frame-rate 10 ;;
    esac
    # A stray argument (render and bake: a second scene file).
    failing "$cmd stray" 2 "$cmd" "${BASE[@]}" stray
    failing "$cmd stray empty" 2 "$cmd" "${BASE[@]}" ''
    # -o without its value, at the end.
    case $cmd in
    slopes | convergence | bench | render | bake)
        failing "$cmd -o (no value)" 2 "$cmd" "${BASE[@]}" -o ;;
    esac
done
failing "help with two" 2 help render bake
HELP=(nan '' "$LONGX" $'ren\nder' 'rénder' ' render')
[ -n "$QUICK" ] && HELP=($'ren\nder')
for h in "${HELP[@]}"; do
    failing "help ${h:0:20}" 2 help "$h"
    failing "subcommand ${h:0:20}" 2 "$h"
done

# Scene files and -o: missing files, directories, odd names.
NAMES=("it's" 'say "hi"' $'new\nline' 'with space' 'ünïcødé ☃' '-dash' '$(touch pwned)'
    '`touch pwned`' '*' "$(printf '%0200d' 0)")
[ -n "$QUICK" ] && NAMES=($'new\nline ünïcødé ☃')
mkdir -p "$FIX/a dir.ini"
for cmd in render bake; do
    base_of "$cmd"
    rest=("${BASE[@]:1}")
    failing "$cmd missing scene" 3 "$cmd" "$FIX/missing.ini" "${rest[@]}"
    failing "$cmd scene is a directory" 3 "$cmd" "$FIX/a dir.ini" "${rest[@]}"
    failing "$cmd scene is /dev/null" 3 "$cmd" /dev/null "${rest[@]}"
    failing "$cmd scene empty name" 2 "$cmd" '' "${rest[@]}"
    for n in "${NAMES[@]}"; do
        failing "$cmd missing scene ${n:0:20}" 3 "$cmd" "$FIX/$n.ini" "${rest[@]}"
    done
done
failing "emissivity --water missing" 3 emissivity --wavelength 4 --wind 8 --theta 0 \
    --water "$FIX/missing.csv"
failing "emissivity --water directory" 3 emissivity --wavelength 4 --wind 8 --theta 0 \
    --water "$FIX/a dir.ini"
failing "emissivity --water odd name" 3 emissivity --wavelength 4 --wind 8 --theta 0 \
    --water $'./new\nline.csv'
for n in "${NAMES[@]}"; do
    # An odd name is a name: the scene loads and the output is written
    # under exactly that name, and nothing else appears.
    cp "$FIX/tiny.ini" "$FIX/$n.ini"
    listing
    before=$LISTING
    run render "$FIX/$n.ini" -o "$W/$n.exr" --quiet
    made=no
    [ -f "$W/$n.exr" ] && [ -f "$W/$n.png" ] && made=yes # and its preview
    rm -f "$W/$n.exr" "$W/$n.png"
    listing
    if [ "$RC" -eq 0 ] && [ $made = yes ] && [ "$LISTING" = "$before" ]; then
        pass
    else
        fail "render odd name ${n:0:20}" "exit $RC, written: $made; other files: ${LISTING}"
    fi
    check "no command ran for ${n:0:20}" test ! -e "$W/pwned"
    # The same name in a missing directory, or under a regular file.
    failing "render -o missing dir ${n:0:20}" 3 render "$FIX/tiny.ini" -o "$W/missing/$n.exr" --quiet
    failing "bake -o missing dir ${n:0:20}" 3 bake "$FIX/tiny.ini" -o "$W/missing/$n" --quiet
    failing "slopes -o missing dir ${n:0:20}" 3 slopes --wind 8 --facet 1 --size 2,2 \
        -o "$W/missing/$n.csv" --quiet
done
touch "$W/file"
failing "render -o under a file" 3 render "$FIX/tiny.ini" -o "$W/file/x.exr" --quiet
failing "bake -o under a file" 3 bake "$FIX/tiny.ini" -o "$W/file/x" --quiet
# An -o that is a file: an I/O error (exit 3) for bake, convergence and
# bench alike, and bake leaves no lock file behind.
failing "bake -o a file" 3 bake "$FIX/tiny.ini" -o "$W/file" --quiet
failing "convergence -o a file" 3 convergence --wavelength 4 --wind 8 --theta 30 --facets 1 \
    --sizes 1:1 -o "$W/file" --quiet
failing "bench -o a file" 3 bench --quick -o "$W/file"
rm -f "$W/file"
# bake -o naming no replaceable directory is refused before any work (issue
# 18): ., .., / (exit 2, one line, nothing written).
for d in . .. /; do
    failing "bake -o $d" 2 bake "$FIX/tiny.ini" -o "$d" --quiet
done

# Duplicated options whose last value is valid succeed, with the last one.
if [ -z "$QUICK" ]; then
    maybe "emissivity --wind twice" emissivity --wavelength 4 --wind nan --wind 8 --theta 0
    check_match "emissivity --wind twice takes the last" "$OUT" '^wavelength_um'
    maybe "render --tolerance twice" render "$FIX/tiny.ini" -o "$OK/o.exr" --tolerance nan \
        --tolerance 0.01 --quiet
fi

# Regression: the water table's own ends are inside it (found by the water
# fuzz target: 15.5 um of Hale & Querry was refused as outside 2.4-15.5 um).
for wl in 15.5 2.4; do
    run emissivity --wavelength "$wl" --wind 8 --theta 0
    check_eq "emissivity --wavelength $wl (table end)" "$RC" 0
done
sed 's/^wavelength = 4/wavelength = 15.5/' "$FIX/tiny.ini" >"$FIX/end.ini"
run render "$FIX/end.ini" -o "$OK/end.exr" --quiet
check_eq "render at the table's end" "$RC" 0
# Regression: a table within the bounds of water that the sea-water
# correction takes out of them (n = 1.0 - 0.018 at 15.5 um) is refused
# (found by the water fuzz target), and accepted for pure water.
printf 'wavelength_um,n,k\n2.4,1.279,9.56E-4\n15.5,1.0,0.414\n' >"$FIX/low_n.csv"
failing "--water n below 1 after the correction" 2 emissivity --wavelength 15.5 --wind 8 \
    --theta 85 --water "$FIX/low_n.csv"
run emissivity --wavelength 15.5 --wind 8 --theta 85 --water "$FIX/low_n.csv" --salinity 0
check_eq "--water n = 1 without the correction" "$RC" 0
# Regression: a row whose wavenumber overflows is refused (found by the
# water fuzz target: the table's range started at 0 um).
printf 'wavelength_um,n,k\n2,1.279,6E-4\n2.2250738585072014e-307,1.2,0\n' >"$FIX/tiny_wl.csv"
failing "--water wavelength 2e-307 um" 2 emissivity --wavelength 4 --wind 8 --theta 0 \
    --water "$FIX/tiny_wl.csv"
rm -rf "${OK:?}"/*

# ------------------------------------------------- issue 40: the fault sweep

# failing_with NAME WANT_RC REGEX ARGS...: the failure contract, and the
# one error line matching REGEX.
failing_with() {
    local name=$1 want=$2 re=$3
    shift 3
    failing "$name" "$want" "$@"
    check_match "$name (message)" "$ERR" "$re"
}
# scene_with NAME LINES...: $FIX/NAME.ini, tiny.ini with LINES added after
# its [sensor] line (a later section header starts a section of its own).
scene_with() {
    local name=$1
    shift
    { sed -n '1,/^\[sensor\]/p' "$FIX/tiny.ini"
      printf '%s\n' "$@"
      sed -n '/^\[sensor\]/,$p' "$FIX/tiny.ini" | tail -n +2; } >"$FIX/$name.ini"
}
# The tables of the sky and the air at 4 um, written with a UTF-8 byte
# order mark first (issue 40, item 9), as the scene file may be.
BOM=$'\xEF\xBB\xBF'
printf 'zenith_deg,wavelength_um,radiance\n0,3.9,1\n90,3.9,2\n0,4.1,1\n90,4.1,2\n' >"$FIX/sky.csv"
printf 'range_m,wavelength_um,transmittance,path_radiance\n' >"$FIX/atm.csv"
printf '0,3.9,1,0\n0,4.1,1,0\n1e7,3.9,0.5,0.1\n1e7,4.1,0.5,0.1\n' >>"$FIX/atm.csv"
for t in sky atm; do
    { printf '%s' "$BOM"; cat "$FIX/$t.csv"; } >"$FIX/${t}_bom.csv"
done
printf '%swavelength_um,response\n3.5,1\n4.5,1\n' "$BOM" >"$FIX/resp_bom.csv"
printf '%swavelength_um,n,k\n2,1.3,0.01\n16,1.2,0.4\n' "$BOM" >"$FIX/water_bom.csv"
run emissivity --wavelength 4 --wind 8 --theta 0 --water "$FIX/water_bom.csv"
check_eq "--water with a byte order mark" "$RC" 0
sed -e 's/^wavelength = 4/band = 3.6:4.4\nresponse = resp_bom.csv/' "$FIX/tiny.ini" \
    >"$FIX/resp_bom.ini"
run render "$FIX/resp_bom.ini" -o "$OK/r.exr" --quiet
check_eq "response with a byte order mark" "$RC:$ERR" "0:"
{ cat "$FIX/tiny.ini"
  printf '[sky]\nmodel = table\ntable = sky.csv\n[atmosphere]\ntable = atm.csv\n'; } \
    >"$FIX/tables.ini"
sed 's/\(sky\|atm\)\.csv/\1_bom.csv/' "$FIX/tables.ini" >"$FIX/tables_bom.ini"
run render "$FIX/tables_bom.ini" -o "$OK/t.exr" --quiet
check_eq "sky and atmosphere tables with a byte order mark" "$RC:$ERR" "0:"
# Out-of-range values are printed to as many digits as show why (not
# "1000 is out of range (allowed: [0, 1000])").
sed 's/^90,3.9,2$/90,3.9,1000.0000001/' "$FIX/sky.csv" >"$FIX/sky_big.csv"
sed 's/sky\.csv/sky_big.csv/' "$FIX/tables.ini" >"$FIX/sky_big.ini"
failing_with "sky table radiance 1000.0000001" 2 \
    "radiance: 1000.0000001 is out of range \(allowed: \[0, 1000\] W" \
    render "$FIX/sky_big.ini" -o "$OK/t.exr" --quiet
printf 'wavelength_um,n,k\n2,1.3,0.01\n16,3.0000001,0.4\n' >"$FIX/water_big.csv"
failing_with "--water n 3.0000001" 2 "n: 3.0000001 is outside \[1, 3\]" \
    emissivity --wavelength 4 --wind 8 --theta 0 --water "$FIX/water_big.csv"
printf 'wavelength_um,response\n3.5,1\n4.5,1000000.1\n' >"$FIX/resp_big.csv"
sed 's/resp_bom.csv/resp_big.csv/' "$FIX/resp_bom.ini" >"$FIX/resp_big.ini"
failing_with "response 1000000.1" 2 "response: 1000000.1 is outside \[0, 1000000\]" \
    render "$FIX/resp_big.ini" -o "$OK/r.exr" --quiet
sed 's/^band = .*/band = 3.6:15.5000001/' "$FIX/resp_bom.ini" >"$FIX/band_big.ini"
failing_with "band past the water table by 1e-7 um" 2 \
    "band: 3.6:15.50000010*[0-9]* um is outside the water table \(allowed: 2.4-15.5 um" \
    render "$FIX/band_big.ini" -o "$OK/r.exr" --quiet
# The bake's manifest records the sky and the air that were used (a table
# sky and an atmosphere table were "radiance": null and no atmosphere).
run bake "$FIX/tables.ini" -o "$OK/tables" --quiet
check_eq "bake with tables" "$RC:$ERR" "0:"
manifest=$(tr -d ' \n\t' <"$OK/tables/manifest.json" 2>/dev/null)
check_match "manifest: the table sky" "$manifest" \
    '"sky":\{"model":"table","table":"[^"]*/fix/sky.csv"\}'
check_match "manifest: the atmosphere table" "$manifest" \
    '"atmosphere":\{"air_temperature_K":null,"table":"[^"]*/fix/atm.csv"\}'
run bake "$FIX/tiny.ini" -o "$OK/plain" --quiet
manifest=$(tr -d ' \n\t' <"$OK/plain/manifest.json" 2>/dev/null)
check_match "manifest: an isotropic sky, no atmosphere" "$manifest" \
    '"sky":\{"model":"isotropic","radiance_W_m2_sr_um":null,"temperature_K":250\},"atmosphere":null,'
# Item 4: the sensor's x and y are bounded where the cell indices still
# hold (1e20 overflowed a long in multires.c); the message names the key.
for xy in x=1e20 x=1e308 x=-1e308 y=1e308 y=-1e308; do
    failing_with "render sensor.$xy" 2 \
        "--set sensor.$xy: \[sensor\] ${xy%%=*}: ${xy#*=} is out of range \(allowed: \[-10000000, 10000000\] m\)" \
        render "$FIX/tiny.ini" -o "$OK/x.exr" --quiet --set "sensor.$xy"
done
run render "$FIX/tiny.ini" -o "$OK/x.exr" --quiet --set sensor.x=-1e7 --set sensor.y=1e7
check_eq "render at the sensor's bound" "$RC:$ERR" "0:"
# ... and a look point beyond a long's cells is an error, not undefined.
failing_with "clipmap look point 1e17 m away" 2 "level 0: the sea it shows reaches" \
    render "$FIX/tiny.ini" -o "$OK/x.exr" --quiet --set sensor.look_zenith=89.99999999999999 \
    --set model.windows=clipmap --set model.finest=1e-3
# Item 8: edge cases inside the documented ranges compute, or are refused
# before anything is printed or written.
# A mean slope of (-5, 5) seen 60 deg off: 1/D overflowed where the mirror
# facet's density underflowed (NaN after 103 rows); both are now formed in
# logs in that far tail.
run reflectivity --wavelength 4 --wind 10 --mean -5,5 --inc 60,0 --theta 60 --phi 0:360:1
check_eq "reflectivity --mean -5,5 --phi 0:360:1" "$RC:$ERR" "0:"
check_eq "reflectivity --mean -5,5: every row" "$(printf '%s' "$OUT" | grep -c '')" 362
check_no_match "reflectivity --mean -5,5: finite" "${OUT,,}" '(nan|inf)'
# The sea's time is bounded (1e308 gave "mean slope (-nan, -nan)"), and so
# is every frame's time: a rate of 4.9e-324 Hz put frame 1 at an infinite
# time once frame 0 was written, without naming the option.
failing_with "render sea.time=1e308" 2 \
    "\[sea\] time: 1e308 is out of range \(allowed: \[-1000000000, 1000000000\] s\)" \
    render "$FIX/tiny.ini" -o "$W/t.exr" --quiet --set sea.time=1e308
failing_with "slopes --time 1e308" 2 "--time: 1e308 is outside \[-1000000000, 1000000000\] s" \
    slopes --wind 8 --facet 1 --size 2,2 --quiet --time 1e308
for cmd in render bake; do
    out="$W/f.exr"
    [ $cmd = bake ] && out="$W/f"
    failing_with "$cmd --frame-rate 4.9e-324" 2 \
        "--frames 0:1 at --frame-rate [0-9.e+-]+ Hz: frame 1 falls at inf s, outside" \
        $cmd "$FIX/tiny.ini" -o "$out" --quiet --frames 0:1 --frame-rate 4.9e-324
done
# hfov at or below 1e-154 deg rendered an all-sky image (the focal length
# squared overflowed); the field of view is bounded at 1e-6 deg.
failing_with "render hfov 1e-154" 2 \
    "\[sensor\] hfov: 1e-154 is out of range \(allowed: \[1e-06, 170\] deg\)" \
    render "$FIX/tiny.ini" -o "$W/h.exr" --quiet --set sensor.hfov=1e-154
run render "$FIX/tiny.ini" -o "$OK/h.exr" --set sensor.hfov=1e-6
check_match "render at hfov 1e-6 sees the sea" "$ERR" "levels [0-9.]+,[0-9.,]+\(LR\) m, 1 frame"
# A bake whose far texels are at or past the sensor's horizon (altitude
# 1e-20 m, or a round Earth's horizon inside a clipmap window at 1 m) failed
# "view zenith 90 deg" while render worked: they take the grazing view.
run bake "$FIX/tiny.ini" -o "$OK/low" --quiet --set sensor.altitude=1e-20
check_eq "bake at altitude 1e-20 m" "$RC:$ERR" "0:"
run bake "$FIX/tiny.ini" -o "$OK/round" --quiet --set sensor.altitude=1 \
    --set model.earth=spherical --set model.windows=clipmap
check_eq "bake past a round Earth's horizon" "$RC:$ERR" "0:"
# A look zenith 1e-7 deg short of 90 (the farthest sea 1e17 m away) made
# horizon arcs that did not increase: bake --pov refused them ("horizon arc
# 9 ... increasing") while --blender took them.
for ex in pov blender; do
    run bake "$FIX/tiny.ini" -o "$OK/grazing_$ex" --quiet --"$ex" --set sensor.look_zenith=89.9999999
    check_eq "bake --$ex at look_zenith 89.9999999" "$RC:$ERR" "0:"
done
# A subnormal value is a number (it was "is not a number"), as on the
# command line; one beyond double range is out of range.
for v in 4.9e-324 -1e-400; do
    run render "$FIX/tiny.ini" -o "$OK/d.exr" --quiet --set sea.wind_direction=$v
    check_eq "render wind_direction $v" "$RC:$ERR" "0:"
done
failing_with "render wind_direction 1e400" 2 "\[sea\] wind_direction: 1e400 is out of range" \
    render "$FIX/tiny.ini" -o "$W/d.exr" --quiet --set sea.wind_direction=1e400
# An opaque atmosphere table (transmittance 0 and path radiance 0) failed
# "radiance 0 at pixel (0, 15)" mid-render: it is refused when the scene is
# read, naming the key, the file and the line.
printf 'range_m,wavelength_um,transmittance,path_radiance\n0,3.9,0,0\n0,4.1,0,0\n' >"$FIX/opaque.csv"
printf '1e7,3.9,0,0\n1e7,4.1,0,0\n' >>"$FIX/opaque.csv"
sed 's/atm\.csv/opaque.csv/' "$FIX/tables.ini" >"$FIX/opaque.ini"
failing_with "render an opaque atmosphere table" 2 \
    "\[atmosphere\] table: .*opaque.csv:2: transmittance 0 and path_radiance 0: a path that neither transmits nor radiates" \
    render "$FIX/opaque.ini" -o "$W/o.exr" --quiet
# Item 5: the tables' profiles (rows x spectral samples) are checked
# against the memory this process may use before they are allocated, naming
# the key: 1e5 ranges at 4096 samples need 6.1 GiB, here under a 2 GiB
# limit.  (Not under a wrapper such as valgrind, nor with AddressSanitizer,
# whose shadow memory cannot start under a small address-space limit.)
if [ -z "$SEABAKE_WRAPPER" ] && ! grep -q __asan_init "$SEABAKE" 2>/dev/null; then
    awk 'BEGIN { print "range_m,wavelength_um,transmittance,path_radiance"
        for (i = 0; i < 100000; i++)
            for (w = 3.9; w < 4.2; w += 0.2)
                printf "%d,%.1f,%.6g,0.01\n", 100 * i, w, exp(-1e-4 * i) }' >"$FIX/atm_rows.csv"
    { sed 's/^wavelength = 4/band = 3.9:4.1\nsamples = 4096/' "$FIX/tiny.ini"
      printf '[atmosphere]\ntable = atm_rows.csv\n'; } >"$FIX/atm_rows.ini"
    listing
    before=$LISTING
    SB_CMD="seabake render atm_rows.ini (ulimit -v 2097152)"
    (ulimit -v 2097152 && exec "$SEABAKE" render "$FIX/atm_rows.ini" -o "$W/rows.exr" --quiet) \
        >"$SB_TMP/out" 2>"$SB_TMP/err"
    RC=$? SB_RC=$RC ERR=$(cat "$SB_TMP/err") SB_ERR=$ERR
    listing
    check_eq "atmosphere rows x samples: exit 1, nothing written" "$RC:$LISTING" "1:$before"
    check_match "atmosphere rows x samples: the key and the need" "$ERR" \
        "^seabake: error: \[atmosphere\] table .*atm_rows.csv \(100000 ranges, two columns\): at 4096 spectral samples its rows need 6.1 GiB .*this process may use 2 GiB \(allowed: fewer rows or \[sensor\] samples\)$"
fi
rm -rf "${OK:?}"/*

listing
check_eq "scratch directory empty at the end" "$LISTING" "$W/"
echo "hostile: $CASES cases" >&2
finish
