"""Efficiency: our rays per second over a bare Embree loop's (in Blender 3.4).

Efficiency against raw Embree: our rays per second over those of a bare Embree loop
tracing the very same rays.

Runs inside Blender (3.4, or the bpy 5.0 module) on a saved scene with the Whitted
add-on enabled:

    blender -b SCENE.blend \\
        --python tools/whitted_tools/__main__.py -- perf-raw-embree --json OUT.json \\
        [--threads N] [--repeats 3] [--max-recorded 20000000] [--preset KEY]

1. The scene is exported as the engine exports it and rendered once to warm up.
2. It is rendered once more recording the queries of every n-th pixel (n chosen so
   at most --max-recorded queries are kept), each worker thread its own list.
3. Then `repeats` rounds, each of four runs side by side:
   - a render with the recursive kernel (Settings.waves off): our rays per second are
     all rays traced (camera, shadow, reflection, refraction, cut-out continuations)
     over the trace phase, which includes shading, texture lookups and the recursion;
   - the same render with camera-ray packets off, for what the packets buy;
   - the same render traced in waves (Settings.waves, the default: the add-on's Trace
     in Waves), for what the waves buy;
   - the recorded queries traced again by a loop of single-ray
     rtcIntersect1/rtcOccluded1 calls on as many threads, with no shading and nothing
     else in the loop (SceneAccel::trace_bare): Embree's rays per second;
   - the recorded pixels rendered again with every query answered from the recording
     instead of Embree (RenderJob.replay(): traversal stubbed out, each worker the
     tiles it took): the shading's rays per second, on the same rays as the bare loop.
     1 / that rate is the shading's cost per ray, 1 / Embree's the traversal's. An
     add-on built before replays existed (bench_performance.py --before) gives no
     such figure.

--preset renders at a quality preset (properties/presets.py: DRAFT, PREVIEW, FINAL,
REFERENCE) instead of the file's own controls: adaptive anti-aliasing, the glossy,
light and emitter samples and the depth the preset sets.

Efficiency = ours / Embree's and the packet gain = ours / ours without packets, each
taken within a round and the median of the rounds' ratios: this machine's speed drifts
over minutes, and runs seconds apart drift together. Rates are medians of the rounds.
Above 1 the efficiency would say we trace faster than single-ray Embree (packets);
below, the gap is our shading and overhead.

--packets on|off renders once on one thread, camera packets on or off, for callgrind to
count what Embree spends per camera ray: the measurements behind the packet choice
(native/src/integrator/sampler.cpp, choose_packets; docs/notes/performance_reading.md):

    valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*RenderJob::trace*' \\
        blender -b --factory-startup --addons whitted SCENE.blend \\
        --python tools/whitted_tools/__main__.py -- perf-raw-embree --packets on [--lens 60] \\
        [--resolution 480 270] [--aa 1]

It prints the rays by type and the choice's inputs (instances in view per pixel). With
`callgrind_annotate --inclusive=yes`, a packet's cost per camera ray is rtcIntersect4's
instructions over the camera rays; a single ray's is rtcIntersect1's over all the rays
it traced (camera, reflection, refraction, cut-outs) of the render with packets off,
less the secondary rays' share at their cost in the render with packets on. A build
with the choice sends packets only where the scene suits them, so measuring packets
where it would not takes a build without it: 0160cf1 always sends them.
--packets compare renders with packets and without (on --threads) and prints how many
pixels differ, by how much, and where (x, y from the bottom-left, as RenderJob.inspect
takes them).

--waves on|off renders once on one thread traced in waves or recursively, for callgrind
to count each kernel's instructions by stage (docs/notes/waves.md), with the same
--resolution and --aa:

    valgrind --tool=callgrind --collect-atstart=no '--toggle-collect=whitted::RenderJob::work*' \\
        blender -b --factory-startup --addons whitted SCENE.blend \\
        --python tools/whitted_tools/__main__.py -- perf-raw-embree \\
        --waves on --resolution 160 120 --aa 2
"""

import argparse
import hashlib
import json
import math
import os
import time

import bpy

# isort: split
import numpy as np

from whitted_tools.native_job import run_job
from whitted_tools.timing import median_or_none, paired_median
from whitted_tools.verbs import prog


