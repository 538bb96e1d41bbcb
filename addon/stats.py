"""Render statistics: per-phase times, ray counts, samples and peak memory, for
the status line and JSON.

Headless and farm renders write them as JSON to the file named by the environment
variable WHITTED_STATS (overwritten by each frame); the last render's JSON is
also kept in `scene.whitted.last_stats`.
"""

import json
import os
import resource
from dataclasses import asdict, dataclass


@dataclass
class PhaseTimes:
    """Wall-clock seconds of each phase of one render."""

    export: float = 0.0  # Blender data -> native scene, less the mesh BVH builds
    mesh_bvh: float = 0.0  # per-mesh BVHs, built as meshes are set
    scene_bvh: float = 0.0  # name resolution and the top-level BVH of instances
    world_light: float = 0.0  # the world light's importance map (built once per world)
    trace: float = 0.0  # worker threads, first tile to last
    writeback: float = 0.0  # tiles into Blender's render result
    denoise: float = 0.0  # Open Image Denoise on the finished image (addon/denoise.py)
    total: float = 0.0  # the engine's render() call


def peak_memory_mib():
    """Peak resident memory of this (Blender's) process so far, MiB (Linux: ru_maxrss
    is in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def render_stats(blender_version, quality, settings, native_stats, phases, sanitised, passes):
    """One render's statistics as plain data (what WHITTED_STATS files hold).

    `quality` is the properties.presets.Quality rendered, `settings` the native
    Settings (image size). `sanitised` counts the bad geometry the exporter
    dropped or repaired (export.mesh.Sanitised as a dict: triangles and corner
    normals). `passes` names the render passes written back.
    """
    rays = dict(native_stats["rays"])
    trace = phases.trace
    pixels = native_stats["pixels"]
    return {
        "blender": blender_version,
        "settings": {
            "width": settings.width,
            "height": settings.height,
            **asdict(quality),
            "pixel_filter": settings.pixel_filter.name,
            "filter_width": settings.filter_width,
            "seed": settings.seed,
        },
        "threads": native_stats["threads"],
        "triangles": native_stats["triangles"],
        "curve_segments": native_stats["curve_segments"],
        "points": native_stats["points"],
        "instances": native_stats["instances"],
        "lights": native_stats["lights"],
        "cancelled": native_stats["cancelled"],
        "phases": {
            "export": phases.export,
            "mesh_bvh": phases.mesh_bvh,
            "scene_bvh": phases.scene_bvh,
            "world_light": phases.world_light,
            "trace": trace,
            "writeback": phases.writeback,  # all of `passes`
            "denoise": phases.denoise,
            "total": phases.total,
        },
        "passes": list(passes),
        "rays": rays,
        "rays_per_second": rays["total"] / trace if trace > 0.0 else 0.0,
        "total_internal_reflections": native_stats["total_internal_reflections"],
        # Rays not traced: beyond the max depth, and with a weight below the cutoff.
        "depth_limited": native_stats["depth_limited"],
        "cutoff_skipped": native_stats["cutoff_skipped"],
        # Shadow feelers not sent, by reason (backfacing, unlit, below the cutoff).
        "shadow_rays_skipped": dict(native_stats["shadow_rays_skipped"]),
        # Light samples drawn towards the world where it lights the scene (native
        # scene/world_light.h); their shadow feelers are among rays["shadow"].
        "world_feelers": native_stats["world_feelers"],
        # Feelers to the lamps, emitters and world from points inside a medium (native
        # integrator/volume.h), among rays["shadow"] too; the queries that walked shadow
        # feelers through volume bounds (transmittance.h) and the rays going on behind the
        # bounds they crossed (kernel.h), together rays["volume"]; all 0 without media.
        "volume_feelers": native_stats["volume_feelers"],
        "volume_queries": native_stats["volume_queries"],
        "volume_bounds": native_stats["volume_bounds"],
        # Points a heterogeneous medium's program ran at (its march's steps, native
        # integrator/heterogeneous.h and march.h); 0 without such media.
        "volume_steps": native_stats["volume_steps"],
        # Whether each pixel's camera rays went to Embree as one packet, and the instances
        # in view that chose it (packets up to one per 500 pixels: native sampler.h,
        # choose_packets).
        "camera_packets": {
            "on": native_stats["camera_packets"],
            "visible_instances": native_stats["visible_instances"],
            "instances_per_pixel": native_stats["instances_per_pixel"],
        },
        # Whether pixels were traced in waves (Settings.waves, native integrator/wave.h),
        # and the most memory one worker's wave queues held, in bytes.
        "waves": {"on": native_stats["waves"], "queue_bytes": native_stats["wave_bytes"]},
        # What the scene analysis simulated and skipped: {name, on, why} per effect.
        "effects": [dict(decision) for decision in native_stats["effects"]],
        # Camera samples; adaptive anti-aliasing takes a different number per pixel.
        "samples": native_stats["samples"],
        "pixels": pixels,
        "samples_per_pixel": native_stats["samples"] / pixels if pixels else 0.0,
        # Camera samples per pixel over the border (min, mean, max): a noise threshold
        # stops each pixel apart; and the pixels still noisy at its last check.
        "pixel_samples": _pixel_samples(quality, native_stats),
        "noisy_pixels": native_stats["active_pixels"],
        # The final per-pixel noise estimate (mean, max; Cycles' metric, which a noise
        # threshold t holds below 5 t), under a noise threshold; and whether the time
        # limit ended the sampling.
        "noise": dict(native_stats.get("noise", {})),
        "time_limited": native_stats["time_limited"],
        "peak_memory_mib": peak_memory_mib(),
        "nonfinite_samples": native_stats["nonfinite_samples"],
        "sanitised": dict(sanitised),
    }


def _pixel_samples(quality, native_stats):
    """{min, mean, max} camera samples per pixel: the film counts them under a noise
    threshold; a fixed grid takes n x n everywhere; Whitted's adaptive anti-aliasing
    counts its total only (min and max None)."""
    if quality.adaptive_sampling:
        return dict(zip(("min", "mean", "max"), native_stats["samples_per_pixel"], strict=True))
    pixels = native_stats["pixels"]
    mean = native_stats["samples"] / pixels if pixels else 0.0
    if quality.aa_mode == "ADAPTIVE":
        return {"min": None, "mean": mean, "max": None}
    return {"min": quality.aa_samples**2, "mean": mean, "max": quality.aa_samples**2}


def sampling_decision(stats):
    """The effects report's entry for the noise threshold ({name, on, why}): the samples a
    pixel took, and the pixels still noisy when they reached the most (or the time limit
    ended the sampling)."""
    settings = stats["settings"]
    if not settings["adaptive_sampling"]:
        return {"name": "noise threshold", "on": False, "why": "off: every pixel takes the grid"}
    samples = stats["pixel_samples"]
    why = (
        f"{settings['noise_threshold']:g}: {samples['mean']:.1f} samples per pixel "
        f"({samples['min']:.0f} to {samples['max']:.0f})"
    )
    if stats["noisy_pixels"]:
        ended = "the time limit" if stats["time_limited"] else "the most samples"
        why += f"; {stats['noisy_pixels']:,} pixels still noisy at {ended}"
    return {"name": "noise threshold", "on": True, "why": why}


def _most(stats):
    most = stats["pixel_samples"]["max"]
    return "?" if most is None else f"{most:.0f}"


def summary_line(stats):
    """A one-line summary for Blender's status bar and the log."""
    p = stats["phases"]
    media = media_text(stats)
    return (
        f"Whitted | {stats['settings']['width']}x{stats['settings']['height']} "
        f"in {p['total']:.2f} s (export {p['export']:.2f}, BVH "
        f"{p['mesh_bvh'] + p['scene_bvh']:.2f}, world map {p['world_light']:.2f}, trace "
        f"{p['trace']:.2f}, write-back "
        f"{p['writeback']:.3f}, denoise {p['denoise']:.2f}) | {_rays_line(stats['rays'])}, "
        f"{stats['rays_per_second'] / 1e6:.1f} M rays/s on {stats['threads']} threads "
        f"| {stats['samples_per_pixel']:.1f} samples/px (max {_most(stats)}) "
        f"| cut: depth {stats['depth_limited']}, "
        f"cutoff {stats['cutoff_skipped']} | TIR {stats['total_internal_reflections']} "
        f"{media and f'| {media} '}| peak {stats['peak_memory_mib']:.0f} MiB"
    )


