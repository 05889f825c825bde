#!/bin/bash
# cli.sh - tests of the seabake command line: CSV headers and row counts,
# option syntax, signed angles, every documented error path with its exit
# code and message, no NaN/inf in any output, and numeric sanity.
# $(SHELL) may be a plain POSIX sh: these scripts need bash.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=cli
. "$(dirname "$0")/lib.sh"

: "${top_srcdir:?top_srcdir must name the source directory}"

SEA=(--wavelength 4 --wind 10)

# ------------------------------------------------------------ headers

sb_run spectrum --wind 10
check_ok spectrum.ok
check_eq spectrum.header "$(csv_header)" "wind_ms,fetch_m,facet_m,kc_radm,sigma_x2,sigma_y2,sigma_xy"
check_eq spectrum.rows "$(csv_rows)" 1
check_csv_shape spectrum.shape

sb_run emissivity "${SEA[@]}" --theta 0:80:10
check_ok emissivity.ok
check_eq emissivity.header "$(csv_header)" "wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity"
check_eq emissivity.rows "$(csv_rows)" 9
check_csv_shape emissivity.shape
check_eq emissivity.theta_list "$(csv_all theta_deg | tr '\n' ' ')" "0 10 20 30 40 50 60 70 80 "

sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs 40,0
check_ok reflectivity.ok
check_eq reflectivity.header "$(csv_header)" \
    "wavelength_um,theta_inc_deg,phi_inc_deg,theta_deg,phi_deg,mx,my,sxx,syy,sxy,reflectivity,brdf_per_sr"
check_eq reflectivity.rows "$(csv_rows)" 1
check_csv_shape reflectivity.shape

sb_run energy "${SEA[@]}" --theta 0
check_ok energy.ok
check_eq energy.header "$(csv_header)" \
    "wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity,reflectance,total"
check_eq energy.rows "$(csv_rows)" 1
check_csv_shape energy.shape
energy_total=$(csv_col total 1)
check_close energy.nadir_total "$energy_total" 1 1e-3

# --------------------------------------------------------- row counts

sb_run emissivity "${SEA[@]}" --theta 10,20,30 --phi 0:270:90
check_eq grid.rows "$(csv_rows)" 12
# theta is the outer loop, phi the inner one.
check_eq grid.order "$(printf '%s\n' "$SB_OUT" | sed -n '2,6p' | cut -d, -f2,3 | tr '\n' ' ')" \
    "10,0 10,90 10,180 10,270 20,0 "

sb_run spectrum --wind 5 --facet 0,1,8,64,512
check_eq spectrum.facet_rows "$(csv_rows)" 5
check_csv_shape spectrum.facet_shape

sb_run emissivity "${SEA[@]}" --theta 0:1:0.1
check_eq list.decimal_step_rows "$(csv_rows)" 11
check_eq list.decimal_step_last "$(csv_col theta_deg 11)" 1

sb_run emissivity "${SEA[@]}" --theta 0:25:10
check_eq list.partial_last_step "$(csv_all theta_deg | tr '\n' ' ')" "0 10 20 "

sb_run emissivity "${SEA[@]}" --theta 45
check_eq list.single "$(csv_rows)" 1

sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs 10,0 --obs "20,0;30,180" --obs=" 5 , 90 "
check_ok obs.accumulate
check_eq obs.rows "$(csv_rows)" 4
check_eq obs.order "$(printf '%s\n' "$SB_OUT" | tail -n +2 | cut -d, -f4,5 | tr '\n' ' ')" \
    "10,0 20,0 30,180 5,90 "

sb_run reflectivity "${SEA[@]}" --inc 40,180 --theta -80:80:40 --phi 0,180
check_ok reflectivity.grid
check_eq reflectivity.grid_rows "$(csv_rows)" 10

# ------------------------------------------------------ option syntax

sb_run emissivity --wavelength 4 --wind 10 --theta 0:80:10 --phi 30
spaced=$SB_OUT
sb_run emissivity --wavelength=4 --wind=10 --theta=0:80:10 --phi=30
check_ok syntax.equals
check_eq syntax.equals_same_output "$SB_OUT" "$spaced"

sb_run emissivity --theta 0:80:10 --phi 30 --wind 10 --wavelength 4
check_eq syntax.any_order "$SB_OUT" "$spaced"

