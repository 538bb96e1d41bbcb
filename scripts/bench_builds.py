"""Constant materials traced by two builds of whitted_native side by side: the issue-12
cost clause ("a scene whose materials are constants traces no slower than today") against
a build from before shader programs, and issue 13's (no pass enabled, trace time
unchanged) against a build from before passes.

    .venv/bin/python scripts/bench_builds.py OLD_ADDON_DIR NEW_ADDON_DIR [--rounds 8] \
        [--json FILE --old-label TEXT --new-label TEXT]
    valgrind --tool=callgrind .venv/bin/python scripts/bench_builds.py --small ADDON_DIR

--json writes the figures, the command and the machine to FILE for a page's generator
(scripts/passes_page.py reads docs/images/passes/builds.json), the labels saying what
each build is (its commit).

Each build's module is loaded in its own process (one whitted_native per process), the
two alternating for --rounds rounds; each process renders the scene three times and
keeps its best trace time. The scene is built through the bindings only, with what both
builds accept: 64 smooth spheres (48 x 24 quads) on a floor, Lambert + Phong constants,
one sun, 480x270, 3x3 samples per pixel, 2 threads. Prints each build's best and median
trace seconds, its rays and the image mean (the same scene must give the same image),
the ratio new / old of the best times and the rounds' paired ratios (median [min..max])
of the best trace and of the best CPU seconds (every thread of the process), and the
load average.
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from whitted_tools.binding_scenes import sphere
from whitted_tools.native_job import run_job
from whitted_tools.pages import command_line, machine_lines
from whitted_tools.timing import paired_ratios, spread_text

REPEATS = 3
# The render timed (480x270, 3x3 samples, 2 threads, best of REPEATS) and, with --small,
# the one whose instructions are counted (one render, one thread):
#     valgrind --tool=callgrind .venv/bin/python scripts/bench_builds.py --small DIR
# then `callgrind_annotate --inclusive=yes` gives RenderJob::trace's count (a build with
# symbols: -DCMAKE_CXX_FLAGS=-g -DCMAKE_STRIP=/bin/true).
TIMED = {"width": 480, "height": 270, "aa_samples": 3, "threads": 2}
SMALL = {"width": 160, "height": 90, "aa_samples": 2, "threads": 1}


def trace_best(module_dir, size=TIMED, repeats=REPEATS):
    """Inside one process: render the scene `repeats` times with the module in module_dir."""
    sys.path.insert(0, module_dir)
    import whitted_native as wn

    scene = wn.Scene()
    positions, triangles, normals = sphere(0.5)
    scene.set_mesh("ball", positions, triangles, vertex_normals=normals)
    floor = np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32)
    scene.set_mesh("floor", floor, np.array([[0, 1, 2], [0, 2, 3]], np.uint32))
    ball = wn.Material(diffuse=(0.6, 0.35, 0.2), specular=(0.04,) * 3, shininess=30.0, ambient=0.0)
    scene.set_material("ball", ball)
    scene.set_material("floor", wn.Material(diffuse=(0.5,) * 3, ambient=0.0))
    scene.set_instance("floor", "floor", np.eye(4), ["floor"])
    for i in range(8):
        for j in range(8):
            to_world = np.eye(4)
            to_world[:3, 3] = (1.1 * (i - 3.5), 1.1 * (j - 3.5), 0.5)
            scene.set_instance(f"ball.{i}.{j}", "ball", to_world, ["ball"])
    sun = wn.Light(type=wn.LightType.SUN, color=(3.0,) * 3, direction=(-0.3, 0.4, -0.8))
    scene.set_light("sun", sun)
    to_world = np.eye(4)
    c, s = math.cos(math.radians(35.0)), math.sin(math.radians(35.0))
    to_world[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]  # 35 degrees down at the spheres
    to_world[:3, 3] = (0.0, -9.0, 6.5)
    scene.camera = wn.Camera(to_world=to_world, window=(-0.6, 0.6, -0.3375, 0.3375), clip_end=1e4)
    scene.background = (0.0, 0.0, 0.0)
    best, best_cpu = math.inf, math.inf
    for _ in range(repeats):
        job = wn.RenderJob(scene, wn.Settings(**size))
        started = time.process_time()
        run_job(job)
        # CPU seconds of every thread of the process: they move less than the wall clock
        # when other work shares the cores.
        best_cpu = min(best_cpu, time.process_time() - started)
        image = job.image()
        best = min(best, job.stats()["trace_seconds"])
    rays = job.stats()["rays"]["total"]
    mean = float(image[..., :3].mean())
    print(json.dumps({"trace": best, "cpu": best_cpu, "rays": rays, "mean": mean}))


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--trace":
        trace_best(sys.argv[2])
        return
    if len(sys.argv) == 3 and sys.argv[1] == "--small":
        trace_best(sys.argv[2], SMALL, repeats=1)
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", help="the folder holding the old build's whitted_native")
    parser.add_argument("new", help="the folder holding the new build's whitted_native")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    parser.add_argument("--old-label", default="old", help="what the old build is")
    parser.add_argument("--new-label", default="new", help="what the new build is")
    args = parser.parse_args()
    runs = {"old": [], "new": []}
    for _ in range(args.rounds):
        for name in runs:
            command = [sys.executable, __file__, "--trace", getattr(args, name)]
            output = subprocess.run(command, capture_output=True, text=True, check=True).stdout
            runs[name].append(json.loads(output.splitlines()[-1]))
    figures = {}
    for name, results in runs.items():
        times = [r["trace"] for r in results]
        figures[name] = {
            "label": getattr(args, f"{name}_label"),
            "best": min(times),
            "median": statistics.median(times),
            "rays": results[0]["rays"],
            "image_mean": results[0]["mean"],
        }
        print(
            f"{name} ({getattr(args, name)}): best {min(times):.3f} s, median "
            f"{statistics.median(times):.3f} s, rays {results[0]['rays']}, image mean "
            f"{results[0]['mean']:.6f}"
        )
    paired = paired_ratios([r["trace"] for r in runs["new"]], [r["trace"] for r in runs["old"]])
    paired_cpu = paired_ratios([r["cpu"] for r in runs["new"]], [r["cpu"] for r in runs["old"]])
    best = figures["new"]["best"] / figures["old"]["best"]
    print(
        f"new / old: best {best:.3f}, paired rounds {spread_text(paired)}, CPU seconds "
        f"paired {spread_text(paired_cpu)}"
    )
    print("load average (1, 5, 15 min): " + ", ".join(f"{v:.2f}" for v in os.getloadavg()))
    if args.json:
        record = {
            "command": command_line(python=".venv/bin/python"),
            "rounds": args.rounds,
            "builds": figures,
            "best_ratio": best,
            "paired_ratios": paired,
            "paired_text": spread_text(paired),
            "paired_cpu_ratios": paired_cpu,
            "paired_cpu_text": spread_text(paired_cpu),
            "machine": machine_lines(),
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(record, indent=2) + "\n")
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
