#!/bin/sh
# bench/compare.sh OLDREV NEWREV [bench args...]
#
# Builds two revisions of edgewise (any git revision, or WORKTREE for the
# working tree as it is now), runs `edgewise bench` with the same arguments
# alternately (old new old new ...) so both see the same machine load, and
# prints new/old of median_ms per row (map, size, threads).
#
#   bench/compare.sh HEAD~1 WORKTREE
#   ROUNDS=5 bench/compare.sh v1 v2 e1m1 --data ../shared/data/librequake --size 3840x2160
#
# Default bench args: the four maps of BENCHMARK.md at 1920x1080, one thread.
# Sources and builds are kept in bench/.cache (ignored by git) and reused.
# A revision from before `edgewise bench` existed is measured with the
# current tree's CLI (cli/*.c) linked against that revision's library.
# PAIRED=1 runs each round's two sides at the same time instead, one on
# core 0 and one on core 1 (taskset), swapping cores every round: on a
# shared machine whose speed drifts from second to second both sides then
# see the same drift (it needs two cores, and each side's absolute times
# include the other's share of memory bandwidth).
# INPROC=1 times the two in one process instead (bench/inproc.c): both
# libraries linked into one program, the new one's symbols renamed
# (objcopy), every view rendered by each in turn, so the ratio holds to
# about 1% where the runs above move by 10-20%.  It takes MAP... --data DIR
# --size WxH... --passes P --threads N --classic --no-entities, and both
# revisions must have the public calls it makes (any since ew_set_classic);
# its frames differing column must read 0 for a change meant to keep the
# pixels.  --stage front|scan|draw|models times that stage alone (its
# ew_stats time) and --per-view prints every view's pair.
# OLD_ARGS and NEW_ARGS (split at spaces) go to one side only, for options
# that one side does not have or spells differently: a revision from before
# `--classic` drew the classic look by default, so
#   NEW_ARGS=--classic bench/compare.sh cde885f WORKTREE e1m1 --size 320x200
set -eu

usage() {
    echo "usage: bench/compare.sh OLDREV NEWREV [bench args...]  (ROUNDS=N, default 3)" >&2
    exit 2
}
[ $# -ge 2 ] || usage
OLD=$1
NEW=$2
shift 2
ROUNDS=${ROUNDS:-3}
case $ROUNDS in '' | *[!0-9]* | 0) echo "compare: ROUNDS must be a positive number" >&2; exit 2 ;; esac

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CACHE=$ROOT/bench/.cache
JOBS=$(nproc 2>/dev/null || echo 2)
mkdir -p "$CACHE"

if [ $# -eq 0 ]; then
    set -- e1m1 lqdm7 e4m1 start --data "$ROOT/../shared/data/librequake" --size 1920x1080
fi
for a in "$@"; do
    case $a in --out | --out=* | --table)
        echo "compare: $a is set by compare.sh itself" >&2; exit 2 ;;
    esac
done

# src_of REV: where REV's sources are (after build REV).
src_of() {
    if [ "$1" = WORKTREE ]; then
        echo "$ROOT"
    else
        echo "$CACHE/src-$(git -C "$ROOT" rev-parse --verify --quiet "$1^{commit}" | cut -c1-12)"
    fi
}

