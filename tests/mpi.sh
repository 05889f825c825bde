#!/bin/bash
# mpi.sh - render and bake shared among MPI ranks (seabake(1), PARALLEL
# RUNS WITH MPI): the files of mpirun -np 1 and -np 3 are those of one
# plain process byte for byte (cmp and diff -r of whole files: no output of
# render or bake carries a wall-clock time, so nothing is stripped), the
# summary is printed once, a failed rank fails the run with one
# "seabake: error:" line and leaves what one process leaves (render: the
# frames before the failed one; bake: DIR as it was, no temporaries).
# --oversubscribe: this machine has fewer cores than ranks.
#
# Built without MPI (configure --without-mpi) only the refusal of a launch
# of several ranks is checked, and the rest is skipped with a note, except
# under SEABAKE_REQUIRE_TOOLS=1 (scripts/test, CI: MPI is installed there),
# where a build without MPI is a failure.  Under SEABAKE_WRAPPER (valgrind,
# make check-valgrind) only plain runs are checked under it: valgrind of
# every rank under mpirun takes minutes and reports OpenMPI's own
# allocations; the MPI code paths run in the plain make check.
# $(SHELL) may be a plain POSIX sh: these scripts need bash.
[ -n "${BASH_VERSION:-}" ] || exec bash "$0" "$@"
set -u
TEST_NAME=mpi
. "$(dirname "$0")/lib.sh"

: "${top_srcdir:?top_srcdir must name the source directory}"
EX=$top_srcdir/examples
# OpenMPI refuses to start as root without both (CI runs as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# The plain program starts no MPI: nothing but its own output, under the
# wrapper too.
sb_run render "$EX/tiny.ini" -o "$SB_TMP/plain.exr" --quiet
check_rc plain.render.rc 0
check_eq plain.render.silent "$SB_ERR" ""

if [ -n "$SEABAKE_WRAPPER" ]; then
    skip "runs under mpirun, under $SEABAKE_WRAPPER (minutes of valgrind per rank; the plain run has them)"
    finish
fi
have mpirun openmpi-bin || finish

# sb_mpirun N ARGS...: seabake ARGS as N ranks, with the mpirun options in
# the array MPI_OPTS and a command put before seabake in MPI_WRAP (both
# usually empty); sets SB_OUT, SB_ERR (mpirun's own boxed notices, between
# lines of dashes, removed) and SB_RC (mpirun's: a failed rank's exit code).
MPI_OPTS=()
MPI_WRAP=()
sb_mpirun() {
    local n=$1
    shift
    SB_CMD="mpirun -np $n ${MPI_OPTS[*]} ${MPI_WRAP[*]} seabake $*"
    # An --enable-asan build (scripts/test): OpenMPI does not free all it
    # allocates, so its allocations are suppressed (tests/lsan-openmpi.supp),
    # which needs whole stacks (the slow unwinder) through its components
    # kept loaded; seabake's own leaks are still reported.
    LSAN_OPTIONS="suppressions=$top_srcdir/tests/lsan-openmpi.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
    ASAN_OPTIONS="fast_unwind_on_malloc=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
    OMPI_MCA_mca_base_component_disable_dlclose=1 \
        mpirun --oversubscribe "${MPI_OPTS[@]}" -np "$n" "${MPI_WRAP[@]}" "$SEABAKE" "$@" \
        >"$SB_TMP/out" 2>"$SB_TMP/err.raw" </dev/null
    SB_RC=$?
    SB_OUT=$(cat "$SB_TMP/out")
    SB_ERR=$(awk '/^-+$/ && length($0) > 20 { box = !box; next } !box' "$SB_TMP/err.raw")
}

# same_tree NAME A B: the same file names in A and B, each file equal.
same_tree() {
    if diff -r "$2" "$3" >"$SB_TMP/diff" 2>&1; then
        pass
    else
        fail "$1" "$(head -n 5 "$SB_TMP/diff")"
    fi
}

# no_temporaries NAME DIR: no *.tmp.* (a file's or a bake's) left in DIR.
no_temporaries() {
    local left
    left=$(find "$2" -name '*.tmp.*' | head -n 3)
    check_eq "$1" "$left" ""
}

