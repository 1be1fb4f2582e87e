#!/usr/bin/env python3
"""Reference benchmark: render a Cornell box with Mitsuba 3 (CPU, LLVM) or Blender Cycles (CPU).

--renderer mitsuba (default) renders Mitsuba's built-in ``mi.cornell_box()`` scene with the ``path``
integrator using the ``llvm_ad_rgb`` variant and prints, per repetition, the
render time (``mi.render`` plus a host sync) and the throughput in millions of
camera samples per second (width * height * spp / seconds).

The first repetition includes Dr.Jit's tracing and JIT compilation of the
rendering kernel (or loading it from Dr.Jit's on-disk kernel cache in
~/.drjit; delete that directory for a cold-cache run); later repetitions in
the same process reuse the in-memory kernel.  For whole-process timing run
it under ``/usr/bin/time -v`` or ``time``.

Install (Debian 12), outside the system Python:

    apt-get update && apt-get install -y libllvm19      # LLVM shared library for Dr.Jit
    # (libllvm15 does NOT work with drjit 1.5: "LLVM ERROR: Cannot select ... fminimum")
    python3 -m venv /tmp/refbench
    /tmp/refbench/bin/pip install mitsuba numpy          # tested: mitsuba 3.9.1, drjit 1.5.0
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1

--renderer cycles builds an equivalent Cornell box from scratch with ``bpy``
(factory-empty scene; 2-unit box with white 0.73 / red / green Lambertian
Diffuse BSDF walls, two white boxes, a small one-sided emissive quad under the
ceiling with Mitsuba's radiance, perspective camera with Mitsuba's position and
fov) and renders it with Cycles on the CPU: 2 threads, fixed ``--spp``, no
adaptive sampling, no denoising, no sample clamping, Blackman-Harris pixel
filter (Cycles default; Mitsuba uses a Gaussian).  Only
``bpy.ops.render.render`` is timed; the first render includes Cycles' scene
sync and BVH build.  Depth mapping: Mitsuba's max_depth counts path segments,
Cycles' max_bounces counts indirect bounces and always does direct lighting
(max_bounces 0 == Mitsuba max_depth 2), so max_bounces = max_depth - 2; for
max_depth 1 the emitter is additionally hidden from all non-camera rays so that
only directly seen emission remains.  Wall colours are white 0.73, red
(0.65, 0.05, 0.05), green (0.12, 0.45, 0.15), not the reflectances of Mitsuba's
built-in scene, so the two images differ slightly in tint; box sizes also differ.

    /tmp/refbench/bin/pip install bpy                    # tested: bpy 5.0.1 (needs Python 3.11)
    # bpy links libX11 libXrender libXfixes libXi libxkbcommon libXext libSM libICE libGL;
    # on Debian 12 these come from (they were already present on the test machine):
    apt-get install -y libxrender1 libxxf86vm1 libxfixes3 libxi6 libxkbcommon0 libsm6 libgl1
    # note: bpy 5.0.1 pins numpy 1.26.4 (pip downgrades numpy 2.x); mitsuba 3.9.1 still works with it

--scene FILE.xml renders a Mitsuba scene file instead of ``mi.cornell_box()``: what ``platoon bench
scenes`` writes from each bench scene (crates/platoon-lab/src/mitsuba.rs: platoon's own posed
geometry, camera, lights and materials), size, samples and depth included.

Usage:

    /tmp/refbench/bin/python tools/reference_bench.py --spp 256 --size 256 --max-depth 8
    /tmp/refbench/bin/python tools/reference_bench.py --max-depth 1   # emitters seen directly only
    /tmp/refbench/bin/python tools/reference_bench.py --renderer cycles --spp 256 --size 256 --max-depth 8
    /tmp/refbench/bin/python tools/reference_bench.py --renderer cycles --size 64 --output /tmp/cycles_check.png
    /tmp/refbench/bin/python tools/reference_bench.py --scene /tmp/bench/spheres/scene.xml
"""

import argparse
import os
import sys
import time


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--renderer", choices=("mitsuba", "cycles"), default="mitsuba",
                        help="reference renderer (default mitsuba)")
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel (default 256)")
    parser.add_argument("--size", type=int, default=256, help="image width and height (default 256)")
    parser.add_argument("--max-depth", type=int, default=8,
                        help="path integrator max_depth; 1 = camera rays only (default 8)")
    parser.add_argument("--repeat", type=int, default=1, help="number of renders (default 1)")
    parser.add_argument("--check", action="store_true",
                        help="exit 0 when Mitsuba's llvm_ad_rgb variant loads (mitsuba only)")
    parser.add_argument("--scene", default=None,
                        help="a Mitsuba scene file to render instead of the Cornell box (mitsuba only)")
    parser.add_argument("--output", default=None,
                        help="optional path to write the last image (.exr/.png; cycles: .png)")
    args = parser.parse_args()

    if args.renderer == "cycles":
        return run_cycles(args)
    return run_mitsuba(args)


