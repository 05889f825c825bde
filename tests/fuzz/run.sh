#!/bin/sh
# tests/fuzz/run.sh - builds the libFuzzer targets of tests/fuzz/ with clang
# and runs each for a bounded time over its corpus (`make fuzz` calls it).
#
#   run.sh build          compile the targets into $FUZZ_DIR
#   run.sh run [TARGET]   build, then fuzz each target (or one) for
#                         $FUZZ_SECONDS seconds; fails on any crash, leak,
#                         timeout, out-of-memory or sanitizer report
#
# Environment (make fuzz sets them from configure): top_srcdir,
# top_builddir (holds config.h and the generated sources), FUZZ_DIR
# (default $top_builddir/build-fuzz), FUZZ_CC (clang), FUZZ_SECONDS
# (default 60), FUZZ_CPPFLAGS and FUZZ_LIBS (the dependencies' flags),
# FUZZ_FLAGS (extra libFuzzer options, e.g. -jobs=1 -workers=1), FUZZ_JOBS
# (targets built and fuzzed side by side, one process each; default: the
# processors).
#
# Each target's corpus: $FUZZ_DIR/corpus/T (new inputs found by this run:
# the first directory, the only one written), then the regression corpus
# tests/fuzz/corpus/T kept in the tree and the seeds (examples/*.ini,
# tests/scenes/*, data/*.csv).  Crashing inputs go to $FUZZ_DIR/artifacts/.
# Prints one line per target and a closing "fuzz: N passed, M failed",
# also written to $FUZZ_DIR/fuzz.log.
set -eu
: "${top_srcdir:?}" "${top_builddir:?}"
FUZZ_DIR=${FUZZ_DIR:-$top_builddir/build-fuzz}
FUZZ_CC=${FUZZ_CC:-clang}
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_CPPFLAGS=${FUZZ_CPPFLAGS:-}
FUZZ_LIBS=${FUZZ_LIBS:-}
FUZZ_FLAGS=${FUZZ_FLAGS:-}
FUZZ_JOBS=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}
TARGETS="scene water response cli"
fz=$top_srcdir/tests/fuzz

command -v "$FUZZ_CC" >/dev/null 2>&1 || {
    echo "fuzz: $FUZZ_CC not found (scripts/setup installs clang and libclang-rt-14-dev)" >&2
    exit 1
}

# No -fopenmp: one thread per execution (OpenMP's pragmas are ignored), as
# libFuzzer expects; the library's results do not depend on the threads.
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
CFLAGS="-g -O1 -std=gnu11 -Wall -Wno-unknown-pragmas $SAN -DHAVE_CONFIG_H \
-I$top_builddir -I$top_srcdir/src -I$top_builddir/src -I$top_srcdir/exporters $FUZZ_CPPFLAGS"

# pool CMD...: runs CMD in the background, FUZZ_JOBS at a time; a failure
# leaves a mark that pool_wait reports.
pool_n=0
pool() {
    { "$@" || touch "$FUZZ_DIR/obj/failed"; } &
    pool_n=$((pool_n + 1))
    [ "$pool_n" -lt "$FUZZ_JOBS" ] || { wait; pool_n=0; }
}
pool_wait() {
    wait
    pool_n=0
    if [ -f "$FUZZ_DIR/obj/failed" ]; then
        echo "fuzz: building the targets failed" >&2
        exit 1
    fi
}

