#!/usr/bin/env bash
# Redraws the README's pictures with the commands listed in tests/readme_pictures.txt
# (tests/suite/readme_pictures.rs holds the committed pictures equal to what they draw).
# Run from anywhere; builds the release binary first.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release
while IFS= read -r line; do
    case "$line" in '' | '#'*) continue ;; esac
    picture=${line%%:*}
    read -r -a args <<< "${line#*:}"
    target/release/shadeballs "${args[@]}" --out "$picture"
done < tests/readme_pictures.txt
