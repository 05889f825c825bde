# lib.sh - helpers sourced by the shell tests of seabake.
#
# Environment (set by Makefile.am's TESTS_ENVIRONMENT):
#   SEABAKE          path of the built program (required)
#   SEABAKE_WRAPPER  command put in front of it, e.g. "valgrind ..." (may be empty)
#   MANPAGE          path of man/seabake.1
#   top_srcdir       source directory
#
# A test script sets TEST_NAME, sources this file, calls sb_run and the
# check_* helpers, and ends with `finish`, which prints one line
# "NAME: N passed, M failed" and fails on any failure (or on no check at all).

: "${SEABAKE:?SEABAKE must name the built seabake program}"
SEABAKE_WRAPPER=${SEABAKE_WRAPPER-}
TEST_NAME=${TEST_NAME:-$(basename "$0" .sh)}

SB_PASSED=0
SB_FAILED=0
SB_OUT=
SB_ERR=
SB_RC=0
SB_CMD=

# Scratch space outside the source tree, removed on exit.
SB_TMP=$(mktemp -d "${TMPDIR:-/tmp}/seabake-test.XXXXXX") || exit 99
trap 'rm -rf "$SB_TMP"' EXIT

# sb_run ARGS...: runs seabake; sets SB_OUT, SB_ERR (text) and SB_RC.
sb_run() {
    SB_CMD="seabake $*"
    # The wrapper is split into words on purpose ("valgrind --quiet ...").
    # shellcheck disable=SC2086
    $SEABAKE_WRAPPER "$SEABAKE" "$@" >"$SB_TMP/out" 2>"$SB_TMP/err"
    SB_RC=$?
    SB_OUT=$(cat "$SB_TMP/out")
    SB_ERR=$(cat "$SB_TMP/err")
}

pass() {
    SB_PASSED=$((SB_PASSED + 1))
}

# fail NAME DETAIL...: records a failure with the command that produced it.
fail() {
    local name=$1
    shift
    SB_FAILED=$((SB_FAILED + 1))
    printf 'FAIL: %s: %s\n' "$name" "$*" >&2
    if [ -n "$SB_CMD" ]; then
        printf '  command: %s\n  exit: %s\n' "$SB_CMD" "$SB_RC" >&2
        if [ -n "$SB_ERR" ]; then
            printf '  stderr: %s\n' "$(printf '%s\n' "$SB_ERR" | head -n 5)" >&2
        fi
    fi
}

# check NAME CONDITION-COMMAND...: passes when the command succeeds.
check() {
    local name=$1
    shift
    if "$@"; then pass; else fail "$name" "condition failed: $*"; fi
}

# check_rc NAME WANT: the last run's exit code.
check_rc() {
    if [ "$SB_RC" -eq "$2" ]; then pass; else fail "$1" "exit code $SB_RC, expected $2"; fi
}

# check_eq NAME GOT WANT
check_eq() {
    if [ "$2" = "$3" ]; then pass; else fail "$1" "got '$2', expected '$3'"; fi
}

# check_match NAME TEXT REGEX (extended regular expression)
check_match() {
    if printf '%s\n' "$2" | grep -Eq -- "$3"; then
        pass
    else
        fail "$1" "'$(printf '%s' "$2" | head -c 300)' does not match /$3/"
    fi
}

# check_no_match NAME TEXT REGEX
check_no_match() {
    if printf '%s\n' "$2" | grep -Eq -- "$3"; then
        fail "$1" "'$(printf '%s' "$2" | grep -E -- "$3" | head -n 3)' matches /$3/"
    else
        pass
    fi
}

# check_ok NAME: the last run succeeded, printed CSV and nothing on stderr.
check_ok() {
    if [ "$SB_RC" -ne 0 ]; then
        fail "$1" "exit code $SB_RC, expected 0"
    elif [ -z "$SB_OUT" ]; then
        fail "$1" "no output"
    elif [ -n "$SB_ERR" ]; then
        fail "$1" "unexpected stderr"
    else
        pass
    fi
}

