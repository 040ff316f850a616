#!/bin/sh
# bench/pair.sh [bench args...]
#
# What two cores of this machine give two independent one-thread renderers:
# runs `edgewise bench ... --threads 1` alone, then two copies of it at
# once, ROUNDS times (alone, pair, alone, pair ...), and prints per row
# (map, size) the median frame alone, the two copies' medians when paired,
# and the pair's throughput against one alone:
#
#   throughput = 2 * alone / mean(paired)
#
# Two processes share nothing but the machine (caches, memory bandwidth,
# and on a virtual machine whatever the host's cores share), so this is
# the ceiling of the renderer's own two-thread speed-up here: a two-thread
# frame cannot be shared better than two frames that share no work.
#
#   bench/pair.sh e1m1 lqdm7 --data ../shared/data/librequake --size 1920x1080
#
# Needs ./build/edgewise (make build) and python3.
set -eu

ROUNDS=${ROUNDS:-3}
BIN=${EDGEWISE:-./build/edgewise}
[ -x "$BIN" ] || { echo "bench/pair.sh: $BIN not built (make build)" >&2; exit 2; }
[ $# -ge 1 ] || set -- e1m1 lqdm7 e4m1 start --data ../shared/data/librequake --size 1920x1080
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

r=1
while [ "$r" -le "$ROUNDS" ]; do
    "$BIN" bench "$@" --threads 1 --quiet > "$TMP/alone$r.jsonl"
    "$BIN" bench "$@" --threads 1 --quiet > "$TMP/pa$r.jsonl" &
    "$BIN" bench "$@" --threads 1 --quiet > "$TMP/pb$r.jsonl"
    wait
    r=$((r + 1))
done

python3 - "$TMP" "$ROUNDS" <<'EOF'
import json, statistics, sys
tmp, rounds = sys.argv[1], int(sys.argv[2])
def rows(path):
    out = {}
    for line in open(path):
        d = json.loads(line)
        out[(d["map"], "%dx%d" % (d["width"], d["height"]))] = d["median_ms"]
    return out
alone, paired = {}, {}
for r in range(1, rounds + 1):
    for k, v in rows("%s/alone%d.jsonl" % (tmp, r)).items(): alone.setdefault(k, []).append(v)
    for name in ("pa", "pb"):
        for k, v in rows("%s/%s%d.jsonl" % (tmp, name, r)).items(): paired.setdefault(k, []).append(v)
print("%-8s %-10s %10s %10s %10s" % ("map", "size", "alone ms", "paired ms", "throughput"))
for k in alone:
    a, p = statistics.median(alone[k]), statistics.mean(paired[k])
    print("%-8s %-10s %10.3f %10.3f %10.2f" % (k[0], k[1], a, p, 2 * a / p))
EOF
