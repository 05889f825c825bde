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
check_eq grid.order "$(csv_data | sed -n '2,6p' | cut -d, -f2,3 | tr '\n' ' ')" \
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
check_error error.index_n 2 "--index: 0 is outside \[1, 3\]"
sb_run emissivity "${SEA[@]}" --theta 0 --index 1.3,-0.1
check_error error.index_k 2 "--index: -0.1 is outside \[0, 10\]"
# --index is bounded as a water table's columns (n in [1, 3], k in [0, 10]):
# an absurd index is refused, not turned into a reflectivity of 0.
sb_run reflectivity --index 1e155,0 --wavelength 4 --wind 8 --inc 30,0 --obs 30,180
check_error error.index_huge 2 "--index: 1e155 is outside \[1, 3\]"
sb_run energy "${SEA[@]}" --theta 0 --index 1.3,11
check_error error.index_k_max 2 "--index: 11 is outside \[0, 10\]"
sb_run emissivity "${SEA[@]}" --theta 0 --index 3,10
check_ok error.index_bounds_ok
# Everything is validated before anything is printed: a facet size too
# small for its cutoff pi/L leaves standard output empty.
sb_run spectrum --wind 8 --facet 1,4.9e-324
check_error spectrum.facet_tiny 2 "--facet: 4.94066e-324 m is too small \(its cutoff wavenumber pi/L is not finite\)"

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

# The emissivity rule is --emissivity, as the scene file's [model]
# emissivity key; --method is the facet method of slopes and convergence.
sb_run emissivity "${SEA[@]}" --theta 0 --emissivity bogus
check_error error.emissivity_rule 2 "--emissivity: 'bogus' is not one of auto, fast, full"
sb_run emissivity "${SEA[@]}" --theta 0 --method fast
check_error error.emissivity_no_method 2 "unknown option '--method'"
sb_run energy "${SEA[@]}" --theta 0 --method fast
check_error error.energy_no_method 2 "unknown option '--method'"
sb_run energy "${SEA[@]}" --theta 0 --emissivity full
check_ok energy.emissivity_full
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

# The help's accuracy of the auto rule is the manual's (seabake(1), REFERENCE:
# within 1e-6 of the adaptive Eq 7), not an older, looser figure.
sb_run help emissivity
check_match help.emissivity_auto_figure "$SB_OUT" "within 1e-6 of full to 85 deg"
check help.emissivity_auto_manual grep -q 'within 1e\\-6$' "$MANPAGE"

for args in help --help -h; do
    sb_run $args
    check_rc "help.$args.rc" 0
    check_match "help.$args.usage" "$SB_OUT" "^Usage: seabake SUBCOMMAND"
    check_eq "help.$args.stderr" "$SB_ERR" ""
done
for cmd in spectrum emissivity reflectivity energy slopes convergence bench; do
    sb_run help "$cmd"
    check_rc "help.$cmd.rc" 0
    check_match "help.$cmd.usage" "$SB_OUT" "^Usage: seabake $cmd"
    usage=$SB_OUT
    sb_run "$cmd" --help
    check_eq "help.$cmd.--help" "$SB_OUT" "$usage"
    # -h wins over the other options, whatever they are.
    if [ "$cmd" = bench ]; then sb_run "$cmd" --quick -h; else sb_run "$cmd" --wind 10 -h; fi
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
    skip "/dev/full not available: the write-failure checks are skipped"
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
    sb_run emissivity --wavelength 11 $sea --theta $THETAS --emissivity fast
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
sb_run emissivity --wavelength 4 --cov 0.0361,0.0256,0 --mean 0.15,-0.15 --theta -60:60:20 --emissivity fast
fast_e=$(csv_all emissivity | tr '\n' ' ')
check_close emissivity.fast_vs_auto "$fast_e" "$auto_e" 0.01


# ================================================================ slopes

SLOPES=(slopes --wind 10 --facet 4 --size 8,6 --quiet)
sb_run "${SLOPES[@]}"
check_ok slopes.ok
check_eq slopes.header "$(csv_header)" "i,j,x_m,y_m,mx,my,mxx,mxy,myy,h"
check_eq slopes.rows "$(csv_rows)" 48
check_csv_shape slopes.shape
# Centred on the origin, j outer and i inner; x_m, y_m are facet centres.
check_eq slopes.first "$(csv_col i 1),$(csv_col j 1),$(csv_col x_m 1),$(csv_col y_m 1)" "-4,-3,-14,-10"
check_eq slopes.second "$(csv_col i 2),$(csv_col j 2)" "-3,-3"
check_eq slopes.last "$(csv_col i 48),$(csv_col j 48),$(csv_col x_m 48),$(csv_col y_m 48)" "3,2,14,10"
# Raw moments hold the mean: M - m m^T is a covariance (PSD).
bad=$(printf '%s\n' "$SB_OUT" | tail -n +2 | awk -F, '{
    cxx = $7 - $5 * $5; cyy = $9 - $6 * $6; cxy = $8 - $5 * $6
    if (cxx < 0 || cyy < 0 || cxy * cxy > cxx * cyy * (1 + 1e-6)) print }' | head -n 1)
check_eq slopes.psd "$bad" ""
slopes_ref=$SB_OUT

# The same seed gives the same bytes; another seed another sea.
sb_run "${SLOPES[@]}" --seed 1
check_eq slopes.same_seed "$SB_OUT" "$slopes_ref"
sb_run "${SLOPES[@]}" --seed 2
check_ok slopes.seed2
check slopes.other_seed [ "$SB_OUT" != "$slopes_ref" ]
sb_run "${SLOPES[@]}" --seed 18446744073709551615
check_ok slopes.seed_max

# The thread count changes nothing, whatever the method and generator.
for m in "--method variable-step" "--method variable-step-2n --n 2" "--method one-meter" \
    "--generator fft" "--method variable-step-2n --n 1 --generator fft"; do
    # shellcheck disable=SC2086
    OMP_NUM_THREADS=1 sb_run slopes --wind 10 --facet 4 --size 16,12 --quiet $m
    check_ok "slopes.threads1[$m]"
    one=$SB_OUT
    # shellcheck disable=SC2086
    OMP_NUM_THREADS=2 sb_run slopes --wind 10 --facet 4 --size 16,12 --quiet $m
    check_eq "slopes.threads2[$m]" "$SB_OUT" "$one"
    # shellcheck disable=SC2086
    OMP_NUM_THREADS=3 sb_run slopes --wind 10 --facet 4 --size 16,12 --quiet $m
    check_eq "slopes.threads3[$m]" "$SB_OUT" "$one"
done

# Methods differ; one-meter at L = L0 is Variable Step on the FFT patch.
sb_run slopes --wind 10 --facet 4 --size 8,6 --quiet --method variable-step-2n --n 2
check_ok slopes.2n
check slopes.2n_differs [ "$SB_OUT" != "$slopes_ref" ]
sb_run slopes --wind 10 --facet 1 --size 8,6 --quiet --method one-meter
one_meter=$SB_OUT
sb_run slopes --wind 10 --facet 1 --size 8,6 --quiet --generator fft
check_eq slopes.one_meter_is_fft_variable_step "$SB_OUT" "$one_meter"

# Time moves the waves; a loop period brings them back.
sb_run "${SLOPES[@]}" --time 3
check slopes.time_moves [ "$SB_OUT" != "$slopes_ref" ]
sb_run "${SLOPES[@]}" --loop-period 20
loop0=$(csv_all mx)
sb_run "${SLOPES[@]}" --loop-period 20 --time 20
check_close slopes.loop_period "$(csv_all mx)" "$loop0" 1e-9
sb_run "${SLOPES[@]}" --loop-period 20 --time 10
check slopes.loop_half_differs [ "$(csv_all mx)" != "$loop0" ]

# The summary line: one line on stderr, stdout unchanged.
sb_run slopes --wind 10 --facet 4 --size 8,6
check_rc slopes.summary_rc 0
check_eq slopes.summary_stdout "$SB_OUT" "$slopes_ref"
check_eq slopes.summary_lines "$(printf '%s\n' "$SB_ERR" | grep -c '')" 1
check_match slopes.summary "$SB_ERR" \
    "^slopes: 8 x 6 facets of 4 m, variable-step n=0 \(sinusoids\): mean slope .*; variance of facet means .*; mean sub-facet covariance .*/LR x [0-9.]+, y [0-9.]+$"
# Generated plus sub-facet variance is the low-resolution variance on a
# rectangle (512 m) much larger than the waves.
for m in "--method variable-step" "--method variable-step-2n --n 2" "--method one-meter"; do
    # shellcheck disable=SC2086
    sb_run slopes --wind 10 --facet 8 --size 64,64 $m
    ratio=$(printf '%s\n' "$SB_ERR" | sed -n 's|.*/LR x \([0-9.]*\), y \([0-9.]*\)$|\1 \2|p')
    num_check "slopes.lr_ratio[$m]" 'x > 0.95 && x < 1.05 && y > 0.95 && y < 1.05' \
        x="${ratio% *}" y="${ratio#* }"
done

# Files: CSV (the same bytes as stdout) and EXR, nothing left behind.
sb_run "${SLOPES[@]}" -o "$SB_TMP/s.csv"
check_rc slopes.csv_file_rc 0
check_eq slopes.csv_file_stdout "$SB_OUT" ""
check_eq slopes.csv_file_same "$(cat "$SB_TMP/s.csv")" "$slopes_ref"
sb_run "${SLOPES[@]}" -o="$SB_TMP/s.CSV"
check_eq slopes.csv_file_upper "$(cat "$SB_TMP/s.CSV")" "$slopes_ref"
sb_run "${SLOPES[@]}" -o "$SB_TMP/s.exr"
check_rc slopes.exr_rc 0
check_eq slopes.exr_quiet "$SB_OUT$SB_ERR" ""
check_eq slopes.exr_magic "$(od -An -tx1 -N4 "$SB_TMP/s.exr" 2>/dev/null | tr -d ' \n')" "762f3101"
for a in method facet_m n wind wind_dir_deg fetch_m seed time_s origin generator; do
    check "slopes.exr_attr.$a" grep -qa "seabake:$a" "$SB_TMP/s.exr"
done
for ch in mxx mxy myy; do
    check "slopes.exr_channel.$ch" grep -qa "$ch" "$SB_TMP/s.exr"
done
# The lower-left corner of 8 x 6 facets of 4 m centred on the origin.
check slopes.exr_origin grep -qa -- "-16,-12" "$SB_TMP/s.exr"
if have exrheader openexr; then
    check_match slopes.exrheader "$(exrheader "$SB_TMP/s.exr" 2>&1)" "\(0 0\) - \(7 5\)"
fi
check_eq slopes.no_temporary "$(find "$SB_TMP" -maxdepth 1 -name '*.tmp.*' | grep -c '')" 0

# Every usage error: exit 2, the option named, and no file left behind.
slopes_error() {
    local name=$1 rc=$2 re=$3
    shift 3
    rm -f "$SB_TMP"/bad.*
    sb_run slopes "$@" -o "$SB_TMP/bad.exr"
    check_error "$name" "$rc" "$re"
    check_eq "$name.no_file" "$(find "$SB_TMP" -maxdepth 1 -name 'bad.*' | grep -c '')" 0
}
slopes_error slopes.missing_wind 2 "missing --wind" --facet 4
slopes_error slopes.missing_facet 2 "missing --facet" --wind 10
slopes_error slopes.facet_below_finest 2 "--facet: 0.5 m is below --finest 1 m" \
    --wind 10 --facet 0.5 --finest 1
slopes_error slopes.facet_negative 2 "--facet: -1 is outside \(0, 1000000\] m" --wind 10 --facet -1
slopes_error slopes.facet_zero 2 "--facet: 0 is outside" --wind 10 --facet 0
slopes_error slopes.size_zero 2 "--size: 0 is outside \[1, 65536\] facets" \
    --wind 10 --facet 4 --size 0,4
slopes_error slopes.size_big 2 "--size: 65537 is outside" --wind 10 --facet 4 --size 4,65537
slopes_error slopes.size_form 2 "--size: expected NX,NY" --wind 10 --facet 4 --size 4
slopes_error slopes.size_integer 2 "--size: 2.5 is not an integer" --wind 10 --facet 4 --size 2.5,3
slopes_error slopes.method 2 \
    "--method: 'nonsense' is not one of variable-step, variable-step-2n, one-meter" \
    --wind 10 --facet 4 --method nonsense
slopes_error slopes.n_without_2n 2 "--n applies only to --method variable-step-2n, not variable-step" \
    --wind 10 --facet 4 --n 2
slopes_error slopes.n_with_one_meter 2 "--n applies only to --method variable-step-2n" \
    --wind 10 --facet 4 --method one-meter --n 2
slopes_error slopes.n_missing 2 "missing --n" --wind 10 --facet 4 --method variable-step-2n
slopes_error slopes.n_25 2 "--n: 25 is outside \[0, 20\]" \
    --wind 10 --facet 4 --method variable-step-2n --n 25
slopes_error slopes.n_fraction 2 "--n: 1.5 is not an integer" \
    --wind 10 --facet 4 --method variable-step-2n --n 1.5
slopes_error slopes.n_too_fine 2 "--n: sub-facets of 4 m / 2\^3 = 0.5 m are below --finest 1 m" \
    --wind 10 --facet 4 --method variable-step-2n --n 3
slopes_error slopes.one_meter_not_pow2 2 "--facet: one-meter needs L = --finest 1 m times 2\^n" \
    --wind 10 --facet 3 --method one-meter
slopes_error slopes.fft_step 2 "--generator fft samples steps of --finest 1 m" \
    --wind 10 --facet 3 --generator fft
slopes_error slopes.fft_patch 2 "FFT patch of 32768 points per side .*limit of 16384" \
    --wind 10 --facet 8 --size 4096,4096 --generator fft
slopes_error slopes.generator 2 "--generator: 'bogus' is not one of sinusoids, fft" \
    --wind 10 --facet 4 --generator bogus
slopes_error slopes.seed_negative 2 "--seed: '-1' is not an unsigned integer" \
    --wind 10 --facet 4 --seed -1
slopes_error slopes.seed_overflow 2 "--seed: 18446744073709551616 is outside" \
    --wind 10 --facet 4 --seed 18446744073709551616
slopes_error slopes.loop_negative 2 "--loop-period: -1 is outside \[0, inf\) s" \
    --wind 10 --facet 4 --loop-period -1
slopes_error slopes.time_inf 2 "--time: inf is not a finite number" --wind 10 --facet 4 --time inf
slopes_error slopes.finest_zero 2 "--finest: 0 is outside \(0, 1000000\] m" \
    --wind 10 --facet 4 --finest 0
slopes_error slopes.wind 2 "--wind: 41 is outside \[0.5, 40\] m/s" --wind 41 --facet 4
slopes_error slopes.quiet_value 2 "--quiet takes no value" --wind 10 --facet 4 --quiet=1
slopes_error slopes.double_dash_o 2 "unknown option '--o'" --wind 10 --facet 4 --o x.csv
# A rectangle that cannot fit in memory is refused at once (SEA_ERR_NOMEM:
# exit 1), naming the size it needs, before any work or file.
slopes_error slopes.memory 1 "--size 65536,65536 needs [0-9.]+ GiB; this machine has" \
    --wind 10 --facet 1024 --size 65536,65536 --method variable-step-2n --n 10
sb_run slopes --wind 10 --facet 4 -o "$SB_TMP/bad.txt"
check_error slopes.extension 2 "-o: '.*bad.txt' must end in .csv or .exr"
sb_run slopes --wind 10 --facet 4 -o "$SB_TMP/no/such/dir/x.csv"
check_error slopes.no_directory 3 "-o: the directory '.*no/such/dir' does not exist"
check slopes.no_directory_nothing_made test ! -e "$SB_TMP/no"
sb_run slopes --wind 10 --facet 4 -o
check_error slopes.o_value 2 "-o needs a value"
check_eq slopes.errors_no_temporary "$(find "$SB_TMP" -maxdepth 1 -name '*.tmp.*' | grep -c '')" 0

# =========================================================== convergence

CONV=(convergence --wavelength 4 --wind 5,20 --theta 80 --facets 8 --quiet)
sb_run "${CONV[@]}" -o "$SB_TMP/conv"
if have gnuplot gnuplot-nox; then
    check_rc convergence.rc 0
    check_eq convergence.stderr "$SB_ERR" ""
    check_eq convergence.png_magic "$(od -An -tx1 -N8 "$SB_TMP/conv/convergence.png" 2>/dev/null |
        tr -d ' \n')" "89504e470d0a1a0a"
else
    # without gnuplot: the CSV and the table (the result), no chart, exit 1
    check_rc convergence.no_gnuplot 1
    check_match convergence.no_gnuplot_msg "$SB_ERR" "gnuplot not found: convergence.csv written, chart not drawn"
fi
conv_out=$SB_OUT
check_match convergence.table "$conv_out" "^U10_m_s +x +L_m +facets"
check_match convergence.line5 "$conv_out" \
    "^U10 = 5 m/s: emissivity within 0.1% of LR for L >= [0-9]+ m, reflectivity for L >= [0-9]+ m$"
check_match convergence.line20 "$conv_out" \
    "^U10 = 20 m/s: emissivity within 0.1% of LR for L >= [0-9]+ m, reflectivity for L >= [0-9]+ m$"
# The paper (Fig. 5-6): converged by 64 m at 5 m/s, by 512 m at 20 m/s;
# higher wind, later convergence.
l5=$(printf '%s\n' "$conv_out" | sed -n 's/^U10 = 5 m\/s: emissivity within 0.1% of LR for L >= \([0-9]*\) m, reflectivity for L >= \([0-9]*\) m$/\1 \2/p')
l20=$(printf '%s\n' "$conv_out" | sed -n 's/^U10 = 20 m\/s: emissivity within 0.1% of LR for L >= \([0-9]*\) m, reflectivity for L >= \([0-9]*\) m$/\1 \2/p')
num_check convergence.sizes 'e5 >= 8 && e5 <= 128 && r5 <= 128 && e20 >= 128 && r20 >= 128 && e20 > e5' \
    e5="${l5% *}" r5="${l5#* }" e20="${l20% *}" r20="${l20#* }"
check_eq convergence.no_temporary "$(find "$SB_TMP/conv" -name '*.tmp.*' | grep -c '')" 0

conv_csv=$(cat "$SB_TMP/conv/convergence.csv" 2>/dev/null)
check_match convergence.comments "$(printf '%s\n' "$conv_csv" | grep '^#')" \
    "wavelength_um=4 theta_obs_deg=80 phi_obs_deg=0 theta_inc_deg=-80 phi_inc_deg=0"
check_match convergence.comment_seed "$(printf '%s\n' "$conv_csv" | grep '^#')" \
    "seed=1 method=variable-step .*converged=0.001"
check_match convergence.comment_water "$(printf '%s\n' "$conv_csv" | grep '^#')" \
    "water=hale-querry salinity_g_kg=35"
SB_OUT=$(printf '%s\n' "$conv_csv" | grep -v '^#')
check_eq convergence.header "$(csv_header)" \
    "wind_m_s,x,L_m,facets,n,emis_lr,emis_origin,emis_mean,emis_rms_dev,emis_max_dev,refl_lr,refl_origin,refl_mean,refl_rms_dev,refl_max_dev,var_mx,var_my"
check_eq convergence.rows "$(csv_rows)" 22
check_csv_shape convergence.shape
check_eq convergence.rows_per_wind "$(csv_all wind_m_s | sort | uniq -c | awk '{ printf "%s:%s ", $2, $1 }')" \
    "20:11 5:11 "