def media_text(stats):
    """What media cost, for the summary line and the Last Render panel: their feelers,
    the rays through their bounds and the points their programs ran at; "" in a render
    without media (or statistics saved before media were counted)."""
    feelers = stats.get("volume_feelers", 0)
    rays = stats["rays"].get("volume", 0)
    steps = stats.get("volume_steps", 0)
    if not (feelers or rays or steps):
        return ""
    return (
        f"media: {feelers / 1e6:.2f} M feelers, {rays / 1e6:.2f} M rays through bounds, "
        f"{steps / 1e6:.2f} M steps"
    )


def effects_line(stats):
    """What the render simulated and what it skipped, and why, in one line.

    From the native scene analysis ({"name": "refraction", "on": False, "why": "no
    transmissive material"}) and the shadow feelers not sent, by reason.
    """
    simulated = []
    skipped = []
    for effect in stats["effects"]:
        (simulated if effect["on"] else skipped).append(f"{effect['name']} ({effect['why']})")
    feelers = stats["shadow_rays_skipped"]
    considered = stats["rays"]["shadow"] + sum(feelers.values())

    def share(count):
        return f"{count / considered:.0%}" if considered else "0%"

    return (
        f"Whitted simulated: {', '.join(simulated) or 'nothing'} | skipped: "
        f"{', '.join(skipped) or 'nothing'} | shadow rays: {share(sum(feelers.values()))} "
        f"skipped (light behind surface {share(feelers['backfacing'])}, no light arrives "
        f"{share(feelers['unlit'])}, below cutoff {share(feelers['cutoff'])})"
    )