# check_error NAME WANT_RC REGEX: the last run failed with WANT_RC, printed
# nothing on stdout and exactly one "seabake: error:" line matching REGEX.
check_error() {
    local name=$1 want=$2 re=$3 lines
    lines=$(printf '%s\n' "$SB_ERR" | grep -c '')
    if [ "$SB_RC" -ne "$want" ]; then
        fail "$name" "exit code $SB_RC, expected $want"
    elif [ -n "$SB_OUT" ]; then
        fail "$name" "unexpected stdout: $(printf '%s' "$SB_OUT" | head -c 200)"
    elif [ "$lines" -ne 1 ]; then
        fail "$name" "stderr has $lines lines, expected 1"
    elif ! printf '%s\n' "$SB_ERR" | grep -Eq -- "^seabake: error: .*$re"; then
        fail "$name" "stderr does not match /^seabake: error: .*$re/"
    else
        pass
    fi
}

# csv_header: first line of the last output.
csv_header() {
    printf '%s\n' "$SB_OUT" | grep -v '^#' | head -n 1
}

# csv_rows: number of data rows (lines after the header) of the last output.
csv_rows() {
    printf '%s\n' "$SB_OUT" | grep -v '^#' | tail -n +2 | grep -c ''
}

# claim_limit ID: the bound of claim ID of tests/claims.csv (a "<=" row:
# stated plus its absolute tolerance), for the shell tests that assert a
# figure of the manuals.
claim_limit() {
    awk -F, -v id="$1" '$1 == id { print $8 + $9; found = 1 } END { if (!found) print "nan" }' \
        "${top_srcdir:-.}/tests/claims.csv"
}

# csv_data: $SB_OUT without its comment lines (a leading "#": the model
# the emissivity subcommand names).
csv_data() {
    printf '%s\n' "$SB_OUT" | grep -v '^#'
}

# csv_col NAME ROW: the value of column NAME in data row ROW (1-based).
csv_col() {
    csv_data | awk -F, -v name="$1" -v row="$2" '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
        NR == row + 1 && c { print $c; found = 1 }
        END { if (!found) exit 1 }'
}

# csv_all NAME: every value of column NAME, one per line.
csv_all() {
    csv_data | awk -F, -v name="$1" '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; if (!c) exit 1; next }
        { print $c }'
}

