#!/usr/bin/env bash
# Renders the built-in Cornell box to cornell.png (installs missing system packages first).
# Extra arguments go to `platoon render`; without any, the render stops at the last whole pass
# within 10 seconds (up to 64 spp), so the first image comes quickly on a CPU.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
# The dev profile builds dependencies optimised (see Cargo.toml) and shares its build with the
# tests; the kernel itself runs on the Vulkan device either way.
if [ $# -eq 0 ]; then set -- --time-limit 10; fi
cargo run --bin platoon -- render --out cornell.png "$@"
