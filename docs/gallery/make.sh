#!/usr/bin/env bash
# Remakes every picture of this gallery by running the commands written under them in
# README.md (each line there that starts with `gonio `), from this folder, with a release build.
# About ten minutes on two cores.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$here/../.."
cargo build --release -p gonio --manifest-path "$root/Cargo.toml"
gonio="$root/target/release/gonio"
cd "$here"
grep '^gonio ' README.md | while read -r line; do
    echo "+ $line"
    # The line is ours (README.md of this folder), so it is split as a shell would split it.
    eval "\"$gonio\" ${line#gonio }"
done
