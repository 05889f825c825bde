#!/bin/bash
# man_examples.sh - runs every command of the EXAMPLES in seabake(1), so
# that the manual cannot drift from the program, checks that every
# option the program knows is documented there, and that every page of the
# manual formats cleanly and cites pages that exist.
#
# An example is a line starting with "seabake " inside an .EX/.EE block;
# a line ending with a backslash continues on the next one.  The roff
# escapes used in commands (\- \e \(dq \(aq \&) are undone first.  A shell
# loop "for VAR in V1 V2 ...; do" ... "done" around such lines runs them
# once per value, $VAR replaced by it.  A Python program written as
# "python3 - <<'EOF'" ... "EOF" in such a block runs with a python3 that
# has numpy (lib.sh's numpy_python): it must succeed and print something;
# a program that reads a file reads what the commands before it wrote.
# $(SHELL) may be a plain POSIX sh: these scripts need bash.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=man_examples
. "$(dirname "$0")/lib.sh"

: "${MANPAGE:?MANPAGE must name man/seabake.1}"

if [ ! -r "$MANPAGE" ]; then
    fail manpage.readable "cannot read $MANPAGE"
    finish
fi

# One command per line, continuations joined, without the leading "seabake".
awk -v pydir="$SB_TMP" '
    /^\.EX/ { inex = 1; next }
    /^\.EE/ { inex = 0; next }
    !inex { next }
    inpy && /^EOF$/ { inpy = 0; close(pyfile); next }
    inpy {
        line = $0
        gsub(/\\-/, "-", line)
        gsub(/\\\(dq/, "\"", line)
        gsub(/\\\(aq/, "\047", line)
        gsub(/\\&/, "", line)
        gsub(/\\e/, "\\", line)
        print line > pyfile
        next
    }
    /^python3 \\- <<\\\(aqEOF\\\(aq$/ {
        npy++
        pyfile = pydir "/example" npy ".py"
        printf "" > pyfile
        print "@python " pyfile
        inpy = 1
        next
    }
    /^for [A-Za-z_][A-Za-z0-9_]* in .*; do$/ {
        loopvar = $2
        nvals = 0
        for (f = 4; f <= NF && $f != "do"; f++) {
            v = $f
            sub(/;$/, "", v)
            if (v != "") vals[++nvals] = v
        }
        next
    }
    /^done$/ { loopvar = ""; next }
    {
        line = $0
        if (loopvar != "") sub(/^[ \t]+/, "", line)
        gsub(/\\-/, "-", line)
        gsub(/\\\(dq/, "\"", line)
        gsub(/\\\(aq/, "\047", line)
        gsub(/\\&/, "", line)
        gsub(/\\e/, "\\", line)
        if (cmd == "" && line !~ /^seabake /) next
        cmd = cmd (cmd == "" ? "" : " ") line
        if (cmd ~ /\\$/) { sub(/[ \t]*\\$/, "", cmd); next }
        if (loopvar == "") {
            print substr(cmd, 9)
        } else {
            for (k = 1; k <= nvals; k++) {
                c = substr(cmd, 9)
                gsub("\\$" loopvar, vals[k], c)
                print c
            }
        }
        cmd = ""
    }
    END { if (cmd != "") print substr(cmd, 9) }
' "$MANPAGE" >"$SB_TMP/examples"

n_examples=$(grep -c '' "$SB_TMP/examples")
if [ "$n_examples" -eq 0 ]; then
    fail examples.present "no 'seabake ...' command in any .EX/.EE block of $MANPAGE"
else
    pass
fi

# Examples run in a scratch directory, so that the files they write (-o)
# vanish with it; the scenes of the render examples are found there as
# examples/NAME.ini, as from the top of the source tree.
mkdir -p "$SB_TMP/cwd" || exit 99
ln -s "$(cd "${top_srcdir:-$(dirname "$0")/..}" && pwd)/examples" "$SB_TMP/cwd/examples" &&
    cd "$SB_TMP/cwd" || exit 99
i=0
while IFS= read -r example; do
    i=$((i + 1))
    case $example in
    "@python "*)
        pyfile=${example#@python }
        SB_CMD="python3 $pyfile: $(tr '\n' ';' <"$pyfile")"
        if numpy_python; then
            SB_OUT=$("$NUMPY_PY" "$pyfile" 2>"$SB_TMP/err")
            SB_RC=$?
            SB_ERR=$(cat "$SB_TMP/err")
            check_ok "example $i: $SB_CMD"
            check_no_match "example $i nan/inf: $SB_CMD" "$SB_OUT" "[Nn][Aa][Nn]|[Ii][Nn][Ff]"
        fi
        continue
        ;;
    esac
    # The manual's own quoting splits the words, as a shell user would.
    eval "set -- $example"
    sb_run "$@"
    if [ "$1" = convergence ] && [ "$SB_RC" -eq 1 ] && ! have gnuplot gnuplot-nox; then
        # The chart needs gnuplot; without it the command says so and fails.
        check_match "example $i: seabake $example (no gnuplot)" "$SB_ERR" "gnuplot not found"
        continue
    fi
    case " $* " in
    " convergence "* | " bench "*)
        # A table on stdout and files in a directory, not CSV on stdout.
        check_ok "example $i: seabake $example"
        ;;
    " convert "*)
        # The output goes to a file: nothing on stdout, and with --quiet
        # nothing on stderr.
        check_rc "example $i: seabake $example" 0
        check_eq "example $i stdout: seabake $example" "$SB_OUT" ""
        check_eq "example $i stderr: seabake $example" "$SB_ERR" ""
        ;;
    *" -o "*)
        # The output goes to a file: nothing on stdout or stderr.
        check_rc "example $i: seabake $example" 0
        check_eq "example $i stderr: seabake $example" "$SB_ERR" ""
        ;;
    *)
        check_ok "example $i: seabake $example"
        check_csv_shape "example $i csv: seabake $example"
        ;;
    esac
    check_no_match "example $i nan/inf: seabake $example" "$SB_OUT" "[Nn][Aa][Nn]|[Ii][Nn][Ff]"
done <"$SB_TMP/examples"

# Every option defined in the help of every subcommand listed by
# 'seabake help' has its own entry in the manual: ".TP" followed by
# ".B --opt" or ".BI --opt ARG" (roff writes - as \-).
sb_run help
commands=$(printf '%s\n' "$SB_OUT" | awk '
    /^Subcommands:/ { on = 1; next }
    on && /^$/ { on = 0 }
    on && /^  [a-z]/ && $1 != "help" { print $1 }')
check_match "help lists subcommands" "$commands" "spectrum"
for cmd in $commands; do
    sb_run help "$cmd"
    check_rc "help $cmd" 0
    # Option definitions are the help lines that start with blanks and - or --.
    for opt in $(printf '%s\n' "$SB_OUT" | sed -n 's/^ *\(--*[a-z][a-z-]*\).*/\1/p' | sort -u); do
        roff=$(printf '%s' "$opt" | sed 's/-/\\-/g')
        if ROFF_OPT=$roff awk '
            prev == ".TP" && ($0 == ".B " ENVIRON["ROFF_OPT"] ||
                              index($0, ".BI " ENVIRON["ROFF_OPT"] " ") == 1) { found = 1 }
            { prev = $0 }
            END { exit !found }' "$MANPAGE"; then
            pass
        else
            fail "documented $cmd $opt" "no '.B $opt' or '.BI $opt' entry in $MANPAGE"
        fi
    done
done

# seabake-scene(5) names every section the reader takes, and counts them
# right: the list is the one the reader's error message gives.
printf '[nosuch]\n' >"$SB_TMP/sections.ini"
sb_run render "$SB_TMP/sections.ini" -o "$SB_TMP/sections.exr"
sections=$(printf '%s\n' "$SB_ERR" | sed -n 's/.*unknown section (allowed: \([a-z, ]*\)).*/\1/p' |
    tr -d ' ' | tr ',' ' ')
check_match "scene sections listed" "$sections" "^sea swell sun"
n=$(printf '%s\n' $sections | grep -c '')
words="zero one two three four five six seven eight nine ten"
nword=$(printf '%s\n' $words | sed -n "$((n + 1))p")
scene5="$(dirname "$MANPAGE")/seabake-scene.5"
check "scene(5) counts $n sections" grep -q "It is an INI file of $nword sections" "$scene5"
for sec in $sections; do
    check "scene(5) lists [$sec]" grep -q "^\.BR* \[$sec\]" "$scene5"
done

# Every page of the manual (those beside $MANPAGE: seabake.1,
# seabake-scene.5, seabake-model.7) formats without warnings where a
# formatter is installed, names only seabake pages that exist, and cites
# nothing outside the project.
mandir=$(dirname "$MANPAGE")
pages=$(cd "$mandir" && ls seabake*.[1-9] 2>/dev/null)
check_match "manual pages" "$pages" "^seabake-model\.7$"
# groff: scripts/setup installs it; absent, a SKIP line (a failure under
# SEABAKE_REQUIRE_TOOLS=1)
have_groff=0
have groff groff && have_groff=1
for page in $pages; do
    if [ "$have_groff" = 1 ]; then
        warnings=$(groff -man -ww -z "$mandir/$page" 2>&1)
        check_eq "groff warnings $page" "$warnings" ""
    fi
    # .BR seabake\-scene (5) and the like, roff's \- written as -.
    for ref in $(sed -n 's/^\.BR* \(seabake[a-z\\-]*\) (\([1-9]\)).*/\1.\2/p' "$mandir/$page" |
        sed 's/\\-/-/g' | sort -u); do
        check "$page cites $ref" test -r "$mandir/$ref"
    done
    check_no_match "$page cites only the project" "$(cat "$mandir/$page")" \
        "PHYSICS\.md|DESIGN\.md|STYLE\.md|CLIENTS\.md|shared/"
done
finish
