#!/usr/bin/env bash
# Renders the built-in Cornell box to cornell.png (installs missing system packages first).
# Extra arguments go to `platoon render`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
# The dev profile builds dependencies optimised (see Cargo.toml) and shares its build with the
# tests; the kernel itself runs on the Vulkan device either way.
cargo run --bin platoon -- render --out cornell.png "$@"
