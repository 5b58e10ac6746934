#!/usr/bin/env bash
# docs/design/coat.md's "Under a sun" table: one coated ball (base roughness 0.4, coat
# weight 1), copper or a red plastic under a coat of roughness 1 or 0.3, lit by a map black
# but for issue 37's sun (the truth, the GPU Monte Carlo, the split sum) and by the
# directional light its texels add up to (the renderer's lights). Each ball's mean over
# the pixels of the same ball under a uniform light, against the truth's, per channel.
# Then the coat alone (over a black plastic of index 1, which sends nothing back) under the
# sun's light and under a uniform environment, against the truth; and the coat over a black
# metal on the sun map, the split sum against the truth.
#
#   bash tests/coat_under_a_sun.sh [SPP] [BINARY] [OLD_BINARY]
#       (default 4096 samples a pixel for the truth and the Monte Carlo,
#       target/release/shadeballs; OLD_BINARY adds a column of its lights, e.g. main's)
#
# About 9 minutes at 4096 spp on the quiet 2-core machine, most of it the truth's walks.
set -euo pipefail
cd "$(dirname "$0")/.."
spp=${1:-4096}
bin=${2:-target/release/shadeballs}
old=${3:-}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

cargo build --release -q -p shadeballs-lab --example sun_map --example ball_mean
examples=target/release/examples
light=$("$examples/sun_map" "$out/sun.exr" --sun-only | sed -n '/^\[\[light\]\]/,$p')

# scene NAME MATERIAL LIGHTING: the one ball of "Under a rough coat" under LIGHTING.
scene() {
    cat > "$out/$1.toml" <<EOF
preset = "accurate"
geometry = "smith-correlated"
background = "black"
labels = false

[camera]
position = [0, 0, 300]
target = [0, 0, 0]
vfov_deg = 16

$3

[[ball]]
position = [0, 0, 0]
radius = 35
roughness = 0.4
model = "kulla-conty"
material = { $2 }
EOF
}
render() {
    "$1" render --scene "$out/$2.toml" --width 160 --height 160 --aa off "${@:4}" \
        --out "$out/$3.exr" >/dev/null 2>&1 || { echo "error: $3 did not render" >&2; exit 1; }
}
# mean PICTURE: the ball's mean "R G B" over the mask's pixels.
mean() {
    "$examples/ball_mean" --mask "$out/mask.exr" "$out/$1.exr" | sed 's/.*mean \([^,]*\).*/\1/'
}
# against MEAN TRUTH: the signed relative errors in %, per channel.
against() {
    awk -v a="$1" -v t="$2" 'BEGIN { split(a, x, " "); split(t, y, " ");
        printf "%+.1f, %+.1f, %+.1f %%", 100 * (x[1] / y[1] - 1), 100 * (x[2] / y[2] - 1), 100 * (x[3] / y[3] - 1) }'
}

scene mask "base_color = [0.5, 0.5, 0.5], metallic = 1" "[environment]
radiance = [1, 1, 1]"
render "$bin" mask mask --backend vulkan

header="| ball | truth (its standard error) | the light | Monte Carlo, the map | split sum, the map |"
rule="|---|---|---|---|---|"
if [ -n "$old" ]; then
    header="$header the light, $old |"
    rule="$rule---|"
fi
echo "truth and Monte Carlo at $spp spp, $bin"
echo "$header"
echo "$rule"
for base in copper red; do
    case $base in
        copper) material="base_color = [0.95, 0.64, 0.54], metallic = 1" ;;
        red) material="base_color = [0.8, 0.1, 0.08], metallic = 0" ;;
    esac
    for coat in 1.0 0.3; do
        m="$material, clearcoat = 1.0, clearcoat_roughness = $coat"
        scene map "$m" "[environment]
map = \"sun.exr\""
        scene light "$m" "$light"
        render "$bin" map truth --backend truth --spp "$spp"
        render "$bin" map mc --backend montecarlo --spp "$spp"
        render "$bin" map split --backend vulkan
        render "$bin" light lit --backend vulkan
        truth=$(mean truth)
        se=$("$examples/ball_mean" --mask "$out/mask.exr" "$out/truth.exr" \
            | sed 's/.*standard error //')
        noise=$(awk -v s="$se" -v t="$truth" 'BEGIN { split(s, x, " "); split(t, y, " ");
            printf "%.1f, %.1f, %.1f %%", 100 * x[1] / y[1], 100 * x[2] / y[2], 100 * x[3] / y[3] }')
        row="| $base, coat $coat | $(echo "$truth" | tr ' ' ',' | sed 's/,/, /g') ($noise)"
        row="$row | $(against "$(mean lit)" "$truth") | $(against "$(mean mc)" "$truth")"
        row="$row | $(against "$(mean split)" "$truth") |"
        if [ -n "$old" ]; then
            render "$old" light old --backend vulkan
            row="$row $(against "$(mean old)" "$truth") |"
        fi
        echo "$row"
    done
done

# The coat alone: the truth at 4 x SPP under the sun (its exits rarely find it), SPP / 8
# under the uniform environment (every exit counts).
void="base_color = [0, 0, 0], metallic = 0, ior = 1.0, clearcoat = 1.0"
sun_map="[environment]
map = \"sun.exr\""
echo
echo "the coat alone, grey: truth at $((4 * spp)) spp under the sun, $((spp / 8)) spp under a uniform environment"
echo "| coat roughness | light | truth (its standard error) | the model |"
echo "|---|---|---|---|"
# coated MATERIAL ROUGHNESS TRUTH_LIGHT MODEL_LIGHT TRUTH_SPP NAME: one row, the ball of
# MATERIAL under a coat of ROUGHNESS, the truth lit by TRUTH_LIGHT and the model (Vulkan) by
# MODEL_LIGHT.
coated() {
    scene map "$1, clearcoat_roughness = $2" "$3"
    render "$bin" map truth --backend truth --spp "$5"
    scene light "$1, clearcoat_roughness = $2" "$4"
    render "$bin" light model --backend vulkan
    local truth model se
    truth=$(mean truth | cut -d' ' -f1)
    model=$(mean model | cut -d' ' -f1)
    se=$("$examples/ball_mean" --mask "$out/mask.exr" "$out/truth.exr" \
        | sed 's/.*standard error //' | cut -d' ' -f1)
    awk -v r="$2" -v n="$6" -v t="$truth" -v m="$model" -v s="$se" 'BEGIN {
        printf "| %s | %s | %.4f (%.1f %%) | %+.1f %% |\n", r, n, t, 100 * s / t, 100 * (m / t - 1) }'
}
# Under the sun: the truth under the sun map, the model under the sun's light.
coated "$void" 1.0 "$sun_map" "$light" $((4 * spp)) "the sun"
uniform="[environment]
radiance = [1, 1, 1]"
for roughness in 0.1 0.3 0.5 0.7 0.85 1.0; do
    coated "$void" "$roughness" "$uniform" "$uniform" $((spp / 8)) uniform
done

# The coat over a black metal (F0 = 0) on the sun map: the split sum against the truth
# (4 x SPP spp under the roughest coat, whose exits rarely find the sun; SPP under 0.3).
black="base_color = [0, 0, 0], metallic = 1, clearcoat = 1.0"
echo
echo "the coat over a black metal on the sun map, the split sum"
echo "| coat roughness | light | truth (its standard error) | the model |"
echo "|---|---|---|---|"
coated "$black" 1.0 "$sun_map" "$sun_map" $((4 * spp)) "the sun map"
coated "$black" 0.3 "$sun_map" "$sun_map" "$spp" "the sun map"
