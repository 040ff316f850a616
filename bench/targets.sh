#!/bin/sh
# bench/targets.sh [DATA]: the six speed targets of issue 32 measured in one
# run, each the way docs/performance.md says, on every shared map with
# views.  Prints the tables as they come; takes 5-10 minutes on 2 cores
# (more the first time, when compare.sh builds fdb285d).
# Run it on a quiet machine: the ratios come from frames alternated in one
# process, so drift cancels, but a second busy process (or, on a shared
# virtual machine, another tenant) still takes a core from the two-thread
# rows, or slows the one-thread frames: target 4 therefore runs THREAD_RUNS
# times (default 3) and reports each row's median run beside the range, with
# each run's `work` (the two threads' processor time in the frames over the
# one thread's: 0.98-1.06 in an undisturbed run, well above 1 where the
# second core ran slow, below 1 where the one-thread frames did, which
# makes the speed-up look better than it is).
#
#   1  fog:          frame with fog / the same frame without (one library, --b-args), also
#                    with loops up to AVX2, and the lookup floor of 8-bit fog without VBMI
#   2  true colour:  true colour / 8-bit (--vs-color), warm and --cold, with and without .lit
#   3  worst view:   slowest view's median / fdb285d's, --classic --no-entities (compare.sh),
#                    WORST_RUNS times (default 3), each row's median reported
#   4  two threads:  one thread / two threads in one process, and bench's model
#   5  between frames: bench --gap 16, process CPU per frame / the frames' own work
#   6  many cores:   bench's predicted speed-up on 4, 8 and 16 cores (no many-core machine here)
#
# SKIP="1 3" leaves targets out; MAPS and SIZES override the defaults.
# PER_CPU=1: target 4 also times each processor alone (inproc --per-cpu,
# about three times as long): where the two differ in speed, as a shared
# virtual machine's do from minute to minute, 1.8x is out of reach, and
# x_eq, two equal processors at the efficiency measured, is printed too.
# At the end one table puts every target's figure side by side, a row per
# map (bench/targets_summary.awk, which reads the tables above it).
set -eu
if [ -z "${EW_TARGETS_INNER:-}" ]; then  # the run itself, copied to a log the summary reads
    log=$(mktemp)
    { rc=0; EW_TARGETS_INNER=1 sh "$0" "$@" || rc=$?; echo "$rc" >"$log.rc"; } 2>&1 | tee "$log"
    rc=$(cat "$log.rc")
    awk -f "$(dirname "$0")/targets_summary.awk" "$log"
    rm -f "$log" "$log.rc"
    exit "$rc"