# The summary line without its seconds.
timeless() {
    printf '%s\n' "$1" | sed -E 's/[0-9][0-9.e+-]* s( |,|:|\)|$)/S s\1/g; s/\([0-9.e+-]+ texels\/s\)/(R texels\/s)/'
}

# -------------------------------------------------------- built with MPI?
# A subcommand that does not share its work is refused under N > 1 ranks;
# a build without MPI refuses any N > 1 launch.  Either way: one message.
sb_mpirun 2 spectrum --wind 10
if printf '%s\n' "$SB_ERR" | grep -q 'built without MPI'; then
    check_error nompi.refused 2 "launched as one of 2 MPI ranks, but this seabake was built without MPI"
    if [ "${SEABAKE_REQUIRE_TOOLS:-0}" = 1 ]; then
        fail nompi.required "seabake was built without MPI (scripts/setup installs libopenmpi-dev; configure uses it when found)"
    else
        skip "seabake built without MPI: the sharing checks are skipped"
    fi
    finish
fi
check_error spectrum.refused 2 "spectrum does not share its work among MPI ranks: run it as one process"
# the help and the version once
sb_mpirun 3 --version
check_rc version.rc 0
check_eq version.once "$SB_OUT" "$("$SEABAKE" --version)"
sb_mpirun 3 render --help
check_rc render.help.rc 0
check_eq render.help.once "$SB_OUT" "$("$SEABAKE" render --help)"