def parse_args(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--json", help="write the results here (required but with --packets)")
    parser.add_argument("--threads", type=int, default=0, help="0: Blender's setting")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--max-recorded", type=int, default=20_000_000)
    parser.add_argument("--preset", help="a quality preset's key, instead of the file's controls")
    parser.add_argument(
        "--renders-only",
        action="store_true",
        help="only the renders of step 1 (to profile them: the profile-trace verb)",
    )
    parser.add_argument(
        "--packets",
        choices=("on", "off", "compare"),
        help="one render with camera packets on or off on one thread (callgrind), or both "
        "compared pixel by pixel, instead of the measurements",
    )
    parser.add_argument(
        "--waves",
        choices=("on", "off"),
        help="one render traced in waves or recursively on one thread (callgrind), instead "
        "of the measurements",
    )
    parser.add_argument("--lens", type=float, help="--packets: the camera's focal length (mm)")
    parser.add_argument(
        "--resolution", nargs=2, type=int, metavar=("W", "H"), help="--packets, --waves"
    )
    parser.add_argument("--aa", type=int, help="--packets, --waves: anti-aliasing samples per axis")
    args = parser.parse_args(argv)
    if args.json is None and args.packets is None and args.waves is None:
        parser.error("--json is required (but with --packets or --waves)")
    return args


def export(threads, preset_key=None):
    """The scene as the engine syncs it (a Frame), and the native module; at the quality
    preset `preset_key` when given."""
    from whitted.native import load_native
    from whitted.properties.presets import apply_quality, preset
    from whitted.sync.frame import sync_frame

    scene = bpy.context.scene
    if preset_key:
        apply_quality(scene.whitted, preset(preset_key))
    if threads:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads
    native = load_native()
    return native, sync_frame(bpy.context.evaluated_depsgraph_get(), native)


def render(native, frame, settings, **recording):
    return run_job(frame.job(native, settings, **recording))


def image_sha256(job):
    """SHA-256 of a finished job's float32 RGBA pixels: equal digests, the same image to
    the bit (the page compares the builds, and packets on and off, with it)."""
    return hashlib.sha256(job.image().tobytes()).hexdigest()


def replay_rate(recorded):
    """Rays per second of the recorded pixels rendered again with every query answered
    from the recording, and the rays of that replay; (None, None) with a module that
    cannot replay."""
    if not hasattr(recorded, "replay"):
        return None, None
    replay = run_job(recorded.replay())
    return rate(replay), replay.stats()["rays"]["total"]


def rate(job):
    """A finished job's rays per second over its trace phase."""
    stats = job.stats()
    return stats["rays"]["total"] / stats["trace_seconds"]


def shape_scene(args):
    """--packets and --waves: the camera, resolution and samples asked for."""
    scene = bpy.context.scene
    if args.lens:
        scene.camera.data.lens = args.lens
    if args.resolution:
        scene.render.resolution_x, scene.render.resolution_y = args.resolution
    if args.aa:
        scene.whitted.aa_samples = args.aa


def one_kernel(args):
    """--waves: one render on one thread, traced in waves or recursively."""
    shape_scene(args)
    native, frame = export(1)
    frame.settings.waves = args.waves == "on"
    stats = render(native, frame, frame.settings).stats()
    print("rays:", stats["rays"], "waves:", stats["waves"])


def packets(args):
    """--packets: one render with camera packets on or off, or both compared."""
    shape_scene(args)
    # One thread for callgrind; the image is the same on any number.
    native, frame = export(args.threads if args.packets == "compare" else 1)
    settings = frame.settings
    if args.packets == "compare":
        compare_packets(native, frame, settings)
        return
    settings.packets = args.packets == "on"
    stats = render(native, frame, settings).stats()
    print("rays:", stats["rays"])
    for key in ("camera_packets", "visible_instances", "instances_per_pixel"):
        print(f"{key}:", stats.get(key, "(a build without the packet choice)"))


def compare_packets(native, frame, settings):
    """How many pixels the render with camera packets and the one without differ in."""
    settings.packets = True
    on = render(native, frame, settings).image()
    settings.packets = False
    off = render(native, frame, settings).image()
    difference = np.abs(on - off).max(axis=-1)
    rows, columns = np.nonzero(difference)
    print(f"pixels differing: {rows.size} of {difference.size}, at most {difference.max():.4g}")
    for y, x in list(zip(rows, columns, strict=True))[:10]:
        print(f"  ({x}, {y}): packets {on[y, x]}, single rays {off[y, x]}")


def render_in_waves(native, frame, settings):
    """The render traced in waves, or None with a build that has none."""
    if not hasattr(settings, "waves"):
        return None
    settings.waves = True
    try:
        return render(native, frame, settings)
    finally:
        settings.waves = False


def main(argv):
    args = parse_args(argv)
    if args.packets:
        packets(args)
        return
    if args.waves:
        one_kernel(args)
        return
    native, frame = export(args.threads, args.preset)
    settings = frame.settings
    if hasattr(settings, "waves"):
        # "Whitted" is the recursive kernel, the reference; the renders in waves, the
        # default, are measured beside it (render_in_waves).
        settings.waves = False
    warm_up = render(native, frame, settings)  # page in the BVHs, start the threads once
    chosen = warm_up.stats()  # the packet choice of the renders with packets on
    rays_per_render = chosen["rays"]["total"]
    if args.renders_only:
        for _ in range(args.repeats):
            render(native, frame, settings)
        return
    stride = max(1, math.ceil(rays_per_render / args.max_recorded))
    # With what each query found, for the replays, where the module can replay.
    results = {"record_results": True} if hasattr(native.RenderJob, "replay") else {}
    started = time.perf_counter()
    recorded = render(native, frame, settings, record_stride=stride, **results)
    record_seconds = time.perf_counter() - started
    # Rounds of the four measurements side by side, so that each ratio is taken between
    # runs a few seconds apart (this machine's speed drifts over minutes): a render, the
    # same render without camera-ray packets (what the packets buy), the bare Embree loop
    # over the recorded rays, and the replay of the recorded pixels (the shading alone).
    rounds = []
    for _ in range(args.repeats):
        job = render(native, frame, settings)
        settings.packets = False
        single_job = render(native, frame, settings)
        settings.packets = True
        wave_job = render_in_waves(native, frame, settings)
        bare = recorded.trace_bare()
        stubbed_rps, stubbed_rays = replay_rate(recorded)
        rounds.append(
            {
                "whitted": rate(job),
                "waves": rate(wave_job) if wave_job is not None else None,
                "trace_seconds": job.stats()["trace_seconds"],
                "single": rate(single_job),
                "embree": bare["rays"] / bare["seconds"],
                "embree_seconds": bare["seconds"],
                "stubbed": stubbed_rps,
            }
        )
    image = image_sha256(job)
    single_image = image_sha256(single_job)

    def median(key):
        return median_or_none(r[key] for r in rounds)

    def paired(top, bottom):
        """The median of the rounds' ratios top / bottom."""
        return paired_median([r[top] for r in rounds], [r[bottom] for r in rounds])

    result = {
        "blender": bpy.app.version_string,
        "native_module": os.path.realpath(native.__file__),  # which add-on's build ran
        "threads": chosen["threads"],
        "preset": args.preset,
        # Camera rays per pixel, and all rays per camera ray: what the preset multiplies.
        "camera_rays_per_pixel": chosen["rays"]["camera"] / (settings.width * settings.height),
        "rays_per_camera_ray": rays_per_render / max(1, chosen["rays"]["camera"]),
        "width": settings.width,
        "height": settings.height,
        "rays_per_render": rays_per_render,
        "whitted_trace_seconds": median("trace_seconds"),
        "whitted_rays_per_second": median("whitted"),
        # Whether the render sent each pixel's camera rays as a packet (Settings.packets
        # on: where the scene suits them), and the estimate that chose it.
        # (Builds before the choice always sent packets.)
        "camera_packets": chosen.get("camera_packets", True),
        "instances_per_pixel": chosen.get("instances_per_pixel"),
        # Without camera-ray packets (Settings.packets off), in the same rounds.
        "whitted_single_ray_rays_per_second": median("single"),
        "packet_gain": paired("whitted", "single"),
        "image_sha256": image,  # packets on
        "single_ray_image_sha256": single_image,  # packets off
        "record_stride": stride,
        "recorded_rays": bare["rays"],
        "record_render_seconds": record_seconds,
        "embree_seconds": median("embree_seconds"),
        "embree_rays_per_second": median("embree"),
        # Each round's Whitted rate over its bare Embree rate, the median of the rounds.
        "efficiency": paired("whitted", "embree"),
        # The same render traced in waves (Settings.waves, native integrator/wave.h), in
        # the same rounds: its rate, over the recursion's and over bare Embree's (the same
        # rays: the wave traces what the recursion does). None: a build without waves.
        "waves_rays_per_second": median_or_none(r["waves"] for r in rounds if r["waves"]),
        "waves_gain": paired("waves", "whitted") if wave_job is not None else None,
        "waves_efficiency": paired("waves", "embree") if wave_job is not None else None,
        # The recorded pixels with traversal stubbed out (replays): the shading alone.
        "stubbed_rays": stubbed_rays,
        "stubbed_rays_per_second": median("stubbed"),
        "repeats": args.repeats,
        "rounds": rounds,
    }
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(result, out, indent=2)
    print(json.dumps(result, indent=2))