# build REV: prints the path of an edgewise binary that has `bench`.
build() {
    rev=$1
    if [ "$rev" = WORKTREE ]; then
        src=$ROOT
        key=worktree
    else
        sha=$(git -C "$ROOT" rev-parse --verify --quiet "$rev^{commit}") || {
            echo "compare: $rev: not a revision of $ROOT" >&2; return 1; }
        key=$(printf %.12s "$sha")
        src=$CACHE/src-$key
        if [ ! -d "$src" ]; then
            # A plain export, not a worktree: nothing to register or prune in .git.
            rm -rf "$src.tmp" && mkdir -p "$src.tmp"
            git -C "$ROOT" archive "$sha" | tar -x -C "$src.tmp"
            mv "$src.tmp" "$src"
        fi
    fi
    dir=$CACHE/build-$key
    log=$CACHE/build-$key.log
    echo "compare: building $rev in $dir" >&2
    # the static library too: INPROC links it, and the CLI no longer needs it
    if ! { cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release &&
           cmake --build "$dir" -j "$JOBS" --target edgewise edgewise_cli; } >"$log" 2>&1; then
        tail -n 20 "$log" >&2
        echo "compare: $rev does not build (log: $log)" >&2
        return 1
    fi
    if "$dir/edgewise" bench --help >/dev/null 2>&1; then
        echo "$dir/edgewise"
        return 0
    fi
    # No bench command in that revision: the current CLI, that revision's library.
    png=$(pkg-config --cflags --libs libpng 2>/dev/null || echo -lpng)
    # Revisions from before ew_set_threads run every row on one thread; from
    # before the scene API, world only; from before deferred z-fill, full.
    defs=
    grep -q ew_set_threads "$src/include/edgewise.h" || defs=-DEW_BENCH_NO_THREADS
    grep -q ew_set_scene "$src/include/edgewise.h" || defs="$defs -DEW_BENCH_NO_SCENE"
    grep -q ew_set_full_zfill "$src/include/edgewise.h" || defs="$defs -DEW_BENCH_NO_ZFILL"
    grep -q ms_serial "$src/include/edgewise.h" || defs="$defs -DEW_BENCH_NO_SERIAL"
    # The command's sources, less edgewise_gen's (cli/gen_docs.c, a program of its own).
    cli_src=
    for f in "$ROOT"/cli/*.c; do
        case $f in */gen_docs.c) ;; *) cli_src="$cli_src $f" ;; esac
    done
    # shellcheck disable=SC2086
    if ! ${CC:-cc} -std=c11 -O3 -DNDEBUG $defs -I"$src/include" -I"$src/src" $cli_src \
            "$dir/libedgewise.a" $png -lm -pthread -o "$dir/edgewise-harness" >>"$log" 2>&1; then
        tail -n 20 "$log" >&2
        echo "compare: $rev has no 'bench' and the current CLI does not build against it" >&2
        return 1
    fi
    echo "compare: $rev has no 'bench': using the current CLI on its library" >&2
    echo "$dir/edgewise-harness"
}

A=$(build "$OLD")
B=$(build "$NEW")

if [ "${INPROC:-0}" = 1 ]; then
    for tool in nm objcopy; do
        command -v $tool >/dev/null 2>&1 || { echo "compare: INPROC=1 needs $tool (binutils)" >&2; exit 2; }
    done
    LA=$(dirname "$A")/libedgewise.a
    LB=$(dirname "$B")/libedgewise.a
    IN=$CACHE/inproc
    mkdir -p "$IN"
    # Every symbol the new library defines gets a b_ prefix, in its own
    # references too, so the two can be linked side by side.
    nm --defined-only -g "$LB" | awk 'NF == 3 { print $3, "b_" $3 }' | sort -u >"$IN/syms"
    objcopy --redefine-syms="$IN/syms" "$LB" "$IN/libB.a"
    png=$(pkg-config --libs libpng 2>/dev/null || echo -lpng)
    # A revision from before ew_set_classic (cde885f) is reached through
    # bench/inproc_old.c, built against its own header.
    old_obj=
    old_def=
    SA=$(src_of "$OLD")
    if ! grep -q ew_set_classic "$SA/include/edgewise.h"; then
        ${CC:-cc} -std=c11 -O2 -I"$SA/include" -I"$ROOT/bench" -c "$ROOT/bench/inproc_old.c" -o "$IN/inproc_old.o" ||
            { echo "compare: bench/inproc_old.c does not build against $OLD" >&2; exit 1; }
        old_obj=$IN/inproc_old.o
        old_def=-DEW_INPROC_OLD
        echo "compare: $OLD has no ew_set_classic: side A through bench/inproc_old.c, --classic to B only" >&2
    fi
    # shellcheck disable=SC2086
    ${CC:-cc} -std=c11 -O2 $old_def -I"$ROOT/include" -I"$ROOT/bench" "$ROOT/bench/inproc.c" $old_obj "$LA" \
        "$IN/libB.a" $png -lz -lm -pthread \
        -o "$IN/inproc" || { echo "compare: bench/inproc.c does not build" >&2; exit 1; }
    echo "compare: in one process, A = $OLD, B = $NEW" >&2
    exec "$IN/inproc" "$@"
fi

