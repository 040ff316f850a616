# bench/targets_summary.awk LOG: the tables bench/targets.sh printed, read
# back into one row per map with every target's figure side by side.
#   fog, true colour: the median frame's ratio / the worst view's, the larger
#     of the sizes run (1080p and 4K by default); target at most 1.15
#   floor: the least 8-bit fog can add without AVX-512 VBMI (one table
#     lookup a pixel), the larger over the sizes; beside fog8avx2
#   worst view: slow_B/A against fdb285d, the median of the runs; in
#     brackets the fraction BENCHMARK.md's table asks for ("-": no column)
#   two threads: x_mean, the median of the runs / the median of the runs
#     with work within 0.98-1.06 (undisturbed; "-": none); target at least 1.80
#   gap: the largest cpu/work of --gap 16; target at most 1.15
#   serial: the largest serial share of target 6, in percent; at most 2
function num(x) { return x ~ /^[0-9]+(\.[0-9]+)?$/ }
function keep(k, m, w) {  # the larger median and worst-view ratio over the sizes
    if (!(k in med) || m + 0 > med[k] + 0) med[k] = m
    if (!(k in worst) || w + 0 > worst[k] + 0) worst[k] = w
}
function map_seen(m) { if (!(m in seen)) { seen[m] = 1; maps[nmaps++] = m } }
BEGIN {
    # BENCHMARK.md: what the worst view must come down to against fdb285d
    goal["e1m1 640x480"] = 0.83; goal["lqdm7 640x480"] = 1.00; goal["e4m1 640x480"] = 0.89; goal["start 640x480"] = 1.00
    goal["e1m1 1920x1080"] = 1.00; goal["lqdm7 1920x1080"] = 1.00; goal["e4m1 1920x1080"] = 1.00
    goal["start 1920x1080"] = 0.86
}
/^== target/ {
    sec = ""
    if ($0 ~ /target 1: fog .*--color 8bit/) sec = "fog8"
    else if ($0 ~ /target 1: fog .*--color true/) sec = "fogT"
    else if ($0 ~ /target 1: fog .*AVX2/) sec = "fogA"
    else if ($0 ~ /target 1: the lookup floor/) sec = "fl"
    else if ($0 ~ /target 2: true colour over 8-bit --cold --no-lit/) sec = "tcn"
    else if ($0 ~ /target 2: true colour over 8-bit --cold/) sec = "tc"
    else if ($0 ~ /target 2: true colour over 8-bit --no-lit/) sec = "tn"
    else if ($0 ~ /target 2: true colour over 8-bit/) sec = "tw"
    else if ($0 ~ /target 3: each row/) sec = "w"
    else if ($0 ~ /target 4: each row/) sec = "x"
    else if ($0 ~ /target 5/) sec = "g"
    else if ($0 ~ /target 6/) sec = "s"
    next
}
sec ~ /^(fog8|fogT|fogA|tw|tn|tc|tcn)$/ && $2 ~ /^[0-9]+x[0-9]+$/ && num($7) && num($8) {
    map_seen($1); keep(sec SUBSEP $1, $7, $8); next
}
sec == "fl" && $2 ~ /^[0-9]+x[0-9]+$/ && num($5) {
    map_seen($1); if (!((sec, $1) in val) || $5 + 0 > val[sec, $1] + 0) val[sec, $1] = $5; next
}
(sec == "w" || sec == "x") && $3 == "median" && num($4) {
    map_seen($1); val[sec, $1, $2] = $4
    for (f = 5; f < NF; f++) if ($f == "undisturbed") val["xu", $1, $2] = $(f + 1)
    next
}
sec == "g" && $2 == "threads" && num($NF) { map_seen($1); if (!((sec, $1) in val) || $NF + 0 > val[sec, $1] + 0) val[sec, $1] = $NF; next }
sec == "s" && $3 == "serial" { s = $5; sub(/:$/, "", s); map_seen($1)
    if (!((sec, $1) in val) || s + 0 > val[sec, $1] + 0) val[sec, $1] = s; next }
function pair(k) { return (k in med) ? sprintf("%.2f/%.2f", med[k], worst[k]) : "-" }
function wv(m, size,   k) {
    k = m " " size
    if (!(("w", m, size) in val)) return "-"
    return sprintf("%.3f (%s)", val["w", m, size], (k in goal) ? sprintf("%.2f", goal[k]) : "-")
}
function xv(m, size,   u) {  # the median run / the median undisturbed run
    if (!(("x", m, size) in val)) return "-"
    u = ("xu", m, size) in val ? val["xu", m, size] : "-"
    return sprintf("%.2f/%s", val["x", m, size], num(u) ? sprintf("%.2f", u) : "-")
}
END {
    if (!nmaps) exit
    print "== all targets side by side (fog and true colour: median/worst view, the larger over the sizes)"
    printf "%-7s %-10s %-10s %-10s %-6s %-10s %-10s %-10s %-10s %-14s %-14s %-10s %-10s %-6s %s\n", "map", "fog8", "fogT",
        "fog8avx2", "floor", "tc", "tc_nolit", "tc_cold", "tc_cnolit", "worst_640", "worst_1080", "x2_1080", "x2_4K", "gap",
        "serial%"
    for (i = 0; i < nmaps; i++) {
        m = maps[i]
        printf "%-7s %-10s %-10s %-10s %-6s %-10s %-10s %-10s %-10s %-14s %-14s %-10s %-10s %-6s %s\n", m,
            pair("fog8" SUBSEP m), pair("fogT" SUBSEP m), pair("fogA" SUBSEP m),
            (("fl", m) in val) ? sprintf("%.2f", val["fl", m]) : "-", pair("tw" SUBSEP m),
            pair("tn" SUBSEP m), pair("tc" SUBSEP m), pair("tcn" SUBSEP m), wv(m, "640x480"), wv(m, "1920x1080"),
            xv(m, "1920x1080"), xv(m, "3840x2160"), (("g", m) in val) ? sprintf("%.2f", val["g", m]) : "-",
            (("s", m) in val) ? sprintf("%.2f", 100 * val["s", m]) : "-"
    }
    print "targets: fog and true colour at most 1.15; worst view at most the bracket; x2 (every run / undisturbed runs) at least 1.80; gap at most 1.15; serial at most 2"
}