# ------------------------------------------------------------------ render
# Frames 0 to 5 with AOVs and their previews: 3 ranks take frames
# {0, 3}, {1, 4}, {2, 5}; the previews' tone curves are frame 0's on every
# rank (rank 0 broadcasts them).
R=(render "$EX/tiny.ini" --frames 0:5 --aov level,emissivity,temperature)
for d in one np1 np3; do mkdir -p "$SB_TMP/r_$d"; done
sb_run "${R[@]}" -o "$SB_TMP/r_one/t.exr"
check_rc render.one.rc 0
summary_one=$(timeless "$SB_ERR")
sb_mpirun 1 "${R[@]}" -o "$SB_TMP/r_np1/t.exr"
check_rc render.np1.rc 0
sb_mpirun 3 "${R[@]}" -o "$SB_TMP/r_np3/t.exr"
check_rc render.np3.rc 0
check_eq render.np3.summary_once "$(timeless "$SB_ERR")" "$(timeless "${summary_one//r_one/r_np3}")"
check_eq render.files "$(ls "$SB_TMP/r_one" | wc -l)" 48
same_tree render.np1.identical "$SB_TMP/r_one" "$SB_TMP/r_np1"
same_tree render.np3.identical "$SB_TMP/r_one" "$SB_TMP/r_np3"
# The shared tone curve matters: frame 4 alone would have its own.
png_range() { grep -ao 'seabake:range_K.[0-9.:]*' "$1" | cut -c17-; }
check_eq render.np3.range_of_frame0 "$(png_range "$SB_TMP/r_np3/t_0004.png")" \
    "$(png_range "$SB_TMP/r_one/t_0000.png")"
mkdir -p "$SB_TMP/r_alone"
sb_run render "$EX/tiny.ini" --frames 4:4 -o "$SB_TMP/r_alone/t.exr" --quiet
check render.alone_differs [ "$(png_range "$SB_TMP/r_alone/t_0004.png")" != \
    "$(png_range "$SB_TMP/r_one/t_0000.png")" ]

# One frame shared by rows (rank k: rows k, k + 3, ...), written by rank 0.
for d in one np2 np3; do mkdir -p "$SB_TMP/f_$d"; done
F=(render "$EX/tiny.ini" --aov level,reflectivity)
sb_run "${F[@]}" -o "$SB_TMP/f_one/t.exr"
check_rc frame.one.rc 0
summary_one=$(timeless "$SB_ERR")
sb_mpirun 2 "${F[@]}" -o "$SB_TMP/f_np2/t.exr"
check_rc frame.np2.rc 0
sb_mpirun 3 "${F[@]}" -o "$SB_TMP/f_np3/t.exr"
check_rc frame.np3.rc 0
check_eq frame.np3.summary_once "$(timeless "$SB_ERR")" "$(timeless "${summary_one//f_one/f_np3}")"
same_tree frame.np2.identical "$SB_TMP/f_one" "$SB_TMP/f_np2"
same_tree frame.np3.identical "$SB_TMP/f_one" "$SB_TMP/f_np3"

# A frame that cannot be written (its name is a directory) on rank 1 of 3
# (frame 4): the run fails as one process does, with its one message;
# frames 0-3 stay, frame 5 (rank 2, written in the same round) is removed.
for d in one np3; do mkdir -p "$SB_TMP/x_$d/t_0004.exr"; done
sb_run render "$EX/tiny.ini" --frames 0:5 -o "$SB_TMP/x_one/t.exr" --quiet
check_error render.fail.one 3 "cannot write .*/x_one/t_0004.exr: Is a directory"
err_one=$SB_ERR
sb_mpirun 3 render "$EX/tiny.ini" --frames 0:5 -o "$SB_TMP/x_np3/t.exr" --quiet
check_error render.fail.np3 3 "cannot write .*/x_np3/t_0004.exr: Is a directory"
check_eq render.fail.same_message "$SB_ERR" "${err_one//x_one/x_np3}"
check_eq render.fail.same_files "$(ls -A "$SB_TMP/x_np3" | tr '\n' ' ')" \
    "$(ls -A "$SB_TMP/x_one" | tr '\n' ' ')"
check_eq render.fail.frames_before "$(ls -A "$SB_TMP/x_np3" | tr '\n' ' ')" \
    "t_0000.exr t_0000.png t_0001.exr t_0001.png t_0002.exr t_0002.png t_0003.exr t_0003.png t_0004.exr "
no_temporaries render.fail.no_temporaries "$SB_TMP/x_np3"

# Rank 1 stops on SIGTERM once frame 4, its second, is written (so that it
# is rendering, and has frames left, whatever the machine's speed): one
# message from rank 0 naming the frames kept, which are exactly those
# there (the frames after the interrupted one, written by other ranks in
# its round, removed), and no temporaries.
# rank1_term GLOB: MPI_WRAP's script for that: rank 1 runs seabake and
# sends it SIGTERM once a path matches GLOB (an event, polled every 50 ms,
# not a duration; if seabake ends first, nothing is sent and the checks
# below fail); the other ranks run it as they are.
rank1_term() {
    {
        echo '#!/bin/bash'
        echo '[ "${OMPI_COMM_WORLD_RANK:-0}" = 1 ] || exec "$@"'
        echo '"$@" &'
        echo 'pid=$!'
        echo "until compgen -G '$1' >/dev/null || ! kill -0 \"\$pid\" 2>/dev/null; do"
        echo '    sleep 0.05'
        echo 'done'
        echo 'kill -TERM "$pid" 2>/dev/null'
        echo 'wait "$pid"'
    } >"$SB_TMP/rank1_term.sh"
    chmod +x "$SB_TMP/rank1_term.sh"
    MPI_WRAP=("$SB_TMP/rank1_term.sh")
}
mkdir -p "$SB_TMP/t_np3"
rank1_term "$SB_TMP/t_np3/t_0004.exr"
sb_mpirun 3 render "$EX/tiny.ini" --frames 0:200 -o "$SB_TMP/t_np3/t.exr" --png none
MPI_WRAP=()
check render.term.failed [ "$SB_RC" -ne 0 ]
check_eq render.term.one_line "$(printf '%s\n' "$SB_ERR" | grep -c '')" 1
check_match render.term.message "$SB_ERR" \
    "^seabake: error: interrupted by signal 15: ([0-9]+ frames? written \(0 to [0-9]+\), the rest not|no file written)$"
kept=$(printf '%s\n' "$SB_ERR" | sed -nE 's/.*\(0 to ([0-9]+)\).*/\1/p')
want=""
for ((i = 0; i <= ${kept:--1}; i++)); do want="$want$(printf 't_%04d.exr ' "$i")"; done
check_eq render.term.frames_kept "$(ls -A "$SB_TMP/t_np3" | tr '\n' ' ')" "$want"
no_temporaries render.term.no_temporaries "$SB_TMP/t_np3"

# One frame that rank 0 cannot write (its name is a directory): the other
# ranks' rows were rendered for nothing; one message, nothing written.
mkdir -p "$SB_TMP/y_np3/t.exr"
sb_mpirun 3 render "$EX/tiny.ini" -o "$SB_TMP/y_np3/t.exr" --quiet
check_error frame.fail.np3 3 "cannot write .*/y_np3/t.exr: Is a directory"
check_eq frame.fail.nothing "$(ls -A "$SB_TMP/y_np3")" t.exr
no_temporaries frame.fail.no_temporaries "$SB_TMP/y_np3"

# -------------------------------------------------------------------- bake
# One frame (shared by texel rows: rank k bakes rows k, k + 3, ... of every
# level), and frames 0 to 4 with the exports (round robin): rank 0 writes
# every file, the others send their rows or their frames' levels.
sb_run bake "$EX/tiny.ini" -o "$SB_TMP/b_one"
check_rc bake.one.rc 0
summary_one=$(timeless "$SB_ERR")
sb_mpirun 1 bake "$EX/tiny.ini" -o "$SB_TMP/b_np1"
check_rc bake.np1.rc 0
sb_mpirun 3 bake "$EX/tiny.ini" -o "$SB_TMP/b_np3"
check_rc bake.np3.rc 0
check_eq bake.np3.summary_once "$(timeless "$SB_ERR" | sed 's/b_np3/DIR/')" \
    "$(timeless "$summary_one" | sed 's/b_one/DIR/')"
same_tree bake.np1.identical "$SB_TMP/b_one" "$SB_TMP/b_np1"
same_tree bake.np3.identical "$SB_TMP/b_one" "$SB_TMP/b_np3"

B=(bake "$EX/tiny.ini" --frames 0:4 --pov --blender --quiet)
sb_run "${B[@]}" -o "$SB_TMP/bf_one"
check_rc bake.frames.one.rc 0
sb_mpirun 3 "${B[@]}" -o "$SB_TMP/bf_np3"
check_rc bake.frames.np3.rc 0
check_eq bake.frames.np3.silent "$SB_ERR" ""
# 187 maps, previews and exported files, the 5 frames' sensor images and
# their waves (3 levels, a PNG and an EXR each)
check_eq bake.frames.files "$(ls "$SB_TMP/bf_one" | wc -l)" 222
same_tree bake.frames.np3.identical "$SB_TMP/bf_one" "$SB_TMP/bf_np3"

# A parent that does not exist: found before any work, one message.
sb_mpirun 3 bake "$EX/tiny.ini" -o "$SB_TMP/missing/dir"
check_error bake.parent.np3 3 "-o: .*missing"
check_eq bake.parent.nothing "$(ls -A "$SB_TMP" | grep -c missing)" 0

# Rank 0, the writer, cannot write a file over 8 KiB (ulimit -f, SIGXFSZ
# ignored: EFBIG) while ranks 1 and 2 send frames 1 and 2: the run fails
# with one process's message under the same limit, DIR keeps its old
# bake and no temporary directory is left.  TCP between the ranks:
# OpenMPI's shared-memory segments are files, which the limit would stop.
cat >"$SB_TMP/rank0_fsize.sh" <<'EOF'
#!/bin/bash
if [ "${OMPI_COMM_WORLD_RANK:-0}" = 0 ]; then trap '' XFSZ; ulimit -f 8; fi
exec "$@"
EOF
chmod +x "$SB_TMP/rank0_fsize.sh"
# old_bake DIR: an earlier bake in DIR (another seed), which a failed bake
# must leave as it was; kept DIR: its manifest's checksum.
old_bake() { "$SEABAKE" bake "$EX/tiny.ini" -o "$1" --set sea.seed=99 --quiet; }
kept() { cksum <"$1/manifest.json"; }
for d in one np3; do old_bake "$SB_TMP/w_$d"; done
old_manifest=$(kept "$SB_TMP/w_one")
SB_CMD="seabake bake (ulimit -f 8)"
"$SB_TMP/rank0_fsize.sh" "$SEABAKE" bake "$EX/tiny.ini" --frames 0:4 -o "$SB_TMP/w_one" \
    >/dev/null 2>"$SB_TMP/err.one"
SB_RC=$?
check_eq bake.fsize.one.rc "$SB_RC" 3
err_one=$(cat "$SB_TMP/err.one")
MPI_OPTS=(--mca btl self,tcp)
MPI_WRAP=("$SB_TMP/rank0_fsize.sh")
sb_mpirun 3 bake "$EX/tiny.ini" --frames 0:4 -o "$SB_TMP/w_np3"
MPI_OPTS=()
MPI_WRAP=()
check_error bake.fsize.np3 3 "File too large"
check_eq bake.fsize.same_message "$SB_ERR" "$err_one"
check_eq bake.fsize.kept "$(kept "$SB_TMP/w_np3")" "$old_manifest"
no_temporaries bake.fsize.no_temporaries "$SB_TMP"
# the same in one frame shared by rows
old_bake "$SB_TMP/w1_np3"
"$SB_TMP/rank0_fsize.sh" "$SEABAKE" bake "$EX/tiny.ini" -o "$SB_TMP/w_one" >/dev/null 2>"$SB_TMP/err.one"
err_one=$(cat "$SB_TMP/err.one")
MPI_OPTS=(--mca btl self,tcp)
MPI_WRAP=("$SB_TMP/rank0_fsize.sh")
sb_mpirun 3 bake "$EX/tiny.ini" -o "$SB_TMP/w1_np3"
MPI_OPTS=()
MPI_WRAP=()
check_error bake.rows.fsize.np3 3 "File too large"
check_eq bake.rows.fsize.same_message "$SB_ERR" "$err_one"
check_eq bake.rows.fsize.kept "$(kept "$SB_TMP/w1_np3")" "$old_manifest"
no_temporaries bake.rows.fsize.no_temporaries "$SB_TMP"

# Rank 1 (a sender) stops on SIGTERM in a 41-frame bake once rank 0 has
# written frame 4, rank 1's second, into the temporary directory: the run
# fails with the signal's message, from rank 0, DIR keeps its old content,
# nothing is left.
old_bake "$SB_TMP/s_np3"
rank1_term "$SB_TMP/s_np3.tmp.*/optics_0_0004.exr"
sb_mpirun 3 bake "$EX/tiny.ini" --frames 0:40 -o "$SB_TMP/s_np3"
MPI_WRAP=()
# (mpirun's code is the first failed rank's: 3, or 143 for rank 1's signal)
check bake.term.failed [ "$SB_RC" -ne 0 ]
check_eq bake.term.one_line "$(printf '%s\n' "$SB_ERR" | grep -c '')" 1
check_eq bake.term.message "$SB_ERR" \
    "seabake: error: interrupted by signal 15: the output directory is left as it was"
check_eq bake.term.kept "$(kept "$SB_TMP/s_np3")" "$old_manifest"
no_temporaries bake.term.no_temporaries "$SB_TMP"
# and in one frame shared by rows (examples/mast.ini), once level 1's
# maps are written (the levels follow one another: every rank is then
# baking level 2 or later)
old_bake "$SB_TMP/s1_np3"
rank1_term "$SB_TMP/s1_np3.tmp.*/optics_1.exr"
sb_mpirun 3 bake "$EX/mast.ini" -o "$SB_TMP/s1_np3"
MPI_WRAP=()
check bake.rows.term.failed [ "$SB_RC" -ne 0 ]
check_eq bake.rows.term.message "$SB_ERR" \
    "seabake: error: interrupted by signal 15: the output directory is left as it was"
check_eq bake.rows.term.kept "$(kept "$SB_TMP/s1_np3")" "$old_manifest"
no_temporaries bake.rows.term.no_temporaries "$SB_TMP"

finish