RUN=$CACHE/compare-last
rm -rf "$RUN" && mkdir -p "$RUN"
i=1
if [ "${PAIRED:-0}" = 1 ] && ! command -v taskset >/dev/null 2>&1; then
    echo "compare: PAIRED=1 needs taskset (util-linux)" >&2
    exit 2
fi
while [ "$i" -le "$ROUNDS" ]; do
    if [ "${PAIRED:-0}" = 1 ]; then
        echo "compare: round $i/$ROUNDS: $OLD and $NEW at once" >&2
        co=$((i % 2)); cn=$((1 - co))
        # shellcheck disable=SC2086
        taskset -c "$co" "$A" bench "$@" ${OLD_ARGS:-} --out "$RUN/old.$i.jsonl" >/dev/null &
        po=$!
        # shellcheck disable=SC2086
        taskset -c "$cn" "$B" bench "$@" ${NEW_ARGS:-} --out "$RUN/new.$i.jsonl" >/dev/null &
        pn=$!
        wait "$po" && wait "$pn" || { echo "compare: a bench run failed" >&2; exit 1; }
    else
        echo "compare: round $i/$ROUNDS: $OLD" >&2
        # shellcheck disable=SC2086
        "$A" bench "$@" ${OLD_ARGS:-} --out "$RUN/old.$i.jsonl" >/dev/null
        echo "compare: round $i/$ROUNDS: $NEW" >&2
        # shellcheck disable=SC2086
        "$B" bench "$@" ${NEW_ARGS:-} --out "$RUN/new.$i.jsonl" >/dev/null
    fi
    i=$((i + 1))
done

# Per row: the median over rounds of each side's median_ms, then new/old;
# the spread of the per-round ratios shows how much to trust it.
awk -v old="$OLD" -v new="$NEW" -v rounds="$ROUNDS" '
function str(line, key) {
    if (!match(line, "\"" key "\":\"[^\"]*\"")) return ""
    return substr(line, RSTART + length(key) + 4, RLENGTH - length(key) - 5)
}
function num(line, key) {
    if (!match(line, "\"" key "\":[-+0-9.eE]+")) return ""
    return substr(line, RSTART + length(key) + 3, RLENGTH - length(key) - 3) + 0
}
function median(list,   n, v, i, j, t) {
    n = split(list, v, " ")
    for (i = 2; i <= n; i++)
        for (j = i; j > 1 && v[j - 1] + 0 > v[j] + 0; j--) { t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
    return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
}
FNR == 1 { side = FILENAME; sub(/.*\//, "", side); split(side, parts, "."); side = parts[1]; round = parts[2] }
/"floor":true/ { next }
{
    # Rows match on the thread count asked for (0 = all cores), which both sides share.
    thr = num($0, "threads_requested"); if (thr == "") thr = num($0, "threads")
    key = sprintf("%-10s %9s %3s", str($0, "map"), num($0, "width") "x" num($0, "height"), thr == 0 ? "all" : thr)
    if (!(key in seen)) { seen[key] = 1; order[++nkeys] = key }
    ms[side, key] = ms[side, key] " " num($0, "median_ms")
    at[side, key, round] = num($0, "median_ms")
}
END {
    printf "%-10s %9s %3s %9s %9s %8s  %s\n", "map", "size", "thr", "old_ms", "new_ms", "new/old", "per-round range"
    logsum = 0; nlog = 0
    for (k = 1; k <= nkeys; k++) {
        key = order[k]
        o = median(ms["old", key]); n = median(ms["new", key])
        lo = ""; hi = ""
        for (r = 1; r <= rounds; r++) {
            if (!(("old", key, r) in at) || !(("new", key, r) in at) || at["old", key, r] <= 0) continue
            q = at["new", key, r] / at["old", key, r]
            if (lo == "" || q < lo) lo = q
            if (hi == "" || q > hi) hi = q
        }
        ratio = o > 0 ? n / o : 0
        if (ratio > 0) { logsum += log(ratio); nlog++ }
        printf "%s %9.3f %9.3f %8.3f  %.3f-%.3f\n", key, o, n, ratio, lo, hi
    }
    if (nlog) printf "geometric mean new/old over %d rows: %.3f  (%s -> %s, %d rounds)\n", nlog, exp(logsum / nlog), old, new, rounds
}' "$RUN"/old.*.jsonl "$RUN"/new.*.jsonl
