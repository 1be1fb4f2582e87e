#!/bin/bash
# platoon on a lent GPU machine (docs/PERFORMANCE.md "On a GPU"), run by the session's device
# tool from the repository root with two ignored folders carried:
# - .gl: Debian's libvulkan1 and glvnd packages, downloaded as the tool's README says;
# - .devbin (made by tools/device_bundle.sh): platoon.xz (a stripped release binary, xz-compressed to fit the 64 MiB a call
#   carries), lvp.tar.xz (Debian 12's lavapipe and every library it needs but glibc and
#   libstdc++, from `ldd libvulkan_lvp.so`, under lib/, each given RUNPATH $ORIGIN by
#   `patchelf --set-rpath` so that they find each other and the NVIDIA driver keeps the
#   system's libraries), and shared/ with scenes/CesiumMan.glb
#   and envmaps/courtyard.exr.
# Measures: the devices; storage against texel buffers on the GPU (1080p, depth 8); both
# traversals (issue 61: the own BVH and the device's ray queries, where the GPU offers them;
# the device tool's notes say its H100/H200 offer ray-tracing pipelines but no ray queries);
# bench kernel; bench balance in real mode on the GPU beside lavapipe (Brigade's hybrid case); a
# still on the GPU alone and on both. Writes gpu.log and balance.csv/png to $OUT.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/lvp && tar -C /tmp/lvp -xJf .devbin/lvp.tar.xz
xz -dc .devbin/platoon.xz >/tmp/platoon && chmod +x /tmp/platoon
P=/tmp/platoon
export PLATOON_SHARED_DIR=$PWD/.devbin/shared
exec > >(tee $OUT/gpu.log) 2>&1
NV=$(ls /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
  /etc/vulkan/icd.d/nvidia_icd.json 2>/dev/null | head -1)
printf '{"file_format_version":"1.0.0","ICD":{"api_version":"1.1.230","library_path":"%s"}}\n' \
  /tmp/lvp/lib/libvulkan_lvp.so >/tmp/lvp/lvp_icd.json
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=$NV:/tmp/lvp/lvp_icd.json
echo "== devices (ICD $NV)"
if ! $P devices; then
  VK_LOADER_DEBUG=error,driver $P devices 2>&1 | tail -30
  exit 1
fi
G=$($P devices | grep -v llvmpipe | grep -m1 -o '^[0-9]\+')
L=$($P devices | grep llvmpipe | grep -m1 -o '^[0-9]\+')
echo "GPU $G, lavapipe $L"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv
nproc
r() { timeout 60 $P render "$@" 2>&1 | grep -E 'samples/s|rays/s|error|Error|warning'; }
echo "== built-in box 1920x1080 256 spp, depth 8, GPU: storage vs texel buffers"
for m in storage-buffers texel-buffers storage-buffers texel-buffers; do
  echo "-- $m"; r --devices $G --width 1920 --height 1080 --spp 256 --memory $m --out /tmp/box.png
done
echo "== bench scenes at 1080p, depth 8, 64 spp, GPU"
mkdir -p /tmp/bf
timeout 120 $P bench scenes --scenes all --depths 1 --spp 1 --size 16 --repeat 1 --keep /tmp/bf \
  --mitsuba /nonexistent >/dev/null 2>&1
ls /tmp/bf/*.glb
for s in cornell-48 field room atrium; do
  env=""; [ $s = atrium ] && env="--env-color 0.5,0.6,0.8"
  for m in storage-buffers texel-buffers storage-buffers texel-buffers; do
    echo "-- $s $m"
    r /tmp/bf/$s.glb $env --devices $G --width 1920 --height 1080 --spp 64 --max-depth 8 \
      --memory $m --out /tmp/$s.exr
  done
done
echo "== traversals (issue 61): own against ray-query on the GPU, 1080p, 64 spp, depth 8"
if $P devices | grep "^$G:" | grep -q "ray queries: yes"; then
  for s in cornell-48 room atrium; do
    env=""; [ $s = atrium ] && env="--env-color 0.5,0.6,0.8"
    for t in own ray-query own ray-query; do
      echo "-- $s $t"
      r /tmp/bf/$s.glb $env --devices $G --width 1920 --height 1080 --spp 64 --max-depth 8 \
        --traversal $t --out /tmp/$s-$t.exr
    done
  done
else
  echo "-- the GPU offers no ray queries: the refusal"
  r --devices $G --width 64 --height 64 --spp 1 --traversal ray-query --out /tmp/rq.png
fi
echo "== a still on the GPU alone, then GPU + lavapipe (room, 1080p, 256 spp)"
for d in $G "$G,$L"; do
  echo "-- devices $d"
  /usr/bin/time -f "wall %e s" timeout 120 $P render /tmp/bf/room.glb --devices $d --width 1920 \
    --height 1080 --spp 256 --out /tmp/room_$d.png 2>&1 | grep -E 'samples/s|rays/s|device|wall|rror'
done
echo "== bench kernel (GPU)"
timeout 120 $P bench kernel --repeat 3 --device $G --shared .devbin/shared
echo "== bench balance, real mode: GPU + lavapipe, GPU + two lavapipes"
timeout 240 $P bench balance --mode real --devices2 $G,$L --devices3 $G,$L,$L --width 960 \
  --height 540 --spp 2 --frames 64 --out $OUT
echo "== done"
