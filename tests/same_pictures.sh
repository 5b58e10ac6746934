#!/usr/bin/env bash
# Renders every built-in scene (and the default) with the `shadeballs` binary BIN on Vulkan,
# GL and the CPU, to PNG and EXR, plus a map with the Turquin term and the games202 preset
# without antialiasing, into folder OUT. Run it with the binaries of two commits and compare
# the folders (`cmp`), to show that a change leaves every picture byte for byte the same
# (`.exr` too: its blocks are written in a fixed order, output::encode_exr):
#   tests/same_pictures.sh old/shadeballs before && tests/same_pictures.sh target/release/shadeballs after
#   tests/same_pictures.sh --compare before after
# Refusals (GL has no truth) are logged to OUT/log.txt and count as pictures: the same
# refusal on both sides compares equal.
set -u
if [ "${1:-}" = "--compare" ]; then
    a=$2 b=$3 differ=0 n=0
    for f in "$a"/*.png "$a"/*.exr "$a"/*.status; do
        n=$((n + 1))
        cmp -s "$f" "$b/$(basename "$f")" || { echo "differs: $(basename "$f")"; differ=1; }
    done
    echo "$n files compared"
    exit $differ
fi
bin=$1 out=$2
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
: > "$out/log.txt"
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    export XDG_RUNTIME_DIR
fi
# One picture: NAME then render's flags; its exit status goes to NAME.status.
picture() {
    local name=$1
    shift
    "$bin" render "$@" --width 240 --height 135 --spp 4 --out "$out/$name" >/dev/null 2>>"$out/log.txt"
    echo $? > "$out/$name.status"
}
for s in "$repo"/assets/scenes/*.toml default; do
    n=$(basename "$s" .toml)
    sc=()
    [ "$s" != default ] && sc=(--scene "$s")
    for ext in png exr; do
        picture "$n.vulkan.$ext" "${sc[@]}" --backend vulkan
        WGPU_BACKEND=gl picture "$n.gl.$ext" "${sc[@]}" --backend gl
        picture "$n.cpu.$ext" "${sc[@]}" --backend cpu
    done
    picture "$n.sky.exr" "${sc[@]}" --backend vulkan --environment sky --ibl-term turquin
    picture "$n.games202.png" "${sc[@]}" --backend vulkan --aa off --preset games202
done
