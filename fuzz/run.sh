#!/usr/bin/env bash
# fuzz/run.sh [TARGET...]: builds the libFuzzer targets with clang in
# $FUZZ_BUILD (build-fuzz), writes fresh seeds with make_seeds, runs each
# target (default: every one built) for $FUZZ_SECONDS seconds and ends with a
# summary: per target its executions and seconds, then each new finding by
# file name with its first error line (or "no findings").
# `make fuzz FUZZ_SECONDS=N` calls this.
#
#   FUZZ_SECONDS  seconds per target (60)
#   FUZZ_JOBS     targets run at once (1; at most the number of cores)
#   FUZZ_NICE     nice level of the fuzzers (0)
#   EW_SHARED     ../shared: its real maps, models and lumps are read as an
#                 extra, read-only corpus directory when present, and the
#                 ericw maps' .lit files and BSPX lumps (data/ericw/maps)
#                 are made into seeds of the lit and bspx targets
#
# Corpora grow in $FUZZ_BUILD/corpus/NAME across runs; crash, timeout and
# out-of-memory inputs land in $FUZZ_BUILD/findings/NAME/ and logs in
# $FUZZ_BUILD/logs/NAME.log.  Exit status 1 if any target found something.
set -euo pipefail
cd "$(dirname "$0")/.."

SECS=${FUZZ_SECONDS:-60}
BUILD=${FUZZ_BUILD:-build-fuzz}
JOBS=${FUZZ_JOBS:-1}
NICE=${FUZZ_NICE:-0}
SHARED=${EW_SHARED:-../shared}
DATA=$SHARED/data/librequake
ERICW=$SHARED/data/ericw/maps
# Bigger files slow every execution down for little new structure.
EXTRA_MAX_BYTES=${FUZZ_EXTRA_MAX_BYTES:-131072}

if ! command -v clang >/dev/null 2>&1; then
    echo "fuzz: clang not found (apt-get install clang libclang-rt-14-dev)" >&2
    exit 2
fi
cmake -S . -B "$BUILD" -DCMAKE_C_COMPILER=clang -DEW_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD" -j "$(nproc 2>/dev/null || echo 2)" >/dev/null

# Small real maps, converted to BSP2 for the BSP2 target as well.
small_maps=()
if [ -d "$DATA/maps" ]; then
    while IFS= read -r f; do small_maps+=("$f"); done < <(find "$DATA/maps" -name '*.bsp' -size -"$EXTRA_MAX_BYTES"c | sort)
else
    echo "fuzz: $DATA not found: no real maps, models or lumps as extra corpus"
fi
# The ericw maps' light: .lit files and the BSPX lumps of the maps that have
# them (RGBLIGHTING, LMSHIFT, LMOFFSET, DECOUPLED_LM, LIGHTGRID_OCTREE...),
# fitted by make_seeds to the targets' base maps at run time.
real_light=()
if [ -d "$ERICW" ]; then
    while IFS= read -r f; do real_light+=("$f"); done < <(find "$ERICW" -name '*.lit' -o -name '*.bsp' | sort)
else
    echo "fuzz: $ERICW not found: the lit and bspx targets start from the generated seeds only"
fi
rm -rf "$BUILD/seeds"
"$BUILD/fuzz/make_seeds" "$BUILD/seeds" "${small_maps[@]}" ${real_light[@]:+--real "${real_light[@]}"} 2>&1 |
    grep -v 'no BSPX directory' >&2 || true
[ -d "$BUILD/seeds/render" ] || { echo "fuzz: make_seeds failed" >&2; exit 2; }

# extra_dir NAME GLOB...: a directory of links to the matching files of
# ../shared no bigger than EXTRA_MAX_BYTES (libFuzzer only adds to the first
# corpus directory, so these are never written).
extra_dir() {
    local name=$1 dir="$BUILD/extra/$1"
    shift
    rm -rf "$dir"
    mkdir -p "$dir"
    local f
    for f in "$@"; do
        [ -f "$f" ] || continue
        [ "$(stat -c %s "$f")" -le "$EXTRA_MAX_BYTES" ] || continue
        ln -s "$(realpath "$f")" "$dir/$(basename "$f")"
    done
    echo "$dir"
}

