#!/bin/sh
# mc_regen.sh - the Monte Carlo tables of tests/data stay true: a few of
# their rows are traced again by the programs that wrote them, with the
# same settings on surfaces of other seeds, and must agree with the stored
# rows within their statistical error.  (The full tables take minutes of
# CPU: tests/mc_oracle.c, tests/mc_sea_oracle.c.)
#
#  - tests/data/mc_emissivity.csv (one-scale surfaces, 1024^2, 8 cells a
#    correlation length, 32 seeds): 10 m/s, 4 and 10 um, 40, 80 and 85 deg,
#    both azimuths, on 8 new surfaces (seeds 33-40), columns eps1, eps and
#    eps_pol.  Each new mean differs from the stored one by a difference of
#    two independent means whose spread is that of one surface, sd =
#    se_stored sqrt(32): sigma = sd sqrt(1/32 + 1/8).
#  - tests/data/mc_sea_emissivity.csv (sea-spectrum surfaces, 1024^2 cells
#    of 4 cm, 12 seeds, one row per seed): 10 m/s, 80 and 85 deg, both
#    azimuths, on 4 new surfaces (seeds 13-16), the gap model_smith - eps1:
#    the model at each surface's own slope covariance takes out most of
#    the spread the long waves give eps1 (a surface's sd 4.8e-3 instead of
#    0.04 at 85 deg along the wind), and tests/test_mc.c holds the model,
#    stored and today's, to an independent Eq 7 within 1e-6; sd from the
#    12 stored rows, sigma = sd sqrt(1/12 + 1/4).
#  - tests/data/mc_stokes.csv (one-scale surfaces, 1024^2, 16 seeds, all
#    hits with polarisation): 10 m/s, 4 and 10 um, 80 and 85 deg, wind at
#    45 deg to the view, on 4 new surfaces (seeds 17-20), columns Q, U and
#    dolp; sigma = se_stored sqrt(16) sqrt(1/16 + 1/4).
#  - tests/data/mc_sea_full_emissivity.csv (8192^2 surfaces, 1 GB each and
#    a minute of CPU apiece): not traced again here.
#
# Bound: |new - stored| <= 4 sigma.  52 comparisons (strongly correlated:
# the wavelengths share their paths, the columns their surfaces); at 4
# sigma a correct tracer fails one with probability at most 52 x 6.3e-5 =
# 3.3e-3 for any other choice of seeds, while a change of the tracer that
# moves a row by 4 sigma (2e-4 to 1e-3 at 80-85 deg, 2e-5 at 40) fails.
# The seeds are fixed, so the outcome is reproducible.  About 35 s of CPU.
: "${top_srcdir:?top_srcdir must name the source directory}"
TEST_NAME=mc_regen
passed=0
failed=0
tmp=$(mktemp -d "${TMPDIR:-/tmp}/seabake-mc.XXXXXX") || exit 99
trap 'rm -rf "$tmp"' EXIT
data=$top_srcdir/tests/data

# compare NAME: reads "what value sigma" lines from $tmp/cmp; one check each.
compare() {
    if [ ! -s "$tmp/cmp" ]; then
        failed=$((failed + 1))
        echo "FAIL: $TEST_NAME: $1: nothing compared"
        return
    fi
    while read -r what d sigma; do
        if awk -v d="$d" -v s="$sigma" 'BEGIN { exit !(d <= 4 * s && d >= -4 * s && s > 0) }'; then
            passed=$((passed + 1))
            echo "$TEST_NAME: $1 $what: new - stored $d, sigma $sigma"
        else
            failed=$((failed + 1))
            echo "FAIL: $TEST_NAME: $1 $what: new - stored $d beyond 4 sigma ($sigma)"
        fi
    done <"$tmp/cmp"
}

