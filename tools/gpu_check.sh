#!/bin/bash
# platoon on a lent GPU machine (issue 39; docs/PERFORMANCE.md "On a GPU"): devices, the built-in
# box at 1080p, each bench scene's rays/s at 1080p (megakernel and streaming), bench kernel,
# bench scenes (platoon alone). Run by the session's device tool from the repository root, with
# two ignored folders carried: .gl (Debian's libvulkan1 and glvnd packages, downloaded as the
# tool's README says) and .devbin (a stripped release binary `platoon`, and shared/ with
# scenes/CesiumMan.glb and envmaps/courtyard.exr). Writes gpu.log and cornell1080.png to $OUT.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
P=$PWD/.devbin/platoon
export PLATOON_SHARED_DIR=$PWD/.devbin/shared
log=$OUT/gpu.log
exec > >(tee $log) 2>&1
echo "== devices"
if ! $P devices 2>&1 | grep -qi nvidia; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
if ! $P devices; then
  VK_LOADER_DEBUG=error,driver $P devices 2>&1 | tail -20
  ldd /usr/local/nvidia/lib64/libGLX_nvidia.so.0 | grep -i 'not found'
  exit 1
fi
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv
nproc
echo "== built-in box 1920x1080 256 spp"
for k in mega spt; do timeout 60 $P render --width 1920 --height 1080 --spp 256 --kernel $k --out /tmp/box_$k.png; done
cp /tmp/box_mega.png $OUT/cornell1080.png
echo "== scenes"
mkdir -p /tmp/bf
timeout 90 $P bench scenes --scenes all --depths 1 --spp 1 --size 16 --repeat 1 --keep /tmp/bf > /dev/null 2>&1
ls /tmp/bf/*.glb
for s in cornell-48 spheres field room atrium; do
  env=""; [ $s = atrium ] && env="--env-color 0.5,0.6,0.8"; [ $s = spheres ] && env="--env-color 0.25,0.3,0.4"
  for d in 1 8; do for k in mega spt; do
    [ $d = 1 ] && [ $k = spt ] && continue
    echo "-- $s depth $d $k"
    for r in 1 2; do timeout 60 $P render /tmp/bf/$s.glb $env --width 1920 --height 1080 --spp 64 --max-depth $d --kernel $k --out /tmp/$s.exr 2>&1 | grep -E 'samples/s|error|warning'; done
  done; done
done
echo "== bench kernel"
timeout 100 $P bench kernel --repeat 3 --shared .devbin/shared
echo "== bench scenes (platoon alone, whole processes)"
timeout 100 $P bench scenes --scenes all --depths 1,8 --spp 256 --size 512 --repeat 3 --mitsuba /nonexistent
echo "== done"
