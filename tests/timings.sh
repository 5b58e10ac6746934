#!/usr/bin/env bash
# The README's and docs/viewer.md's time figures, measured the way they are quoted: the
# first PNG (`shadeballs render`, spawn to exit) of the default scene and of the homework's,
# and the viewer's median frame interval while orbiting (`view --frames 150 --orbit` under
# Xvfb) of both, in alternating runs, then the median of each. Vulkan (lavapipe here)
# unless BACKEND says gl; `MESA_SHADER_CACHE_DISABLE=true` in the environment times a
# fresh machine's first run (Mesa compiling every shader).
#
#   bash tests/timings.sh [RUNS] [BINARY] [BACKEND]
#                         (default 7 runs, target/release/shadeballs, vulkan)
#
# Prints one line a figure; the load average at the end says how busy the machine was.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-7}
bin=${2:-target/release/shadeballs}
backend=${3:-vulkan}
homework=assets/scenes/homework.toml
out=$(mktemp -d)
trap 'rm -rf "$out"; [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true' EXIT

median() { sort -n | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

for _ in $(seq "$runs"); do
    for scene in default homework; do
        args=()
        [ "$scene" = homework ] && args=(--scene "$homework")
        t0=$(date +%s%N)
        "$bin" render --backend "$backend" "${args[@]}" --out "$out/$scene.png" >/dev/null 2>&1
        t1=$(date +%s%N)
        echo $(((t1 - t0) / 1000000)) >> "$out/png-$scene"
    done
done
for scene in default homework; do
    echo "first PNG, $scene scene: median $(median < "$out/png-$scene") ms of $runs runs"
done

display=:$((90 + RANDOM % 9))
Xvfb "$display" -screen 0 1600x1000x24 >/dev/null 2>&1 &
xvfb=$!
sleep 1
for _ in $(seq "$runs"); do
    for scene in default homework; do
        args=()
        [ "$scene" = homework ] && args=(--scene "$homework")
        DISPLAY=$display "$bin" view --backend "$backend" --frames 150 --orbit "${args[@]}" 2>&1 \
            | sed -n 's/.*median frame interval \([0-9.]*\) ms.*/\1/p' >> "$out/view-$scene"
    done
done
for scene in default homework; do
    echo "view --frames 150 --orbit, $scene scene: median frame interval $(median < "$out/view-$scene") ms of $runs runs"
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
