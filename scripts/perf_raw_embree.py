"""Efficiency against raw Embree: our rays per second over those of a bare Embree loop
tracing the very same rays.

Runs inside Blender (3.4, or the bpy 5.0 module) on a saved scene with the Whitted
add-on enabled:

    blender -b SCENE.blend --python scripts/perf_raw_embree.py -- --json OUT.json \\
        [--threads N] [--repeats 3] [--max-recorded 20000000]

1. The scene is exported as the engine exports it and rendered `repeats` times
   without recording: our rays per second are all rays traced (camera, shadow,
   reflection, refraction, cut-out continuations) over the trace phase, which
   includes shading, texture lookups and the recursion. Then `repeats` times
   more with camera-ray packets off, for what the packets buy.
2. It is rendered once more recording the queries of every n-th pixel (n chosen so
   at most --max-recorded queries are kept), each worker thread its own list.
3. Those queries are traced again by a loop of single-ray rtcIntersect1/rtcOccluded1
   calls on as many threads, with no shading and nothing else in the loop
   (SceneAccel::trace_bare), `repeats` times: Embree's rays per second.

Efficiency = ours / Embree's, medians of the repeats. Above 1 would mean we trace
faster than single-ray Embree (packets); below, the gap is our shading and overhead.
"""

import argparse
import json
import math
import statistics
import time

import bpy
from whitted_tools.cli import script_args


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", required=True, help="write the results here")
    parser.add_argument("--threads", type=int, default=0, help="0: Blender's setting")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--max-recorded", type=int, default=20_000_000)
    parser.add_argument(
        "--renders-only",
        action="store_true",
        help="only the renders of step 1 (to profile them: scripts/profile_trace.sh)",
    )
    return parser.parse_args(script_args())


def export(threads):
    """The scene as the engine syncs it (a Frame), and the native module."""
    from whitted.native import load_native
    from whitted.sync.frame import sync_frame

    scene = bpy.context.scene
    if threads:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    native = load_native()
    return native, sync_frame(bpy.context.evaluated_depsgraph_get(), native)


def render(native, frame, settings, record_stride=0):
    job = frame.job(native, settings, record_stride=record_stride)
    job.start()
    while not job.wait(1.0):
        pass
    return job


def main():
    args = parse_args()
    native, frame = export(args.threads)
    settings = frame.settings
    render(native, frame, settings)  # warm-up: page in the BVHs, start the threads once
    ours = []
    for _ in range(args.repeats):
        stats = render(native, frame, settings).stats()
        ours.append((stats["rays"]["total"], stats["trace_seconds"], stats["threads"]))
    rays_per_render = ours[0][0]
    if args.renders_only:
        return
    # The same renders without camera-ray packets: what the packets buy.
    settings.packets = False
    single = []
    for _ in range(args.repeats):
        stats = render(native, frame, settings).stats()
        single.append(stats["rays"]["total"] / stats["trace_seconds"])
    settings.packets = True
    stride = max(1, math.ceil(rays_per_render / args.max_recorded))
    started = time.perf_counter()
    recorded = render(native, frame, settings, record_stride=stride)
    record_seconds = time.perf_counter() - started
    bare = [recorded.trace_bare() for _ in range(args.repeats)]

    whitted_rps = statistics.median(rays / seconds for rays, seconds, _ in ours)
    embree_rps = statistics.median(b["rays"] / b["seconds"] for b in bare)
    result = {
        "blender": bpy.app.version_string,
        "threads": ours[0][2],
        "width": settings.width,
        "height": settings.height,
        "rays_per_render": rays_per_render,
        "whitted_trace_seconds": statistics.median(s for _, s, _ in ours),
        "whitted_rays_per_second": whitted_rps,
        # Without camera-ray packets (Settings.packets off), in the same run.
        "whitted_single_ray_rays_per_second": statistics.median(single),
        "record_stride": stride,
        "recorded_rays": bare[0]["rays"],
        "record_render_seconds": record_seconds,
        "embree_seconds": statistics.median(b["seconds"] for b in bare),
        "embree_rays_per_second": embree_rps,
        "efficiency": whitted_rps / embree_rps,
        "repeats": args.repeats,
    }
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(result, out, indent=2)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