sb_run emissivity --wavelength 4 --wind 3 --wind 10 --theta 0:80:10 --phi 30
check_eq syntax.last_wins "$SB_OUT" "$spaced"

# Negative values are values, with or without '='.
sb_run emissivity "${SEA[@]}" --mean -0.1,0.05 --theta -80:80:10
check_ok negative.ok
check_eq negative.rows "$(csv_rows)" 17
check_eq negative.mx "$(csv_col mx 1)" -0.1
check_eq negative.first_theta "$(csv_col theta_deg 1)" -80
neg_spaced=$SB_OUT
sb_run emissivity "${SEA[@]}" --mean=-0.1,0.05 --theta=-80:80:10
check_eq negative.equals "$SB_OUT" "$neg_spaced"

sb_run emissivity "${SEA[@]}" --theta -30 --phi -45
check_ok negative.phi
check_eq negative.phi_printed "$(csv_col phi_deg 1)" -45

sb_run spectrum --wind 10 --wind-dir -30
check_ok negative.wind_dir
sxy=$(csv_col sigma_xy 1)
num_check negative.wind_dir_rotates 'x < -1e-4' x="$sxy"

# -------------------------------------------------- signed zenith angles

sb_run emissivity "${SEA[@]}" --mean 0.15,-0.15 --theta -30 --phi 0
e_neg=$(csv_col emissivity 1)
sb_run emissivity "${SEA[@]}" --mean 0.15,-0.15 --theta 30 --phi 180
e_pos=$(csv_col emissivity 1)
check_eq fold.emissivity "$e_neg" "$e_pos"
# The mean slope breaks the +-theta symmetry: folding must not just drop the sign.
sb_run emissivity "${SEA[@]}" --mean 0.15,-0.15 --theta 30 --phi 0
check fold.asymmetric [ "$(csv_col emissivity 1)" != "$e_neg" ]

sb_run energy "${SEA[@]}" --mean 0.1,0 --theta -50 --phi 0
t_neg=$(csv_col total 1)
sb_run energy "${SEA[@]}" --mean 0.1,0 --theta 50 --phi 180
check_eq fold.energy "$(csv_col total 1)" "$t_neg"

sb_run reflectivity "${SEA[@]}" --mean 0.1,0.05 --inc -40,0 --obs 30,0
r_neg=$(csv_col reflectivity 1)
sb_run reflectivity "${SEA[@]}" --mean 0.1,0.05 --inc 40,180 --obs -30,180
check_eq fold.reflectivity "$(csv_col reflectivity 1)" "$r_neg"
check_eq fold.printed_as_given "$(csv_col theta_inc_deg 1),$(csv_col theta_deg 1)" "40,-30"

# ------------------------------------------------------ water options

sb_run emissivity "${SEA[@]}" --index 1.35,0.0046 --theta 0:80:40
check_ok index.ok
check_eq index.rows "$(csv_rows)" 3
# With --index the wavelength is a label: no table, so no band check.
sb_run emissivity --wavelength 1.0 --wind 10 --index 1.35,0.0046 --theta 0
check_ok index.any_wavelength

sb_run emissivity "${SEA[@]}" --theta 0:80:40
default_water=$SB_OUT
sb_run emissivity "${SEA[@]}" --theta 0:80:40 --water hale-querry --salinity 35
check_eq water.defaults "$SB_OUT" "$default_water"
sb_run emissivity "${SEA[@]}" --theta 0:80:40 --water segelstein
check_ok water.segelstein
check water.segelstein_differs [ "$SB_OUT" != "$default_water" ]
sb_run emissivity "${SEA[@]}" --theta 0:80:40 --salinity 0
check_ok water.pure
check water.salinity_matters [ "$SB_OUT" != "$default_water" ]

# The shipped table, read as a user file, gives the built-in results.
sb_run emissivity "${SEA[@]}" --theta 0:80:40 --water "$top_srcdir/data/water_nk_hale_querry.csv"
check_ok water.user_file
check_eq water.user_file_same "$SB_OUT" "$default_water"

printf 'wavelength_um,n\n3,1.4\n5,1.3\n' >"$SB_TMP/bad.csv"
sb_run emissivity "${SEA[@]}" --theta 0 --water "$SB_TMP/bad.csv"
check_error water.malformed 2 "--water: "

# ------------------------------------------------------------ errors