def newest_libllvm():
    """The newest libLLVM.so.N of Debian's libllvmN packages that Dr.Jit can use (16 or later)."""
    import glob
    import re
    found = []
    for path in glob.glob("/usr/lib/x86_64-linux-gnu/libLLVM*.so*"):
        m = re.search(r"libLLVM(?:-|\.so\.)(\d+)", os.path.basename(path))
        if m and int(m.group(1)) >= 16:
            found.append((int(m.group(1)), path))
    return max(found)[1] if found else None


def run_mitsuba(args) -> int:
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        llvm = newest_libllvm()
        if llvm:
            os.environ["DRJIT_LIBLLVM_PATH"] = llvm
        else:
            print("note: DRJIT_LIBLLVM_PATH is not set and no libLLVM 16+ was found; "
                  "Dr.Jit will search for libLLVM itself", file=sys.stderr)

    t_import = time.perf_counter()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    if args.check:
        return 0

    if args.scene:
        # Size, samples and depth are the file's.
        scene = mi.load_file(args.scene)
        film = scene.sensors()[0].film()
        width, height = film.size()
        spp = scene.sensors()[0].sampler().sample_count()
        label = f"scene={args.scene}"
    else:
        scene_dict = mi.cornell_box()
        scene_dict["sensor"]["film"]["width"] = args.size
        scene_dict["sensor"]["film"]["height"] = args.size
        scene_dict["sensor"]["sampler"]["sample_count"] = args.spp
        scene_dict["integrator"] = {"type": "path", "max_depth": args.max_depth}
        scene = mi.load_dict(scene_dict)
        width = height = args.size
        spp = args.spp
        label = f"max_depth={args.max_depth}"
    setup_s = time.perf_counter() - t_import

    print(f"mitsuba {mi.__version__} variant={mi.variant()} size={width}x{height} "
          f"spp={spp} {label} (import+load {setup_s:.3f} s)")

    samples = width * height * spp
    image = None
    for i in range(args.repeat):
        t0 = time.perf_counter()
        # seed varies per run; .numpy() forces evaluation and sync to host
        image = mi.render(scene, spp=spp, seed=i).numpy()
        dt = time.perf_counter() - t0
        print(f"render {i + 1}: {dt:.3f} s  {samples / dt / 1e6:.2f} M samples/s"
              + ("  (first render: includes trace + JIT compile / kernel-cache load)" if i == 0 else ""))

    if args.output and image is not None:
        mi.util.write_bitmap(args.output, image)
        print(f"wrote {args.output}")
    return 0


