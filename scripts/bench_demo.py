"""Benchmark (not a test): per-phase times and ray throughput of the demo scene.

Renders the built-in demo scene with `blender -b FILE -E WHITTED -f 1` several times,
each render writing its statistics to the JSON file named by WHITTED_STATS, and prints
the median of each phase and the rays per second by ray type.

    .venv/bin/python scripts/bench_demo.py [--blender blender] [--resolution 1280 720]
                                           [--repeats 5] [--threads 0]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from whitted_tools import SCRIPTS
from whitted_tools.blender import blender_command

PHASES = ("export", "mesh_bvh", "scene_bvh", "trace", "writeback", "total")
RAY_TYPES = ("camera", "shadow", "reflection", "refraction", "total")


def run(cmd, env=None):
    result = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if result.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}")
    return result


def render_once(blender, blend, threads, workdir, index):
    stats_path = workdir / f"stats-{index}.json"
    env = dict(os.environ, WHITTED_STATS=str(stats_path))
    cmd = [blender, "-b", str(blend), "-E", "WHITTED", "-o", str(workdir / "frame-"), "-F", "PNG"]
    if threads:
        cmd += ["-t", str(threads)]
    run([*cmd, "-f", "1"], env=env)
    return json.loads(stats_path.read_text())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--resolution", type=int, nargs=2, default=(1280, 720))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=0, help="0: Blender's default")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="whitted-bench-") as tmp:
        workdir = Path(tmp)
        blend = workdir / "demo.blend"
        width, height = args.resolution
        run(
            blender_command(
                SCRIPTS / "demo_scene.py",
                *("--save", blend, "--resolution", width, height, "--no-render"),
                blender=args.blender,
            )
        )
        runs = [
            render_once(args.blender, blend, args.threads, workdir, i) for i in range(args.repeats)
        ]

    first = runs[0]
    print(
        f"Whitted demo scene, {width}x{height}, {first['settings']['aa_samples']}^2 samples "
        f"per pixel, depth {first['settings']['max_depth']}, {first['threads']} threads, "
        f"Blender {first['blender']}, median of {len(runs)} renders"
    )
    print(f"command: python {' '.join(sys.argv)}")
    print()
    print("| phase | seconds (median) | min | max |")
    print("|---|---:|---:|---:|")
    for phase in PHASES:
        values = [r["phases"][phase] for r in runs]
        print(
            f"| {phase} | {statistics.median(values):.4f} | {min(values):.4f} | {max(values):.4f} |"
        )
    print()
    trace = statistics.median(r["phases"]["trace"] for r in runs)
    print("| ray type | rays | share | Mrays/s over the trace phase |")
    print("|---|---:|---:|---:|")
    for kind in RAY_TYPES:
        count = first["rays"][kind]
        share = count / first["rays"]["total"] if first["rays"]["total"] else 0.0
        print(f"| {kind} | {count} | {share:.1%} | {count / trace / 1e6:.2f} |")


if __name__ == "__main__":
    main()