check_eq convergence.x "$(csv_all x | head -n 11 | tr '\n' ' ')" "1 2 3 4 5 6 7 8 9 10 11 "
check_eq convergence.L "$(csv_all L_m | head -n 11 | tr '\n' ' ')" "1 2 4 8 16 32 64 128 256 512 1024 "
check_eq convergence.facets "$(csv_all facets | sort -u)" 8
check_eq convergence.lr_constant "$(csv_all emis_lr | head -n 11 | sort -u | grep -c '')" 1
# Small facets differ from LR, the largest agree with it; the deviations
# are bounded by the largest one.
bad=$(printf '%s\n' "$SB_OUT" | tail -n +2 | awk -F, '
    $2 == 1 && !($10 > 0.001 * $6 && $15 > 0.001 * $11) { print "x=1 converged: " $0 }
    $2 == 11 && !($10 <= 0.001 * $6 && $15 <= 0.001 * $11) { print "x=11 not converged: " $0 }
    !($9 <= $10 + 1e-12 && $14 <= $15 + 1e-12) { print "rms > max: " $0 }
    !($7 > 0 && $7 < 1 && $8 > 0 && $8 < 1) { print "emissivity outside (0, 1): " $0 }')
check_eq convergence.behaviour "$bad" ""

# The same seed gives the same table whatever the thread count.
OMP_NUM_THREADS=1 sb_run convergence --wavelength 4 --wind 10 --theta 60 --facets 4 --sizes 1:6 \
    --quiet -o "$SB_TMP/conv1"
check_rc convergence.threads1_rc "$([ -x "$(command -v gnuplot)" ] && echo 0 || echo 1)"
OMP_NUM_THREADS=2 sb_run convergence --wavelength 4 --wind 10 --theta 60 --facets 4 --sizes 1:6 \
    --quiet -o "$SB_TMP/conv2"
check_eq convergence.threads "$(cat "$SB_TMP/conv2/convergence.csv")" \
    "$(cat "$SB_TMP/conv1/convergence.csv")"
SB_OUT=$(grep -v '^#' "$SB_TMP/conv1/convergence.csv")
check_eq convergence.sizes_option "$(csv_all x | tr '\n' ' ')" "1 2 3 4 5 6 "
check_eq convergence.inc_default "$(grep -c 'theta_inc_deg=-60 phi_inc_deg=0' "$SB_TMP/conv1/convergence.csv")" 1

# The methods: one-meter reduces the facets beyond 4096 m per side,
# variable-step-2n keeps sub-facets >= 1 m.
sb_run convergence --wavelength 4 --wind 10 --theta 60 --facets 2 --sizes 1:4 \
    --method variable-step-2n --n 2 --quiet -o "$SB_TMP/conv3"
SB_OUT=$(grep -v '^#' "$SB_TMP/conv3/convergence.csv")
check_eq convergence.2n_n "$(csv_all n | tr '\n' ' ')" "0 1 2 2 "
# (16 facets of 256 and 512 m, 65,536 and 262,144 sub-facets each: 12 s
# natively; 2 facets under valgrind)
OM_FACETS=16
[ -n "$SEABAKE_WRAPPER" ] && OM_FACETS=2
sb_run convergence --wavelength 4 --wind 10 --theta 60 --facets "$OM_FACETS" --sizes 8:9 \
    --method one-meter --quiet -o "$SB_TMP/conv4"
SB_OUT=$(grep -v '^#' "$SB_TMP/conv4/convergence.csv")
check_eq convergence.one_meter_facets "$(csv_all facets | tr '\n' ' ')" "$OM_FACETS $OM_FACETS "
check_eq convergence.one_meter_n "$(csv_all n | tr '\n' ' ')" "7 8 "

# Without gnuplot the CSV is still written, and the command fails (exit 1).
mkdir -p "$SB_TMP/bin" "$SB_TMP/fakebin"
ln -sf "$(command -v cat)" "$SB_TMP/bin/cat"
PATH="$SB_TMP/bin" sb_run convergence --wavelength 4 --wind 5 --theta 80 --facets 2 --sizes 1:3 \
    --quiet -o "$SB_TMP/conv5"
check_rc convergence.absent_rc 1
check_match convergence.absent_msg "$SB_ERR" \
    "^seabake: error: gnuplot not found: convergence.csv written, chart not drawn$"
check convergence.absent_csv [ -s "$SB_TMP/conv5/convergence.csv" ]
check convergence.absent_no_png [ ! -e "$SB_TMP/conv5/convergence.png" ]
check_match convergence.absent_table "$SB_OUT" "^U10 = 5 m/s: emissivity"
# A gnuplot that fails: exit 3, its message, no chart and no temporary file.
printf '#!/bin/sh\necho "fake gnuplot: refused" >&2\nexit 1\n' >"$SB_TMP/fakebin/gnuplot"
chmod +x "$SB_TMP/fakebin/gnuplot"
PATH="$SB_TMP/fakebin:$SB_TMP/bin" sb_run convergence --wavelength 4 --wind 5 --theta 80 \
    --facets 2 --sizes 1:3 --quiet -o "$SB_TMP/conv6"
check_rc convergence.gnuplot_fails_rc 3
check_match convergence.gnuplot_fails_msg "$SB_ERR" "gnuplot failed: fake gnuplot: refused"
check convergence.gnuplot_fails_no_png [ ! -e "$SB_TMP/conv6/convergence.png" ]
# All or nothing, as render and bake: no CSV, no table on standard output,
# and the directory this run created is removed again.
check_eq convergence.gnuplot_fails_no_table "$SB_OUT" ""
check convergence.gnuplot_fails_no_csv [ ! -e "$SB_TMP/conv6/convergence.csv" ]
check convergence.gnuplot_fails_no_dir [ ! -e "$SB_TMP/conv6" ]
# Into an existing directory: its earlier results are left as they were.
mkdir -p "$SB_TMP/conv7" && printf 'earlier\n' >"$SB_TMP/conv7/convergence.csv"
PATH="$SB_TMP/fakebin:$SB_TMP/bin" sb_run convergence --wavelength 4 --wind 5 --theta 80 \
    --facets 2 --sizes 1:3 --quiet -o "$SB_TMP/conv7"
check_error convergence.gnuplot_fails_keeps_rc 3 "gnuplot failed: fake gnuplot: refused"
check_eq convergence.gnuplot_fails_keeps "$(cat "$SB_TMP/conv7/convergence.csv")" earlier
check_eq convergence.gnuplot_fails_no_temporary \
    "$(find "$SB_TMP/conv7" -name '*.tmp.*' | grep -c '')" 0
# One rule for output paths: -o is created, its parent must exist (no
# nested creation); the error names the missing parent.
sb_run convergence --wavelength 4 --wind 5 --theta 80 --facets 1 --sizes 1 --quiet \
    -o "$SB_TMP/new/sub"
check_error convergence.no_parent 3 "-o: the directory '.*/new' does not exist$"
check convergence.no_parent_nothing_made [ ! -e "$SB_TMP/new" ]

# No output name becomes gnuplot syntax (gnuplot expands backquotes and has
# system()): the chart goes to gnuplot's standard output.  A name with a
# newline and a system() call runs nothing; one with doubled quotes draws
# no stray file beside DIR; both get their chart inside DIR.
evil_cmd=$'x\nsystem("touch '"$SB_TMP"$'/PWNED")\n'
evil_quote="q''x"
evil_shell="b\`touch $SB_TMP/PWNED2\`\$(touch $SB_TMP/PWNED3)'\""
mkdir -p "$SB_TMP/evil"
for name in "$evil_cmd" "$evil_quote" "$evil_shell"; do
    # the names hold slashes: their parent directories must exist
    mkdir -p "$(dirname "$SB_TMP/evil/$name")"
    sb_run convergence --wavelength 4 --wind 8 --theta 30 --facets 1 --sizes 1:1 --quiet \
        -o "$SB_TMP/evil/$name"
    check_rc convergence.hostile_name_rc 0
    check convergence.hostile_name_png [ -s "$SB_TMP/evil/$name/convergence.png" ]
done
check convergence.hostile_nothing_ran [ ! -e "$SB_TMP/PWNED" -a ! -e "$SB_TMP/PWNED2" \
    -a ! -e "$SB_TMP/PWNED3" ]
check_eq convergence.hostile_charts "$(find "$SB_TMP/evil" -name convergence.png -printf x)" xxx
check_eq convergence.hostile_no_stray \
    "$(find "$SB_TMP/evil" -type f ! -name convergence.png ! -name convergence.csv -printf '%f ')" ""
check_eq convergence.hostile_no_temporary "$(find "$SB_TMP/evil" -name '*.tmp.*' | grep -c '')" 0

CONV_ERR=(convergence --wavelength 4 --wind 5 --theta 80 -o "$SB_TMP/conv-bad")
sb_run convergence --wavelength 4 --theta 80
check_error convergence.missing_wind 2 "missing --wind"
sb_run convergence --wavelength 4 --wind 5
check_error convergence.missing_theta 2 "missing --theta"
sb_run convergence --wind 5 --theta 80
check_error convergence.missing_wavelength 2 "missing --wavelength"
sb_run "${CONV_ERR[@]}" --theta 90
check_error convergence.theta 2 "--theta: 90 is outside \[0, 90\) degrees"
sb_run "${CONV_ERR[@]}" --theta -10
check_error convergence.theta_negative 2 "--theta: -10 is outside"
sb_run "${CONV_ERR[@]}" --wind 5,41
check_error convergence.wind_list 2 "--wind: 41 is outside \[0.5, 40\] m/s"
sb_run "${CONV_ERR[@]}" --facets 0
check_error convergence.facets 2 "--facets: 0 is outside \[1, 256\]"
sb_run "${CONV_ERR[@]}" --facets 300
check_error convergence.facets_max 2 "--facets: 300 is outside \[1, 256\]"
# --converged REL: the relative deviation within which a size counts as
# converged (render's and bake's --tolerance is an accuracy target).
sb_run "${CONV_ERR[@]}" --converged 0
check_error convergence.converged 2 "--converged: 0 is outside \(0, 1\)"
sb_run "${CONV_ERR[@]}" --tolerance 0.01
check_error convergence.no_tolerance 2 "unknown option '--tolerance'"
sb_run "${CONV_ERR[@]}" --sizes 5:3
check_error convergence.sizes_backwards 2 "--sizes: '5:3' runs backwards"
sb_run "${CONV_ERR[@]}" --sizes 0:4
check_error convergence.sizes_range 2 "--sizes: 0 is outside \[1, 11\]"
sb_run "${CONV_ERR[@]}" --sizes 1:2:3
check_error convergence.sizes_form 2 "--sizes: '1:2:3' is not X1:X2"
sb_run "${CONV_ERR[@]}" --n 2
check_error convergence.n 2 "--n applies only to --method variable-step-2n"
sb_run "${CONV_ERR[@]}" --inc 90,0
check_error convergence.inc 2 "--inc: 90 is outside"
sb_run "${CONV_ERR[@]}" --wavelength 20
check_error convergence.wavelength 2 "--wavelength: .*outside"
sb_run "${CONV_ERR[@]}" --water /nonexistent.csv
check_error convergence.water 3 "--water: /nonexistent.csv"
check convergence.errors_no_directory [ ! -e "$SB_TMP/conv-bad" ]
printf 'x\n' >"$SB_TMP/plainfile"
sb_run convergence --wavelength 4 --wind 5 --theta 80 --sizes 1 -o "$SB_TMP/plainfile"
check_error convergence.o_not_directory 3 "-o: '.*plainfile' is not a directory"

# ================================================================= bench

sb_run bench --threads 0
check_error bench.threads 2 "--threads: 0 is outside \[1, [0-9]+\] \(at most 4 threads a CPU, [0-9]+ online\)"
sb_run bench --quick=1
check_error bench.quick_value 2 "--quick takes no value"
sb_run bench --size 4
check_error bench.unknown 2 "unknown option '--size'"
if [ -n "$SEABAKE_WRAPPER" ]; then
    skip "bench --quick under $SEABAKE_WRAPPER (too slow; the plain run has it)"
else
    # A directory name gnuplot would interpret, as for convergence above.
    bench_dir="$SB_TMP/bench"$'\nsystem("touch '"$SB_TMP"$'/PWNED_BENCH")\n'"q''x"
    mkdir -p "$(dirname "$bench_dir")"
    sb_run bench --quick --threads 2 -o "$bench_dir"
    check_rc bench.rc 0
    check bench.hostile_nothing_ran [ ! -e "$SB_TMP/PWNED_BENCH" ]
    check bench.hostile_charts [ -s "$bench_dir/speed_accuracy.png" \
        -a -s "$bench_dir/image_speed_accuracy.png" ]
    ln -s "$bench_dir" "$SB_TMP/bench"
    check_eq bench.stderr "$SB_ERR" ""
    check_match bench.table "$SB_OUT" "^section +method +settings"
    check_match bench.ratio "$SB_OUT" \
        "^FFT to sinusoids at equal spectrum resolution \(N = 128, step 1 m\): .* ratio [0-9.e+]+; max \|difference\| [0-9.e+-]+ relative$"
    # The FFT and the same waves as sinusoids agree to round-off.
    diff=$(printf '%s\n' "$SB_OUT" | sed -n 's/.*max |difference| \([0-9.e+-]*\) relative$/\1/p')
    num_check bench.same_waves 'd >= 0 && d < 1e-9' d="$diff"
    check_match bench.optics_table "$SB_OUT" "^quantity +method +settings +s/call +max err +rms err$"
    # No NaN in the tables: the reflectivity, which has no reference, shows "-".
    check_no_match bench.table_no_nan "$SB_OUT" "[Nn][Aa][Nn]|[Ii][Nn][Ff]"
    check_match bench.reflectivity_no_error "$SB_OUT" "^reflectivity +closed-form .* [0-9.e+-]+ +- +-$"
    check_match bench.summary "$SB_OUT" \
        "^Default emissivity \(auto\) over 56 conditions, theta <= 85 deg: [0-9.e+-]+ s per call, [0-9.e+-]+ times faster than full \([0-9.e+-]+ s\); max \|error\| [0-9.e+-]+, RMS [0-9.e+-]+$"
    check_match bench.summary_correlated "$SB_OUT" \
        "^With correlated shadowing \(the program's default\): [0-9.e+-]+ s per call \([0-9.e+-]+ times Smith's\), max \|error\| [0-9.e+-]+ against its reference; target 5e-07 s at 1e-06: ratio target / time [0-9.]+ \(> 1: met\)$"
    SB_OUT=$(cat "$SB_TMP/bench/bench.csv" 2>/dev/null)
    check_eq bench.header "$(csv_header)" \
        "quantity,method,settings,seconds_per_call,max_error,rms_error,conditions"
    # 6 wave rows; full, fast, auto, full and auto with correlated shadowing
    # and 5 x 3 product rules; reflectivity; energy with each of the 3
    # emissivity methods; 3 scenes x (reference + 5 methods) whole images.
    check_eq bench.rows "$(csv_rows)" 48
    check_eq bench.fields "$(printf '%s\n' "$SB_OUT" | awk -F, '{ print NF }' | sort -u)" 7
    check_eq bench.quantities "$(csv_all quantity | uniq | tr '\n' ' ')" \
        "waves emissivity reflectivity energy image "
    check_eq bench.methods "$(csv_all method | uniq -c | awk '{ printf "%s%s ", $1, $2 }')" \
        "1variable-step 1variable-step-2n 1one-meter 1variable-step 1fft-sample 1sinusoids-sample 1full 1fast 1auto 1full 1auto 15rule 1closed-form 1full 1auto 1fast 1reference 1variable-step 3variable-step-2n 1one-meter 1reference 1variable-step 3variable-step-2n 1one-meter 1reference 1variable-step 3variable-step-2n 1one-meter "
    check_eq bench.rules "$(printf '%s\n' "$SB_OUT" | awk -F, '$2 == "rule" { printf "%s;", $3 }')" \
        "Eq 7 GL 8 x GH 4;Eq 7 GL 8 x GH 8;Eq 7 GL 8 x GH 16;Eq 7 GL 16 x GH 4;Eq 7 GL 16 x GH 8;Eq 7 GL 16 x GH 16;Eq 7 GL 32 x GH 4;Eq 7 GL 32 x GH 8;Eq 7 GL 32 x GH 16;Eq 7 GL 64 x GH 4;Eq 7 GL 64 x GH 8;Eq 7 GL 64 x GH 16;Eq 7 GL 128 x GH 4;Eq 7 GL 128 x GH 8;Eq 7 GL 128 x GH 16;"
    check_eq bench.threads_column "$(csv_all conditions | sed -n 's/.*; \([0-9]*\) threads$/\1/p' | sort -u)" 2
    bad=$(printf '%s\n' "$SB_OUT" | tail -n +2 | awk -F, '!($4 > 0)')
    check_eq bench.positive_times "$bad" ""
    # Errors: numbers with 0 <= rms <= max wherever there is a reference
    # (emissivity, energy), none for the closed-form reflectivity.
    bad=$(printf '%s\n' "$SB_OUT" | awk -F, '($1 == "emissivity" || $1 == "energy") &&
        !($5 ~ /^[0-9.e+-]+$/ && $6 ~ /^[0-9.e+-]+$/ && $6 >= 0 && $6 <= $5 + 0)')
    check_eq bench.errors "$bad" ""
    check_eq bench.no_reflectivity_error \
        "$(printf '%s\n' "$SB_OUT" | awk -F, '$1 == "reflectivity" { print $5 $6 }')" ""
    err_of() { printf '%s\n' "$SB_OUT" | awk -F, -v q="$1" -v m="$2" -v s="${3-}" \
        '$1 == q && $2 == m && (s == "" || index($3, s) == 1) { print $5 }'; }
    # The reference against itself is exact; the default meets its 1e-6 with
    # either shadowing (issue 14; its orders, in the settings, depend on the
    # conditions) and Eq 12 does not (its own approximation); more nodes do
    # not do worse.  A setting names the row by its beginning.
    check_eq bench.full_exact "$(err_of emissivity full | sort -u)" 0
    num_check bench.auto_accurate 'e >= 0 && e <= 1e-6' \
        e="$(err_of emissivity auto 'Eq 7 default: GL ')"
    num_check bench.auto_correlated_accurate 'e >= 0 && e <= 1e-6' \
        e="$(err_of emissivity auto "Eq 7 default with correlated shadowing (the program's)")"
    num_check bench.fast_approximate 'e > 1e-3' e="$(err_of emissivity fast)"
    num_check bench.rules_converge 'a > b' a="$(err_of emissivity rule 'Eq 7 GL 8 x GH 4')" \
        b="$(err_of emissivity rule 'Eq 7 GL 128 x GH 16')"
    num_check bench.energy_auto 'e <= 1e-4' e="$(err_of energy auto)"
    # Whole images: errors are numbers, 0 for the references; more
    # sub-facets come closer to the reference on every scene.
    bad=$(printf '%s\n' "$SB_OUT" | awk -F, '$1 == "image" &&
        !($5 ~ /^[0-9.e+-]+$/ && $6 ~ /^[0-9.e+-]+$/ && $6 >= 0 && $6 <= $5 + 0)')
    check_eq bench.image_errors "$bad" ""
    check_eq bench.image_reference "$(printf '%s\n' "$SB_OUT" |
        awk -F, '$1 == "image" && $2 == "reference" { printf "%s;", $5 }')" "0;0;0;"
    for fig in 7 8 9; do
        num_check "bench.image_converges.$fig" 'a > b' \
            a="$(printf '%s\n' "$SB_OUT" | awk -F, -v f="fig$fig" '$1 == "image" && $2 == "variable-step" && index($3, f) == 1 { print $6 }')" \
            b="$(printf '%s\n' "$SB_OUT" | awk -F, -v f="fig$fig n=3" '$1 == "image" && index($3, f) == 1 { print $6 }')"
    done
    check_match bench.image_table "$SB_OUT" "^image,variable-step-2n,fig8 n=2"
    check_eq bench.png_magic "$(od -An -tx1 -N8 "$SB_TMP/bench/speed_accuracy.png" 2>/dev/null |
        tr -d ' \n')" "89504e470d0a1a0a"
    check_eq bench.image_png_magic "$(od -An -tx1 -N8 "$SB_TMP/bench/image_speed_accuracy.png" 2>/dev/null |
        tr -d ' \n')" "89504e470d0a1a0a"
    check bench.no_temporaries [ -z "$(ls -A "$SB_TMP/bench" | grep -v '^bench.csv$' |
        grep -v '^speed_accuracy.png$' | grep -v '^image_speed_accuracy.png$')" ]
fi

# ================================================================ render

# A small copy of the shipped tiny scene (tinier under a memory checker).
RSIZE=48
[ -n "$SEABAKE_WRAPPER" ] && RSIZE=12
RDIR="$SB_TMP/render"
mkdir -p "$RDIR/cwd" || exit 99
sed -e "s/^width = .*/width = $RSIZE/" -e "s/^height = .*/height = $RSIZE/" \
    "$top_srcdir/examples/tiny.ini" >"$RDIR/sea.ini"
RSCENE=$RDIR/sea.ini
magic() {
    od -An -tx1 -N"$2" "$1" 2>/dev/null | tr -d ' \n'
}
# exr_header FILE: the channel list attribute of the header, in hex
# (after "channels\0chlist\0").
exr_header() {
    od -An -tx1 -N4000 "$1" | tr -d ' \n' |
        sed -n 's/.*6368616e6e656c730063686c69737400\(.\{0,240\}\).*/\1/p'
}
# absent COMMAND...: succeeds when the command fails.
absent() {
    ! "$@"
}
# render_files PATTERN: how many files in $RDIR match the glob PATTERN.
render_files() {
    find "$RDIR" -maxdepth 1 -name "$1" | grep -c ''
}

# A FIFO is refused as "not a regular file" (exit 3) without waiting for a
# writer: as the scene file, its water and response tables, and --water.
# timeout turns a regression (a hang in open) into a failure, not a stuck suite.
mkfifo "$RDIR/fifo"
fifo_case() { # fifo_case NAME ARGS...
    local name=$1
    shift
    SB_CMD="seabake $*"
    # shellcheck disable=SC2086
    timeout 30 $SEABAKE_WRAPPER "$SEABAKE" "$@" >"$SB_TMP/out" 2>"$SB_TMP/err"
    SB_RC=$?
    SB_OUT=$(cat "$SB_TMP/out")
    SB_ERR=$(cat "$SB_TMP/err")
    check_error "fifo.$name" 3 "fifo.*not a regular file"
}
fifo_case water_option emissivity --wavelength 4 --wind 8 --theta 0 --water "$RDIR/fifo"
fifo_case scene render "$RDIR/fifo" -o "$RDIR/fifo.exr"
sed -e "s|^\[sea\]|[sea]\nwater = $RDIR/fifo|" "$RSCENE" >"$RDIR/fifo_water.ini"
fifo_case scene_water render "$RDIR/fifo_water.ini" -o "$RDIR/fifo.exr"
sed -e "s|^wavelength = .*|band = 3.5:4.5\nresponse = $RDIR/fifo|" "$RSCENE" >"$RDIR/fifo_resp.ini"
fifo_case scene_response render "$RDIR/fifo_resp.ini" -o "$RDIR/fifo.exr"
check_eq fifo.nothing_written "$(find "$RDIR" -name 'fifo*.exr*' -o -name 'fifo*.png*' | grep -c '')" 0
rm -f "$RDIR/fifo" "$RDIR"/fifo_*.ini

# windows = clipmap with a level no pixel reads: its (infinite) pixel bounds
# were converted to integers before the clipmap window replaced them
# (undefined behaviour, caught by the UBSan run of scripts/test).
printf '%s\n' '[sea]' 'wind_speed = 8' '[sensor]' 'altitude = 50' 'look_zenith = 60' \
    'hfov = 40' 'width = 8' 'height = 6' 'wavelength = 4' '[model]' 'windows = clipmap' \
    >"$RDIR/clip_unread.ini"
sb_run render "$RDIR/clip_unread.ini" -o "$RDIR/clip_unread.exr" --quiet --png none
check_rc render.clipmap_unread_level 0

# The whole plan is checked against memory before anything is allocated:
# 16384^2 pixels need 31 GiB together (each array alone fits in 24 GiB).
sed -e 's/^width = .*/width = 16384/' -e 's/^height = .*/height = 16384/' "$RSCENE" \
    >"$RDIR/huge.ini"
sb_run render "$RDIR/huge.ini" -o "$RDIR/huge.exr"
check_error render.memory_plan 1 "needs [0-9.]+ GiB \(image [0-9.]+, per-pixel geometry [0-9.]+, scratch [0-9.]+ GiB\); this process may use"
check render.memory_plan_nothing [ ! -e "$RDIR/huge.exr" -a ! -e "$RDIR/huge.png" ]
# (Not under a wrapper such as valgrind, nor with AddressSanitizer, whose
# shadow memory cannot start under a small address-space limit.)
if [ -z "$SEABAKE_WRAPPER" ] && ! grep -q __asan_init "$SEABAKE" 2>/dev/null; then
    # A limit on the process (ulimit -v) counts, not only the RAM: 2048^2
    # pixels (0.5 GiB) under a 256 MiB limit.
    sed -e 's/^width = .*/width = 2048/' -e 's/^height = .*/height = 2048/' "$RSCENE" \
        >"$RDIR/big.ini"
    SB_CMD="seabake render big.ini (ulimit -v 262144)"
    (ulimit -v 262144 && exec "$SEABAKE" render "$RDIR/big.ini" -o "$RDIR/big.exr") \
        >"$SB_TMP/out" 2>"$SB_TMP/err"
    SB_RC=$?
    SB_OUT=$(cat "$SB_TMP/out")
    SB_ERR=$(cat "$SB_TMP/err")
    check_error render.memory_rlimit 1 "needs [0-9.]+ GiB .*this process may use 0.25 GiB"
else
    skip "render under ulimit -v, under a wrapper or AddressSanitizer (no shadow memory" \
        "there; the plain run has it)"
fi

sb_run render "$RSCENE" -o "$RDIR/out.exr" --aov level,emissivity,reflectivity,temperature
check_rc render.rc 0
check_eq render.stdout "$SB_OUT" ""
check_match render.summary "$SB_ERR" \
    "^render: .*out\.exr: $RSIZE x $RSIZE, levels [0-9.,]+.*\(LR\) m, 1 frame, [0-9.e+-]+ s, brightness temperature [0-9.]+ to [0-9.]+ K$"
check_eq render.exr_magic "$(magic "$RDIR/out.exr" 4)" "762f3101"
check_eq render.png_magic "$(magic "$RDIR/out.png" 8)" "89504e470d0a1a0a"
check_eq render.png_depth_8 "$(od -An -tu1 -j24 -N1 "$RDIR/out.png" | tr -d ' ')" 8
for a in level emissivity reflectivity temperature; do
    check_eq "render.aov_magic.$a" "$(magic "$RDIR/out.$a.exr" 4)" "762f3101"
done
for a in quantity unit scene time_s seed levels; do
    check "render.exr_attr.$a" grep -qa "seabake:$a" "$RDIR/out.exr"
done
check render.exr_unit grep -qa "W m^-2 sr^-1 um^-1" "$RDIR/out.exr"
check render.exr_scene grep -qaF "$RSCENE" "$RDIR/out.exr"
check render.exr_levels grep -qaE "[0-9]+\(LR\)" "$RDIR/out.exr"
check render.exr_no_frame_attr absent grep -qa "seabake:frame" "$RDIR/out.exr"
check render.aov_unit_reflectivity grep -qa "sr^-1" "$RDIR/out.reflectivity.exr"
if have exrheader openexr; then
    header=$(exrheader "$RDIR/out.exr" 2>&1)
    check_match render.exrheader_channel "$header" "^ *Y, 32-bit floating-point"
    check_match render.exrheader_zip "$header" "zip"
    check_match render.exrheader_size "$header" "\(0 0\) - \($((RSIZE - 1)) $((RSIZE - 1))\)"
    check_match render.exrheader_quantity "$header" 'seabake:quantity .*"radiance"'
    check_match render.exrheader_time "$header" 'seabake:time_s .*"0"'
    for au in level:m emissivity:1 reflectivity:sr^-1 temperature:K; do
        header=$(exrheader "$RDIR/out.${au%%:*}.exr" 2>&1)
        check_match "render.exrheader_unit.${au%%:*}" "$header" \
            "seabake:unit \(type string\): \"$(printf '%s' "${au#*:}" | sed 's/\^/\\^/')\""
        check_match "render.exrheader_aov_channel.${au%%:*}" "$header" "^ *Y, 32-bit floating-point"
    done
fi
check_eq render.no_temporary "$(render_files '*.tmp.*')" 0
# Previews: the main one and each AOV's beside its EXR, grey but the level
# (RGB, a palette per facet size, recorded); the tone curve recorded.
check_eq render.png_grey "$(png_color_type "$RDIR/out.png")" 0
check_eq render.aov_png_level_rgb "$(png_color_type "$RDIR/out.level.png")" 2
for a in emissivity reflectivity temperature; do
    check_eq "render.aov_png_grey.$a" "$(png_color_type "$RDIR/out.$a.png")" 0
done
check_match render.aov_png_palette "$(png_text "$RDIR/out.level.png" seabake:palette)" \
    '^[0-9.]+ m #[0-9a-f]{6}(, [0-9.]+ m( \(LR\))? #[0-9a-f]{6})*$'
check_match render.png_tone "$(png_text "$RDIR/out.png" seabake:tone)" \
    '^brightness temperature: linear [0-9.]+ K black'
check_eq render.aov_png_temperature_same "$(png_text "$RDIR/out.temperature.png" seabake:tone)" \
    "$(png_text "$RDIR/out.png" seabake:tone)"

# --aov stokes: OUT.stokes.exr, channels I, Q, U in the radiance's unit, I
# the radiance itself; the radiance file is byte for byte the one without
# it.  [sensor] polarizer: the radiance a camera behind a polariser reads,
# I + Q cos 2a + U sin 2a; at 0 and 90 deg they average to I (the unit
# suite polar checks the planes to 1e-6); a bake refuses it (its maps are
# I), naming the key.
sb_run render "$RSCENE" -o "$RDIR/pol.exr" --aov stokes --png none --quiet
check_rc render.stokes_rc 0
check render.stokes_file test -s "$RDIR/pol.stokes.exr"
for c in I Q U; do
    sb_run convert "$RDIR/pol.stokes.exr" "$RDIR/pol_$c.npy" --channel "$c"
    check_rc "render.stokes_channel_$c" 0
done
check render.stokes_unit grep -qa "W m^-2 sr^-1" "$RDIR/pol.stokes.exr"
check render.stokes_quantity grep -qa "stokes" "$RDIR/pol.stokes.exr"
sb_run render "$RSCENE" -o "$RDIR/nopol.exr" --png none --quiet
check render.stokes_radiance_same cmp -s "$RDIR/pol.exr" "$RDIR/nopol.exr"
sb_run convert "$RDIR/nopol.exr" "$RDIR/nopol.npy"
check render.stokes_i_is_radiance cmp -s <(tail -c +129 "$RDIR/nopol.npy") <(tail -c +129 "$RDIR/pol_I.npy")
sb_run render "$RSCENE" -o "$RDIR/pol0.exr" --set sensor.polarizer=0 --png none --quiet
check_rc render.polarizer_rc 0
check render.polarizer_differs bash -c "! cmp -s '$RDIR/pol0.exr' '$RDIR/nopol.exr'"
rm -rf "$RDIR/polbake"
sb_run bake "$RSCENE" -o "$RDIR/polbake" --set sensor.polarizer=30
check_error bake.polarizer 2 "\\[sensor\\] polarizer = 30 deg: a bake's maps are the radiance I"
check bake.polarizer_no_dir test ! -e "$RDIR/polbake"

# The same scene gives the same bytes, whatever the thread count.
sb_run render "$RSCENE" -o "$RDIR/again.exr" --threads 1 --quiet
check_eq render.quiet "$SB_OUT$SB_ERR" ""
check render.same_bytes cmp -s "$RDIR/out.exr" "$RDIR/again.exr"
check render.same_png cmp -s "$RDIR/out.png" "$RDIR/again.png"
sb_run render "$RSCENE" -o "$RDIR/again.exr" --threads 2 --quiet
check render.same_bytes_threads cmp -s "$RDIR/out.exr" "$RDIR/again.exr"

# Default names: the scene's base name in the current directory; --png none;
# a 16-bit preview; --format half (the level AOV stays 32-bit).
# shellcheck disable=SC2086
(cd "$RDIR/cwd" && $SEABAKE_WRAPPER "$SEABAKE" render ../sea.ini --quiet) 2>"$RDIR/err"
check_eq render.default_err "$(cat "$RDIR/err")" ""
check render.default_exr test -s "$RDIR/cwd/sea.exr"
check render.default_png test -s "$RDIR/cwd/sea.png"
sb_run render "$RSCENE" -o "$RDIR/nopng.exr" --png none --quiet
check_rc render.png_none_rc 0
check render.png_none test ! -e "$RDIR/nopng.png"
sb_run render "$RSCENE" -o "$RDIR/deep.exr" --png "$RDIR/preview16.png" --png-depth 16 --quiet
check_eq render.png_depth_16 "$(od -An -tu1 -j24 -N1 "$RDIR/preview16.png" | tr -d ' ')" 16
check render.png_named_not_default test ! -e "$RDIR/deep.png"
sb_run render "$RSCENE" -o "$RDIR/half.exr" --format half --aov level --png none --quiet
check_rc render.half_rc 0
check render.aov_png_none test ! -e "$RDIR/half.level.png"
# --png-range: one linear ramp, LO black, HI white, for the temperatures.
sb_run render "$RSCENE" -o "$RDIR/fixed.exr" --png-range 250:320.5 --aov temperature --quiet
check_rc render.png_range_rc 0
check_eq render.png_range_text "$(png_text "$RDIR/fixed.png" seabake:range_K)" "250:320.5"
check_eq render.png_range_tone "$(png_text "$RDIR/fixed.png" seabake:tone)" \
    "brightness temperature: linear 250 K black to 320.5 K white"
check_eq render.png_range_aov "$(png_text "$RDIR/fixed.temperature.png" seabake:range_K)" "250:320.5"
if have exrheader openexr; then
    check_match render.half_channel "$(exrheader "$RDIR/half.exr" 2>&1)" "Y, 16-bit floating-point"
    check_match render.half_level_stays_float "$(exrheader "$RDIR/half.level.exr" 2>&1)" \
        "Y, 32-bit floating-point"
fi

# Frames: numbered sets, t = time + f / rate, nothing without a number.
sb_run render "$RSCENE" -o "$RDIR/anim.exr" --frames 0:1 --aov level --quiet
check_rc render.frames_rc 0
for f in 0000 0001; do
    check_eq "render.frame_exr.$f" "$(magic "$RDIR/anim_$f.exr" 4)" "762f3101"
    check_eq "render.frame_aov.$f" "$(magic "$RDIR/anim_$f.level.exr" 4)" "762f3101"
    check_eq "render.frame_png.$f" "$(magic "$RDIR/anim_$f.png" 8)" "89504e470d0a1a0a"
done
check_eq render.frames_count "$(render_files 'anim*')" 8
check render.frame_time grep -qaF "0.04" "$RDIR/anim_0001.exr"
check render.frame_attr grep -qa "seabake:frame" "$RDIR/anim_0001.exr"
check render.frames_differ absent cmp -s "$RDIR/anim_0000.exr" "$RDIR/anim_0001.exr"
# One tone curve per run, from the first frame: frame 1's preview carries
# frame 0's range, which frame 1 alone would not give.
r0=$(png_text "$RDIR/anim_0000.png" seabake:range_K)
check_match render.frame_range_text "$r0" '^[0-9.e+-]+:[0-9.e+-]+$'
check_eq render.frames_share_range "$(png_text "$RDIR/anim_0001.png" seabake:range_K)" "$r0"
check_eq render.frames_share_tone "$(png_text "$RDIR/anim_0001.png" seabake:tone)" \
    "$(png_text "$RDIR/anim_0000.png" seabake:tone)"
check_eq render.frames_share_palette "$(png_text "$RDIR/anim_0001.level.png" seabake:palette)" \
    "$(png_text "$RDIR/anim_0000.level.png" seabake:palette)"
sb_run render "$RSCENE" -o "$RDIR/alone.exr" --frames 1:1 --quiet
check render.frame_alone_differs [ "$(png_text "$RDIR/alone_0001.png" seabake:range_K)" != "$r0" ]
sb_run render "$RSCENE" -o "$RDIR/slow.exr" --frames 3:3 --frame-rate 10 --png none --quiet
check render.frame_rate grep -qaF "0.3" "$RDIR/slow_0003.exr"
if have exrheader openexr; then
    check_match render.exrheader_frame_time "$(exrheader "$RDIR/anim_0001.exr" 2>&1)" \
        'seabake:time_s .*"0.04"'
    check_match render.exrheader_frame "$(exrheader "$RDIR/slow_0003.exr" 2>&1)" \
        'seabake:frame .*"3"'
    check_match render.exrheader_rate "$(exrheader "$RDIR/slow_0003.exr" 2>&1)" \
        'seabake:time_s .*"0.3"'
fi

# --explain: the levels, why they are low-resolution, the samples.
sb_run render "$RSCENE" -o "$RDIR/explain.exr" --explain --quiet --png none
check_rc render.explain_rc 0
check_match render.explain_level "$SB_ERR" "level +[0-9]+: [0-9.]+ m, window [0-9]+ x [0-9]+ facets from"
check_match render.explain_lr "$SB_ERR" "low-resolution: the waves longer than .* less than a thousandth of the tolerance \\(1e-06\\)"
check_match render.explain_samples "$SB_ERR" "1 spectral sample, at 4 um"
check_no_match render.explain_no_fallback "$SB_ERR" "fallback"
check_match render.explain_emissivity "$SB_ERR" "emissivity: fast \(not scaled by the tolerance\)"
check_match render.explain_waves "$SB_ERR" "waves: [0-9]+ sinusoids, 8 bins per octave x 32 directions \(the same at every tolerance\)$"
check_match render.explain_reflections "$SB_ERR" "reflections: auto \(a second hit in the sea around wherever it can move a pixel by more than 0.01 of the tolerance"
check_no_match render.explain_not_reference "$SB_ERR" "reference:"
# --reflections overrides [model] reflections: said by --explain, written in
# the EXR's header, and out of range refused before any work.
sb_run render "$RSCENE" -o "$RDIR/refl2.exr" --reflections 2 --explain --quiet --png none
check_rc render.reflections_rc 0
check_match render.explain_reflections2 "$SB_ERR" "reflections: 2 \(every facet's mirror ray may meet the sea again, in the sea around"
sb_run render "$RSCENE" -o "$RDIR/refl1.exr" --reflections 1 --explain --quiet --png none
check_match render.explain_reflections1 "$SB_ERR" "reflections: 1 \(the paper"
sb_run render "$RSCENE" -o "$RDIR/reflauto.exr" --reflections auto --quiet --png none
check_rc render.reflections_auto_rc 0
sb_run render "$RSCENE" -o "$RDIR/refldef.exr" --quiet --png none
check render.reflections_auto_is_default cmp -s "$RDIR/reflauto.exr" "$RDIR/refldef.exr"
for bad in 0 4 2.5 x '' AUTO; do
    sb_run render "$RSCENE" -o "$RDIR/refl_bad.exr" --reflections "$bad"
    check_error "render.reflections_bad_$bad" 2 "--reflections: '$bad' is not a number of surface hits \(allowed: auto, 1, 2, 3\)"
    check_eq "render.reflections_bad_nofile_$bad" "$(ls "$RDIR"/refl_bad* 2>/dev/null)" ""
done
# --reference: said by --explain, at least two hits
sb_run render "$RSCENE" -o "$RDIR/ref.exr" --reference --reflections 1 --explain --quiet --png none
check_rc render.reference_rc 0
check_match render.explain_reference "$SB_ERR" "reference: every approximation the tolerance allows replaced by its exact form"
check_match render.explain_reference_hits "$SB_ERR" "reflections: 2 \(every facet's mirror ray"
sb_run emissivity --wavelength 4 --wind 10 --theta 80 --reflections 2 --scales 1
check_rc emissivity.reflections_rc 0
e1=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --reflections 1 --scales 1 | tail -1 | cut -d, -f9)
e2=$(printf '%s\n' "$SB_OUT" | tail -1 | cut -d, -f9)
# 10 m/s, 80 deg, 4 um: a second hit adds 0.031 (seabake-model(7))
check_eq emissivity.reflections_adds "$(awk -v a="$e1" -v b="$e2" 'BEGIN { print (b > a + 0.02 && b < 1) ? "more" : a " -> " b }')" more
# auto, the default, follows the second hit there
ea=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --scales 1 | tail -1 | cut -d, -f9)
check_eq emissivity.reflections_auto "$ea" "$e2"
sb_run emissivity --wavelength 4 --wind 10 --theta 80 --reflections 4
check_error emissivity.reflections_range 2 "--reflections: '4' is not a number of surface hits \(allowed: auto, 1, 2, 3\)"
sb_run energy --wavelength 4 --wind 10 --theta 80 --reflections 2
check_error energy.no_reflections 2 "unknown option '--reflections'"
# --shadowing: correlated by default (--explain says so), smith on request;
# at 80 deg, 4 um, 10 m/s the correlated emissivity is 0.0074 higher
# (seabake-model(7), SHADOWING); a wrong name is a usage error, no file.
sb_run render "$RSCENE" -o "$RDIR/shadow.exr" --explain --quiet --png none
check_match render.explain_shadowing "$SB_ERR" "shadowing: correlated \(a facet turned toward"
sb_run render "$RSCENE" -o "$RDIR/shadow.exr" --shadowing smith --explain --quiet --png none
check_match render.explain_shadowing_smith "$SB_ERR" "shadowing: smith \(the paper's Eq 9c-9e"
for bad in x Smith ''; do
    sb_run render "$RSCENE" -o "$RDIR/shadow_bad.exr" --shadowing "$bad"
    check_error "render.shadowing_bad_$bad" 2 "--shadowing: '$bad' is not one of smith, correlated"
    check_eq "render.shadowing_bad_nofile_$bad" "$(ls "$RDIR"/shadow_bad* 2>/dev/null)" ""