def _cycles_cornell_box(bpy, size: int, spp: int, max_bounces: int, camera_only: bool) -> None:
    """Build a Cornell box from scratch in an empty Blender scene (Z up).

    Box interior is [-1, 1]^3, open side at y = -1, camera on the -y axis.
    """
    import math

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    def diffuse(name, rgb):
        mat = bpy.data.materials.new(name)
        if mat.node_tree is None:  # Blender < 5 creates materials without a node tree
            mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.clear()
        bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*rgb, 1.0)
        bsdf.inputs["Roughness"].default_value = 0.0  # 0 = Lambertian (non-zero = Oren-Nayar)
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
        return mat

    def emitter(name, radiance, back_rgb):
        # One-sided like Mitsuba's area emitter: emission on the front face,
        # plain diffuse on the back face.
        mat = bpy.data.materials.new(name)
        if mat.node_tree is None:  # Blender < 5 creates materials without a node tree
            mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.clear()
        peak = max(radiance)
        emit = nt.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*(c / peak for c in radiance), 1.0)
        emit.inputs["Strength"].default_value = peak
        back = nt.nodes.new("ShaderNodeBsdfDiffuse")
        back.inputs["Color"].default_value = (*back_rgb, 1.0)
        geom = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geom.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(emit.outputs["Emission"], mix.inputs[1])
        nt.links.new(back.outputs["BSDF"], mix.inputs[2])
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
        if hasattr(mat, "cycles") and hasattr(mat.cycles, "emission_sampling"):
            mat.cycles.emission_sampling = "FRONT"
        return mat

    def mesh_object(name, verts, faces, mat):
        me = bpy.data.meshes.new(name)
        me.from_pydata(verts, [], faces)
        me.update()
        me.materials.append(mat)
        ob = bpy.data.objects.new(name, me)
        scene.collection.objects.link(ob)
        return ob

    def quad(name, corners, mat):
        # corners counter-clockwise seen from the side the normal points to
        return mesh_object(name, corners, [(0, 1, 2, 3)], mat)

    def box(name, cx, cy, w, d, h, angle_deg, mat):
        a = math.radians(angle_deg)
        ca, sa = math.cos(a), math.sin(a)
        verts = []
        for z in (-1.0, -1.0 + h):
            for dx, dy in ((-w / 2, -d / 2), (w / 2, -d / 2), (w / 2, d / 2), (-w / 2, d / 2)):
                verts.append((cx + ca * dx - sa * dy, cy + sa * dx + ca * dy, z))
        faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
        return mesh_object(name, verts, faces, mat)

    white = diffuse("white", (0.73, 0.73, 0.73))
    red = diffuse("red", (0.65, 0.05, 0.05))
    green = diffuse("green", (0.12, 0.45, 0.15))
    light = emitter("light", (18.387, 13.9873, 6.75357), (0.73, 0.73, 0.73))  # Mitsuba's radiance

    quad("floor", [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)], white)
    quad("ceiling", [(-1, -1, 1), (-1, 1, 1), (1, 1, 1), (1, -1, 1)], white)
    quad("back", [(-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)], white)
    quad("left", [(-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)], red)
    quad("right", [(1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1)], green)
    box("short_box", 0.33, -0.3, 0.6, 0.6, 0.6, -18.0, white)
    box("tall_box", -0.33, 0.3, 0.6, 0.6, 1.2, 17.0, white)
    # small quad just under the ceiling, normal pointing down (-z)
    lx, ly, lz = 0.23, 0.19, 0.99
    lamp = quad("light", [(-lx, -ly, lz), (-lx, ly, lz), (lx, ly, lz), (lx, -ly, lz)], light)
    if camera_only:
        # max_depth 1: Cycles has no "no direct lighting" bounce count (0 bounces
        # still does next-event estimation), so hide the emitter from all but
        # camera rays: only directly seen emission remains, like Mitsuba.
        lamp.visible_diffuse = False
        lamp.visible_glossy = False
        lamp.visible_transmission = False
        lamp.visible_volume_scatter = False
        lamp.visible_shadow = False

    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.angle = math.radians(39.3077)  # Mitsuba cornell_box() fov
    cam = bpy.data.objects.new("camera", cam_data)
    cam.location = (0.0, -3.9, 0.0)
    cam.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # look along +y, up = +z
    scene.collection.objects.link(cam)
    scene.camera = cam

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = size
    r.resolution_y = size
    r.resolution_percentage = 100
    r.threads_mode = "FIXED"
    r.threads = 2
    r.use_compositing = False
    r.use_sequencer = False
    r.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Standard"  # plain sRGB, like Mitsuba's PNG output

    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.time_limit = 0.0
    c.max_bounces = max_bounces
    # per-type limits default to fewer (diffuse 4), so raise them to the total
    c.diffuse_bounces = max_bounces
    c.glossy_bounces = max_bounces
    c.transmission_bounces = max_bounces
    c.volume_bounces = max_bounces
    c.transparent_max_bounces = max_bounces
    c.sample_clamp_direct = 0.0  # no clamping (Cycles clamps indirect at 10 by default)
    c.sample_clamp_indirect = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.blur_glossy = 0.0


def run_cycles(args) -> int:
    t_import = time.perf_counter()
    import bpy
    # Mitsuba's max_depth counts path segments (1 = emitters seen directly,
    # 2 = + direct lighting); Cycles' max_bounces counts indirect bounces and
    # always includes direct lighting (0 bounces = Mitsuba max_depth 2).
    max_bounces = max(args.max_depth - 2, 0)
    camera_only = args.max_depth <= 1
    _cycles_cornell_box(bpy, args.size, args.spp, max_bounces, camera_only)
    setup_s = time.perf_counter() - t_import
    scene = bpy.context.scene
    print(f"blender {bpy.app.version_string} cycles device={scene.cycles.device} "
          f"threads={scene.render.threads} size={args.size}x{args.size} spp={args.spp} "
          f"max_depth={args.max_depth} (max_bounces={max_bounces}"
          f"{', emitter camera-visible only' if camera_only else ''}) (import+build {setup_s:.3f} s)")

    samples = args.size * args.size * args.spp
    for i in range(args.repeat):
        scene.cycles.seed = i
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=False)
        dt = time.perf_counter() - t0
        print(f"render {i + 1}: {dt:.3f} s  {samples / dt / 1e6:.2f} M samples/s"
              + ("  (first render: includes scene sync + BVH build + kernel setup)" if i == 0 else ""))

    if args.output:
        bpy.data.images["Render Result"].save_render(filepath=os.path.abspath(args.output))
        print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