sb_run emissivity "${SEA[@]}" --theta 0 --bogus 1
check_error error.unknown_option 2 "unknown option '--bogus'"
sb_run emissivity "${SEA[@]}" --theta 0 -x
check_error error.unknown_short 2 "unknown option '-x'"
sb_run spectrum --wind 10 --theta 0
check_error error.option_of_other_subcommand 2 "unknown option '--theta'"
sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs 40,0 --method fast
check_error error.no_method_for_reflectivity 2 "unknown option '--method'"
sb_run emissivity "${SEA[@]}" --theta 0 stray
check_error error.positional 2 "unexpected argument 'stray'"
sb_run emissivity "${SEA[@]}" --theta
check_error error.missing_value 2 "--theta needs a value"

sb_run emissivity --wavelength 4 --theta 0
check_error error.missing_wind 2 "missing --wind"
sb_run spectrum
check_error error.spectrum_missing_wind 2 "missing --wind"
sb_run emissivity --wind 10 --theta 0
check_error error.missing_wavelength 2 "missing --wavelength"
sb_run emissivity "${SEA[@]}"
check_error error.missing_theta 2 "missing --theta"
sb_run reflectivity "${SEA[@]}" --obs 40,0
check_error error.missing_inc 2 "missing --inc"
sb_run reflectivity "${SEA[@]}" --inc 40,180
check_error error.missing_obs 2 "--obs"

sb_run emissivity "${SEA[@]}" --theta 90
check_error error.theta_90 2 "--theta: 90 is outside \(-90, 90\) degrees"
sb_run emissivity "${SEA[@]}" --theta -90
check_error error.theta_minus_90 2 "--theta: -90 is outside"
sb_run emissivity "${SEA[@]}" --theta 0:95:5
check_error error.theta_list_end 2 "--theta: 95 is outside"
sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs "10,0;95,0"
check_error error.obs_theta 2 "--obs: 95 is outside \(-90, 90\)"
sb_run reflectivity "${SEA[@]}" --inc 90,0 --obs 10,0
check_error error.inc_theta 2 "--inc: 90 is outside"
sb_run reflectivity "${SEA[@]}" --inc 40 --obs 10,0
check_error error.inc_form 2 "--inc: expected THETA,PHI"
sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs "10,0;"
check_error error.obs_empty_pair 2 "--obs: expected THETA,PHI"
sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs 10,0 --theta 20
check_error error.obs_and_theta 2 "--theta cannot be combined with --obs"

sb_run emissivity --wavelength 1.0 --wind 10 --theta 0
check_error error.wavelength_short 2 "--wavelength: .*outside"
sb_run emissivity --wavelength 20 --wind 10 --theta 0
check_error error.wavelength_long 2 "--wavelength: .*outside"
sb_run energy --wavelength 20 --wind 10 --theta 0
check_error error.energy_wavelength 2 "--wavelength: "
sb_run reflectivity --wavelength 1 --wind 10 --inc 40,180 --obs 40,0
check_error error.reflectivity_wavelength 2 "--wavelength: "
sb_run emissivity --wavelength -4 --wind 10 --theta 0
check_error error.wavelength_negative 2 "--wavelength: -4 is outside \(0, inf\) um"