fi
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DATA=${1:-$ROOT/../shared/data/librequake}
MAPS=${MAPS:-e1m1 lqdm7 e4m1 start lqdm1 e2m1 slope}
SIZES=${SIZES:-1920x1080 3840x2160}
SKIP=${SKIP:-}
PER_CPU=${PER_CPU:-0}
FOG=${FOG:-0.08,0.45,0.42,0.38}  # a map's usual fog; 1,0.3,0.3,0.35 hides all but the nearest walls (and draws less)
cd "$ROOT"
make build >/dev/null
cmake --build build --target inproc >/dev/null
IN=./build/inproc
sizes=
for s in $SIZES; do sizes="$sizes --size $s"; done
want() { case " $SKIP " in *" $1 "*) return 1 ;; esac; return 0; }
# check CMD...: runs CMD, and where it fails says so and marks the run
# failed.  Most commands here feed a pipeline (sh has no pipefail), whose
# status is its last command's: a bench that failed would pass unseen.
fails=$(mktemp)
trap 'rm -f "$fails"' EXIT
check() {
    "$@" || {
        echo "targets: failed (exit $?): $*" >&2
        echo x >>"$fails"
    }
}
# medians FILE THR XCOL [WCOL]: the rows of FILE (several runs' tables)
# whose third field is THR, per map and size: column XCOL's median over
# the runs beside its range, and column WCOL of each run, sorted with it;
# with WCOL also the median over the runs whose WCOL (two threads' work
# over one's) lies within 0.98-1.06, the runs no other process disturbed
# (below, the one-thread frames were slowed, and the ratio flatters).
medians() {
    awk -v thr="$2" -v xc="$3" -v wc="${4:-0}" '$3 == thr && $xc ~ /^[0-9.]+$/ {
             k = $1 " " $2
             if (!(k in m)) { order[n++] = k; m[k] = 0 }
             x[k, m[k]] = $xc; w[k, m[k]] = wc ? $wc : ""; m[k]++
         }
         END { for (i = 0; i < n; i++) { k = order[i]; c = m[k]
                   for (a = 0; a < c; a++) for (b = a + 1; b < c; b++)  # sort the runs by column XCOL
                       if (x[k, b] < x[k, a]) { t = x[k, a]; x[k, a] = x[k, b]; x[k, b] = t
                                                t = w[k, a]; w[k, a] = w[k, b]; w[k, b] = t }
                   med = c % 2 ? x[k, (c - 1) / 2] : (x[k, c / 2 - 1] + x[k, c / 2]) / 2
                   ws = ""; if (wc) { ws = "  work"; for (a = 0; a < c; a++) ws = ws " " w[k, a] }
                   us = ""
                   if (wc) {  # the runs the machine left alone: work within -2%..+6% of one thread
                       u = 0; for (a = 0; a < c; a++) if (w[k, a] >= 0.98 && w[k, a] <= 1.06) q[u++] = x[k, a]
                       us = u ? sprintf("  undisturbed %.3f of %d", u % 2 ? q[(u - 1) / 2] : (q[u / 2 - 1] + q[u / 2]) / 2, u) \
                              : "  undisturbed - of 0"
                   }
                   printf "%-22s median %.3f  (%.3f-%.3f)%s%s\n", k, med, x[k, 0], x[k, c - 1], ws, us } }' "$1"
}

# shellcheck disable=SC2086
if want 1; then
    for c in 8bit true; do
        echo "== target 1: fog $FOG over no fog, --color $c (B/A: median; slow_B/A: worst view)"
        $IN $MAPS --data "$DATA" $sizes --passes 3 --color $c --b-args "--fog $FOG"
    done
    # What a processor without AVX-512 VBMI runs (most desktops), and the
    # least fog can add there: one table lookup a pixel (bench's lookup floor).
    echo "== target 1: fog $FOG over no fog, 8-bit, loops up to AVX2 (--simd avx2)"
    $IN $MAPS --data "$DATA" $sizes --passes 3 --simd avx2 --b-args "--fog $FOG"
    echo "== target 1: the lookup floor: 1 + lookup_floor_ms / mean_ms of the fog-free 8-bit row"
    printf '%-10s %9s %8s %9s %7s\n' map size mean_ms lookup_ms floor_x
    for m in $MAPS; do
        for s in $SIZES; do
            check ./build/edgewise bench "$m" --data "$DATA" --size "$s" --passes 3 --no-fog --quiet |
                awk -v m="$m" -v s="$s" '{
                    match($0, /"mean_ms":[0-9.e+-]+/); mean = substr($0, RSTART + 10, RLENGTH - 10)
                    match($0, /"lookup_floor_ms":[0-9.e+-]+/); lf = substr($0, RSTART + 18, RLENGTH - 18)
                    printf "%-10s %9s %8.3f %9.3f %7.3f\n", m, s, mean, lf, 1 + lf / mean }'
        done
    done
fi
if want 2; then
    for mode in "" "--no-lit" "--cold" "--cold --no-lit"; do
        echo "== target 2: true colour over 8-bit $mode (B/A: median; slow_B/A: worst view)"
        $IN $MAPS --data "$DATA" $sizes --passes 3 --vs-color $mode
    done
