#!/usr/bin/env bash
# The whole test suite of both crates (the library and binary at the root, the lab in lab/),
# from a fresh Debian machine: installs what the tests need (Mesa's lavapipe Vulkan driver,
# Xvfb and xdotool for the viewer test), then checks formatting, lints, the docs (the
# library's also without default features), and runs every test, the examples' and the
# doctests in release mode (one build serves the tests and the programs;
# docs/design/machine.md, "Build").
set -euo pipefail
cd "$(dirname "$0")/.."

# g++ builds FLIP's C++ reference (nv-flip-sys, for the lab's `shadeballs-lab compare`);
# its cc compiles `bake --out tables.h` in a test. glslang-tools validates the GLSL of
# `export-shader` and `bake --out tables.glsl`.
# The viewer's window under Xvfb also needs the X11 client libraries winit loads at run
# time (Xlib, Xcursor, Xrandr, XInput2, xkbcommon-x11).
packages=(g++ glslang-tools mesa-vulkan-drivers libvulkan1 xvfb xauth xdotool
    libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "installing: ${missing[*]}" >&2
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# Mesa warns on every start without a private runtime folder.
if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "$XDG_RUNTIME_DIR" ]; then
    export XDG_RUNTIME_DIR="$(mktemp -d)"
    chmod 700 "$XDG_RUNTIME_DIR"
fi

# Each step prints the seconds the run has taken so far, to see where CI's time goes.
step() {
    echo "== ${SECONDS}s: $*" >&2
    "$@"
}

step cargo fmt --all -- --check
step cargo clippy --release --workspace --all-targets -- -D warnings
# The library as another program links it (no default features: no winit, egui, clap or
# plotting crate) is built by the suite's readme_library test, the README's own host
# program with a second one that checks a map file is refused naming the feature. Neither
# a unit-test build of it (about 120 s of CI's 20 minutes, the workspace's tests again) nor
# its docs (`cargo doc --no-default-features -p shadeballs`: 26 to 34 s, checking wgpu and
# naga again with the lean graph's features) run here: the docs below are the default
# build's, where every feature's items are documented and their links checked.
export RUSTDOCFLAGS="-D warnings"
step cargo doc --release --no-deps --workspace
unset RUSTDOCFLAGS
# Both crates: the library's unit tests (the maths, beside its code) and its integration
# test binary, the lab's test binary, the examples (built, and run by their tests) and the
# doctests of the facade.
step cargo test --release --workspace
echo "== ${SECONDS}s: done" >&2
