#!/usr/bin/env bash
# Renders the built-in Cornell box to cornell.png (installs missing system packages first).
# Without arguments this is the first image of a fresh machine: the CLI is built in the `quick`
# profile (nothing optimised: Cargo.toml says why that is enough for the box) without the
# benches, the trade-off tool and the viewer (`--no-default-features`: no rapier, plotters or
# winit), and the render stops at the last whole pass within 10 seconds (up to 64 spp).
# Extra arguments go to `platoon render` (an --out of theirs replaces cornell.png; paths are
# the caller's, from where the script is run), built in the optimised dev profile the tests
# share (a big scene's loading and BVH builds want it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/tools/install-deps.sh"
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
if [ $# -eq 0 ]; then
    exec cargo run --manifest-path "$root/Cargo.toml" --profile quick --no-default-features \
        --bin platoon -- render --out cornell.png --time-limit 10
fi
out=(--out cornell.png)
for a in "$@"; do
    case "$a" in
        -o | -o* | --out | --out=*) out=() ;;
    esac
done
exec cargo run --manifest-path "$root/Cargo.toml" --bin platoon -- render "${out[@]}" "$@"
