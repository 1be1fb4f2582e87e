#!/usr/bin/env bash
# The whole test suite: installs missing system packages, then runs every test of the
# workspace on lavapipe (forced, so other installed drivers do not change results), and ends
# with one line totalling all test binaries.
set -euo pipefail
cd "$(dirname "$0")/.."
# ffmpeg for the video test; Open MPI and libclang (rsmpi's bindings) for the MPI tests.
tools/install-deps.sh ffmpeg openmpi-bin libopenmpi-dev libclang-dev
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
export VK_ICD_FILENAMES=$VK_DRIVER_FILES
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
log=$(mktemp)
trap 'rm -f "$log" "$log.oidn" "$log.py"' EXIT
status=0
# One set of features for every cargo command below, so that each reuses what the first built:
# a command that selects other packages or features resolves its dependencies' features anew,
# and one proc-macro built with other features (syn's, which bindgen wants with more) rebuilds
# nearly everything above it (a separate MPI stage and OIDN stage cost 7 minutes of a fresh
# machine's run that way, docs/PERFORMANCE.md).
# MPI: the CLI with the feature `mpi`, whose tests run under `mpirun -np 3` against one
# process, bit for bit (docs/DISTRIBUTED.md).
features=platoon-cli/mpi
# Open Image Denoise: Debian has no package; tools/oidn.sh finds it ($OIDN_DIR) or fetches the
# pyoidn wheel's copy into the cache. Without it the build has no `oidn` and its tests say why
# they were skipped; the Python module's tests check the refusal (built without it).
if oidn_dir=$(tools/oidn.sh 2>"$log.oidn"); then
    features+=,platoon-cli/oidn
    export OIDN_DIR=$oidn_dir
    export LD_LIBRARY_PATH=$oidn_dir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
else
    echo "Open Image Denoise's tests skipped: $(cat "$log.oidn")"
fi
rm -f "$log.oidn"
cargo test --workspace --all-targets --features "$features" "$@" 2>&1 | tee "$log" || status=$?
# The examples in the API documentation (--all-targets leaves doc tests out).
cargo test --workspace --doc --features "$features" "$@" 2>&1 | tee -a "$log" || status=$?
# The Python module (crates/platoon-py, outside the workspace): built into a virtual
# environment by tools/python.sh, its tests under pytest against the CLI built above. pytest's
# summary joins the total as one more "test result" line.
# The examples the Python module's tests run beside it (scripted_game): `cargo test
# --all-targets` builds examples as tests, under hashed names only.
cargo build --workspace --examples --features "$features" 2>&1 | tee -a "$log" || status=$?
if python=$(tools/python.sh); then
    PLATOON_CLI=$CARGO_TARGET_DIR/debug/platoon "$python" -m pytest crates/platoon-py/tests -q \
        -p no:cacheprovider 2>&1 | tee "$log.py" || status=$?
    tail -n 1 "$log.py" | awk '{ for (i = 2; i <= NF; i++) { n = $(i - 1) + 0
        if ($i ~ /^passed/) p = n; if ($i ~ /^failed/) f = n; if ($i ~ /^skipped/) s = n } }
        END { printf "test result: pytest. %d passed; %d failed; %d ignored;\n", p, f, s }' >> "$log"
    rm -f "$log.py"
else
    echo "the Python module did not build"
    status=1
fi
# The Bevy plugin (crates/platoon-bevy, outside the workspace: Bevy is a large build that the
# workspace's own tests do not need): a headless Bevy app rendering through it on lavapipe.
cargo test --manifest-path crates/platoon-bevy/Cargo.toml "$@" 2>&1 | tee -a "$log" || status=$?
awk '/^test result:/ { p += $4; f += $6; s += $8 }
     END { printf "platoon: %d passed, %d failed, %d skipped\n", p, f, s }' "$log"
exit "$status"
