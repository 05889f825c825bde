#!/bin/bash
# example.sh - runs examples/emissivity.c, the library's C example, and checks
# its table against `seabake emissivity` and `seabake spectrum` for the same
# inputs (4 um, Hale & Querry at 35 g/kg, 10 m/s, low resolution, phi 0, auto
# rule; the flat sea as --cov 0,0,0).  Both compute with the same library
# calls, so they agree to the example's printed digits: emissivities within
# 1e-6 (six decimals), slope variances within 1e-5 (five).
#
# make check runs the example built against the uninstalled shared library
# (through libtool, which also lets SEABAKE_WRAPPER, e.g. valgrind, see the
# binary itself); make installcheck runs the copies it compiled against the
# installed library, with the installed program.
#
# Environment, besides lib.sh's: EMISSIVITY_EXAMPLE, the example program;
# LIBTOOL, the build's libtool (empty for an installed, non-libtool program).
# $(SHELL) may be a plain POSIX sh: these scripts need bash.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=${TEST_NAME:-example}
. "$(dirname "$0")/lib.sh"

: "${EMISSIVITY_EXAMPLE:?EMISSIVITY_EXAMPLE must name the built examples/emissivity}"
LIBTOOL=${LIBTOOL-}
THETAS="0 30 60 70 80 85"

# The example, under the wrapper (words split on purpose: "valgrind --quiet ...").
SB_CMD="emissivity (examples/emissivity.c)"
# shellcheck disable=SC2086
${LIBTOOL:+$LIBTOOL --mode=execute} $SEABAKE_WRAPPER "$EMISSIVITY_EXAMPLE" \
    >"$SB_TMP/example" 2>"$SB_TMP/err"
SB_RC=$?
SB_ERR=$(cat "$SB_TMP/err")
example=$(cat "$SB_TMP/example")
check_rc example.rc 0
check_eq example.stderr "$SB_ERR" ""
check_eq example.header "$(printf '%s\n' "$example" | sed -n 2p)" "theta_deg  emissivity  the_paper  flat_sea"
rows=$(printf '%s\n' "$example" | tail -n +3)
check_eq example.rows "$(printf '%s\n' "$rows" | grep -c '')" 6
ex_theta=$(printf '%s\n' "$rows" | awk '{ print $1 + 0 }')
ex_eps=$(printf '%s\n' "$rows" | awk '{ print $2 }')
ex_paper=$(printf '%s\n' "$rows" | awk '{ print $3 }')
ex_flat=$(printf '%s\n' "$rows" | awk '{ print $4 }')
check_close example.angles "$ex_theta" "$THETAS" 0
# Sane: in (0, 1], falling with the angle; rough water beats the flat
# surface's Fresnel emissivity at grazing angles.
num_check example.range "$(printf '%s\n' "$ex_eps" | awk '$1 <= 0 || $1 > 1 { b = 1 } END { print b + 0 }') == 0"
num_check example.falling \
    "$(printf '%s\n' "$ex_eps" | awk 'NR > 1 && $1 >= p { b = 1 } { p = $1 } END { print b + 0 }') == 0"
num_check example.grazing 'e > f + 0.1' e="$(printf '%s\n' "$ex_eps" | tail -n 1)" \
    f="$(printf '%s\n' "$ex_flat" | tail -n 1)"

# The same numbers from the program: its default is the library's default
# model, and the paper's model is three options away.
thetas=$(echo $THETAS | tr ' ' ,)
sb_run emissivity --wavelength 4 --wind 10 --theta "$thetas"
check_ok program.emissivity
check_close example.vs_program "$ex_eps" "$(csv_all emissivity)" 1e-6
check_match program.model_comment "$(printf '%s\n' "$SB_OUT" | sed -n 1p)" \
    "^# seabake emissivity: correlated shadowing, 2 scales, reflections auto, tolerance 0.001, rule auto$"
sb_run emissivity --wavelength 4 --wind 10 --theta "$thetas" --shadowing smith --scales 1 \
    --reflections 1
check_ok program.paper
check_close example.paper_vs_program "$ex_paper" "$(csv_all emissivity)" 1e-6
check_match program.paper_comment "$(printf '%s\n' "$SB_OUT" | sed -n 1p)" "\(the paper's model\)$"
sb_run emissivity --wavelength 4 --cov 0,0,0 --theta "$thetas"
check_ok program.flat
check_close example.flat_vs_program "$ex_flat" "$(csv_all emissivity)" 1e-6
sb_run spectrum --wind 10
check_ok program.spectrum
sxx=$(printf '%s\n' "$example" | sed -n 1p | sed -n 's/.*sigma_x^2 = \([0-9.]*\).*/\1/p')
syy=$(printf '%s\n' "$example" | sed -n 1p | sed -n 's/.*sigma_y^2 = \([0-9.]*\).*/\1/p')
check_close example.slopes_vs_program "$sxx $syy" "$(csv_col sigma_x2 1) $(csv_col sigma_y2 1)" 1e-5

finish