done
sb_run render "$RSCENE" -o "$RDIR/shadow_bad.exr" --set model.shadowing=uncorrelated
check_error render.shadowing_key_bad 2 "\[model\] shadowing: unknown name 'uncorrelated' \(allowed: smith, correlated\)"
es=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --shadowing smith --scales 1 --reflections 1 | tail -1 | cut -d, -f9)
ec=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --scales 1 --reflections 1 | tail -1 | cut -d, -f9)
check_eq emissivity.shadowing_default "$(awk -v s="$es" -v c="$ec" 'BEGIN { d = c - s; print (d > 0.007 && d < 0.008) ? "correlated" : s " -> " c }')" correlated
sb_run energy --wavelength 4 --wind 10 --theta 80 --shadowing x
check_error energy.shadowing_bad 2 "--shadowing: 'x' is not one of smith, correlated"
# --scales: 2 by default in scenes (--explain says so, with the split), 1
# on request, in the emissivity subcommand too (with --wind), where 2 adds
# 0.0077 at 80 deg, 4 um, 10 m/s along the wind with one hit
# (seabake-model(7), TWO SCALES); 2 needs the spectrum; out of range: usage
# errors.
sb_run render "$RSCENE" -o "$RDIR/scales.exr" --explain --quiet --png none
check_match render.explain_scales "$SB_ERR" "scales: 2 \(the slopes of the waves longer than [0-9.]+ m, half the slope variance"
sb_run render "$RSCENE" -o "$RDIR/scales.exr" --scales 1 --explain --quiet --png none
check_match render.explain_scales_1 "$SB_ERR" "scales: 1 \(one Gaussian surface, the paper"
sb_run render "$RSCENE" -o "$RDIR/scales_bad.exr" --scales 3
check_error render.scales_bad 2 "--scales: 3 is outside \[1, 2\]"
check_eq render.scales_bad_nofile "$(ls "$RDIR"/scales_bad* 2>/dev/null)" ""
sb_run render "$RSCENE" -o "$RDIR/scales_bad.exr" --set model.scales=0
check_error render.scales_key_bad 2 "\[model\] scales: 0 is out of range \(allowed: an integer in \[1, 2\]\)"
e1=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --scales 1 --reflections 1 | tail -1 | cut -d, -f9)
e2=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --reflections 1 | tail -1 | cut -d, -f9)
check_eq emissivity.scales_adds "$(awk -v a="$e1" -v b="$e2" 'BEGIN { d = b - a; print (d > 0.007 && d < 0.0085) ? "two scales" : a " -> " b }')" "two scales"
sb_run emissivity --wavelength 4 --cov 0.03,0.02,0 --theta 80 --scales 2
check_error emissivity.scales_cov 2 "--scales 2 splits the sea spectrum's slopes: give --wind, not --cov"
# two scales and second hits together: the default model, as scenes
sb_run emissivity --wavelength 4 --wind 10 --theta 80 --scales 2 --reflections 2
check_rc emissivity.scales_reflections 0
e22=$(printf '%s\n' "$SB_OUT" | tail -1 | cut -d, -f9)
ed=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 | tail -1 | cut -d, -f9)
check_eq emissivity.scales_reflections_default "$e22" "$ed"
# --reference: within the tolerance of the default (10 m/s, 80 deg: 3.5e-5)
er=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 4 --wind 10 --theta 80 --reference | tail -1 | cut -d, -f9)
check_close emissivity.reference_close "$ed" "$er" 1e-4
sb_run energy --wavelength 4 --wind 10 --theta 80 --scales 2
check_error energy.no_scales 2 "unknown option '--scales'"
# --stokes: three more columns, the emissivity column unchanged; at one
# hit and one scale e_q is the one-hit model's that tests/data/mc_stokes.csv
# records (8 decimals there); along the wind e_u vanishes, at 45 deg not
sb_run emissivity --wavelength 10 --wind 10 --theta 80 --phi 0,45 --stokes
check_ok emissivity.stokes
check_eq emissivity.stokes_header "$(csv_header)" \
    "wavelength_um,theta_deg,phi_deg,mx,my,sxx,syy,sxy,emissivity,e_q,e_u,dolp"
