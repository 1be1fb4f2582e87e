#!/bin/bash
# Fills .devbin for tools/gpu_check.sh (a lent GPU machine, whose calls carry at most 64 MiB and
# reach no package registry): the release binary stripped and xz-compressed, Debian 12's lavapipe
# with every library it needs but glibc and libstdc++ (each given RUNPATH $ORIGIN, so that they
# find each other without LD_LIBRARY_PATH, which the NVIDIA driver would also see), and the
# shared files bench kernel reads. Takes about 4 minutes on 2 cores (xz -9 of 177 MB of LLVM).
set -eu
cd "$(dirname "$0")/.."
target=${CARGO_TARGET_DIR:-$HOME/.cache/platoon-target}
command -v patchelf >/dev/null || { echo "needs patchelf (apt-get install patchelf)" >&2; exit 1; }
grep -qx '/.devbin/' .git/info/exclude || echo /.devbin/ >>.git/info/exclude
cargo build --release -p platoon-cli
mkdir -p .devbin/shared/scenes .devbin/shared/envmaps
strip -o /tmp/platoon.stripped "$target/release/platoon"
xz -6 -T0 -c /tmp/platoon.stripped >.devbin/platoon.xz
cp ../shared/scenes/CesiumMan.glb .devbin/shared/scenes/
cp ../shared/envmaps/courtyard.exr .devbin/shared/envmaps/
lvp=/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so
stage=$(mktemp -d)
mkdir "$stage/lib"
cp "$lvp" "$stage/lib/"
for l in $(ldd "$lvp" | awk '/=>/{print $3}'); do
  case $(basename "$l") in libc.so* | libm.so* | libstdc++* | libgcc_s* | libpthread* | ld-linux*) continue ;; esac
  cp -L "$l" "$stage/lib/"
done
for f in "$stage"/lib/*; do patchelf --set-rpath '$ORIGIN' "$f"; done
tar -C "$stage" -cf - lib | xz -9 -T0 >.devbin/lvp.tar.xz
rm -rf "$stage"
du -sh .devbin/*
