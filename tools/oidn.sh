#!/usr/bin/env bash
# Finds Intel Open Image Denoise for `--features oidn` and prints its root (what OIDN_DIR
# names: lib/libOpenImageDenoise.so under it). Debian has no package: the pyoidn wheel on PyPI
# carries the library, so without $OIDN_DIR it is downloaded once (about 90 MB) and unpacked
# into platoon's cache folder; nothing is installed into Python. Exits non-zero, saying why,
# when neither works (no pip, no network).
set -euo pipefail
if [[ -n "${OIDN_DIR:-}" ]]; then
    if [[ -e "$OIDN_DIR/lib/libOpenImageDenoise.so" ]]; then
        echo "$OIDN_DIR"
        exit 0
    fi
    echo "OIDN_DIR=$OIDN_DIR holds no lib/libOpenImageDenoise.so" >&2
    exit 1
fi
cache=${XDG_CACHE_HOME:-$HOME/.cache}/platoon/oidn
root=$cache/pyoidn/oidn
if [[ ! -e "$root/lib/libOpenImageDenoise.so" ]]; then
    mkdir -p "$cache"
    if ! python3 -m pip download --quiet --no-deps --only-binary=:all: -d "$cache/wheel" pyoidn >&2; then
        echo "could not download the pyoidn wheel (pip and PyPI are needed)" >&2
        exit 1
    fi
    python3 -m zipfile -e "$cache"/wheel/pyoidn-*.whl "$cache"
fi
echo "$root"
