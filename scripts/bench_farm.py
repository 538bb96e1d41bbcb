"""Measure the farm (scripts/farm.py) on this machine and write docs/FARM.md:

    .venv/bin/python scripts/bench_farm.py [--out docs/FARM.md] [--frames 8] [--size 320 240]

Frames per minute of the demo animation (tests/farm/make_scene.py) on 1 and 2 local
Dask workers (each a separate process running one Blender 3.4 per frame), the
scheduler's own cost per task (trivial tasks on the same cluster), and, on paper,
what the same design sends and holds at 100 machines. About two minutes.
"""

import argparse
import os
import platform
import sys
import tempfile
import time

from whitted_tools import REPO
from whitted_tools.blender import blender_command, run_process
from whitted_tools.pages import write_page

REPO_ROOT = str(REPO)
TIMEOUT = 900  # seconds a farm run, or one Blender, may take


def farm_run(blend, frames, workers, out):
    command = [sys.executable, os.path.join(REPO_ROOT, "scripts", "farm.py"), blend]
    command += ["--frames", f"1-{frames}", "--workers", str(workers), "--output", out]
    started = time.perf_counter()
    run_or_exit(command)
    return time.perf_counter() - started


def run_or_exit(command):
    _, problem = run_process(command, TIMEOUT)
    if problem:
        sys.exit(f"bench_farm: {problem}")


def scheduler_overhead(tasks=400):
    from distributed import Client, LocalCluster

    with (
        LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        client.submit(abs, -1).result()  # warm up
        started = time.perf_counter()
        futures = client.map(abs, range(-tasks, 0), pure=False)
        client.gather(futures)
        batch = (time.perf_counter() - started) / tasks
        started = time.perf_counter()
        for value in range(50):
            client.submit(abs, -value, pure=False).result()
        round_trip = (time.perf_counter() - started) / 50
        payload = b"x" * (1 << 20)
        started = time.perf_counter()
        scattered = client.scatter(payload, broadcast=True)
        broadcast = time.perf_counter() - started
        del scattered
    return batch, round_trip, broadcast


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=os.path.join(REPO_ROOT, "docs", "FARM.md"))
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--size", nargs=2, type=int, default=(320, 240))
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="whitted-bench-farm-") as folder:
        blend = os.path.join(folder, "anim.blend")
        maker = os.path.join(REPO_ROOT, "tests", "farm", "make_scene.py")
        run_or_exit(blender_command(maker, blend, "--size", *args.size))
        os.environ.pop("WHITTED_STATS", None)
        # Once to warm the file cache, then timed.
        for _ in range(2):
            started = time.perf_counter()
            run_or_exit(
                ["blender", "-b", blend, "-E", "WHITTED", "-o", os.path.join(folder, "t_####"),
                 "-f", "1"]
            )  # fmt: skip
            one_blender = time.perf_counter() - started
        rows = []
        for workers in (1, 2):
            seconds = farm_run(blend, args.frames, workers, os.path.join(folder, f"out{workers}"))
            rows.append((workers, seconds, args.frames / seconds * 60))
        blend_bytes = os.path.getsize(blend)
        frame_bytes = os.path.getsize(os.path.join(folder, "out1", "0001.exr"))
    batch, round_trip, broadcast = scheduler_overhead()
    load = (load_before, os.getloadavg()[0])
    lines = page_lines(
        args, rows, one_blender, batch, round_trip, broadcast, blend_bytes, frame_bytes, load
    )
    write_page(args.out, lines)


def page_lines(
    args, rows, one_blender, batch, round_trip, broadcast, blend_bytes, frame_bytes, load
):
    width, height = args.size
    return [
        "# The farm: measured here, and at 100 machines on paper",
        "",
        "Made by `.venv/bin/python scripts/bench_farm.py` (how to use the farm: README,",
        '"Rendering on many machines"). Machine: '
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}. Load average (1 min) before and after the run:",
        f"{load[0]:.1f} and {load[1]:.1f}; above the core count, other processes shared the",
        "cores and every number below is slower than on an idle machine.",
        "",
        f"## Frames per minute ({args.frames} frames of the demo animation, "
        f"{width} x {height}, Blender 3.4)",
        "",
        "Each run is the whole command (`scripts/farm.py SCENE --frames 1-"
        f"{args.frames} --workers N`): starting the LocalCluster, packing the scene,",
        "scattering it, one Blender per frame, writing and checking every EXR.",
        "",
        "| workers | seconds | frames per minute |",
        "|---|---|---|",
        *(f"| {w} | {s:.1f} | {fpm:.1f} |" for w, s, fpm in rows),
        "",
        f"One `blender -b scene.blend -E WHITTED -f 1` alone takes {one_blender:.2f} s here,",
        "most of it Blender starting and loading the file: on frames this small the farm's",
        "throughput is Blender's start-up, and two workers on two cores cannot double it",
        "(each Blender uses one thread here; a real frame's trace time dominates instead).",
        "",
        "## The scheduler's cost per task",
        "",
        "| measure | time |",
        "|---|---|",
        f"| a batch of 400 trivial tasks (`client.map`), per task | {batch * 1e3:.2f} ms |",
        f"| one trivial task submitted and awaited, round trip | {round_trip * 1e3:.2f} ms |",
        f"| scattering 1 MiB to every worker (broadcast) | {broadcast * 1e3:.1f} ms |",
        "",
        "Against seconds per frame, the scheduler's share is well under 1%.",
        "",
        "## At 100 machines (on paper)",
        "",
        "- **Sent per task**: the task's arguments (a key of the scene copy, the frame, the",
        "  border, a few settings: under 1 KB); the scene itself goes once per worker",
        f"  (scatter with broadcast; this scene file is {blend_bytes / 1024:.0f} KiB), and",
        "  workers that join later fetch it from a peer, not from the client.",
        f"- **Sent back per task**: the frame's EXR ({frame_bytes / 1024:.0f} KiB here; a",
        "  1920 x 1080 float RGBA frame is about 33 MB before ZIP compression) and its",
        "  statistics. 100 workers finishing a frame each every 30 s send the client",
        "  about 110 MB/s at 1080p: the client's network, not the scheduler, is the limit",
        "  there; tiles make each result smaller, not the total.",
        "- **Held by the scheduler**: one small record per task and per worker; an",
        "  animation of 10,000 frames is 10,000 tasks, a few MB of state. Results pass",
        "  through the client one at a time and are dropped once the EXR is written.",
        f"- **Scheduler work**: about {batch * 1e3:.1f} ms per task measured here; 100 workers",
        "  at one frame per 30 s ask for 3.3 tasks a second, far below the "
        f"{1 / batch:.0f} tasks a",
        "  second this 2-core machine's scheduler handled in the batch above.",
        "- **Faults**: a lost worker's running task is given to another worker by the",
        "  scheduler; a failed frame is retried on another worker (up to `--retries`);",
        "  the report, rewritten after every frame, lets a rerun resume.",
        "- **Start-up**: each task starts a Blender (seconds); for frames of seconds,",
        "  render several frames per task, or keep frames large (tiles for huge ones).",
    ]


if __name__ == "__main__":
    main()
