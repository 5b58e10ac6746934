#!/usr/bin/env bash
# Two builds' frame cost, like with like: alternating `view --backend vulkan --frames 150
# --orbit` runs under Xvfb of an OLD and a NEW binary on three scenes (the default, the
# homework's, the metallic-roughness chart), then each one's median frame interval and the
# ratio new / old, and the same for each run's CPU time (user + sys, start-up included). A
# change to shaders/ or src/gpu is timed this way against main's binary.
#
#   bash tests/compare_frames.sh OLD_BINARY [NEW_BINARY] [RUNS]
#       (default target/release/shadeballs, 3 runs)
#
# The load average at the end says how busy the machine was.
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: bash tests/compare_frames.sh OLD_BINARY [NEW_BINARY] [RUNS]}
new=${2:-target/release/shadeballs}
runs=${3:-3}
# `time` prints the run's user and system seconds.
TIMEFORMAT='%U %S'
scenes=(default homework metallic_roughness)
out=$(mktemp -d)
trap 'rm -rf "$out"; [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true' EXIT

median() { sort -n | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

display=:$((90 + RANDOM % 9))
Xvfb "$display" -screen 0 1600x1000x24 >/dev/null 2>&1 &
xvfb=$!
sleep 1
for _ in $(seq "$runs"); do
    for scene in "${scenes[@]}"; do
        args=()
        [ "$scene" != default ] && args=(--scene "assets/scenes/$scene.toml")
        for which in old new; do
            bin=$old
            [ "$which" = new ] && bin=$new
            # The process's CPU time (user + sys, every thread) beside its frame interval:
            # it is less sensitive to what else the machine runs.
            { time DISPLAY=$display "$bin" view --backend vulkan --frames 150 --orbit \
                "${args[@]}" > "$out/log" 2>&1; } 2> "$out/time"
            sed -n 's/.*median frame interval \([0-9.]*\) ms.*/\1/p' "$out/log" >> "$out/$scene-$which"
            awk '{print $1 + $2}' "$out/time" >> "$out/$scene-$which.cpu"
        done
    done
done
for scene in "${scenes[@]}"; do
    o=$(median < "$out/$scene-old")
    n=$(median < "$out/$scene-new")
    echo "$scene: old $o ms, new $n ms, ratio $(awk -v n="$n" -v o="$o" 'BEGIN {printf "%.3f", n / o}') \
(runs: old $(tr '\n' ' ' < "$out/$scene-old")/ new $(tr '\n' ' ' < "$out/$scene-new"))"
    oc=$(median < "$out/$scene-old.cpu")
    nc=$(median < "$out/$scene-new.cpu")
    echo "  CPU time of the run: old $oc s, new $nc s, ratio $(awk -v n="$nc" -v o="$oc" \
'BEGIN {printf "%.3f", n / o}') (runs: old $(tr '\n' ' ' < "$out/$scene-old.cpu")/ new \
$(tr '\n' ' ' < "$out/$scene-new.cpu"))"
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