extras_for() {
    case $1 in
    bsp29 | render) extra_dir "$1" "$DATA"/maps/*.bsp ;;
    bsp2) [ -d "$BUILD/seeds/bsp2-extra" ] && echo "$BUILD/seeds/bsp2-extra" ;;
    lmp) extra_dir "$1" "$DATA"/gfx/*.lmp ;;
    mdl) extra_dir "$1" "$DATA"/progs/*.mdl ;;
    spr) extra_dir "$1" "$DATA"/progs/*.spr ;;
    demo) extra_dir "$1" "$DATA"/../demos/*.dem ;;
    esac
    return 0
}

if [ $# -gt 0 ]; then
    targets=("$@")
else
    targets=()
    for t in pak bsp29 bsp2 lmp render mdl spr lit bspx demo; do
        [ -x "$BUILD/fuzz/fuzz_$t" ] && targets+=("$t")
    done
fi

mkdir -p "$BUILD/logs"
run_one() {
    local t=$1
    local corpus="$BUILD/corpus/$t" found="$BUILD/findings/$t"
    mkdir -p "$corpus" "$found"
    # Seeds are (re)added under fixed names; libFuzzer's own files are hashes.
    if [ -d "$BUILD/seeds/$t" ]; then
        for s in "$BUILD/seeds/$t"/*; do cp "$s" "$corpus/seed-$(basename "$s")"; done
    fi
    local extra
    extra=$(extras_for "$t")
    ls "$found" > "$BUILD/logs/$t.before" 2>/dev/null || true
    local start=$SECONDS
    # shellcheck disable=SC2086
    nice -n "$NICE" "$BUILD/fuzz/fuzz_$t" -max_total_time="$SECS" -rss_limit_mb=2048 -timeout=10 \
        -print_final_stats=1 -artifact_prefix="$found/" "$corpus" $extra \
        > "$BUILD/logs/$t.log" 2>&1 || true
    echo $((SECONDS - start)) > "$BUILD/logs/$t.secs"
}

# The first error line of each artifact libFuzzer wrote, from its log: the
# sanitizer's or the target's own line before "Test unit written to FILE".
# Prints "FILE<TAB>LINE" per artifact.
finding_lines() {
    awk '
        /runtime error:|ERROR: |^fuzz: |^ALARM: / { if (first == "") first = $0 }
        /Test unit written to / {
            f = $0; sub(/.*Test unit written to /, "", f); n = split(f, p, "/")
            print p[n] "\t" (first == "" ? "(no error line in the log)" : first); first = ""
        }' "$1"
}

# One block per target; 1 if it found anything new.
summary() {
    local t=$1 log="$BUILD/logs/$1.log"
    local execs secs corpus new
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    # a run that ended on a crash may not print its final stats
    [ -n "$execs" ] || execs=$(grep -oE '^#[0-9]+' "$log" | tail -n 1 | tr -d '#')
    secs=$(cat "$BUILD/logs/$t.secs" 2>/dev/null || echo "?")
    corpus=$(find "$BUILD/corpus/$t" -type f | wc -l)
    new=$(ls "$BUILD/findings/$t" 2>/dev/null | grep -E '^(crash|timeout|oom|leak|slow-unit)-' |
          grep -vxF -f "$BUILD/logs/$t.before" || true)
    printf 'fuzz_%-7s %5ss  executions %10s  corpus %5s  ' "$t" "$secs" "${execs:-?}" "$corpus"
    if [ -z "$new" ]; then
        echo "no findings"
        return 0
    fi
    echo "$(echo "$new" | wc -l) finding(s) (log $log)"
    local lines f line
    lines=$(finding_lines "$log")
    for f in $new; do
        line=$(printf '%s\n' "$lines" | awk -F '\t' -v f="$f" '$1 == f { print $2; exit }')
        printf '    %s/%s\n        %s\n' "$BUILD/findings/$t" "$f" "${line:-(see the log)}"
    done
    return 1
}

echo "fuzz: ${#targets[@]} targets, ${SECS}s each, $JOBS at a time"
running=0
for t in "${targets[@]}"; do
    if [ ! -x "$BUILD/fuzz/fuzz_$t" ]; then
        echo "fuzz: no target fuzz_$t in $BUILD/fuzz" >&2
        exit 2
    fi
    run_one "$t" &
    running=$((running + 1))
    if [ "$running" -ge "$JOBS" ]; then
        wait -n || true
        running=$((running - 1))
    fi
done
wait

echo "fuzz: summary"
status=0
for t in "${targets[@]}"; do summary "$t" || status=1; done
[ $status -eq 0 ] && echo "fuzz: no findings" || echo "fuzz: findings above (exit 1)"
exit $status