fi
if want 3; then
    # One run's worst-view ratio moves by up to 4% from the next's (the
    # same code read 0.97-0.99 and 0.97-1.01 at 1080p): WORST_RUNS runs
    # (default 3), each row's median beside the range.
    runs=${WORST_RUNS:-3}
    out=$(mktemp)
    for s in 640x480 1920x1080; do
        i=1
        while [ "$i" -le "$runs" ]; do
            echo "== target 3: worst view against fdb285d, $s, --classic --no-entities (slow_B/A), run $i of $runs"
            check env INPROC=1 bench/compare.sh fdb285d WORKTREE $MAPS --data "$DATA" --size $s --passes 5 --threads 1 \
                --classic --no-entities | tee -a "$out"
            i=$((i + 1))
        done
    done
    echo "== target 3: each row's slow_B/A, the median of $runs runs (the range)"
    medians "$out" 1 8
    rm -f "$out"
fi
if want 4; then
    echo "== target 4: two threads over one (x_mean, x_med, x_view) and bench's model (x_pred)"
    runs=${THREAD_RUNS:-3}
    pc=
    [ "$PER_CPU" = 1 ] && pc=--per-cpu
    out=$(mktemp)
    i=1
    while [ "$i" -le "$runs" ]; do
        echo "== target 4: run $i of $runs"
        if [ "$i" -eq 1 ]; then
            check $IN --threads-vs 1,2 $MAPS --data "$DATA" $sizes --passes 5 --runs $pc | tee -a "$out"
        else  # the model does not change from run to run
            check $IN --threads-vs 1,2 $MAPS --data "$DATA" $sizes --passes 5 --no-model --runs $pc | tee -a "$out"
        fi
        i=$((i + 1))
    done
    echo "== target 4: each row's x_mean, the median of $runs runs (the range; each run's work)"
    medians "$out" 1,2 6 13
    if [ -n "$pc" ]; then  # field 22: x_eq, after "0 of 32  cpus A,B  eff E  x_eq"
        echo "== target 4 (each processor alone): each row's x_eq, the median of $runs runs (the range)"
        medians "$out" 1,2 22
    fi
    rm -f "$out"
fi
if want 5; then
    echo "== target 5: --gap 16: process CPU per frame over the frames' own work"
    for m in $MAPS; do
        check ./build/edgewise bench "$m" --data "$DATA" --size 1920x1080 --threads 2 --threads 0 --gap 16 --passes 2 \
            --quiet | sed -n 's/.*"map":"\([^"]*\)".*"threads_requested":\([0-9]*\).*"cpu_ms_per_frame":\([0-9.]*\).*"work_ms_per_frame":\([0-9.]*\).*"cpu_over_work":\([0-9.]*\).*/\1 threads \2: cpu \3 ms, work \4 ms, cpu\/work \5/p'
    done
fi
if want 6; then
    echo "== target 6: predicted speed-up on 2, 4, 8, 16 cores (bench --bands; one thread measured)"
    for s in $SIZES; do
        for m in $MAPS; do
            check ./build/edgewise bench "$m" --data "$DATA" --size "$s" --threads 1 --bands 2 --bands 4 --bands 8 \
                --bands 16 --passes 2 --quiet |
                sed -n 's/.*"map":"\([^"]*\)".*"width":\([0-9]*\),"height":\([0-9]*\).*"serial_share":\([0-9.]*\).*"predicted_speedup_2":\([0-9.]*\).*"predicted_speedup_4":\([0-9.]*\).*"predicted_speedup_8":\([0-9.]*\).*"predicted_speedup_16":\([0-9.]*\).*/\1 \2x\3 serial share \4: 2 \5, 4 \6, 8 \7, 16 \8/p'
        done
    done
fi
if [ -s "$fails" ]; then
    echo "targets: $(wc -l <"$fails") command(s) failed; their rows are missing above" >&2
    exit 1
fi