check_csv_shape emissivity.stokes_shape
plain=$($SEABAKE_WRAPPER "$SEABAKE" emissivity --wavelength 10 --wind 10 --theta 80 --phi 0,45 |
    tail -2 | cut -d, -f9)
check_eq emissivity.stokes_same_emissivity "$(csv_all emissivity)" "$plain"
check_eq emissivity.stokes_u_along \
    "$(awk -v u="$(csv_col e_u 1)" 'BEGIN { print (u < 1e-12 && u > -1e-12) }')" 1
check_eq emissivity.stokes_u_45 "$(awk -v u="$(csv_col e_u 2)" 'BEGIN { print (u < -1e-3) }')" 1
check_close emissivity.stokes_dolp "$(csv_col dolp 1)" \
    "$(awk -v q="$(csv_col e_q 1)" -v e="$(csv_col emissivity 1)" \
        'BEGIN { printf "%.10g", q / e }')" 1e-9
sb_run emissivity --wavelength 10 --wind 10 --theta 80 --scales 1 --reflections 1 --stokes
check_close emissivity.stokes_mc_table "$(csv_col e_q 1)" \
    "$(grep '^10,10,80,0,' "$top_srcdir/tests/data/mc_stokes.csv" | cut -d, -f23)" 1e-8
sb_run energy --wavelength 4 --wind 10 --theta 80 --stokes
check_error energy.no_stokes 2 "unknown option '--stokes'"

# examples/horizon.ini (clear sky, air, two reflections), shrunk: the sky
# at the horizon reads the air's 288 K, the sea between it and 290 K.
sb_run render "$top_srcdir/examples/horizon.ini" -o "$RDIR/horizon.exr" --set sensor.width=48 \
    --set sensor.height=27 --png none
check_rc render.horizon_rc 0
check_match render.horizon_range "$SB_ERR" "brightness temperature 28[78]\.[0-9]+ to 289\.[0-9]+ K"
# The exports take a clear sky and the air (issue 45; tests/povray.sh and
# tests/blender.sh compare their renders): the POV-Ray scene's sky is a
# sky_sphere by direction, the manifest holds the table the Blender import
# reads, and the emission maps' description names the air.
sb_run bake "$top_srcdir/examples/horizon.ini" -o "$RDIR/hz" --pov --blender --quiet \
    --set sensor.width=48 --set sensor.height=27 --set model.reflections=1 --png none
check_rc bake.horizon_exports 0
check_match bake.horizon_sky_sphere "$(cat "$RDIR/hz/scene.pov" 2>/dev/null)" \
    '^Seabake_Sky_Sphere\(Seabake_Sky_Pigment\)$'
check_match bake.horizon_color_map "$(cat "$RDIR/hz/sea.inc" 2>/dev/null)" \
    'function \{ sqrt\(max\(y, 0\)\) \}'
hzman=$(tr -d ' \n\t' <"$RDIR/hz/manifest.json" 2>/dev/null)
check_match bake.horizon_sky_table "$hzman" '"sky_table":\{"coordinate":"[^"]*","s":\[0,'
check_match bake.horizon_emission_air "$hzman" 'acrosstheairalongtherangetothesensor'
# ... and the fallbacks of LIMITS AND FALLBACKS a scene takes.
sed -e 's/^wind_speed *=.*/wind_speed = 1/' -e 's/^zenith *=.*/zenith = 100/' \
    "$RSCENE" > "$RDIR/fallback.ini"
sb_run render "$RDIR/fallback.ini" -o "$RDIR/fallback.exr" --explain --quiet --png none
check_rc render.fallback_rc 0
check_match render.explain_alpha_m "$SB_ERR" "fallback: at 1 m/s .* low-wind continuation"
check_match render.explain_sun_down "$SB_ERR" "fallback: the sun \(zenith 100 deg\) is below the horizon"

# --tolerance: overrides the scene's; a loose one scales the emissivity
# orders, thins the wave directions and skips variable-step-2n sub-facets.
sed -e 's/^emissivity = .*/emissivity = auto/' -e 's/^\[model\]/[model]\nmethod = variable-step-2n\nn = 1/' \
    "$RSCENE" \
    >"$RDIR/sea2n.ini"
sb_run render "$RDIR/sea2n.ini" -o "$RDIR/tol.exr" --tolerance 0.1 --explain --quiet --png none
check_rc render.tolerance_rc 0
check render.tolerance_file test -s "$RDIR/tol.exr"
check_match render.tolerance_header "$SB_ERR" "tolerance 0.1, method variable-step-2n"
check_match render.tolerance_emissivity "$SB_ERR" "emissivity: auto rule, orders x 0.5 \(scaled down"
check_match render.tolerance_waves "$SB_ERR" "waves: [0-9]+ sinusoids, 8 bins per octave x 32 directions \(the same"
check_match render.tolerance_skipped "$SB_ERR" \
    "level +[0-9]+: sub-facets of [0-9.]+ m resolve [0-9.e-]+ of the slope variance: skipped, less than the tolerance \(n = 0\)"
check_match render.tolerance_lr "$SB_ERR" "less than a thousandth of the tolerance \(0.0001\)$"
sb_run render "$RDIR/sea2n.ini" -o "$RDIR/tol2.exr" --explain --quiet --png none
check_match render.tolerance_computed "$SB_ERR" "of the slope variance: computed, at least the tolerance"
check_match render.tolerance_default_emissivity "$SB_ERR" "emissivity: auto rule, orders x 1 \(the full rule"
# the orders printed are the library's (seabake.h SEA_EMIS_AUTO_*), not a copy
check_match render.default_emissivity_orders "$SB_ERR" \
    "n_gl = ceil\(1 \(17 \+ 12 s_X\)\), n_gh = ceil\(1 \(2 \+ 8 s \+ 20 s\^2\)\)"

# Scene-file errors: FILE:LINE, exit 2, no output file.
render_error() {
    local name=$1 rc=$2 re=$3 scene=$4
    rm -f "$RDIR"/bad.*
    sb_run render "$scene" -o "$RDIR/bad.exr" --aov level
    check_error "$name" "$rc" "$re"
    check_eq "$name.no_file" "$(render_files 'bad.*')" 0
}
sed 's/^wind_speed = .*/wind_sped = 8/' "$RSCENE" >"$RDIR/e_key.ini"
render_error render.scene_unknown_key 2 "e_key.ini:[0-9]+: \[sea\] wind_sped: unknown key" \
    "$RDIR/e_key.ini"
sed 's/^wind_speed = .*/wind_speed = 41/' "$RSCENE" >"$RDIR/e_range.ini"
render_error render.scene_range 2 \
    "e_range.ini:[0-9]+: \[sea\] wind_speed: 41 is out of range \(allowed: \[0.5, 40\] m/s\)" \
    "$RDIR/e_range.ini"
grep -v '^altitude' "$RSCENE" >"$RDIR/e_missing.ini"
render_error render.scene_missing_key 2 "e_missing.ini:[0-9]+: \[sensor\] altitude: missing required key" \
    "$RDIR/e_missing.ini"
sed 's/^\[sun\]/[moon]/' "$RSCENE" >"$RDIR/e_section.ini"
render_error render.scene_section 2 "e_section.ini:[0-9]+: \[moon\]: unknown section" \
    "$RDIR/e_section.ini"
printf '[sea\nwind_speed = 8\n' >"$RDIR/e_syntax.ini"
render_error render.scene_syntax 2 "e_syntax.ini:1: syntax error" "$RDIR/e_syntax.ini"
sed 's/^wavelength = .*/wavelength = 1/' "$RSCENE" >"$RDIR/e_band.ini"
render_error render.scene_wavelength 2 "e_band.ini:[0-9]+: \[sensor\] wavelength: 1 um is outside the water table" \
    "$RDIR/e_band.ini"
printf 'a\000b\n' >"$RDIR/e_binary.ini"
render_error render.scene_binary 2 "e_binary.ini: contains a NUL byte" "$RDIR/e_binary.ini"
render_error render.scene_unreadable 3 "no-such-scene.ini: cannot open" "$RDIR/no-such-scene.ini"

# Usage errors: exit 2, no file.
render_usage() {
    local name=$1 re=$2
    shift 2
    rm -f "$RDIR"/bad.*
    sb_run render "$@"
    check_error "$name" 2 "$re"
    check_eq "$name.no_file" "$(render_files 'bad.*')" 0
}
render_usage render.aov_nonsense "--aov: 'nonsense' is not one of level, emissivity, reflectivity, temperature, stokes" \
    "$RSCENE" -o "$RDIR/bad.exr" --aov level,nonsense
render_usage render.aov_twice "--aov: 'level' is given twice" "$RSCENE" -o "$RDIR/bad.exr" --aov level,level
render_usage render.aov_stokes_twice "--aov: 'stokes' is given twice" "$RSCENE" -o "$RDIR/bad.exr" \
    --aov stokes,level,stokes
render_usage render.polarizer_range "\\[sensor\\] polarizer: 200 is out of range \\(allowed: \\[-180, 180\\] deg\\)" \
    "$RSCENE" -o "$RDIR/bad.exr" --set sensor.polarizer=200
render_usage render.missing_scene "missing SCENE.ini" -o "$RDIR/bad.exr"
render_usage render.two_scenes "unexpected argument" "$RSCENE" "$RSCENE" -o "$RDIR/bad.exr"
render_usage render.extension "-o: '.*bad.txt' must end in .exr" "$RSCENE" -o "$RDIR/bad.txt"
render_usage render.png_extension "--png: '.*bad.jpg' must end in .png" \
    "$RSCENE" -o "$RDIR/bad.exr" --png "$RDIR/bad.jpg"
render_usage render.png_depth "--png-depth: 12 is not 8 or 16" "$RSCENE" -o "$RDIR/bad.exr" --png-depth 12
render_usage render.png_depth_none "--png-depth applies only to a preview" \
    "$RSCENE" -o "$RDIR/bad.exr" --png none --png-depth 16
render_usage render.png_range_zero "--png-range: 0 is outside \(0, 10000\] K" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 0:300
render_usage render.png_range_high "--png-range: 20000 is outside \(0, 10000\] K" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 200:20000
render_usage render.png_range_order "--png-range: '300:200': LO must be below HI" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 300:200
render_usage render.png_range_equal "--png-range: '300:300': LO must be below HI" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 300:300
render_usage render.png_range_form "--png-range: '300' is not LO:HI \(kelvin, 0 < LO < HI <= 10000\)" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 300
render_usage render.png_range_inf "--png-range: inf is not a finite number" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range 250:inf
render_usage render.png_range_nan "--png-range: 'nan' is not a number" \
    "$RSCENE" -o "$RDIR/bad.exr" --png-range nan:300
render_usage render.png_range_none "--png-range applies only to a preview" \
    "$RSCENE" -o "$RDIR/bad.exr" --png none --png-range 250:300
render_usage render.frames_form "--frames: expected A:B" "$RSCENE" -o "$RDIR/bad.exr" --frames 3
render_usage render.frames_backwards "--frames: '3:1' runs backwards" "$RSCENE" -o "$RDIR/bad.exr" --frames 3:1
render_usage render.frames_integer "--frames: '0.5:2' must hold integers" \
    "$RSCENE" -o "$RDIR/bad.exr" --frames 0.5:2
render_usage render.frames_negative "--frames: -1 is outside \[0, 999999\]" \
    "$RSCENE" -o "$RDIR/bad.exr" --frames -1:2
render_usage render.frames_many "--frames: '0:100000' has 100001 frames, more than 100000" \
    "$RSCENE" -o "$RDIR/bad.exr" --frames 0:100000
render_usage render.rate_alone "--frame-rate applies only with --frames" \
    "$RSCENE" -o "$RDIR/bad.exr" --frame-rate 30
render_usage render.rate_zero "--frame-rate: 0 is outside \(0, inf\) Hz" \
    "$RSCENE" -o "$RDIR/bad.exr" --frames 0:1 --frame-rate 0
render_usage render.tolerance_zero "--tolerance: 0 is outside \(0, 0.1\]" \
    "$RSCENE" -o "$RDIR/bad.exr" --tolerance 0
render_usage render.tolerance_high "--tolerance: 0.2 is outside \(0, 0.1\]" \
    "$RSCENE" -o "$RDIR/bad.exr" --tolerance 0.2
render_usage render.tolerance_text "--tolerance: " "$RSCENE" -o "$RDIR/bad.exr" --tolerance abc
render_usage render.threads "--threads: 0 is outside \[1, [0-9]+\]" "$RSCENE" -o "$RDIR/bad.exr" --threads 0
# Threads are capped at 4 x the online CPUs: --threads 1024 is a usage
# error naming the range, not libgomp's "Thread creation failed".
cpus=$(getconf _NPROCESSORS_ONLN)
render_usage render.threads_cap "--threads: 1024 is outside \[1, $((4 * cpus))\] \(at most 4 threads a CPU, $cpus online\)" \
    "$RSCENE" -o "$RDIR/bad.exr" --threads 1024
render_usage render.threads_over "--threads: $((4 * cpus + 1)) is outside" \
    "$RSCENE" -o "$RDIR/bad.exr" --threads $((4 * cpus + 1))
sb_run render "$RSCENE" -o "$RDIR/cap.exr" --threads $((4 * cpus)) --png none --quiet
check_rc render.threads_at_cap 0
rm -f "$RDIR"/cap.*
# render and bake share --format float|half and --compression none|zip|piz;
# --half is gone (an unknown option).
render_usage render.no_half "unknown option '--half'" "$RSCENE" -o "$RDIR/bad.exr" --half
render_usage render.bad_format "--format: 'double' is not float or half" \
    "$RSCENE" -o "$RDIR/bad.exr" --format double
