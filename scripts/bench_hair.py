"""Benchmark (not a test): what hair costs. Particle hair on a 1 m plane (hair_scenes.
particle_hair: `--parents` hairs with `--children` interpolated children each, 9 keys a
strand), rendered by Whitted and Cycles at the same size in one Blender; prints the
keys, Whitted's export (reading the keys through co_hair) and BVH times per million
keys, its trace time and rays per second, and Cycles' total render time.

    blender -b --factory-startup --python-exit-code 1 --python scripts/bench_hair.py -- \\
        [--parents 5000] [--children 20] [--resolution 320 240] [--repeats 3]
"""

import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import bpy
from whitted_tools.blender import factory_scene
from whitted_tools.cli import script_args
from whitted_tools.hair_scenes import particle_hair
from whitted_tools.render import render_exr


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parents", type=int, default=5000)
    parser.add_argument("--children", type=int, default=20)
    parser.add_argument("--resolution", nargs=2, type=int, default=(320, 240))
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(script_args())
    scene = factory_scene()
    particle_hair(scene, args.parents, args.children)
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.cycles.samples = 16
    scene.cycles.max_bounces = 0
    scene.cycles.use_denoising = False
    with tempfile.TemporaryDirectory() as work:
        stats_path = os.path.join(work, "stats.json")
        os.environ["WHITTED_STATS"] = stats_path
        whitted, cycles = [], []
        for _ in range(args.repeats):
            render_exr(scene, os.path.join(work, "w.exr"), engine="WHITTED")
            whitted.append(json.loads(Path(stats_path).read_text(encoding="utf-8")))
            started = time.perf_counter()
            render_exr(scene, os.path.join(work, "c.exr"), engine="CYCLES")
            cycles.append(time.perf_counter() - started)
    segments = whitted[0]["curve_segments"]
    strands = args.parents * args.children
    keys = segments + strands  # a strand of k keys has k - 1 segments

    def median(what):
        return statistics.median(s["phases"][what] for s in whitted)

    trace = median("trace")
    rays = whitted[0]["rays"]["total"]
    print(f"bench_hair: Blender {bpy.app.version_string}, {strands:,} strands, {keys:,} keys")
    export, bvh = median("export"), median("mesh_bvh")
    print(f"  export {export:.3f} s ({export / keys * 1e6:.2f} s per M keys)")
    print(f"  mesh BVH {bvh:.3f} s ({bvh / segments * 1e6:.2f} s per M segments)")
    print(
        f"  trace {trace:.3f} s, {rays / trace / 1e6:.2f} M rays/s; total {median('total'):.3f} s"
    )
    print(f"  Cycles ({scene.cycles.samples} samples): {statistics.median(cycles):.3f} s total")


if __name__ == "__main__":
    main()
