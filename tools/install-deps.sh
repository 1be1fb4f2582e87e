#!/usr/bin/env bash
# Installs what platoon needs on Debian 12 that a machine with Rust may lack: the Vulkan loader,
# Mesa's lavapipe (software Vulkan), the Khronos validation layer (tests), and the tools that
# build nv-flip (g++), python3, the font of bench balance plots, the X11
# libraries `platoon view` opens its window with, and Xvfb and xdotool for the viewer test.
# shaderc comes from Debian (libshaderc-dev with glslang-dev and spirv-tools, linked in seconds);
# `--features shaderc-from-source` builds it instead, which needs cmake and ninja-build.
# Packages named as arguments are installed too (tools/test.sh adds ffmpeg, for the video test,
# and Open MPI with libclang, for the MPI tests; the first image waits for none of them).
# Uses sudo only when not root.
set -euo pipefail
packages=(mesa-vulkan-drivers libvulkan1 vulkan-validationlayers libshaderc-dev glslang-dev spirv-tools python3 g++ git
    fonts-dejavu-core
    libx11-6 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 xvfb xdotool "$@")
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    exit 0
fi
echo "installing: ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
