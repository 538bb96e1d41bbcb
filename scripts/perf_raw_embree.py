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
4. The recording kept what each query found, so the recorded pixels are rendered again
   `repeats` times with every query answered from it instead of Embree
   (RenderJob.replay(): traversal stubbed out, each worker the tiles it took): the
   shading's rays per second, on the same rays as step 3. 1 / that rate is the shading's
   cost per ray, 1 / Embree's the traversal's. An add-on built before replays existed
   (bench_performance.py --before) gives no such figure.

Efficiency = ours / Embree's, medians of the repeats. Above 1 would mean we trace
faster than single-ray Embree (packets); below, the gap is our shading and overhead.
"""

import argparse
import hashlib
import json
import math
import os
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


def finish(job):
    job.start()
    while not job.wait(1.0):
        pass
    return job


def render(native, frame, settings, **recording):
    return finish(frame.job(native, settings, **recording))


def image_sha256(job):
    """SHA-256 of a finished job's float32 RGBA pixels: equal digests, the same image to
    the bit (the page compares the builds, and packets on and off, with it)."""
    return hashlib.sha256(job.image().tobytes()).hexdigest()


def stubbed(recorded, repeats):
    """Rays per second of the recorded pixels rendered again with every query answered
    from the recording (the median of `repeats` replays), and the rays of one; (None,
    None) with a module that cannot replay."""
    if not hasattr(recorded, "replay"):
        return None, None
    replays = [finish(recorded.replay()).stats() for _ in range(repeats)]
    rate = statistics.median(r["rays"]["total"] / r["trace_seconds"] for r in replays)
    return rate, replays[0]["rays"]["total"]


def main():
    args = parse_args()
    native, frame = export(args.threads)
    settings = frame.settings
    render(native, frame, settings)  # warm-up: page in the BVHs, start the threads once
    ours = []
    for _ in range(args.repeats):
        job = render(native, frame, settings)
        stats = job.stats()
        ours.append((stats["rays"]["total"], stats["trace_seconds"], stats["threads"]))
    image = image_sha256(job)
    chosen = job.stats()  # the packet choice of the renders with packets on
    rays_per_render = ours[0][0]
    if args.renders_only:
        return
    # The same renders without camera-ray packets: what the packets buy.
    settings.packets = False
    single = []
    for _ in range(args.repeats):
        job = render(native, frame, settings)
        stats = job.stats()
        single.append(stats["rays"]["total"] / stats["trace_seconds"])
    single_image = image_sha256(job)
    settings.packets = True
    stride = max(1, math.ceil(rays_per_render / args.max_recorded))
    # With what each query found, for the replays, where the module can replay.
    results = {"record_results": True} if hasattr(native.RenderJob, "replay") else {}
    started = time.perf_counter()
    recorded = render(native, frame, settings, record_stride=stride, **results)
    record_seconds = time.perf_counter() - started
    bare = [recorded.trace_bare() for _ in range(args.repeats)]
    stubbed_rps, stubbed_rays = stubbed(recorded, args.repeats)

    whitted_rps = statistics.median(rays / seconds for rays, seconds, _ in ours)
    embree_rps = statistics.median(b["rays"] / b["seconds"] for b in bare)
    result = {
        "blender": bpy.app.version_string,
        "native_module": os.path.realpath(native.__file__),  # which add-on's build ran
        "threads": ours[0][2],
        "width": settings.width,
        "height": settings.height,
        "rays_per_render": rays_per_render,
        "whitted_trace_seconds": statistics.median(s for _, s, _ in ours),
        "whitted_rays_per_second": whitted_rps,
        # Whether the render sent each pixel's camera rays as a packet (Settings.packets
        # on: where the scene suits them), and the estimate that chose it.
        # (Builds before the choice always sent packets.)
        "camera_packets": chosen.get("camera_packets", True),
        "instances_per_pixel": chosen.get("instances_per_pixel"),
        # Without camera-ray packets (Settings.packets off), in the same run.
        "whitted_single_ray_rays_per_second": statistics.median(single),
        "image_sha256": image,  # packets on
        "single_ray_image_sha256": single_image,  # packets off
        "record_stride": stride,
        "recorded_rays": bare[0]["rays"],
        "record_render_seconds": record_seconds,
        "embree_seconds": statistics.median(b["seconds"] for b in bare),
        "embree_rays_per_second": embree_rps,
        "efficiency": whitted_rps / embree_rps,
        # The recorded pixels with traversal stubbed out (replays): the shading alone.
        "stubbed_rays": stubbed_rays,
        "stubbed_rays_per_second": stubbed_rps,
        "repeats": args.repeats,
    }
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(result, out, indent=2)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