sb_run emissivity --wavelength 4 --wind -1 --theta 0
check_error error.wind_negative 2 "--wind: -1 is outside \[0.5, 40\] m/s"
sb_run emissivity --wavelength 4 --wind 40.5 --theta 0
check_error error.wind_above_max 2 "--wind: 40.5 is outside \[0.5, 40\] m/s"
sb_run spectrum --wind inf
check_error error.wind_inf 2 "--wind: inf is not a finite number"
sb_run spectrum --wind 10 --fetch 500
check_error error.fetch_short 2 "--fetch: 500 is outside \[1000, inf\] m"
sb_run spectrum --wind 10 --fetch -inf
check_error error.fetch_minus_inf 2 "--fetch: -inf"
sb_run spectrum --wind 10 --fetch inf
check_ok fetch.inf_accepted
check_eq fetch.inf_printed_as_0 "$(csv_col fetch_m 1)" 0
sb_run spectrum --wind 10 --fetch 20000
check_eq fetch.finite_printed "$(csv_col fetch_m 1)" 20000
sb_run spectrum --wind 10 --facet -1
check_error error.facet_negative 2 "--facet: -1 is outside \[0, 1000000\] m"
sb_run emissivity "${SEA[@]}" --theta 0 --salinity 50
check_error error.salinity 2 "--salinity: 50 is outside \[0, 45\] g/kg"
sb_run emissivity "${SEA[@]}" --theta 0 --mean 6,0
check_error error.mean_range 2 "--mean: 6 is outside \[-5, 5\]"
sb_run emissivity "${SEA[@]}" --theta 0 --mean 0.1
check_error error.mean_form 2 "--mean: expected MX,MY"
sb_run emissivity --wavelength 4 --theta 0 --cov 0.01,0.01,0.02
check_error error.cov_not_psd 2 "--cov: SXY = 0.02"
sb_run emissivity --wavelength 4 --theta 0 --cov -0.01,0.01,0
check_error error.cov_negative 2 "--cov: -0.01 is outside \[0, 10\]"
sb_run emissivity --wavelength 4 --theta 0 --cov 0.036,0.025,0 --facet 8
check_error error.cov_and_facet 2 "--facet cannot be combined with --cov"
sb_run emissivity --wavelength 4 --theta 0 --cov 0.036,0.025,0 --wind 10
check_error error.cov_and_wind 2 "--wind cannot be combined with --cov"
sb_run emissivity "${SEA[@]}" --theta 0 --index 1.35,0.0046 --water segelstein
check_error error.index_and_water 2 "--water cannot be combined with --index"
sb_run emissivity "${SEA[@]}" --theta 0 --index 0,0.1
check_error error.index_n 2 "--index: 0 is outside \(0, inf\)"
sb_run emissivity "${SEA[@]}" --theta 0 --index 1.3,-0.1
check_error error.index_k 2 "--index: -0.1 is outside \[0, inf\)"

sb_run emissivity "${SEA[@]}" --theta 0:10:0
check_error error.list_zero_step 2 "--theta: the step of '0:10:0' must be > 0"
sb_run emissivity "${SEA[@]}" --theta 10:0:1
check_error error.list_backwards 2 "--theta: '10:0:1' runs backwards"
sb_run emissivity "${SEA[@]}" --theta 0:10
check_error error.list_two_parts 2 "--theta: '0:10' is not a list"
sb_run emissivity "${SEA[@]}" --theta 0,,10
check_error error.list_empty_item 2 "--theta: '' is not a number"
sb_run emissivity "${SEA[@]}" --theta 0:80:1e-4
check_error error.list_too_long 2 "--theta: .* more than 100000"
sb_run emissivity --wavelength 4 --wind ten --theta 0
check_error error.not_a_number 2 "--wind: 'ten' is not a number"
sb_run emissivity --wavelength 4 --wind 10abc --theta 0
check_error error.trailing_garbage 2 "--wind: '10abc' is not a number"
sb_run emissivity --wavelength 4 --wind= --theta 0
check_error error.empty_value 2 "--wind: '' is not a number"
sb_run emissivity --wavelength 4 --wind nan --theta 0
check_error error.nan 2 "--wind: 'nan' is not a number"
sb_run emissivity --wavelength 4 --wind 0x10 --theta 0
check_error error.hex 2 "--wind: '0x10' is not a number"
sb_run emissivity "${SEA[@]}" --theta 0 --phi 1e999
check_error error.overflow 2 "--phi: 1e999 is too large"
sb_run emissivity "${SEA[@]}" --theta 0 --phi inf
check_error error.phi_inf 2 "--phi: inf is not a finite number"

sb_run emissivity "${SEA[@]}" --theta 0 --method bogus
check_error error.method 2 "--method: 'bogus' is not one of auto, fast, full"
sb_run emissivity "${SEA[@]}" --theta 0 --water /nonexistent.csv
check_error error.water_unreadable 3 "--water: /nonexistent.csv"
check_no_match error.io_no_help_hint "$SB_ERR" "see 'seabake help"
sb_run emissivity "${SEA[@]}" --theta 0 --water "$SB_TMP"
check error.water_directory [ "$SB_RC" -eq 3 ]

sb_run bogus
check_error error.unknown_subcommand 2 "unknown subcommand 'bogus'"
sb_run --wind 10
check_error error.option_first 2 "unknown option '--wind'"
sb_run
check_rc error.no_arguments 2
check_match error.no_arguments_usage "$SB_ERR" "^Usage: seabake"
check_eq error.no_arguments_stdout "$SB_OUT" ""
sb_run help bogus
check_error error.help_unknown 2 "unknown subcommand 'bogus'"