def progress_line(native_stats, seconds):
    """The status line while rendering: rays so far, their rate, samples per pixel."""
    rays = native_stats["rays"]["total"]
    rate = rays / seconds / 1e6 if seconds > 0.0 else 0.0
    pixels = native_stats["pixels"]
    per_pixel = native_stats["samples"] / pixels if pixels else 0.0
    return (
        f"Whitted | {native_stats['threads']} threads | {rays / 1e6:.1f} M rays "
        f"| {rate:.1f} M rays/s | {per_pixel:.1f} samples/px | {seconds:.1f} s "
        f"| peak {peak_memory_mib():.0f} MiB"
    )


def _rays_line(rays):
    return (
        f"{rays['total'] / 1e6:.2f} M rays (camera {rays['camera'] / 1e6:.2f}, shadow "
        f"{rays['shadow'] / 1e6:.2f}, reflection {rays['reflection'] / 1e6:.2f}, refraction "
        f"{rays['refraction'] / 1e6:.2f}, glossy {rays['glossy'] / 1e6:.2f}, transparent "
        f"{rays['transparent'] / 1e6:.2f}{_program_rays_text(rays)})"
    )


# The rays shader programs trace (native RayCounts), by the name the statistics give them.
PROGRAM_RAYS = {"ambient_occlusion": "ambient occlusion", "bevel": "bevel"}


def _program_rays_text(rays):
    """ ", ambient occlusion 0.12, bevel 0.03" (M rays) for the kinds a render traced; ""
    without them (or in statistics saved before they were counted)."""
    return "".join(
        f", {label} {rays[kind] / 1e6:.2f}"
        for kind, label in PROGRAM_RAYS.items()
        if rays.get(kind)
    )


def to_json(stats):
    return json.dumps(stats, indent=2)


def write_json(path, stats):
    # Atomically: a reader (a farm) never sees a half-written file.
    partial = f"{path}.{os.getpid()}.partial"
    with open(partial, "w", encoding="utf-8") as out:
        out.write(to_json(stats))
    os.replace(partial, path)
