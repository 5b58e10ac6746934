#!/usr/bin/env bash
# The whole test suite of both crates (the library and binary at the root, the lab in lab/),
# from a fresh Debian machine: installs what the tests need (Mesa's lavapipe Vulkan driver,
# Xvfb and xdotool for the viewer test), then checks formatting and the library's docs, and
# builds and runs every test, the examples' and the doctests in release mode, linted by
# clippy as they build (one build serves the lints, the tests and the programs;
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
# The library's docs as a host program sees them, every library feature on (image files,
# labels, scene files, glTF; not the binary's `cli`, whose viewer, clap and egui the library
# does not expose): every public item documented and its links checked. A clean machine
# checks their dependencies for rustdoc in about 50 s; the whole workspace's docs took
# 100 s (the lab's and the binary's winit, egui and clap too), which the separate
# `cargo clippy` step this replaced used to share.
export RUSTDOCFLAGS="-D warnings"
step cargo doc --release --no-deps --no-default-features \
    --features image-files,labels,scene-files,gltf -p shadeballs
unset RUSTDOCFLAGS
# Both crates: the library's unit tests (the maths, beside its code) and its integration
# test binary, the lab's test binary, the examples (built, and run by their tests) and the
# doctests of the facade. Clippy lints the workspace's own crates as this build compiles
# them (what `cargo clippy` does: clippy-driver wraps rustc for workspace members), with
# warnings as errors, so no separate check of every dependency comes first (it took about
# 140 s of CI's 20 minutes). That covers every target `cargo test` builds (the library,
# the binaries, the tests, the examples); the lab's 30-line `cargo bench` entry point is
# the one target it does not build. The library without default features is built by the
# suite's readme_library test, the README's own host program with a second one that checks
# a map file is refused naming the feature (a unit-test build of it would be about 120 s
# more, the workspace's tests again).
clippy_driver="$(rustup which clippy-driver 2>/dev/null || command -v clippy-driver || true)"
if [ -z "$clippy_driver" ]; then
    echo "error: clippy-driver not found (rustup component add clippy)" >&2
    exit 1
fi
export RUSTC_WORKSPACE_WRAPPER="$clippy_driver"
export CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"
step cargo test --release --workspace
echo "== ${SECONDS}s: done" >&2