# check_csv_shape NAME: every row has as many fields as the header, and
# every data field is a finite number (no empty field, nan or inf).
check_csv_shape() {
    local bad
    bad=$(csv_data | awk -F, '
        NR == 1 { n = NF; next }
        NF != n { print "row " NR - 1 ": " NF " fields, header has " n; exit }
        {
            for (i = 1; i <= NF; i++)
                if ($i !~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/) {
                    print "row " NR - 1 ", field " i ": \"" $i "\" is not a finite number"; exit
                }
        }
        END { if (NR < 2) print "no data row" }')
    if [ -z "$bad" ]; then pass; else fail "$1" "$bad"; fi
}

# num_check NAME EXPR VAR=VALUE...: passes when the awk expression EXPR is
# true with the given variables, e.g. num_check x 'a >= 0 && a <= 1' a=0.98.
num_check() {
    local name=$1 expr=$2
    shift 2
    local args=() kv
    for kv in "$@"; do args+=(-v "$kv"); done
    if awk "${args[@]}" "BEGIN { exit !($expr) }"; then
        pass
    else
        fail "$name" "not ($expr) with $*"
    fi
}

# check_close NAME A B TOL: |A - B| <= TOL; A and B may be equally long
# lists of numbers separated by blanks or newlines, compared element by element.
check_close() {
    local name=$1 bad
    bad=$(awk -v a="$2" -v b="$3" -v tol="$4" 'BEGIN {
        n = split(a, x, /[ \n]+/); m = split(b, y, /[ \n]+/)
        while (n > 0 && x[n] == "") n--
        while (m > 0 && y[m] == "") m--
        if (n != m || n == 0) { print n " values against " m; exit }
        for (i = 1; i <= n; i++) {
            d = x[i] - y[i]; if (d < 0) d = -d
            if (!(d <= tol)) { print "item " i ": " x[i] " vs " y[i] " differ by " d " > " tol; exit }
        }
    }')
    if [ -z "$bad" ]; then pass; else fail "$name" "$bad"; fi
}

# skip WHY...: says that some checks do not run here, on a line of its own
# "SKIP: NAME: WHY" that scripts/test counts (a skip is never silent).
skip() {
    echo "SKIP: $TEST_NAME: $*" >&2
}

# have PROGRAM PACKAGE: whether PROGRAM is installed.  Where it is absent,
# the checks that need it are skipped with a SKIP line naming the Debian
# package, except under scripts/test and CI (SEABAKE_REQUIRE_TOOLS=1), which
# install every package the tests use: there an absent program is a
# failure, so that a check cannot silently stop running on a fresh machine.
have() {
    command -v "$1" >/dev/null 2>&1 && return 0
    if [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ]; then
        fail "have.$1" "$1 is not installed (Debian package $2; scripts/setup installs it)"
    else
        skip "$1 is not installed (Debian package $2): its checks are skipped"
    fi
    return 1
}

# numpy_python: sets NUMPY_PY to a Python 3 that imports numpy (python3 on
# the PATH, else Debian's /usr/bin/python3: a pyenv or venv python3 may lack
# the Debian module) and succeeds; where there is none, as have: a SKIP line,
# or a failure under SEABAKE_REQUIRE_TOOLS=1 (scripts/setup installs
# python3-numpy).
NUMPY_PY=
numpy_python() {
    local py
    for py in python3 /usr/bin/python3; do
        if command -v "$py" >/dev/null 2>&1 && "$py" -c 'import numpy' >/dev/null 2>&1; then
            NUMPY_PY=$py
            return 0
        fi
    done
    if [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ]; then
        fail have.numpy "no python3 imports numpy (Debian package python3-numpy; scripts/setup installs it)"
    else
        skip "no python3 imports numpy (Debian package python3-numpy): its checks are skipped"
    fi
    return 1
}

# wait_until COMMAND...: waits for an event (a file appearing, a line
# written) by running COMMAND every 50 ms until it succeeds; nothing depends
# on how long the work before the event takes.  A guard of 20 minutes (a
# stuck program) returns 1 instead of hanging the suite.
wait_until() {
    local n=0
    until "$@"; do
        [ "$n" -ge 24000 ] && return 1
        sleep 0.05
        n=$((n + 1))
    done
    return 0
}

# exists GLOB: whether a path matches the glob (bash).
exists() {
    compgen -G "$1" >/dev/null
}

# png_color_type FILE: the colour type of a PNG (byte 25: 0 grey, 2 RGB).
png_color_type() {
    od -An -tu1 -j25 -N1 "$1" 2>/dev/null | tr -d ' '
}

# png_text FILE KEY: the text of the PNG's tEXt chunk KEY (empty if none).
png_text() {
    local keyhex
    keyhex=$(printf '%s' "$2" | od -An -v -tx1 | tr -d ' \n')
    od -An -v -tx1 "$1" 2>/dev/null | tr -d ' \n' | awk -v k="$keyhex" '
        function hexval(h,   i, v) {
            v = 0
            for (i = 1; i <= length(h); i++)
                v = v * 16 + index("0123456789abcdef", substr(h, i, 1)) - 1
            return v
        }
        {
            p = index($0, "74455874" k "00")
            if (p < 9)
                exit
            n = hexval(substr($0, p - 8, 8)) - length(k) / 2 - 1
            v = substr($0, p + 8 + length(k) + 2, 2 * n)
            out = ""
            for (i = 1; i <= length(v); i += 2)
                out = out sprintf("%c", hexval(substr(v, i, 2)))
            print out
        }'
}


# finish: prints the summary line; non-zero exit on any failure or no check.
finish() {
    printf '%s: %d passed, %d failed\n' "$TEST_NAME" "$SB_PASSED" "$SB_FAILED"
    if [ "$SB_FAILED" -ne 0 ] || [ "$SB_PASSED" -eq 0 ]; then
        exit 1
    fi
    exit 0
}
