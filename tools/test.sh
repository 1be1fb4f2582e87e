#!/usr/bin/env bash
# The whole test suite: installs missing system packages, then runs every test of the
# workspace on lavapipe (forced, so other installed drivers do not change results).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
export VK_ICD_FILENAMES=$VK_DRIVER_FILES
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
cargo test --workspace --all-targets "$@"
