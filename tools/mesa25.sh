#!/usr/bin/env bash
# Finds a lavapipe that offers ray queries (VK_KHR_ray_query over VK_KHR_acceleration_structure,
# Mesa 24.1 and later) and prints its ICD file (what VK_DRIVER_FILES names). Debian 12's Mesa is
# 22.3: without $PLATOON_MESA25_ICD, bookworm-backports' mesa-vulkan-drivers (25.x) is
# downloaded once (about 12 MB) with a private apt configuration and unpacked into platoon's
# cache folder, beside the system's Mesa, not installed (lavapipe 25 runs on Debian 12's LLVM 15
# and libdrm). Exits non-zero, saying why, when that fails (no apt-get, no network).
set -euo pipefail
if [[ -n "${PLATOON_MESA25_ICD:-}" ]]; then
    if [[ -e "$PLATOON_MESA25_ICD" ]]; then
        echo "$PLATOON_MESA25_ICD"
        exit 0
    fi
    echo "PLATOON_MESA25_ICD=$PLATOON_MESA25_ICD is no file" >&2
    exit 1
fi
cache=${XDG_CACHE_HOME:-$HOME/.cache}/platoon/mesa25
icd=$cache/lvp_icd.x86_64.json
lib=$cache/root/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so
if [[ -e "$icd" && -e "$lib" ]]; then
    echo "$icd"
    exit 0
fi
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
if ! command -v apt-get >/dev/null || [[ ! -e $keyring ]]; then
    echo "apt-get and Debian's archive keyring are needed to fetch Mesa from bookworm-backports" >&2
    exit 1
fi
apt=$cache/apt
mkdir -p "$apt/lists/partial" "$apt/archives/partial"
echo "deb [signed-by=$keyring] http://deb.debian.org/debian bookworm-backports main" \
    >"$apt/sources.list"
# Only this folder's lists and archives: the system's apt sources and state stay as they are.
opts=(-o "Dir::Etc::SourceList=$apt/sources.list" -o Dir::Etc::SourceParts=/nonexistent
    -o "Dir::State::Lists=$apt/lists" -o "Dir::Cache::Archives=$apt/archives"
    -o Dir::Cache::pkgcache= -o Dir::Cache::srcpkgcache= -o Debug::NoLocking=true
    -o APT::Sandbox::User=root)
if ! apt-get "${opts[@]}" -qq update >&2; then
    echo "could not read bookworm-backports' package lists (network?)" >&2
    exit 1
fi
rm -f "$apt"/archives/*.deb
if ! (cd "$apt/archives" && apt-get "${opts[@]}" -qq download \
    mesa-vulkan-drivers/bookworm-backports >&2); then
    echo "could not download mesa-vulkan-drivers from bookworm-backports" >&2
    exit 1
fi
rm -rf "$cache/root"
dpkg-deb -x "$apt"/archives/mesa-vulkan-drivers_*.deb "$cache/root"
[[ -e "$lib" ]] || { echo "the package holds no libvulkan_lvp.so" >&2; exit 1; }
# The package's ICD names its library by file name alone: the system's loader would find
# Debian 12's lavapipe under that name, so the copy here names its own by path.
api=$(sed -n 's/.*"api_version": *"\([^"]*\)".*/\1/p' "$cache/root/usr/share/vulkan/icd.d/lvp_icd.json")
printf '{ "file_format_version": "1.0.0", "ICD": { "api_version": "%s", "library_path": "%s" } }\n' \
    "$api" "$lib" >"$icd.tmp"
mv "$icd.tmp" "$icd"
echo "$icd"
