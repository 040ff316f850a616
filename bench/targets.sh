#!/bin/sh
# bench/targets.sh [DATA]: the six speed targets of issue 32 measured in one
# run, each the way docs/performance.md says, on every shared map with
# views.  Prints the tables as they come; takes 20-40 minutes on 2 cores.
# Run it on a quiet machine: the ratios come from frames alternated in one
# process, so drift cancels, but a second busy process still takes a core
# from the two-thread rows.
#
#   1  fog:          frame with fog / the same frame without (one library, --b-args)
#   2  true colour:  true colour / 8-bit (--vs-color), warm and --cold, with and without .lit
#   3  worst view:   slowest view's median / fdb285d's, --classic --no-entities (compare.sh)
#   4  two threads:  one thread / two threads in one process, and bench's model
#   5  between frames: bench --gap 16, process CPU per frame / the frames' own work
#   6  many cores:   bench's predicted speed-up on 4, 8 and 16 cores (no many-core machine here)
#
# SKIP="1 3" leaves targets out; MAPS and SIZES override the defaults.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DATA=${1:-$ROOT/../shared/data/librequake}
MAPS=${MAPS:-e1m1 lqdm7 e4m1 start lqdm1 e2m1 slope}
SIZES=${SIZES:-1920x1080 3840x2160}
SKIP=${SKIP:-}
FOG=${FOG:-0.08,0.45,0.42,0.38}  # a map's usual fog; 1,0.3,0.3,0.35 hides all but the nearest walls (and draws less)
cd "$ROOT"
make build >/dev/null
cmake --build build --target inproc >/dev/null
IN=./build/inproc
sizes=
for s in $SIZES; do sizes="$sizes --size $s"; done
want() { case " $SKIP " in *" $1 "*) return 1 ;; esac; return 0; }

# shellcheck disable=SC2086
if want 1; then
    for c in 8bit true; do
        echo "== target 1: fog $FOG over no fog, --color $c (B/A: median; slow_B/A: worst view)"
        $IN $MAPS --data "$DATA" $sizes --passes 3 --color $c --b-args "--fog $FOG"
    done
fi
if want 2; then
    for mode in "" "--no-lit" "--cold" "--cold --no-lit"; do
        echo "== target 2: true colour over 8-bit $mode (B/A: median; slow_B/A: worst view)"
        $IN $MAPS --data "$DATA" $sizes --passes 3 --vs-color $mode
    done
fi
if want 3; then
    for s in 640x480 1920x1080; do
        echo "== target 3: worst view against fdb285d, $s, --classic --no-entities (slow_B/A)"
        INPROC=1 bench/compare.sh fdb285d WORKTREE $MAPS --data "$DATA" --size $s --passes 5 --threads 1 \
            --classic --no-entities
    done
fi
if want 4; then
    echo "== target 4: two threads over one (x_mean, x_med, x_view) and bench's model (x_pred)"
    $IN --threads-vs 1,2 $MAPS --data "$DATA" $sizes --passes 5
fi
if want 5; then
    echo "== target 5: --gap 16: process CPU per frame over the frames' own work"
    for m in $MAPS; do
        ./build/edgewise bench "$m" --data "$DATA" --size 1920x1080 --threads 2 --threads 0 --gap 16 --passes 2 \
            --quiet | sed -n 's/.*"map":"\([^"]*\)".*"threads_requested":\([0-9]*\).*"cpu_ms_per_frame":\([0-9.]*\).*"work_ms_per_frame":\([0-9.]*\).*"cpu_over_work":\([0-9.]*\).*/\1 threads \2: cpu \3 ms, work \4 ms, cpu\/work \5/p'
    done
fi
if want 6; then
    echo "== target 6: predicted speed-up on 2, 4, 8, 16 cores (bench --bands; one thread measured)"
    for s in $SIZES; do
        for m in $MAPS; do
            ./build/edgewise bench "$m" --data "$DATA" --size "$s" --threads 1 --bands 2 --bands 4 --bands 8 \
                --bands 16 --passes 2 --quiet |
                sed -n 's/.*"map":"\([^"]*\)".*"width":\([0-9]*\),"height":\([0-9]*\).*"serial_share":\([0-9.]*\).*"predicted_speedup_2":\([0-9.]*\).*"predicted_speedup_4":\([0-9.]*\).*"predicted_speedup_8":\([0-9.]*\).*"predicted_speedup_16":\([0-9.]*\).*/\1 \2x\3 serial share \4: 2 \5, 4 \6, 8 \7, 16 \8/p'
        done
    done
fi
