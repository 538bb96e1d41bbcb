"""What noise-driven sampling's rounds cost against whole pixels, through the bindings.

Noise-driven sampling's rounds against a fixed-count render of whole pixels
(docs/notes/adaptive_sampling.md): a lit floor under a half-mirror blocker, seen from
above at 160x120 through a jittered 8x8 grid, traced by each kernel (waves, recursion)
three ways: fixed 64 samples a pixel, adaptive at threshold 0 (every pixel its 64, in
rounds: the rounds' overhead) and adaptive at threshold 0.01 with a minimum of 4.

    .venv/bin/python -m whitted_tools bench-rounds [--native build] [--threads 2] [--repeats 5]
    valgrind --tool=callgrind --collect-atstart=no "--toggle-collect=whitted::RenderJob::work*" \\
        .venv/bin/python -m whitted_tools bench-rounds --threads 1 --repeats 1 --only t0 waves

Prints, per kernel and way, the best trace_seconds of --repeats renders, the samples per
pixel (min, mean, max), the rays and the image's sum (the same build and way give the
same image). --native: the folder holding whitted_native (a build directory or addon/).
"""

import argparse
from pathlib import Path

import numpy as np

from whitted_tools import REPO
from whitted_tools.builds import native_module
from whitted_tools.verbs import prog

WAYS = {
    "fixed": {},
    "t0": {"adaptive_sampling": True, "noise_threshold": 0.0},
    "t01": {"adaptive_sampling": True, "noise_threshold": 0.01, "adaptive_min_samples": 4},
}
KERNELS = ("waves", "recursion")


def quad(x0, x1, y0, y1, z):
    positions = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], np.float32)
    return positions, np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def floor_and_blocker(wn):
    """A lit floor under a half-mirror blocker (hard shadow edges, a reflection)."""
    scene = wn.Scene()
    scene.set_mesh("floor", *quad(-10, 10, -10, 10, 0))
    scene.set_material("white", wn.Material(diffuse=(0.5,) * 3, ambient=0.0))
    scene.set_instance("floor", "floor", np.eye(4), ["white"])
    scene.set_mesh("blocker", *quad(-0.3, 0.3, -0.3, 0.3, 1.0))
    mirror = wn.Material(diffuse=(0.3,) * 3, reflectivity=(0.5,) * 3, ambient=0.0)
    scene.set_material("mirror", mirror)
    scene.set_instance("blocker", "blocker", np.eye(4), ["mirror"])
    light = wn.Light(type=wn.LightType.POINT, color=(40.0,) * 3, position=(0, 0, 2))
    scene.set_light("key", light)
    to_world = np.eye(4)
    to_world[2, 3] = 5.0
    scene.camera = wn.Camera(to_world=to_world, window=(-1.0, 1.0, -0.75, 0.75), clip_end=1e4)
    scene.background = (0.0, 0.0, 0.0)
    return scene


def run(wn, scene, way, kernel, size, threads, repeats):
    """(best trace_seconds, samples_per_pixel, rays, image sum) of `repeats` renders."""
    settings = wn.Settings(
        width=size[0],
        height=size[1],
        aa_samples=8,
        aa_mode=wn.AntiAliasing.JITTERED,
        threads=threads,
        **WAYS[way],
    )
    settings.waves = kernel == "waves"
    best = None
    for _ in range(repeats):
        job = wn.RenderJob(scene, settings)
        job.start()
        while not job.wait(1.0):
            pass
        stats = job.stats()
        best = stats["trace_seconds"] if best is None else min(best, stats["trace_seconds"])
    image_sum = float(job.image().astype(np.float64).sum())
    return best, stats["samples_per_pixel"], stats["rays"]["total"], image_sum


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--native", type=Path, default=REPO / "build")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--size", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--only", nargs=2, metavar=("WAY", "KERNEL"))
    args = parser.parse_args(argv)
    wn = native_module(args.native)
    scene = floor_and_blocker(wn)
    runs = [tuple(args.only)] if args.only else [(w, k) for k in KERNELS for w in WAYS]
    for way, kernel in runs:
        best, spp, rays, image_sum = run(
            wn, scene, way, kernel, args.size, args.threads, args.repeats
        )
        low, mean, high = spp
        print(
            f"{kernel:<9} {way:<5} best {best:.3f} s  spp ({low}, {mean:.2f}, {high})  "
            f"rays {rays}  sum {image_sum!r}"
        )