# Usage errors point to the help of the subcommand.
sb_run emissivity "${SEA[@]}" --theta 95
check_match error.help_hint "$SB_ERR" "\(see 'seabake help emissivity'\)$"

# ------------------------------------------------------------- help

for args in help --help -h; do
    sb_run $args
    check_rc "help.$args.rc" 0
    check_match "help.$args.usage" "$SB_OUT" "^Usage: seabake SUBCOMMAND"
    check_eq "help.$args.stderr" "$SB_ERR" ""
done
for cmd in spectrum emissivity reflectivity energy; do
    sb_run help "$cmd"
    check_rc "help.$cmd.rc" 0
    check_match "help.$cmd.usage" "$SB_OUT" "^Usage: seabake $cmd"
    usage=$SB_OUT
    sb_run "$cmd" --help
    check_eq "help.$cmd.--help" "$SB_OUT" "$usage"
    sb_run "$cmd" --wind 10 -h
    check_eq "help.$cmd.-h" "$SB_OUT" "$usage"
done
sb_run --version
check_rc version.rc 0
check_match version.text "$SB_OUT" "^seabake [0-9]+\.[0-9]+"

# ------------------------------------------------------ write failures

if [ -w /dev/full ]; then
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" spectrum --wind 10 >/dev/full 2>"$SB_TMP/err"
    SB_RC=$? SB_OUT= SB_ERR=$(cat "$SB_TMP/err") SB_CMD="seabake spectrum --wind 10 >/dev/full"
    check_error write.full_disk 3 "standard output"
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" help >/dev/full 2>"$SB_TMP/err"
    SB_RC=$? SB_OUT= SB_ERR=$(cat "$SB_TMP/err") SB_CMD="seabake help >/dev/full"
    check_error write.help_full_disk 3 "standard output"
else
    echo "cli: /dev/full not available, write-failure checks skipped" >&2
fi

# ---------------------------------------------- no NaN or inf anywhere

THETAS=-89.99,-89.9,-85,-60,-30,0,30,60,85,89.9,89.99
for sea in "--wind 0.5" "--wind 30" "--wind 10 --mean 1,0" "--wind 5 --facet 2 --mean -0.3,0.2" \
    "--cov 1e-8,1e-8,0" "--cov 1e-8,1e-8,0 --mean 1,0" "--wind 10 --wind-dir 60 --fetch 5000"; do
    # shellcheck disable=SC2086
    sb_run emissivity --wavelength 4 $sea --theta $THETAS --phi 0,45,90,180
    check_ok "sweep.emissivity[$sea]"
    check_csv_shape "sweep.emissivity_shape[$sea]"
    bad=$(csv_all emissivity | awk '$1 < 0 || $1 > 1' | head -n 1)
    check_eq "sweep.emissivity_in_0_1[$sea]" "$bad" ""

    # shellcheck disable=SC2086
    sb_run emissivity --wavelength 11 $sea --theta $THETAS --method fast
    check_ok "sweep.fast[$sea]"
    check_csv_shape "sweep.fast_shape[$sea]"

    for inc in 40,180 0,0 -89.99,30; do
        # shellcheck disable=SC2086
        sb_run reflectivity --wavelength 4 $sea --inc $inc --theta $THETAS --phi 0,90,180
        check_ok "sweep.reflectivity[$sea;$inc]"
        check_csv_shape "sweep.reflectivity_shape[$sea;$inc]"
        bad=$(printf '%s\n' "$SB_OUT" | tail -n +2 | awk -F, '$11 < 0 || $12 < 0' | head -n 1)
        check_eq "sweep.reflectivity_nonneg[$sea;$inc]" "$bad" ""
    done

    # shellcheck disable=SC2086
    sb_run energy --wavelength 4 $sea --theta -89.99,-60,0,60,89.99 --phi 0,90
    check_ok "sweep.energy[$sea]"
    check_csv_shape "sweep.energy_shape[$sea]"
    bad=$(printf '%s\n' "$SB_OUT" | tail -n +2 | awk -F, '$9 < 0 || $9 > 1 || $10 < 0 || $11 > 1 + 1e-6' | head -n 1)
    check_eq "sweep.energy_bounds[$sea]" "$bad" ""