if ./tests/mc_oracle -n 1024 -l 8 -s 8 -S 33 -r 100000 -w 10 -t 40,80,85 -p 0,90 \
    -o "$tmp/mc.csv" 2>"$tmp/mc.err"; then
    # stored: wind,wl,theta,phi,sxx,syy,eps1,eps1_se,eps,eps_se,eps_pol,eps_pol_se,...
    grep -hv '^#' "$data/mc_emissivity.csv" "$tmp/mc.csv" | awk -F, '
        $1 == "wind_ms" { file++; next }
        file == 1 { key = $1 "," $2 "," $3 "," $4; e[key, 1] = $7; s[key, 1] = $8
                    e[key, 2] = $9; s[key, 2] = $10; e[key, 3] = $11; s[key, 3] = $12; next }
        file == 2 {
            key = $1 "," $2 "," $3 "," $4
            if (!((key, 1) in e)) { print key " no-stored-row 0"; next }
            split("eps1 eps eps_pol", name, " ")
            for (c = 1; c <= 3; c++) {
                v = c == 1 ? $7 : c == 2 ? $9 : $11
                sigma = s[key, c] * sqrt(32) * sqrt(1 / 32 + 1 / 8)
                printf "%s:%s %.3g %.3g\n", key, name[c], v - e[key, c], sigma
            }
        }' >"$tmp/cmp"
    compare mc_emissivity
else
    failed=$((failed + 1))
    echo "FAIL: $TEST_NAME: tests/mc_oracle failed: $(tail -n 3 "$tmp/mc.err")"
fi

if ./tests/mc_sea_oracle -n 1024 -d 0.04 -s 4 -S 13 -r 50000 -w 10 -t 80,85 -p 0,90 \
    -o "$tmp/sea.csv" 2>"$tmp/sea.err"; then
    # wind,seed,theta,phi,sxx,syy,sxy,eps1,model_smith,...: per direction
    grep -hv '^#' "$data/mc_sea_emissivity.csv" "$tmp/sea.csv" | awk -F, '
        $1 == "wind_ms" { file++; next }
        { key = $1 "," $3 "," $4; g = $9 - $8
          n[file, key]++; sum[file, key] += g; sq[file, key] += g * g
          if (file == 2) keys[key] = 1 }
        END {
            for (key in keys) {
                if (n[1, key] < 2) { print key " no-stored-rows 0"; continue }
                m1 = sum[1, key] / n[1, key]; m2 = sum[2, key] / n[2, key]
                var = (sq[1, key] - n[1, key] * m1 * m1) / (n[1, key] - 1)
                sigma = sqrt((var > 0 ? var : 0) * (1 / n[1, key] + 1 / n[2, key]))
                printf "%s:model_smith-eps1 %.3g %.3g\n", key, m2 - m1, sigma
            }
        }' >"$tmp/cmp"
    compare mc_sea_emissivity
else
    failed=$((failed + 1))
    echo "FAIL: $TEST_NAME: tests/mc_sea_oracle failed: $(tail -n 3 "$tmp/sea.err")"
fi

if ./tests/mc_stokes_oracle -n 1024 -l 8 -s 4 -S 17 -r 50000 -w 10 -t 80,85 -p 45 \
    -o "$tmp/stokes.csv" 2>"$tmp/stokes.err"; then
    # wind,wl,theta,phi,sxx,syy,I,I_se,Q,Q_se,U,U_se,V,dolp,dolp_se,...
    grep -hv '^#' "$data/mc_stokes.csv" "$tmp/stokes.csv" | awk -F, '
        $1 == "wind_ms" { file++; next }
        file == 1 { key = $1 "," $2 "," $3 "," $4; q[key] = $9; qs[key] = $10
                    u[key] = $11; us[key] = $12; d[key] = $14; ds[key] = $15; next }
        file == 2 {
            key = $1 "," $2 "," $3 "," $4
            if (!(key in q)) { print key " no-stored-row 0"; next }
            f = sqrt(16) * sqrt(1 / 16 + 1 / 4)
            printf "%s:Q %.3g %.3g\n", key, $9 - q[key], qs[key] * f
            printf "%s:U %.3g %.3g\n", key, $11 - u[key], us[key] * f
            printf "%s:dolp %.3g %.3g\n", key, $14 - d[key], ds[key] * f
        }' >"$tmp/cmp"
    compare mc_stokes
else
    failed=$((failed + 1))
    echo "FAIL: $TEST_NAME: tests/mc_stokes_oracle failed: $(tail -n 3 "$tmp/stokes.err")"
fi

echo "$TEST_NAME: $passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