render_usage render.bad_compression "--compression: 'lzw' is not none, zip or piz" \
    "$RSCENE" -o "$RDIR/bad.exr" --compression lzw
cp "$RSCENE" "$RDIR/bad.exr"
sb_run render "$RDIR/bad.exr" -o "$RDIR/bad.exr"
check_error render.scene_is_output 2 "-o: '.*bad.exr' is the scene file"
check_eq render.scene_kept "$(cat "$RDIR/bad.exr")" "$(cat "$RSCENE")"
rm -f "$RDIR/bad.exr"

# Output errors: exit 3 before any work, nothing left.
sb_run render "$RSCENE" -o "$RDIR/no/such/dir/x.exr"
check_error render.no_directory 3 "-o: the directory '.*no/such/dir' does not exist"
check render.no_directory_nothing_made test ! -e "$RDIR/no"
printf 'x\n' >"$RDIR/plainfile"
sb_run render "$RSCENE" -o "$RDIR/plainfile/x.exr"
check_error render.not_directory 3 "-o: '.*plainfile' is not a directory"
sb_run render "$RSCENE" -o "$RDIR/ok.exr" --png "$RDIR/no/such/dir/x.png"
check_error render.png_no_directory 3 "--png: the directory '.*no/such/dir' does not exist"
check render.png_no_directory_no_exr test ! -e "$RDIR/ok.exr"
# A file of the frame that fails after others were written (the preview's
# name is a directory): the frame's files are removed.
mkdir -p "$RDIR/taken.png"
sb_run render "$RSCENE" -o "$RDIR/partial.exr" --aov level --png "$RDIR/taken.png"
check_error render.partial 3 "taken.png"
check_eq render.partial_removed "$(render_files 'partial*')" 0
check_eq render.errors_no_temporary "$(render_files '*.tmp.*')" 0

# --format and --compression as in bake; the default stays FLOAT, ZIP.
if have exrheader openexr; then
    check_match render.default_zip "$(exrheader "$RDIR/out.exr" 2>&1)" "compression \(type compression\): zip"
    sb_run render "$RSCENE" -o "$RDIR/piz.exr" --format half --compression piz --aov level --png none --quiet
    check_rc render.piz_rc 0
    check_match render.piz "$(exrheader "$RDIR/piz.exr" 2>&1)" "compression \(type compression\): piz"
    check_match render.piz_level "$(exrheader "$RDIR/piz.level.exr" 2>&1)" "compression \(type compression\): piz"
    sb_run render "$RSCENE" -o "$RDIR/none.exr" --compression none --png none --quiet
    check_match render.none "$(exrheader "$RDIR/none.exr" 2>&1)" "compression \(type compression\): none"
    check_match render.none_float "$(exrheader "$RDIR/none.exr" 2>&1)" "Y, 32-bit floating-point"
fi

# --set SECTION.KEY=VALUE overrides a scene key, validated as in the file;
# repeatable; the error names the option.
sb_run render "$RSCENE" -o "$RDIR/set.exr" --png none --set sensor.width=20 --set sensor.height=10
check_rc render.set_rc 0
check_match render.set_applied "$SB_ERR" "^render: .*set\.exr: 20 x 10,"
sb_run render "$RSCENE" -o "$RDIR/set.exr" --png none --quiet --set sea.wind_speed=12
check render.set_wind_differs absent cmp -s "$RDIR/set.exr" "$RDIR/out.exr"
render_usage render.set_range "--set sea.wind_speed=99: \[sea\] wind_speed: 99 is out of range \(allowed: \[0.5, 40\] m/s\)" \
    "$RSCENE" -o "$RDIR/bad.exr" --set sea.wind_speed=99
render_usage render.set_form "--set bogus: not SECTION.KEY=VALUE" "$RSCENE" -o "$RDIR/bad.exr" --set bogus
render_usage render.set_key "--set sea.wind=8: \[sea\] wind: unknown key" \
    "$RSCENE" -o "$RDIR/bad.exr" --set sea.wind=8

# --emissivity overrides the scene's rule, as --set model.emissivity does.
sb_run render "$RSCENE" -o "$RDIR/emis_fast.exr" --png none --emissivity fast --explain
check_match render.emissivity_option "$SB_ERR" "^render: emissivity: fast "
sb_run render "$RSCENE" -o "$RDIR/emis_set.exr" --png none --quiet --set model.emissivity=fast
check render.emissivity_as_set cmp -s "$RDIR/emis_fast.exr" "$RDIR/emis_set.exr"
render_usage render.emissivity_bad "--emissivity: 'bogus' is not one of auto, fast, full" \
    "$RSCENE" -o "$RDIR/bad.exr" --emissivity bogus

# --unset SECTION.KEY removes a file's key, its default back, before any
# --set: a band scene becomes one wavelength; the errors name the option.
MW="$top_srcdir/examples/midwave.ini"
render_usage render.unset_needed "--set sensor.wavelength=4: \[sensor\] wavelength: conflicts with band" \
    "$MW" -o "$RDIR/bad.exr" --set sensor.wavelength=4
sb_run render "$MW" -o "$RDIR/unset.exr" --png none --set sensor.width=16 --set sensor.height=12 \
    --set sensor.wavelength=4 --unset sensor.band --explain
check_rc render.unset_rc 0
check_match render.unset_one_wavelength "$SB_ERR" "^render: 1 spectral sample, at 4 um"
# the default back: unsetting wind_direction is the scene with wind_direction = 0
sed 's/^wind_direction = .*/wind_direction = 0/' "$MW" >"$RDIR/mw0.ini"
sb_run render "$RDIR/mw0.ini" -o "$RDIR/unset0.exr" --png none --quiet --set sensor.width=16 \
    --set sensor.height=12
sb_run render "$MW" -o "$RDIR/unset1.exr" --png none --quiet --set sensor.width=16 \
    --set sensor.height=12 --unset sea.wind_direction
sb_run compare "$RDIR/unset1.exr" "$RDIR/unset0.exr"
check_match render.unset_default "$(printf '%s\n' "$SB_OUT" | tail -n 1)" "^192,0,"

render_usage render.unset_form "--unset sensor.band=3: not SECTION.KEY" \
    "$MW" -o "$RDIR/bad.exr" --unset sensor.band=3
render_usage render.unset_key "--unset sensor.bogus: \[sensor\] bogus: unknown key" \
    "$MW" -o "$RDIR/bad.exr" --unset sensor.bogus
render_usage render.set_needs_value "--set sensor.band: not SECTION.KEY=VALUE" \
    "$MW" -o "$RDIR/bad.exr" --set sensor.band
check render.unset_no_output [ ! -e "$RDIR/bad.exr" ]

# Signals.  SIGTERM (no terminal, no bar): the render stops within a row,
# writes nothing for the frame in progress (earlier frames are complete),
# says so and dies of the signal; no temporary file is left.
mkdir -p "$RDIR/sig"
SB_CMD="seabake render --frames 0:99999, then SIGTERM"
# shellcheck disable=SC2086
$SEABAKE_WRAPPER "$SEABAKE" render "$RSCENE" -o "$RDIR/sig/a.exr" --frames 0:99999 \
    >"$SB_TMP/out" 2>"$SB_TMP/err" &
sig_pid=$!
n=0
while [ ! -e "$RDIR/sig/a_0001.exr" ] && [ $n -lt 600 ]; do sleep 0.1; n=$((n + 1)); done
kill -TERM "$sig_pid"
wait "$sig_pid"
SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
check_error render.sigterm 143 "interrupted by signal 15: [0-9]+ frames written \(0 to [0-9]+\), the rest not$"
sig_frames=$(printf '%s\n' "$SB_ERR" | sed -n 's/.*: \([0-9]*\) frames written.*/\1/p')
check_eq render.sigterm_frames "$(find "$RDIR/sig" -name 'a_*.exr' | grep -c '')" "$sig_frames"
check_eq render.sigterm_previews "$(find "$RDIR/sig" -name 'a_*.png' | grep -c '')" "$sig_frames"
check_eq render.sigterm_no_temporary "$(find "$RDIR/sig" -name '*.tmp.*' | grep -c '')" 0
# Ctrl-C on a terminal (script(1) gives the render a pseudo-terminal, so the
# progress bar shows; ^C typed into it sends SIGINT): the bar's line is
# ended before the message, and the render dies of SIGINT.  A suite started
# in the background of a shell without job control inherits SIGINT ignored,
# which seabake keeps (as for nohup): env --default-signal=INT gives the
# render the terminal's ^C whatever started the suite, and timeout ends a
# render that missed it (a failure, not a hung suite).
if [ -n "$SEABAKE_WRAPPER" ]; then
    skip "^C on a terminal, under $SEABAKE_WRAPPER (the plain run has it)"
elif have script bsdutils; then
    rm -rf "$RDIR/sig" && mkdir -p "$RDIR/sig"
    SB_CMD="script: seabake render --frames 0:99999, then ^C"
    { n=0
      while [ ! -e "$RDIR/sig/a_0001.exr" ] && [ $n -lt 600 ]; do sleep 0.1; n=$((n + 1)); done
      printf '\003'; sleep 5; } |
        timeout -s KILL 180 script -qec "env --default-signal=INT $SEABAKE render '$RSCENE' \
            -o '$RDIR/sig/a.exr' --frames 0:99999" /dev/null >"$SB_TMP/tty" 2>&1
    SB_RC=$?
    check_rc render.sigint 130
    tty_out=$(tr '\r' '\n' <"$SB_TMP/tty")
    check_match render.sigint_bar "$tty_out" "^render: \[[#.]+\] +[0-9]+% frame [0-9]+/100000"
    # the time left, once a second and a hundredth of the work have passed:
    # five frames of the mast view (seconds each)
    timeout -s KILL 300 script -qec "$SEABAKE render '$top_srcdir/examples/mast.ini' \
        -o '$RDIR/sig/eta.exr' --set sensor.width=480 --set sensor.height=270 --frames 0:4 \
        --png none" /dev/null >"$SB_TMP/tty" 2>&1
    check_match render.progress_time_left "$(tr '\r' '\n' <"$SB_TMP/tty")" \
        "^render: \[[#.]+\] +[0-9]+% frame [1-5]/5, ([0-9]+ min [0-9]+|[0-9]+) s left"
    rm -f "$RDIR"/sig/eta_*.exr
    # the message starts a line: the bar's line was ended
    check_match render.sigint_message "$tty_out" "^seabake: error: interrupted by signal 2: [0-9]+ frames written"
    check_no_match render.sigint_no_summary "$tty_out" "^render: .*brightness temperature"
    check_eq render.sigint_no_temporary "$(find "$RDIR/sig" -name '*.tmp.*' | grep -c '')" 0
fi

# Issue 40, item 3.  A file size limit (ulimit -f): seabake ignores
# SIGXFSZ itself, so the write fails with EFBIG through the error path
# (a message, exit 3, no temporary), where SIGXFSZ killed it (exit 153)
# and left OUT.exr.tmp.XXXXXX.  (No "trap '' XFSZ" here: the program's
# own disposition is tested.)
mkdir -p "$RDIR/fsz"
SB_CMD="seabake render --compression none (ulimit -f 1)"
# shellcheck disable=SC2086
(ulimit -f 1 && exec $SEABAKE_WRAPPER "$SEABAKE" render "$RSCENE" -o "$RDIR/fsz/r.exr" \
    --compression none --quiet) >"$SB_TMP/out" 2>"$SB_TMP/err"
SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
check_error render.file_size_limit 3 "cannot write .*r\.exr: File too large"
check_eq render.file_size_limit_nothing "$(ls -A "$RDIR/fsz" | tr '\n' ' ')" ""