done

sb_run spectrum --wind 0.5 --facet 0,0.01,1,100,1e6
check_ok sweep.spectrum_low_wind
check_csv_shape sweep.spectrum_low_wind_shape
sb_run spectrum --wind 40 --fetch 1000 --facet 0:1000:100
check_ok sweep.spectrum_high_wind
check_csv_shape sweep.spectrum_high_wind_shape

# --------------------------------------------------- numeric sanity

# The paper's low-resolution slopes at 10 m/s: sigma_x = 0.19, sigma_y = 0.16.
sb_run spectrum --wind 10
sx2=$(csv_col sigma_x2 1)
sy2=$(csv_col sigma_y2 1)
num_check spectrum.sigma_x 'sqrt(v) > 0.185 && sqrt(v) < 0.195' v="$sx2"
num_check spectrum.sigma_y 'sqrt(v) > 0.155 && sqrt(v) < 0.165' v="$sy2"
num_check spectrum.sigma_x2 'v > 0.034 && v < 0.038' v="$sx2"
num_check spectrum.sigma_y2 'v > 0.0235 && v < 0.0265' v="$sy2"

# A wind along y swaps the two variances.
sb_run spectrum --wind 10 --wind-dir 90
check_close spectrum.wind_dir_90_x "$(csv_col sigma_x2 1)" "$sy2" 1e-9
check_close spectrum.wind_dir_90_y "$(csv_col sigma_y2 1)" "$sx2" 1e-9

# Sub-facet variance grows with the facet size up to the low-resolution value.
sb_run spectrum --wind 10 --facet 1,8,64,1e6
check_eq spectrum.kc "$(csv_col kc_radm 1)" 3.141592654
v1=$(csv_col sigma_x2 1) v8=$(csv_col sigma_x2 2) v64=$(csv_col sigma_x2 3) vbig=$(csv_col sigma_x2 4)
num_check spectrum.facet_monotonic 'a < b && b <= c && c <= d * (1 + 1e-9)' a="$v1" b="$v8" c="$v64" d="$vbig"
num_check spectrum.facet_converges 'd / lr > 1 - 1e-6 && d / lr < 1 + 1e-6' d="$vbig" lr="$sx2"

# The emissivity option plumbing: --facet uses the sub-facet covariance.
sb_run emissivity "${SEA[@]}" --facet 8 --theta 0
check_eq emissivity.facet_cov "$(csv_col sxx 1)" "$v8"

# Energy at nadir (4 um, 10 m/s): no loss.
sb_run energy "${SEA[@]}" --theta 0 --phi 0
check_close energy.nadir "$(csv_col total 1)" 1 1e-3
check_close energy.sum "$(awk -v e="$(csv_col emissivity 1)" -v r="$(csv_col reflectance 1)" \
    'BEGIN { printf "%.12g", e + r }')" "$(csv_col total 1)" 1e-9

# The BRDF column is the reflectivity over cos(theta_inc).
sb_run reflectivity "${SEA[@]}" --inc 40,180 --obs 40,0
check_close reflectivity.brdf "$(awk -v b="$(csv_col brdf_per_sr 1)" -v r="$(csv_col reflectivity 1)" \
    'BEGIN { printf "%.12g", b * cos(40 * atan2(0, -1) / 180) / r }')" 1 1e-8
# A nearly flat sea reflects only near the mirror direction (40, 0).
sb_run reflectivity --wavelength 4 --cov 1e-4,1e-4,0 --inc 40,180 --obs "40,0;20,0;40,90"
num_check reflectivity.glint 'm > 1000 * a && m > 1000 * b' \
    m="$(csv_col reflectivity 1)" a="$(csv_col reflectivity 2)" b="$(csv_col reflectivity 3)"

# The fast method (Eq 12) stays within 1 % of Eq 7 for the paper's case.
sb_run emissivity --wavelength 4 --cov 0.0361,0.0256,0 --mean 0.15,-0.15 --theta -60:60:20
auto_e=$(csv_all emissivity | tr '\n' ' ')
sb_run emissivity --wavelength 4 --cov 0.0361,0.0256,0 --mean 0.15,-0.15 --theta -60:60:20 --method fast
fast_e=$(csv_all emissivity | tr '\n' ' ')
check_close emissivity.fast_vs_auto "$fast_e" "$auto_e" 0.01

finish
