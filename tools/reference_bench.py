#!/usr/bin/env python3
"""Reference benchmark: render the Cornell box with Mitsuba 3 (CPU, LLVM backend).

Renders Mitsuba's built-in ``mi.cornell_box()`` scene with the ``path``
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

Usage:

    /tmp/refbench/bin/python tools/reference_bench.py --spp 256 --size 256 --max-depth 8
    /tmp/refbench/bin/python tools/reference_bench.py --max-depth 1   # emitters seen directly only
"""

import argparse
import os
import sys
import time


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel (default 256)")
    parser.add_argument("--size", type=int, default=256, help="image width and height (default 256)")
    parser.add_argument("--max-depth", type=int, default=8,
                        help="path integrator max_depth; 1 = camera rays only (default 8)")
    parser.add_argument("--repeat", type=int, default=1, help="number of renders (default 1)")
    parser.add_argument("--output", default=None, help="optional path to write the last image (.exr/.png)")
    args = parser.parse_args()

    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        print("note: DRJIT_LIBLLVM_PATH is not set; Dr.Jit will search for libLLVM itself",
              file=sys.stderr)

    t_import = time.perf_counter()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")

    scene_dict = mi.cornell_box()
    scene_dict["sensor"]["film"]["width"] = args.size
    scene_dict["sensor"]["film"]["height"] = args.size
    scene_dict["sensor"]["sampler"]["sample_count"] = args.spp
    scene_dict["integrator"] = {"type": "path", "max_depth": args.max_depth}
    scene = mi.load_dict(scene_dict)
    setup_s = time.perf_counter() - t_import

    print(f"mitsuba {mi.__version__} variant={mi.variant()} size={args.size}x{args.size} "
          f"spp={args.spp} max_depth={args.max_depth} (import+load {setup_s:.3f} s)")

    samples = args.size * args.size * args.spp
    image = None
    for i in range(args.repeat):
        t0 = time.perf_counter()
        # seed varies per run; .numpy() forces evaluation and sync to host
        image = mi.render(scene, spp=args.spp, seed=i).numpy()
        dt = time.perf_counter() - t0
        print(f"render {i + 1}: {dt:.3f} s  {samples / dt / 1e6:.2f} M samples/s"
              + ("  (first render: includes trace + JIT compile / kernel-cache load)" if i == 0 else ""))

    if args.output and image is not None:
        mi.util.write_bitmap(args.output, image)
        print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