# The temporaries of render's files are marked directories
# OUT.tmp.XXXXXX/ (the marker .seabake-temporary: kind file, the target's
# name, pid, host; the data under OUT's name), flock'ed while they live.
# A render killed while writing (SIGKILL cannot be caught) leaves one; the
# next render into the same outputs removes it with a note.  The kill
# comes as soon as a temporary's data shows (a bash glob, no fork, in a
# loop: the marker is written before the data), as a kill in the middle of
# a write finds it; larger frames with every AOV, uncompressed, keep one
# there for a while.  (Not under a wrapper: the frames take far too long
# there.)
if [ -z "$SEABAKE_WRAPPER" ]; then
    shopt -s nullglob
    mkdir -p "$RDIR/kill"
    left=()
    for attempt in 1 2 3; do
        "$SEABAKE" render "$RSCENE" -o "$RDIR/kill/o.exr" --frames 0:99999 --quiet \
            --aov level,emissivity,reflectivity,temperature --compression none \
            --set sensor.width=512 --set sensor.height=384 >/dev/null 2>&1 &
        kill_pid=$! start_s=$SECONDS
        while kill -0 "$kill_pid" 2>/dev/null && [ $((SECONDS - start_s)) -lt 60 ]; do
            left=("$RDIR/kill"/*.tmp.*/o_*)
            if [ ${#left[@]} -gt 0 ]; then
                kill -KILL "$kill_pid"
                break
            fi
        done
        kill -KILL "$kill_pid" 2>/dev/null
        wait "$kill_pid" 2>/dev/null
        left=("$RDIR/kill"/*.tmp.*)
        [ ${#left[@]} -gt 0 ] && break
    done
    shopt -u nullglob
    check render.sigkill_leaves_temporary [ ${#left[@]} -gt 0 ]
    check render.sigkill_marker test -f "${left[0]}/.seabake-temporary"
    check_match render.sigkill_marker_text "$(cat "${left[0]}/.seabake-temporary")" \
        "^kind file$"
    sb_run render "$RSCENE" -o "$RDIR/kill/o.exr" --frames 0:0 --quiet \
        --aov level,emissivity,reflectivity,temperature
    check_rc render.after_sigkill 0
    for t in "${left[@]}"; do
        check_match "render.after_sigkill_note[${t##*/}]" "$SB_ERR" \
            "^render: removed '$t', left by a render that was killed$"
    done
    check_eq render.after_sigkill_leftovers "$(find "$RDIR/kill" -name '*.tmp.*' | grep -c '')" 0
fi
# A temporary as a killed render leaves it (made here as seabake makes
# one) is removed by the next render into those outputs, also beside its
# --png previews; directories and files named like temporaries that
# seabake cannot show it made are never removed: without a marker, a
# plain file, a marker of another kind or target or whose target's name is
# not the directory's, one with a file of the user's beside the data (only
# seabake's data and marker go), and a live one (its flock held).
mkdir -p "$RDIR/stale/png"
mark() { # mark DIR KIND TARGET: the marker seabake writes
    mkdir -p "$1" && printf 'seabake temporary directory\nkind %s\ntarget %s\npid 1\nhost h\n' \
        "$2" "$3" >"$1/.seabake-temporary"
}
mark "$RDIR/stale/o_0003.level.exr.tmp.Stale1" file o_0003.level.exr
echo partial >"$RDIR/stale/o_0003.level.exr.tmp.Stale1/o_0003.level.exr"
mark "$RDIR/stale/png/p_0001.png.tmp.Stale2" file p_0001.png
mkdir -p "$RDIR/stale/o_0001.exr.tmp.AbC123" && echo mine >"$RDIR/stale/o_0001.exr.tmp.AbC123/f"
echo mine >"$RDIR/stale/o_0002.exr.tmp.XyZ789"
mark "$RDIR/stale/o_0004.exr.tmp.Kind01" tmp o_0004.exr
echo mine >"$RDIR/stale/o_0004.exr.tmp.Kind01/f"
mark "$RDIR/stale/o_0005.exr.tmp.Targ01" file other.exr
echo mine >"$RDIR/stale/o_0005.exr.tmp.Targ01/f"
mark "$RDIR/stale/o_0006.exr.tmp.Extra1" file o_0006.exr
echo mine >"$RDIR/stale/o_0006.exr.tmp.Extra1/notes.txt"
mark "$RDIR/stale/o_0007.exr.tmp.Live01" file o_0007.exr
# (the flock held by this shell on its own open of the directory, as the
# live writer holds it; the render opens the directory afresh)
live_fd=
if have flock util-linux; then
    exec {live_fd}<"$RDIR/stale/o_0007.exr.tmp.Live01"
    flock -n "$live_fd" || live_fd=
fi
sb_run render "$RSCENE" -o "$RDIR/stale/o.exr" --png "$RDIR/stale/png/p.png" --frames 0:0
check_rc render.stale_rc 0
check_match render.stale_note "$SB_ERR" \
    "^render: removed '.*stale/o_0003.level.exr.tmp.Stale1', left by a render that was killed$"
check_match render.stale_note_png "$SB_ERR" \
    "^render: removed '.*stale/png/p_0001.png.tmp.Stale2', left by a render that was killed$"
check render.stale_removed test ! -e "$RDIR/stale/o_0003.level.exr.tmp.Stale1"
check render.stale_removed_png test ! -e "$RDIR/stale/png/p_0001.png.tmp.Stale2"
check_eq render.stale_notes "$(printf '%s\n' "$SB_ERR" | grep -c '^render: removed')" 2
for d in o_0001.exr.tmp.AbC123 o_0004.exr.tmp.Kind01 o_0005.exr.tmp.Targ01; do
    check_eq "render.stale_kept[$d]" "$(cat "$RDIR/stale/$d/f" 2>/dev/null)" mine
done
check_eq render.stale_kept_file "$(cat "$RDIR/stale/o_0002.exr.tmp.XyZ789" 2>/dev/null)" mine
check_eq render.stale_kept_extra "$(cat "$RDIR/stale/o_0006.exr.tmp.Extra1/notes.txt" 2>/dev/null)" \
    mine
if [ -n "$live_fd" ]; then
    check render.stale_kept_live test -f "$RDIR/stale/o_0007.exr.tmp.Live01/.seabake-temporary"
    exec {live_fd}<&-
fi
# slopes -o FILE cleans its own output's the same way.
mark "$RDIR/stale/s.csv.tmp.Stale3" file s.csv
sb_run slopes --wind 8 --facet 1 --size 2,2 -o "$RDIR/stale/s.csv" --quiet
check_rc render.stale_slopes_rc 0
check_match render.stale_slopes_note "$SB_ERR" "^slopes: removed '.*stale/s.csv.tmp.Stale3'"

# Thread creation is checked before any work: a bake whose threads cannot
# start (64 of them under a 400 MB address-space limit) fails as seabake's
# own error (exit 1), with no DIR.tmp.XXXXXX and no lock beside DIR
# (libgomp printed "Thread creation failed" and exited mid-bake).  (Not
# under a wrapper, nor with AddressSanitizer: see render.memory_rlimit.)
if [ -z "$SEABAKE_WRAPPER" ] && ! grep -q __asan_init "$SEABAKE" 2>/dev/null; then
    mkdir -p "$RDIR/threads"
    for cmd in bake render; do
        SB_CMD="OMP_NUM_THREADS=64 seabake $cmd (ulimit -v 400000)"
        (ulimit -v 400000 && OMP_NUM_THREADS=64 exec "$SEABAKE" $cmd "$RSCENE" \
            -o "$RDIR/threads/out$([ $cmd = render ] && echo .exr)" --quiet) \
            >"$SB_TMP/out" 2>"$SB_TMP/err"
        SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
        check_error "$cmd.threads_fail" 1 \
            "cannot start 64 threads \([0-9]+ did, with stacks of [0-9.]+ MiB\): .*OMP_NUM_THREADS"
        check_eq "$cmd.threads_fail_nothing" "$(ls -A "$RDIR/threads" | tr '\n' ' ')" ""
    done
fi

# ---------------------------------------------------------- the camera
# A scene with [sensor] camera keys (seabake-model(7), THE CAMERA) also
# gets OUT.camera.exr (T: apparent brightness temperature, K; Y: the
# camera's radiance), OUT.camera.png and, with a gain, OUT.counts.png; the
# radiance image OUT.exr is the same.  Without the keys, no extra file.
check_eq camera.none_exr "$(render_files 'out.camera.*')" 0
check_eq camera.none_counts "$(render_files 'out.counts.*')" 0
sb_run render "$RSCENE" -o "$RDIR/cam.exr" --set sensor.psf_sigma=1.5 --set sensor.gain=100 \
    --set sensor.bit_depth=12
check_rc camera.rc 0
check camera.exr_same cmp -s "$RDIR/out.exr" "$RDIR/cam.exr"
check camera.png_same cmp -s "$RDIR/out.png" "$RDIR/cam.png"
check camera.exr test -s "$RDIR/cam.camera.exr"
check camera.png test -s "$RDIR/cam.camera.png"
check camera.counts test -s "$RDIR/cam.counts.png"
check_eq camera.no_temporary "$(render_files '*.tmp.*')" 0
check_match camera.summary "$SB_ERR" \
    "^render: .*cam\.exr: $RSIZE x $RSIZE, .*brightness temperature [0-9.]+ to [0-9.]+ K; camera: apparent temperature [0-9.]+ to [0-9.]+ K, 0 saturated pixels \(0 high, 0 low\)$"
# channels T and Y, FLOAT (name, NUL, pixel type 2)
check_match camera.channels "$(exr_header "$RDIR/cam.camera.exr")" \
    "^25000000540002000000[0-9a-f]{24}590002000000[0-9a-f]{24}00"
check camera.attr_camera grep -qa "optics gaussian psf_sigma 1.5 pixels" "$RDIR/cam.camera.exr"
check camera.attr_saturated grep -qa "seabake:saturated" "$RDIR/cam.camera.exr"
check_eq camera.counts_depth "$(od -An -tu1 -j24 -N1 "$RDIR/cam.counts.png" | tr -d ' ')" 16
check_eq camera.counts_grey "$(png_color_type "$RDIR/cam.counts.png")" 0
check_eq camera.counts_text "$(png_text "$RDIR/cam.counts.png" seabake:bit_depth)" 12
# Without a gain no counts; no preview with --png none; --format half
# leaves the camera's image FLOAT (half's steps are 0.25 K at 300 K).
sb_run render "$RSCENE" -o "$RDIR/cam2.exr" --set sensor.fill_factor=0.5 --png none \
    --format half --quiet
check_rc camera.nogain_rc 0
check camera.nogain_exr test -s "$RDIR/cam2.camera.exr"
check camera.nogain_no_counts test ! -e "$RDIR/cam2.counts.png"
check camera.nogain_no_png test ! -e "$RDIR/cam2.camera.png"
check_match camera.half_stays_float "$(exr_header "$RDIR/cam2.camera.exr")" "^25000000540002000000"
# The camera's image is uncompressed unless --compression is given (its
# noise barely compresses); OUT.exr keeps the default ZIP.
if have exrheader openexr; then
    check_match camera.uncompressed "$(exrheader "$RDIR/cam.camera.exr" 2>&1)" \
        "compression \(type compression\): none"
    check_match camera.main_zip "$(exrheader "$RDIR/cam.exr" 2>&1)" \
        "compression \(type compression\): zip"
    sb_run render "$RSCENE" -o "$RDIR/cam3.exr" --set sensor.netd=0.05 --png none --quiet \
        --compression zip
    check_rc camera.zip_rc 0
    check_match camera.zip_given "$(exrheader "$RDIR/cam3.camera.exr" 2>&1)" \
        "compression \(type compression\): zip"
fi

# The noise has zero mean: over the image, the camera's temperature is
# the ideal one's within 5 standard errors of a pixel's noise (0.1 K at
# most for a NETD of 50 mK stated at 300 K, a sea at 285 to 346 K at
# 4 um) over the square root of the pixels; and the noise is there.
if have python3 python3; then
    cat >"$RDIR/exr.py" <<'PY'
import struct, sys, zlib
sys.path.insert(0, sys.argv.pop(1))
import exr_read

def exr(path):
    """The channels of an uncompressed EXR, each a flat list (rows from the top)."""
    chans, w, h = exr_read.read(path)
    return {c: [x for row in rows for x in row] for c, (_, rows) in chans.items()}, w, h

def png16(path):
    """The samples of a grey PNG of filters None and Sub (seabake's)."""
    d = open(path, "rb").read()
    i, idat = 8, b""
    while i < len(d):
        n, t = struct.unpack(">I4s", d[i:i + 8])
        if t == b"IHDR":
            w, h, bits = struct.unpack(">IIB", d[i + 8:i + 17])
        if t == b"IDAT":
            idat += d[i + 8:i + 8 + n]
        i += 12 + n
    raw, bpp, vals = zlib.decompress(idat), bits // 8, []
    stride = w * bpp
    for y in range(h):
        f, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        assert f in (0, 1)
        if f == 1:
            for x in range(bpp, stride):
                row[x] = (row[x] + row[x - bpp]) & 255
        vals += [row[x] if bpp == 1 else row[x] << 8 | row[x + 1] for x in range(0, stride, bpp)]
    return vals

if sys.argv[1] == "diff":   # diff A CH B CH: mean and std of A - B
    a, b = exr(sys.argv[2])[0][sys.argv[3]], exr(sys.argv[4])[0][sys.argv[5]]
    d = [x - y for x, y in zip(a, b)]
    m = sum(d) / len(d)
    print("%.6g %.6g %d" % (m, (sum((x - m) ** 2 for x in d) / (len(d) - 1)) ** 0.5, len(d)))
elif sys.argv[1] == "counts":   # counts PNG EXR GAIN OFFSET TOP: worst |c - (o + g Y)| unclipped
    c, y = png16(sys.argv[2]), exr(sys.argv[3])[0]["Y"]
    g, o, top = float(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
    print("%.6g" % max(abs(ci - (o + g * yi)) for ci, yi in zip(c, y) if 0 < o + g * yi < top))
PY
    sb_run render "$RSCENE" -o "$RDIR/noise.exr" --set sensor.netd=0.05 --tolerance 1e-3 \
        --aov temperature --compression none --png none --quiet
    check_rc camera.noise_rc 0
    read -r dmean dstd dn <<<"$(python3 "$RDIR/exr.py" "$top_srcdir/tests" diff \
        "$RDIR/noise.camera.exr" T "$RDIR/noise.temperature.exr" Y)"
    check_eq camera.noise_pixels "$dn" $((RSIZE * RSIZE))
    num_check camera.noise_mean 'm <= 5 * 0.1 / sqrt(n) && m >= -5 * 0.1 / sqrt(n)' \
        "m=$dmean" "n=$dn"
    num_check camera.noise_std 's > 0.02 && s < 0.2' "s=$dstd"
    # the counts are round(offset + gain Y) of the camera's radiance Y
    sb_run render "$RSCENE" -o "$RDIR/counts.exr" --set sensor.gain=300 \
        --set sensor.offset=-20 --set sensor.bit_depth=10 --compression none --png none --quiet
    check_rc camera.counts_rc 0
    worst=$(python3 "$RDIR/exr.py" "$top_srcdir/tests" counts "$RDIR/counts.counts.png" \
        "$RDIR/counts.camera.exr" 300 -20 1023)
    num_check camera.counts_rounding 'w <= 0.5 + 1e-4' "w=$worst"
fi

# Saturation: every pixel above 2^8 - 1 (a gain of 1000 counts per
# W m^-2 sr^-1 um^-1), then every one below 0; an 8-bit counts file.
sb_run render "$RSCENE" -o "$RDIR/sat.exr" --set sensor.gain=1000 --set sensor.bit_depth=8 \
    --png none
check_match camera.saturated_high "$SB_ERR" \
    "camera: .*, $((RSIZE * RSIZE)) saturated pixels \($((RSIZE * RSIZE)) high, 0 low\)$"
check_eq camera.counts_8bit "$(od -An -tu1 -j24 -N1 "$RDIR/sat.counts.png" | tr -d ' ')" 8
sb_run render "$RSCENE" -o "$RDIR/sat.exr" --set sensor.gain=10 --set sensor.offset=-1e6 \
    --png none
check_match camera.saturated_low "$SB_ERR" \
    "camera: .*, $((RSIZE * RSIZE)) saturated pixels \(0 high, $((RSIZE * RSIZE)) low\)$"

# Each frame draws its own temporal noise.
sb_run render "$RSCENE" -o "$RDIR/fr.exr" --set sensor.netd=0.05 --frames 0:1 --png none --quiet
check_rc camera.frames_rc 0
check camera.frames_files test -s "$RDIR/fr_0000.camera.exr" -a -s "$RDIR/fr_0001.camera.exr"
check camera.frames_differ absent cmp -s "$RDIR/fr_0000.camera.exr" "$RDIR/fr_0001.camera.exr"

# A bad camera key: the key, the value and the range, and no file.
for kv in "netd=20:netd: 20 is out of range \(allowed: \(0, 10\] K\)" \
    "psf_sigma=100:psf_sigma: 100 is out of range \(allowed: \(0, 64\] pixels\)" \
    "fpn_gain=0.5:fpn_gain: 0.5 is out of range \(allowed: \[0, 0.1\]\)" \
    "fill_factor=0:fill_factor: 0 is out of range \(allowed: \(0, 1\]\)"; do
    key=${kv%%=*}
    sb_run render "$RSCENE" -o "$RDIR/bad_$key.exr" --set "sensor.${kv%%:*}"
    check_error "camera.bad.$key" 2 "\[sensor\] ${kv#*:}"
    check_eq "camera.bad_nothing.$key" "$(render_files "bad_$key*")" 0
done
sed -e "s/^wavelength = .*/&\nnetd = 11/" "$RSCENE" >"$RDIR/bad_netd.ini"
sb_run render "$RDIR/bad_netd.ini" -o "$RDIR/bad_file.exr"
check_error camera.bad_in_file 2 \
    "bad_netd\.ini:[0-9]+: \[sensor\] netd: 11 is out of range \(allowed: \(0, 10\] K\)"
check_eq camera.bad_in_file_nothing "$(render_files 'bad_file*')" 0
sb_run render "$RSCENE" -o "$RDIR/bad_bits.exr" --set sensor.bit_depth=12
check_error camera.bits_without_gain 2 "\[sensor\] bit_depth: needs gain"

# The tolerance follows from the NETD when nothing gives one: a tenth of
# the NETD's radiance over the sea's (seabake-model(7)): 1.998e-4 for a
# sea at 300 K, 4 um and 50 mK; --explain shows the formula and the value.
sb_run render "$RSCENE" -o "$RDIR/tol.exr" --set sensor.netd=0.05 --set sea.temperature=300 \
    --explain --quiet --png none
check_rc camera.tol_rc 0
check_match camera.tol_header "$SB_ERR" "^render: .*tolerance 0\.0001998[0-9]*, method"
check_match camera.tol_explain "$SB_ERR" \
    "^render: tolerance 0\.0001998[0-9]* from the camera's NETD \(neither the scene nor --tolerance gives one\): f NETD dL/dT\(T_n\) / L\(T_sea\), f = 0\.1, NETD = 0\.05 K, T_n = 300 K, T_sea = 300 K: 0\.0001998$"
check_match camera.explain_camera "$SB_ERR" "^render: camera: optics none, fill_factor 1, netd 0\.05 K at 300 K"
sb_run render "$RSCENE" -o "$RDIR/tol.exr" --set sensor.netd=0.05 --tolerance 1e-3 --explain \
    --quiet --png none
check_match camera.tol_given "$SB_ERR" "^render: tolerance 0\.001 given; the camera's NETD would give f NETD"
check_match camera.tol_given_header "$SB_ERR" "^render: .*tolerance 0\.001, method"
sb_run render "$RSCENE" -o "$RDIR/tol.exr" --set sensor.netd=10 --set sensor.netd_temperature=500 \
    --set sea.temperature=271 --explain --quiet --png none --set sensor.width=8 \
    --set sensor.height=8
check_match camera.tol_clamped "$SB_ERR" "^render: tolerance 0\.1 from the camera's NETD .*, clamped to the range \(0, 0\.1\]$"

# ================================================================ bake

BDIR="$SB_TMP/bake"
mkdir -p "$BDIR" || exit 99
# bake_state DIR: listing, permissions and checksums of a tree ("absent").
bake_state() {
    if [ -e "$1" ]; then
        ls -ld "$1" | awk '{print $1}'
        (cd "$1" && find . -exec ls -ld {} + | awk '{print $1, $NF}' | sort &&
            find . -type f -exec cksum {} + | sort)
    else
        echo absent
    fi
}
# bake_leftovers: temporary or old directories left beside the outputs.
bake_leftovers() {
    find "$BDIR" -maxdepth 1 \( -name '*.tmp.*' -o -name '*.old.*' \) | grep -c ''
}
BGROUPS="moments moments2 optics normal roughness emission"

sb_run bake "$RSCENE" -o "$BDIR/tol" --tolerance 0.2
check_error bake.tolerance_high 2 "--tolerance: 0.2 is outside \(0, 0.1\]"
check bake.tolerance_no_dir test ! -e "$BDIR/tol"
sb_run bake "$RSCENE" -o "$BDIR/tol" --tolerance 0.05 --quiet
check_rc bake.tolerance_rc 0
check_match bake.tolerance_manifest "$(cat "$BDIR/tol/manifest.json")" '"tolerance":[[:space:]]*0.05'
check_match bake.shadowing_manifest "$(cat "$BDIR/tol/manifest.json")" '"shadowing":[[:space:]]*"correlated"'
check_match bake.scales_manifest "$(cat "$BDIR/tol/manifest.json")" '"scales":[[:space:]]*2'
rm -rf "$BDIR/tol"
sb_run bake "$RSCENE" -o "$BDIR/tol" --tolerance 0.05 --shadowing smith --scales 1 --quiet
check_match bake.shadowing_manifest_smith "$(cat "$BDIR/tol/manifest.json")" '"shadowing":[[:space:]]*"smith"'
check_match bake.scales_manifest_1 "$(cat "$BDIR/tol/manifest.json")" '"scales":[[:space:]]*1'
rm -rf "$BDIR/tol"

sb_run bake "$RSCENE" -o "$BDIR/out"
check_rc bake.rc 0
check_eq bake.stdout "$SB_OUT" ""
check_match bake.summary "$SB_ERR" "^bake: .*out: [0-9]+ texels in [0-9.e+-]+ s"
# The maps' seconds and their parts (waves, image, texel optics, view
# texels): parts of that time, so they add up to no more than it (a
# consistency check, not a speed one); no image without --pov.
maps_parts() {
    n='\([0-9.e+-]*\)'
    printf '%s\n' "$1" | sed -n "s/.*maps $n s (waves $n s, image $n s, texel optics $n s, view texels $n s), files.*/\1 \2 \3 \4 \5/p"
}
parts_ok() { # MAPS WAVES IMAGE OPTICS VIEW IMAGE_WANTED(0/1)
    awk -v m="$1" -v a="$2" -v i="$3" -v o="$4" -v v="$5" -v want="$6" 'BEGIN {
        # each printed to 3 significant digits: the parts may exceed their
        # total by their rounding, half a unit of the third digit each
        ok = m > 0 && a > 0 && o > 0 && v > 0 && i >= 0 && a + i + o + v <= m * 1.005 + 2e-3
        ok = ok && (want ? i > 0 : i == 0)
        exit !ok }'
}
# shellcheck disable=SC2046 # (five numbers)
check bake.summary_parts parts_ok $(maps_parts "$SB_ERR") 0
check bake.manifest test -s "$BDIR/out/manifest.json"
# Levels from the manifest: "HR indices|LR indices".
if have python3 python3; then
    check bake.json_valid python3 -m json.tool "$BDIR/out/manifest.json"
    levels=$(python3 -c '
import json, sys
m = json.load(open(sys.argv[1]))
lv = m["levels"]
print(" ".join(str(l["index"]) for l in lv if not l["low_res"]) + "|" +
      " ".join(str(l["index"]) for l in lv if l["low_res"] and "frames" not in l))
' "$BDIR/out/manifest.json")
else
    echo "cli.sh: python3 absent: manifest checked with grep only" >&2
    check bake.json_braces grep -q '^}' "$BDIR/out/manifest.json"
    levels="$(cd "$BDIR/out" && ls moments_*.exr | sed 's/moments_\([0-9]*\)\.exr/\1/' | sort -n |
        tr '\n' ' ' | sed 's/ $//')|x"
fi
hr=${levels%%|*}
lr=${levels#*|}
check_match bake.has_hr "$hr" "^[0-9]"
check_match bake.has_lr "$lr" "[0-9x]"
check_eq bake.lr_in_manifest "$(grep -c '"low_res":[[:space:]]*true' "$BDIR/out/manifest.json")" 1
expected=""
for l in $hr; do
    for g in $BGROUPS; do
        expected="$expected ${g}_$l.exr ${g}_$l.png"
    done
done
got=$(cd "$BDIR/out" && ls | grep -v '^manifest.json$' | sort | tr '\n' ' ')
check_eq bake.files "$got" "$(printf '%s\n' $expected | sort | tr '\n' ' ')"
for l in $hr; do
    for g in $BGROUPS; do
        check_eq "bake.exr_magic.${g}_$l" "$(magic "$BDIR/out/${g}_$l.exr" 4)" "762f3101"
        check_eq "bake.png_magic.${g}_$l" "$(magic "$BDIR/out/${g}_$l.png" 8)" "89504e470d0a1a0a"
        check "bake.manifest_names.${g}_$l" grep -q "\"${g}_$l.exr\"" "$BDIR/out/manifest.json"
    done
done
l0=${hr%% *}
# Previews: normal and roughness in colour (roughness on an absolute scale:
# hue rotation, saturation anisotropy, value roughness; one value per level
# with variable-step, the default, but not a flat mid grey), the others grey
# with one range per quantity for every level.
for l in $hr; do
    check_eq "bake.normal_png_rgb.$l" "$(png_color_type "$BDIR/out/normal_$l.png")" 2
    check_eq "bake.roughness_png_rgb.$l" "$(png_color_type "$BDIR/out/roughness_$l.png")" 2
    for g in moments moments2 optics emission; do
        check_eq "bake.png_grey.${g}_$l" "$(png_color_type "$BDIR/out/${g}_$l.png")" 0
        check_eq "bake.png_range_shared.${g}_$l" "$(png_text "$BDIR/out/${g}_$l.png" seabake:range)" \
            "$(png_text "$BDIR/out/${g}_$l0.png" seabake:range)"
    done
done
check_match bake.png_range_moments "$(png_text "$BDIR/out/moments_$l0.png" seabake:range)" \
    '^-([0-9.e+-]+):\1$'
check_match bake.png_tone_roughness "$(png_text "$BDIR/out/roughness_$l0.png" seabake:tone)" \
    "value = roughness, absolute"
if have python3 python3; then
    # the first pixel of the roughness preview (filter byte, then R G B)
    px=$(python3 -c '
import struct, sys, zlib
d = open(sys.argv[1], "rb").read()
i, idat = 8, b""
while i < len(d):
    n, t = struct.unpack(">I4s", d[i:i + 8])
    if t == b"IDAT":
        idat += d[i + 8:i + 8 + n]
    i += 12 + n
print(" ".join(str(b) for b in zlib.decompress(idat)[1:4]))' "$BDIR/out/roughness_$l0.png")
    check_match bake.roughness_not_mid_grey "$px" '^[0-9]+ [0-9]+ [0-9]+$'
    check bake.roughness_not_mid_grey [ "$px" != "128 128 128" ]
fi
# Channels: R,G,B,A FLOAT for a 4-quantity group; one grey Y for emission
# (name, NUL, pixel type 2 = FLOAT, pLinear 0).
check_match bake.float_channels "$(exr_header "$BDIR/out/optics_$l0.exr")" "410002000000.*520002000000"
check_no_match bake.emission_no_alpha "$(exr_header "$BDIR/out/emission_$l0.exr")" "410002000000"
check_match bake.emission_grey "$(exr_header "$BDIR/out/emission_$l0.exr")" "^13000000590002000000"
check_no_match bake.emission_no_red "$(exr_header "$BDIR/out/emission_$l0.exr")" "520002000000"
check bake.exr_attr grep -qa "seabake:channels" "$BDIR/out/moments_$l0.exr"
check bake.manifest_units grep -q '"radiance":[[:space:]]*"W m^-2 sr^-1 um^-1"' "$BDIR/out/manifest.json"
check bake.manifest_scale grep -qE '"emission_scale":[[:space:]]*[0-9]' "$BDIR/out/manifest.json"
# A scene's camera is recorded in scene.sensor.camera, not applied; a bake
# without one has no such key (its manifest as before).
check_eq bake.manifest_no_camera "$(grep -c '"applied"' "$BDIR/out/manifest.json")" 0
sb_run bake "$RSCENE" -o "$BDIR/cam" --set sensor.netd=0.05 --set sensor.psf_sigma=2 --quiet
check_rc bake.camera_rc 0
check bake.manifest_camera grep -q '"applied":[[:space:]]*false' "$BDIR/cam/manifest.json"
check bake.manifest_camera_psf grep -q '"psf_sigma_px":[[:space:]]*2' "$BDIR/cam/manifest.json"
check bake.manifest_camera_netd grep -q '"netd_K":[[:space:]]*0.05' "$BDIR/cam/manifest.json"
check_eq bake.camera_no_camera_files "$(ls "$BDIR/cam" | grep -c -e camera -e counts)" 0
mkdir "$BDIR/umask_probe"
check_eq bake.dir_mode "$(ls -ld "$BDIR/out" | cut -c1-10)" "$(ls -ld "$BDIR/umask_probe" | cut -c1-10)"

# Re-baking replaces a bake as a whole: files of the earlier options go,
# the new options show, nothing is left beside it.  The manifest lists
# every file of the directory ("files"), itself included.
check_eq bake.files_listed "$(python3 -c 'import json,sys; print(" ".join(json.load(open(sys.argv[1]))["files"]))' "$BDIR/out/manifest.json")" \
    "$(ls "$BDIR/out" | tr '\n' ' ' | sed 's/ $//')"
sb_run bake "$RSCENE" -o "$BDIR/out/" --compression none --format half --quiet
check_rc bake.rebake 0
check_eq bake.rebake_quiet "$SB_ERR" ""
check bake.rebake_manifest grep -q '"compression":[[:space:]]*"none"' "$BDIR/out/manifest.json"
check_eq bake.rebake_leftovers "$(bake_leftovers)" 0
check_match bake.half_channels "$(exr_header "$BDIR/out/optics_$l0.exr")" "410001000000.*520001000000"

# The emission maps have K x K texels per facet (3 by default).
if have python3 python3; then
    etex=$(python3 -c 'import json, sys
m = json.load(open(sys.argv[1]))
print(" ".join("%d/%d" % (l["emission_texels"][0], l["texels"][0]) for l in m["levels"] if not l["low_res"]))' \
        "$BDIR/out/manifest.json")
    check_match bake.emission_texels "$etex" '^[0-9]+/[0-9]+'
    for pair in $etex; do
        check_eq "bake.emission_k3.$pair" "$(( ${pair%/*} ))" "$(( 3 * ${pair#*/} ))"
    done
    ewidth=$(python3 -c 'import sys
sys.path.insert(0, sys.argv[1])
import exr_read
print(exr_read.header(sys.argv[2])[0])' "$top_srcdir/tests" "$BDIR/out/emission_$l0.exr")
    check_eq bake.emission_width "$ewidth" "$(( ${etex%%/*} ))"
fi
sb_run bake "$RSCENE" -o "$BDIR/explain" --explain --quiet
check_rc bake.explain_rc 0
check_match bake.explain_levels "$SB_ERR" "^bake: .*sea.ini: [0-9]+ x [0-9]+ pixels"
check_match bake.explain_waves "$SB_ERR" "bake: waves: [0-9]+ sinusoids"
sb_run bake "$RSCENE" -o "$BDIR/k5" --emission-texels 5 --quiet
check_rc bake.k5 0
check bake.k5_manifest grep -q '"emission_texels"' "$BDIR/k5/manifest.json"
# The exports project the sensor's image by default (sensor.exr, listed in
# the manifest, named in sea.inc); --emission-space map leaves it out.
sb_run bake "$RSCENE" -o "$BDIR/space" --pov --quiet
check_rc bake.space_sensor 0
check bake.space_sensor_file test -s "$BDIR/space/sensor.exr"
check bake.space_sensor_manifest grep -q '"exr":[[:space:]]*"sensor.exr"' "$BDIR/space/manifest.json"
check bake.space_sensor_inc grep -q 'exr "sensor.exr"' "$BDIR/space/sea.inc"
sb_run bake "$RSCENE" -o "$BDIR/space" --pov --emission-space map --quiet
check_rc bake.space_map 0
check_eq bake.space_map_no_file "$(ls "$BDIR/space" | grep -c sensor)" 0
check_eq bake.space_map_no_inc "$(grep -c Seabake_Sensor "$BDIR/space/sea.inc")" 0

# Failures leave DIR exactly as it was, and nothing beside it.
before=$(bake_state "$BDIR/out")
sb_run bake "$RSCENE" -o "$BDIR/out" --emission-texels 2
check_error bake.even_k 2 "--emission-texels: 2 is even \(allowed: odd, 1 to 7"
sb_run bake "$RSCENE" -o "$BDIR/out" --emission-texels 9
check_error bake.big_k 2 "--emission-texels: 9 is outside \\[1, 7\\]"
sb_run bake "$RSCENE" -o "$BDIR/out" --format nonsense
check_error bake.bad_format 2 "--format: 'nonsense' is not float or half"
sb_run bake "$RSCENE" -o "$BDIR/out" --compression lzw
check_error bake.bad_compression 2 "--compression: 'lzw' is not none, zip or piz"
sb_run bake "$RSCENE" -o "$BDIR/out" --frame-rate 10
check_error bake.rate_alone 2 "--frame-rate applies only with --frames"
sb_run bake "$RSCENE" -o "$BDIR/out" --emission-space map
check_error bake.space_alone 2 "--emission-space applies only with --pov or --blender"
sb_run bake "$RSCENE" -o "$BDIR/out" --pov --emission-space texels
check_error bake.bad_space 2 "--emission-space: 'texels' is not sensor or map"
sb_run bake "$RSCENE" -o "$BDIR/pov" --pov
check_rc bake.pov.rc 0
# shellcheck disable=SC2046 # (five numbers)
check bake.pov.summary_parts parts_ok $(maps_parts "$SB_ERR") 1
for f in scene.pov sea.inc scene.ini seabake.inc; do
    check "bake.pov.$f" test -s "$BDIR/pov/$f"
done
check_match bake.pov.camera "$(cat "$BDIR/pov/sea.inc")" 'camera'
# --blender adds the import script (the installed copy, byte for byte) and
# the manifest's "blender" object; without it neither is there.
sb_run bake "$RSCENE" -o "$BDIR/blender" --blender --quiet
check_rc bake.blender.rc 0
check bake.blender.script cmp -s "$BDIR/blender/seabake_import.py" \
    "$top_srcdir/exporters/blender/seabake_import.py"
check bake.blender.manifest grep -q '"script":[[:space:]]*"seabake_import.py"' \
    "$BDIR/blender/manifest.json"
check bake.blender.sky grep -qE '"sky_emission":[[:space:]]*[0-9]' "$BDIR/blender/manifest.json"
check bake.no_blender.script test ! -e "$BDIR/pov/seabake_import.py"
check_no_match bake.no_blender.manifest "$(cat "$BDIR/pov/manifest.json")" '"blender"'
sb_run bake "$RSCENE"
check_error bake.no_dir 2 "missing -o DIR"
sb_run bake "$BDIR/no-such.ini" -o "$BDIR/out"
check_error bake.no_scene 3 "no-such.ini"
check_eq bake.failures_keep_dir "$(bake_state "$BDIR/out")" "$before"
sb_run bake "$RSCENE" -o "$BDIR/no/such/parent/out"
check_error bake.no_parent 3 "-o: the directory '.*no/such/parent' does not exist$"
check bake.no_parent_nothing_made test ! -e "$BDIR/no"
# An unwritable parent.  Root may write anywhere: as root the bake runs as
# nobody (setpriv), for whom the directory is read-only.
as_user=""
if [ "$(id -u)" -eq 0 ]; then
    if command -v setpriv >/dev/null 2>&1 && id nobody >/dev/null 2>&1; then
        as_user="setpriv --reuid=nobody --regid=$(id -g nobody) --clear-groups"
    fi
fi
if [ "$(id -u)" -ne 0 ] || [ -n "$as_user" ]; then
    mkdir -p "$BDIR/ro/out" && : >"$BDIR/ro/out/keep" && chmod 555 "$BDIR/ro"
    [ -n "$as_user" ] && chmod 755 "$BDIR" "$SB_TMP" "$(dirname "$RSCENE")" && \
        chmod o+r "$RSCENE"
    ro_before=$(bake_state "$BDIR/ro/out")
    SB_CMD="$as_user seabake bake $RSCENE -o $BDIR/ro/out"
    # shellcheck disable=SC2086
    $as_user $SEABAKE_WRAPPER "$SEABAKE" bake "$RSCENE" -o "$BDIR/ro/out" >"$SB_TMP/out" \
        2>"$SB_TMP/err"
    SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
    check_error bake.unwritable_parent 3 "-o: cannot (create|write into directory)"
    check_eq bake.unwritable_keeps "$(bake_state "$BDIR/ro/out")" "$ro_before"
    check_eq bake.unwritable_leftovers "$(find "$BDIR/ro" -maxdepth 1 -name 'out.*' | grep -c '')" 0
    chmod 755 "$BDIR/ro"
else
    echo "cli.sh: running as root without setpriv: the unwritable-parent bake is not tested" >&2
fi
# -o '.', '..' or '/' cannot be renamed: refused before any work.
for d in . .. / ./ "$BDIR/.."; do
    sb_run bake "$RSCENE" -o "$d"
    check_error "bake.dot[$d]" 2 "-o: '.*' cannot be replaced by the bake \(name the directory itself, not '.', '..' or '/'\)"
done
check_eq bake.dot_leftovers "$(find "$BDIR/.." -maxdepth 1 -name '*.tmp.*' | grep -c '')" 0
# seabake replaces only what it can show it wrote.  Each case directly and
# through a symbolic link (the link is followed, the directory it points
# to replaced, the link kept): an empty directory and a bake are replaced;
# a bake with one extra file of the user's, a directory that is not a
# bake, a bake whose listed file is a symbolic link, and a manifest that is
# not seabake's are refused before any work, untouched, nothing beside them.
mkdir -p "$BDIR/own"
sb_run bake "$RSCENE" -o "$BDIR/own/seed" --quiet
check_rc bake.own_seed 0
own_case() { # own_case NAME SETUP: makes $BDIR/own/NAME as SETUP says
    rm -rf "${BDIR:?}/own/$1"
    case $2 in
    empty) mkdir "$BDIR/own/$1" ;;
    bake) cp -a "$BDIR/own/seed" "$BDIR/own/$1" ;;
    extra) cp -a "$BDIR/own/seed" "$BDIR/own/$1" && echo data >"$BDIR/own/$1/notes.txt" ;;
    subdir) cp -a "$BDIR/own/seed" "$BDIR/own/$1" && mkdir "$BDIR/own/$1/src" ;;
    user) mkdir -p "$BDIR/own/$1/src" && echo data >"$BDIR/own/$1/notes.txt" ;;
    linked) cp -a "$BDIR/own/seed" "$BDIR/own/$1" && f=$(cd "$BDIR/own/$1" && ls moments_*.exr | head -n 1) &&
            rm "$BDIR/own/$1/$f" && ln -s /etc/hostname "$BDIR/own/$1/$f" ;;
    foreign) mkdir "$BDIR/own/$1" && echo '{"format": "other", "files": ["manifest.json", "a"]}' \
                 >"$BDIR/own/$1/manifest.json" && : >"$BDIR/own/$1/a" ;;
    v01) cp -a "$BDIR/own/seed" "$BDIR/own/$1" &&
         python3 -c 'import json,sys; p=sys.argv[1]; m=json.load(open(p)); del m["files"]; json.dump(m, open(p, "w"))' \
             "$BDIR/own/$1/manifest.json" ;;
    esac
}
for via in dir link; do
    for c in empty bake; do
        own_case "$c" "$c"
        o="$BDIR/own/$c"
        if [ $via = link ]; then ln -sfn "$c" "$BDIR/own/l_$c"; o="$BDIR/own/l_$c"; fi
        sb_run bake "$RSCENE" -o "$o" --quiet
        check_rc "bake.own.$via.$c" 0
        check "bake.own.$via.${c}_new" test -s "$BDIR/own/$c/manifest.json"
        [ $via = link ] && check "bake.own.$via.${c}_link_kept" test -L "$o"
    done
    for c in extra subdir user linked foreign v01; do
        own_case "$c" "$c"
        o="$BDIR/own/$c"
        if [ $via = link ]; then ln -sfn "$c" "$BDIR/own/l_$c"; o="$BDIR/own/l_$c"; fi
        before=$(bake_state "$BDIR/own/$c")
        sb_run bake "$RSCENE" -o "$o" --quiet
        check_error "bake.own.$via.$c" 2 "-o: '.*$( [ $via = link ] && echo l_)$c' is not a bake that seabake wrote \(.*\); seabake replaces only its own bakes: choose another -o, or move or remove '.*' yourself"
        check_eq "bake.own.$via.${c}_untouched" "$(bake_state "$BDIR/own/$c")" "$before"
    done