build() {
    mkdir -p "$FUZZ_DIR/obj"
    rm -f "$FUZZ_DIR/obj/failed"
    # the library's layer folders (src/physics/gen-*.c are programs that
    # write sources, not the library)
    lib_src="$(ls "$top_srcdir"/src/*/*.c | grep -v -e '/gen-[^/]*\.c$' -e '/src/cli/') \
$top_srcdir/exporters/*.c $top_builddir/src/physics/water_data.c $top_builddir/exporters/povray_inc.c \
$top_builddir/exporters/blender_py.c"
    cli_src=$(ls "$top_srcdir"/src/cli/*.c | grep -v '/main\.c$')
    headers=$(ls "$top_srcdir"/src/*.h "$top_srcdir"/src/*/*.h "$top_srcdir"/exporters/*.h \
        "$fz"/*.h "$top_builddir/config.h")
    objs_lib="" objs_cli=""
    for kind in lib cli; do
        if [ $kind = lib ]; then srcs=$lib_src; else srcs=$cli_src; fi
        for s in $srcs; do
            o="$FUZZ_DIR/obj/$kind-$(basename "$s" .c).o"
            stale=0
            [ -f "$o" ] && [ "$o" -nt "$s" ] || stale=1
            for h in $headers; do [ "$h" -nt "$o" ] && stale=1; done
            if [ $stale = 1 ]; then
                echo "  CC (fuzz) $(basename "$s")" >&2
                rm -f "$o"
                # shellcheck disable=SC2086
                pool $FUZZ_CC $CFLAGS -fsanitize=fuzzer-no-link -c "$s" -o "$o"
            fi
            if [ $kind = lib ]; then objs_lib="$objs_lib $o"; else objs_cli="$objs_cli $o"; fi
        done
    done
    pool_wait
    for t in $TARGETS; do
        extra=""
        [ "$t" = cli ] && extra=$objs_cli
        echo "  CCLD (fuzz) fuzz_$t" >&2
        # shellcheck disable=SC2086
        pool $FUZZ_CC $CFLAGS -fsanitize=fuzzer "$fz/fuzz_$t.c" $extra $objs_lib $FUZZ_LIBS \
            -lpthread -lm -o "$FUZZ_DIR/fuzz_$t"
    done
    pool_wait
}

# The seeds of target t, made into $FUZZ_DIR/seeds/t.
seeds() {
    t=$1
    d="$FUZZ_DIR/seeds/$t"
    rm -rf "$d" && mkdir -p "$d"
    case $t in
    scene)
        # the target's directory holds r.csv and w.csv (fuzz_scene.c)
        for f in "$top_srcdir"/examples/*.ini "$top_srcdir"/tests/scenes/*.ini; do
            sed 's/full_response\.csv/r.csv/' "$f" >"$d/$(basename "$f")"
        done
        sed 's/^water = .*/water = w.csv/' "$top_srcdir/tests/scenes/full.ini" >"$d/full_w.ini" ;;
    water)
        # byte 0 picks the salinity ('0' % 3 = 0: pure water; '1': 35 g/kg)
        for f in "$top_srcdir"/data/water_nk_*.csv; do
            { printf '1'; cat "$f"; } >"$d/$(basename "$f")"
        done ;;
    response)
        cp "$top_srcdir"/tests/scenes/*.csv "$d/" ;;
    cli)
        # byte 0 picks the subcommand (0 spectrum ... 7 render, 8 bake)
        printf '\001--wavelength\0004\000--wind\0008\000--theta\0000:80:10' >"$d/emissivity"
        printf '\007scene.ini\000-o\000out.exr\000--frames\0001:3\000--tolerance=0.01' >"$d/render"
        printf '\004--wind=8\000--method\000variable-step-2n\000--n\0003' >"$d/slopes" ;;
    esac
}

run_one() {
    t=$1
    seeds "$t"
    mkdir -p "$FUZZ_DIR/corpus/$t" "$FUZZ_DIR/artifacts/$t"
    dict=""
    [ -f "$fz/$t.dict" ] && dict="-dict=$fz/$t.dict"
    corpora="$FUZZ_DIR/corpus/$t"
    [ -d "$fz/corpus/$t" ] && corpora="$corpora $fz/corpus/$t"
    corpora="$corpora $FUZZ_DIR/seeds/$t"
    log="$FUZZ_DIR/fuzz_$t.log"
    # shellcheck disable=SC2086
    if "$FUZZ_DIR/fuzz_$t" -max_total_time="$FUZZ_SECONDS" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$FUZZ_DIR/artifacts/$t/" $dict $FUZZ_FLAGS \
        $corpora >"$log" 2>&1; then
        stats=$(grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)' "$log" |
            sed 's/^stat:://; s/:  */: /' | tr '\n' ' ' | sed 's/ $//')
        cov=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -1 |
            sed -E 's/.*(cov: [0-9]+ ft: [0-9]+).*/\1/')
        echo "fuzz: $t: ok ($FUZZ_SECONDS s, $cov, $stats)"
        return 0
    fi
    echo "fuzz: $t: FAILED (log $log, artifacts in $FUZZ_DIR/artifacts/$t/)"
    grep -E 'ERROR|SUMMARY|runtime error|invariant failed|Test unit written' "$log" | head -20 |
        sed 's/^/  /'
    return 1
}

case ${1:-run} in
build) build ;;
run)
    build
    only=${2:-}
    # FUZZ_JOBS lanes take the targets in order, each the next one unclaimed
    # (mkdir claims it atomically), and write its verdict to a file; scene,
    # whose corpus replays small renders for about three minutes, comes first
    res="$FUZZ_DIR/results"
    rm -rf "$res" && mkdir -p "$res"
    lane=0
    while [ "$lane" -lt "$FUZZ_JOBS" ]; do
        for t in $TARGETS; do
            [ -z "$only" ] || [ "$only" = "$t" ] || continue
            mkdir "$res/$t.claim" 2>/dev/null || continue
            if run_one "$t" >"$res/$t.out"; then echo ok; else echo failed; fi >"$res/$t.rc"
        done &
        lane=$((lane + 1))
    done
    wait
    passed=0 failed=0
    for t in $TARGETS; do
        [ -f "$res/$t.rc" ] || continue
        cat "$res/$t.out"
        if [ "$(cat "$res/$t.rc")" = ok ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
    done
    echo "fuzz: $passed passed, $failed failed" | tee "$FUZZ_DIR/fuzz.log"
    [ "$failed" -eq 0 ] && [ "$passed" -gt 0 ] ;;
*) echo "usage: $0 build | run [TARGET]" >&2; exit 2 ;;
esac