done
check_match bake.own.user_names "$(sb_run bake "$RSCENE" -o "$BDIR/own/user"; echo "$SB_ERR")" \
    "it has no manifest.json and holds 'notes.txt' and 1 more"
check_match bake.own.extra_names "$(own_case extra extra; sb_run bake "$RSCENE" -o "$BDIR/own/extra"; echo "$SB_ERR")" \
    "it holds what its manifest.json does not list as a file of the bake: 'notes.txt'\)"
check_eq bake.own_leftovers "$(find "$BDIR/own" -maxdepth 1 \( -name '*.tmp.*' -o -name '*.old.*' \) | grep -c '')" 0
# Directories named like seabake's temporaries but not made by it (no
# marker inside) are never removed nor restored from.
mkdir -p "$BDIR/names/results.tmp.backup" "$BDIR/names/results.old.2024ab" \
    "$BDIR/names/results.tmp.AbC123" "$BDIR/names/results.old.XyZ789"
for d in results.tmp.backup results.old.2024ab results.tmp.AbC123 results.old.XyZ789; do
    echo mine >"$BDIR/names/$d/f"
done
names_before=$(bake_state "$BDIR/names")
sb_run bake "$RSCENE" -o "$BDIR/names/results"
check_rc bake.names_rc 0
check_no_match bake.names_silent "$SB_ERR" "removed|restored"
for d in results.tmp.backup results.old.2024ab results.tmp.AbC123 results.old.XyZ789; do
    check_eq "bake.names_kept[$d]" "$(cat "$BDIR/names/$d/f")" mine
done
# ... nor one whose marker names another directory or kind.
mkdir -p "$BDIR/names/results.old.Mrk001"
printf 'seabake temporary directory\nkind old\ntarget other\npid 1\nhost h\n' \
    >"$BDIR/names/results.old.Mrk001/.seabake-temporary"
echo mine >"$BDIR/names/results.old.Mrk001/f"
rm -rf "$BDIR/names/results"
sb_run bake "$RSCENE" -o "$BDIR/names/results" --quiet
check_rc bake.names_marker_other 0
check_eq bake.names_marker_other_kept "$(cat "$BDIR/names/results.old.Mrk001/f")" mine
rm -rf "$BDIR/names"
# A link to nothing is refused.
ln -s nowhere "$BDIR/dangling"
sb_run bake "$RSCENE" -o "$BDIR/dangling"
check_error bake.symlink_dangling 2 "-o: '.*dangling' is a symbolic link to nothing"
rm -rf "$BDIR/own" "$BDIR/dangling"
# The lock file is never followed: a symbolic link in its place is refused
# and the file it names is not created.
mkdir -p "$BDIR/lklink"
ln -s "$BDIR/lklink/elsewhere" "$BDIR/lklink/.out.lock"
sb_run bake "$RSCENE" -o "$BDIR/lklink/out"
check_error bake.lock_symlink 3 "-o: the lock file '.*\.out\.lock' is a symbolic link"
check bake.lock_symlink_not_created test ! -e "$BDIR/lklink/elsewhere"
check bake.lock_symlink_no_out test ! -e "$BDIR/lklink/out"
rm -rf "$BDIR/lklink"
# --set, as for render: the manifest shows the overridden wind.
sb_run bake "$RSCENE" -o "$BDIR/set" --set sea.wind_speed=12.5 --quiet
check_rc bake.set_rc 0
check bake.set_manifest grep -q '"wind_speed_m_s":[[:space:]]*12.5' "$BDIR/set/manifest.json"
sb_run bake "$RSCENE" -o "$BDIR/set" --set sea.wind_speed=0
check_error bake.set_range 2 "--set sea.wind_speed=0: \[sea\] wind_speed: 0 is out of range"
printf 'not a directory\n' >"$BDIR/plain"
sb_run bake "$RSCENE" -o "$BDIR/plain"
check_error bake.dir_is_file 3 "-o: '.*plain' exists and is not a directory"
check_eq bake.file_kept "$(cat "$BDIR/plain")" "not a directory"
check_eq bake.failures_leftovers "$(bake_leftovers)" 0

# Injected failures.  Disk full: a file size limit of 2 KiB (ulimit -f;
# seabake ignores SIGXFSZ, so that write fails with EFBIG as on a full
# disk, and the shell here does not) stops
# the first uncompressed map (16 bytes a texel, over a hundred texels even
# in the small scene used under valgrind); DIR is left as it was and
# nothing is left beside it.
mkdir -p "$BDIR/inj"
sb_run bake "$RSCENE" -o "$BDIR/inj/out" --quiet
check_rc bake.inj_seed 0
inj_before=$(bake_state "$BDIR/inj/out")
SB_CMD="seabake bake --compression none (ulimit -f 2)"
# shellcheck disable=SC2086
(ulimit -f 2 && exec $SEABAKE_WRAPPER "$SEABAKE" bake "$RSCENE" -o "$BDIR/inj/out" \
    --compression none) \
    >"$SB_TMP/out" 2>"$SB_TMP/err"
SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
check_error bake.disk_full 3 "cannot write .*: File too large"
check_eq bake.disk_full_keeps "$(bake_state "$BDIR/inj/out")" "$inj_before"
check_eq bake.disk_full_leftovers "$(find "$BDIR/inj" -maxdepth 1 -name 'out.*' | grep -c '')" 0

# --png none: no previews (nor in the manifest); --threads as render's.
sb_run bake "$RSCENE" -o "$BDIR/nopng" --png none --threads 1 --quiet
check_rc bake.png_none 0
check_eq bake.png_none_files "$(find "$BDIR/nopng" -name '*.png' | grep -c '')" 0
check_no_match bake.png_none_manifest "$(cat "$BDIR/nopng/manifest.json")" "\\.png"
sb_run bake "$RSCENE" -o "$BDIR/nopng2" --png out.png
check_error bake.png_file 2 "--png: 'out.png' is not none"
check bake.png_file_nothing [ ! -e "$BDIR/nopng2" ]
sb_run bake "$RSCENE" -o "$BDIR/nopng2" --threads 0
check_error bake.threads_range 2 "--threads: 0 is outside \\[1, "

# bake_then_signal SIG: a long bake (many frames) into $BDIR/inj/out, sent
# SIG once it has written frame 1 into its temporary directory (so it is
# baking, whatever the machine's speed); sets SB_RC.
bake_then_signal() {
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" bake "$RSCENE" -o "$BDIR/inj/out" --frames 0:999 \
        >"$SB_TMP/out" 2>"$SB_TMP/err" &
    local pid=$!
    wait_until exists "$BDIR/inj/out.tmp.*/optics_0_0001.exr"
    kill "-$1" "$pid"
    wait "$pid"
    SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
}
# SIGTERM (and SIGINT, SIGHUP): the bake removes its temporary directory,
# then dies of the signal (exit status 128 + 15 from the shell).
SB_CMD="seabake bake --frames 0:999, then SIGTERM"
bake_then_signal TERM
check_rc bake.sigterm 143
check_match bake.sigterm_message "$SB_ERR" "interrupted by signal 15: the output directory is left"
check_eq bake.sigterm_keeps "$(bake_state "$BDIR/inj/out")" "$inj_before"
check_eq bake.sigterm_leftovers "$(find "$BDIR/inj" -maxdepth 1 -name 'out.*' | grep -c '')" 0
# SIGTERM as soon as the temporary directory exists, while the scene is
# being prepared (mast.ini: a tenth of a second and more): the signal is
# already caught then, so the directory still goes (it stayed before).
$SEABAKE_WRAPPER "$SEABAKE" bake "$top_srcdir/examples/mast.ini" -o "$BDIR/inj/early" \
    --frames 0:99 --quiet >"$SB_TMP/out" 2>"$SB_TMP/err" &
early_pid=$! n=0
while ! find "$BDIR/inj" -maxdepth 1 -name 'early.tmp.*' | grep -q . && [ $n -lt 600 ]; do
    sleep 0.02
    n=$((n + 1))
done
kill -TERM "$early_pid"
wait "$early_pid"
SB_RC=$? SB_OUT=$(cat "$SB_TMP/out") SB_ERR=$(cat "$SB_TMP/err")
SB_CMD="seabake bake examples/mast.ini --frames 0:99, SIGTERM during the preparation"
check_rc bake.sigterm_prepare 143
check_match bake.sigterm_prepare_message "$SB_ERR" "interrupted by signal 15: the output directory is left"
check_eq bake.sigterm_prepare_leftovers "$(find "$BDIR/inj" -maxdepth 1 -name 'early*' | grep -c '')" 0
# SIGKILL cannot be caught: DIR is untouched and the temporary directory
# stays behind, until the next bake into DIR: it removes it (its owner's
# flock is gone) with a note, and leaves nothing beside DIR.
SB_CMD="seabake bake --frames 0:999, then SIGKILL"
bake_then_signal KILL
check_rc bake.sigkill 137
check_eq bake.sigkill_keeps "$(bake_state "$BDIR/inj/out")" "$inj_before"
check_eq bake.sigkill_temp_left "$(find "$BDIR/inj" -maxdepth 1 -name 'out.tmp.*' | grep -c '')" 1
stale=$(find "$BDIR/inj" -maxdepth 1 -name 'out.tmp.*')
sb_run bake "$RSCENE" -o "$BDIR/inj/out" --quiet
check_rc bake.after_sigkill 0
check_eq bake.after_sigkill_note "$SB_ERR" "bake: removed '$stale', left by a bake that was killed"
check_eq bake.after_sigkill_leftovers "$(find "$BDIR/inj" -maxdepth 1 -name 'out.*' | grep -c '')" 0
check bake.after_sigkill_new test -s "$BDIR/inj/out/manifest.json"
# A live bake's temporary directory is never taken for a stale one: while
# a long bake runs (holding the flock on its temporary), another bake into
# the same DIR leaves it alone; both end without debris.
# (ten frames natively, 10 s; three under valgrind, still far longer)
LIVE_LAST=9
[ -n "$SEABAKE_WRAPPER" ] && LIVE_LAST=2
# shellcheck disable=SC2086
$SEABAKE_WRAPPER "$SEABAKE" bake "$RSCENE" -o "$BDIR/inj/out" --frames "0:$LIVE_LAST" --quiet \
    >"$SB_TMP/out_a" 2>"$SB_TMP/err_a" &
pid_a=$!
n=0
while ! find "$BDIR/inj" -maxdepth 1 -name 'out.tmp.*' | grep -q . && [ $n -lt 600 ]; do
    sleep 0.1
    n=$((n + 1))
done
live=$(find "$BDIR/inj" -maxdepth 1 -name 'out.tmp.*')
sb_run bake "$RSCENE" -o "$BDIR/inj/out" --quiet
check_rc bake.concurrent_b 0
check_eq bake.concurrent_b_silent "$SB_ERR" ""
if kill -0 "$pid_a" 2>/dev/null; then
    check bake.concurrent_live_kept test -d "$live"
fi
wait "$pid_a"
check_eq bake.concurrent_a "$?" 0
check_eq bake.concurrent_a_silent "$(cat "$SB_TMP/err_a")" ""
check_eq bake.concurrent_leftovers "$(find "$BDIR/inj" -maxdepth 1 -name 'out.*' | grep -c '')" 0
check bake.concurrent_manifest test -s "$BDIR/inj/out/manifest.json"
# The commit holds an flock on PARENT/.DIR.lock: a bake finding it taken
# says so and waits (DIR untouched meanwhile), then completes.  Events, not
# durations: the holder takes the lock, then says so (a file) and holds it
# until a line comes through a FIFO; the bake is started once the lock is
# held and checked once it has said that it waits.
if have flock util-linux; then
    mkdir -p "$BDIR/lk"
    mkfifo "$SB_TMP/lk_release"
    flock "$BDIR/lk/.out.lock" sh -c ': >"$1"; read -r _ <"$2"' sh "$SB_TMP/lk_held" \
        "$SB_TMP/lk_release" &
    lock_pid=$!
    wait_until test -e "$SB_TMP/lk_held"
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" bake "$RSCENE" -o "$BDIR/lk/out" >"$SB_TMP/out" 2>"$SB_TMP/err" &
    pid_b=$!
    lock_noted() {
        grep -q "waiting for another bake" "$SB_TMP/err" || ! kill -0 "$pid_b" 2>/dev/null
    }
    wait_until lock_noted
    check bake.lock_waits kill -0 "$pid_b"
    check bake.lock_dir_untouched test ! -e "$BDIR/lk/out"
    echo release >"$SB_TMP/lk_release"
    wait "$lock_pid"
    wait "$pid_b"
    SB_RC=$? SB_ERR=$(cat "$SB_TMP/err")
    check_rc bake.lock_then_done 0
    check_match bake.lock_note "$SB_ERR" "^bake: waiting for another bake to finish writing '.*lk/out'$"
    check bake.lock_done test -s "$BDIR/lk/out/manifest.json"
    check_eq bake.lock_leftovers "$(ls -A "$BDIR/lk" | tr '\n' ' ')" ".out.lock out "
fi
# A bake killed between moving DIR aside and putting the new one in place
# (DIR missing, DIR.old.XXXXXX holding it): the next bake puts it back
# first, then replaces it as usual.
# The state is made as seabake's commit makes it: the bake is marked
# (.seabake-temporary: kind old, its target's name), then renamed aside.
mkdir -p "$BDIR/rs"
sb_run bake "$RSCENE" -o "$BDIR/rs/out" --quiet --set sea.wind_speed=6
printf 'seabake temporary directory\nkind old\ntarget out\npid 1\nhost h\n' \
    >"$BDIR/rs/out/.seabake-temporary"
mv "$BDIR/rs/out" "$BDIR/rs/out.old.AbC123"
sb_run bake "$RSCENE" -o "$BDIR/rs/out" --quiet
check_rc bake.restore_rc 0
check_match bake.restore_note "$SB_ERR" "^bake: '.*rs/out' restored from 'out.old.AbC123', left by a bake that was killed while replacing it$"
check bake.restore_replaced absent grep -q '"wind_speed_m_s":[[:space:]]*6,' "$BDIR/rs/out/manifest.json"
check bake.restore_no_marker test ! -e "$BDIR/rs/out/.seabake-temporary"
check_eq bake.restore_leftovers "$(ls -A "$BDIR/rs" | tr '\n' ' ')" ".out.lock out "

# Frames: every map of every HR level once per frame, numbered.
sb_run bake "$RSCENE" -o "$BDIR/frames" --frames 0:1 --frame-rate 10 --quiet
check_rc bake.frames 0
for f in 0000 0001; do
    for g in $BGROUPS; do
        check "bake.frames.${g}_${l0}_$f" test -s "$BDIR/frames/${g}_${l0}_$f.exr"
        check "bake.frames.${g}_${l0}_$f.png" test -s "$BDIR/frames/${g}_${l0}_$f.png"
    done
done
check_eq bake.frames_count "$(find "$BDIR/frames" -name '*.exr' | grep -c '')" \
    "$(( $(printf '%s\n' $hr | grep -c '') * 12 ))"
check bake.frames_time grep -q '"time_s":[[:space:]]*0.1' "$BDIR/frames/manifest.json"
check bake.frames_differ absent cmp -s "$BDIR/frames/moments_${l0}_0000.exr" \
    "$BDIR/frames/moments_${l0}_0001.exr"


# ================================================================ convert

# seabake convert (issue 45): an EXR's channels as .npy or CSV.  The EXRs
# are uncompressed so that numpy reads them independently of OpenEXR
# (check.py below): the .npy holds, bit for bit, the FLOAT or HALF values
# of the file (HALF widened to float32, which holds each exactly), and the
# CSV's %.9g text reads back as the same float32.
CDIR="$SB_TMP/convert"
mkdir -p "$CDIR" || exit 99
sb_run render "$RSCENE" -o "$CDIR/r.exr" --set sensor.netd=0.05 --aov temperature \
    --compression none --png none --quiet
check_rc convert.render_rc 0
sb_run render "$RSCENE" -o "$CDIR/h.exr" --format half --compression none --png none --quiet
check_rc convert.render_half_rc 0
sb_run convert "$CDIR/r.camera.exr" "$CDIR/cam.npy"
check_rc convert.npy_rc 0
check_eq convert.npy_stdout "$SB_OUT" ""
check_match convert.npy_summary "$SB_ERR" \
    "^convert: '.*r.camera.exr' -> '.*cam.npy': $RSIZE x $RSIZE pixels, float32 shape \($RSIZE, $RSIZE, 2\), last axis T,Y$"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/yt.npy" --channel Y --channel T --quiet
check_rc convert.order_rc 0
check_eq convert.quiet "$SB_ERR" ""
sb_run convert "$CDIR/h.exr" "$CDIR/h.npy"
check_match convert.half_summary "$SB_ERR" "channel Y \(1 half channel, widened exactly\)$"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/cam.csv" --channel T,Y
check_rc convert.csv_rc 0
check_eq convert.csv_header "$(head -n 1 "$CDIR/cam.csv")" "x,y,T,Y"
check_eq convert.csv_rows "$(grep -c '' "$CDIR/cam.csv")" $((RSIZE * RSIZE + 1))
sb_run convert "$CDIR/r.temperature.exr" "$CDIR/t.dat" --format csv --quiet
check_rc convert.format_rc 0
check_eq convert.format_header "$(head -n 1 "$CDIR/t.dat")" "x,y,Y"
if numpy_python; then
    cat >"$CDIR/check.py" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv.pop(1))
import exr_read

def exr(path):
    """The channels of an uncompressed EXR (FLOAT or HALF) as float32 arrays
    (H, W), read without OpenEXR (tests/exr_read.py; each value widened
    exactly, so float32 holds it exactly)."""
    chans, _, _ = exr_read.read(path)
    return {c: np.array(rows, np.float64).astype(np.float32) for c, (_, rows) in chans.items()}

def same(a, b):
    return a.shape == b.shape and a.dtype == b.dtype == np.float32 and \
        np.array_equal(a.view(np.uint32), b.view(np.uint32))

mode, src, dst, names = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(",")
ch = exr(src)
want = ch[names[0]] if len(names) == 1 else np.stack([ch[n] for n in names], axis=-1)
if mode == "npy":
    got = np.load(dst)
else:
    rows = [l.split(",") for l in open(dst).read().splitlines()]
    assert rows[0] == ["x", "y"] + names, rows[0]
    h, w = want.shape[0], want.shape[1]
    xy = [(int(r[0]), int(r[1])) for r in rows[1:]]
    assert xy == [(x, y) for y in range(h) for x in range(w)], "pixel order"
    got = np.array([[float(v) for v in r[2:]] for r in rows[1:]], np.float64).astype(np.float32)
    got = got.reshape(want.shape)
print("exact" if same(got, want) else "differ %d" % np.count_nonzero(got != want))
PY
    # convert_check MODE EXR OUT CHANNELS: exact, or differ N
    convert_check() { "$NUMPY_PY" "$CDIR/check.py" "$top_srcdir/tests" "$@" 2>&1; }
    check_eq convert.npy_exact "$(convert_check npy "$CDIR/r.camera.exr" "$CDIR/cam.npy" T,Y)" \
        exact
    check_eq convert.npy_order "$(convert_check npy "$CDIR/r.camera.exr" "$CDIR/yt.npy" Y,T)" \
        exact
    check_eq convert.npy_half_exact "$(convert_check npy "$CDIR/h.exr" "$CDIR/h.npy" Y)" exact
    check_eq convert.csv_exact "$(convert_check csv "$CDIR/r.camera.exr" "$CDIR/cam.csv" T,Y)" \
        exact
    # the check can fail: the camera's T is not its Y
    check_eq convert.check_can_fail "$(convert_check npy "$CDIR/r.camera.exr" "$CDIR/cam.npy" \
        Y,T | cut -d' ' -f1)" differ
fi

# Refused, with nothing written (no OUT, no temporary beside it).
printf 'not an image\n' >"$CDIR/text.exr"
sb_run convert "$CDIR/none.exr" "$CDIR/e1.npy"
check_error convert.missing 3 "none.exr.*No such file"
sb_run convert "$CDIR/text.exr" "$CDIR/e2.npy"
check_error convert.not_exr 3 "'.*text.exr' is not an OpenEXR file"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/e3.npy" --channel T,Z
check_error convert.unknown_channel 2 "has no channel 'Z' \(its channels: T, Y\)"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/e4.txt"
check_error convert.unknown_ext 2 "'.*e4.txt': unknown output format \(allowed: .*npy.*csv"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/e5.npy" --format csv
check_error convert.format_conflict 2 "--format csv, but"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/nodir/e6.npy"
check_error convert.missing_dir 3 "the directory '.*nodir' does not exist"
sb_run convert "$CDIR/r.camera.exr" "$CDIR/e7.npy" --channel Y,Y
check_error convert.twice 2 "'Y' given twice"
# A write that fails midway (a file size limit of 1 KiB; the CSV is
# larger): an error, and neither OUT nor its temporary is left.
SB_CMD="seabake convert r.camera.exr e8.csv (ulimit -f 1)"
(ulimit -f 1 && exec $SEABAKE_WRAPPER "$SEABAKE" convert "$CDIR/r.camera.exr" "$CDIR/e8.csv") \
    >"$SB_TMP/out" 2>"$SB_TMP/err"
SB_RC=$?
SB_OUT=$(cat "$SB_TMP/out")
SB_ERR=$(cat "$SB_TMP/err")
check_error convert.write_fails 3 "e8.csv.*File too large"
check_eq convert.nothing_left "$(cd "$CDIR" && ls -A | grep -E '^e[0-9]' | tr '\n' ' ')" ""


# --png-tone (issue 45): an 8-12 um sea under a 265 K sky
# (examples/longwave.ini looking 86 deg from nadir, 80 x 64: the horizon in
# view).  Measured: with the scene's curve the sea pixels span grey 186 to
# 255 (27.1 % of 0-255: the sky, 1520 of 5120 pixels, takes the black end);
# with the sea's curve 0 to 255 (100 %), and auto chooses it (the sky's median, 265 K, is below
# the sea's 0.5 % quantile, about 283.6 K, by more than the sea's own
# 0.5-99.5 % range, about 6.6 K).  Asserted: scene < 35 %, sea >= 90 %.
TDIR="$SB_TMP/tone"
mkdir -p "$TDIR" || exit 99
for tone in scene sea auto; do
    sb_run render "$top_srcdir/examples/longwave.ini" -o "$TDIR/$tone.exr" --aov level \
        --set sensor.look_zenith=86 --set sensor.width=80 --set sensor.height=64 \
        --png-tone "$tone" --quiet
    check_rc "tone.$tone.rc" 0
    sb_run convert "$TDIR/$tone.level.exr" "$TDIR/$tone.level.csv" --quiet
    check_rc "tone.$tone.level_csv" 0
done
check_match tone.sea_text "$(png_text "$TDIR/sea.png" seabake:tone)" \
    "^brightness temperature: linear 28[0-9.]+ K black to 2[89][0-9.]+ K white \(the sea's 0.5-99.5 % quantiles; sky clamped\)$"
check_eq tone.auto_is_sea "$(png_text "$TDIR/auto.png" seabake:tone)" \
    "$(png_text "$TDIR/sea.png" seabake:tone)"
check tone.auto_same_png cmp -s "$TDIR/auto.png" "$TDIR/sea.png"
if have python3 python3; then
    cat >"$TDIR/span.py" <<'PY'
import struct, sys, zlib
def png8(path):
    """The samples of an 8-bit grey PNG of filters None and Sub (seabake's)."""
    d = open(path, "rb").read(); i, idat = 8, b""
    while i < len(d):
        n, t = struct.unpack(">I4s", d[i:i + 8])
        if t == b"IHDR": w, h, bits = struct.unpack(">IIB", d[i + 8:i + 17])
        if t == b"IDAT": idat += d[i + 8:i + 8 + n]
        i += 12 + n
    assert bits == 8
    raw, out = zlib.decompress(idat), []
    for y in range(h):
        f, row = raw[y * (w + 1)], bytearray(raw[y * (w + 1) + 1:(y + 1) * (w + 1)])
        assert f in (0, 1)
        if f == 1:
            for x in range(1, w): row[x] = (row[x] + row[x - 1]) & 255
        out += list(row)
    return out
grey = png8(sys.argv[1])
level = [float(l.split(",")[2]) for l in open(sys.argv[2]).read().splitlines()[1:]]
sea = [g for g, l in zip(grey, level) if l > 0]
sky = len(level) - len(sea)
print("%.1f %d %d" % (100.0 * (max(sea) - min(sea)) / 255, len(sea), sky))
PY
    read -r span_scene nsea nsky <<<"$(python3 "$TDIR/span.py" "$TDIR/scene.png" "$TDIR/scene.level.csv")"
    read -r span_sea _ _ <<<"$(python3 "$TDIR/span.py" "$TDIR/sea.png" "$TDIR/sea.level.csv")"
    num_check tone.sky_in_view 'k > 500 && s > 2000' "k=${nsky:-0}" "s=${nsea:-0}"
    num_check tone.scene_span 'p < 35' "p=${span_scene:-100}"
    num_check tone.sea_span 'p >= 90' "p=${span_sea:-0}"
fi
# tiny.ini has no sky in view: auto keeps the scene's curve.
sb_run render "$RSCENE" -o "$TDIR/tiny_auto.exr" --quiet
sb_run render "$RSCENE" -o "$TDIR/tiny_scene.exr" --png-tone scene --quiet
check tone.no_sky_auto_is_scene cmp -s "$TDIR/tiny_auto.png" "$TDIR/tiny_scene.png"
sb_run render "$RSCENE" -o "$TDIR/e.exr" --png-tone dark
check_error tone.bad_name 2 "--png-tone: 'dark' is not a tone \(allowed: auto, scene, sea\)"
sb_run render "$RSCENE" -o "$TDIR/e.exr" --png-tone sea --png-range 270:300
check_error tone.with_range 2 "--png-tone and --png-range: choose one"
sb_run render "$RSCENE" -o "$TDIR/e.exr" --png-tone sea --png none
check_error tone.without_png 2 "--png-tone applies only to a preview"

finish
