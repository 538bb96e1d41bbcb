"""Render statistics: per-phase times and ray counts, for the status line and JSON.

Headless and farm renders write them as JSON to the file named by the environment
variable WHITTED_STATS (overwritten by each frame).
"""

import json
from dataclasses import dataclass


@dataclass
class PhaseTimes:
    """Wall-clock seconds of each phase of one render."""

    export: float = 0.0  # Blender data -> native scene, less the mesh BVH builds
    mesh_bvh: float = 0.0  # per-mesh BVHs, built as meshes are set
    scene_bvh: float = 0.0  # name resolution and the top-level BVH of instances
    trace: float = 0.0  # worker threads, first tile to last
    writeback: float = 0.0  # tiles into Blender's render result
    total: float = 0.0  # the engine's render() call


def render_stats(blender_version, settings, native_stats, phases, sanitised):
    """One render's statistics as plain data (what WHITTED_STATS files hold).

    `sanitised` counts the bad geometry the exporter dropped or repaired
    (export.mesh.Sanitised as a dict: triangles and corner normals).
    """
    rays = dict(native_stats["rays"])
    trace = phases.trace
    return {
        "blender": blender_version,
        "settings": {
            "width": settings.width,
            "height": settings.height,
            "max_depth": settings.max_depth,
            "aa_samples": settings.aa_samples,
            "fresnel": settings.fresnel.name,
        },
        "threads": native_stats["threads"],
        "triangles": native_stats["triangles"],
        "instances": native_stats["instances"],
        "lights": native_stats["lights"],
        "cancelled": native_stats["cancelled"],
        "phases": {
            "export": phases.export,
            "mesh_bvh": phases.mesh_bvh,
            "scene_bvh": phases.scene_bvh,
            "trace": trace,
            "writeback": phases.writeback,
            "total": phases.total,
        },
        "rays": rays,
        "rays_per_second": rays["total"] / trace if trace > 0.0 else 0.0,
        "total_internal_reflections": native_stats["total_internal_reflections"],
        "depth_limited": native_stats["depth_limited"],
        "nonfinite_samples": native_stats["nonfinite_samples"],
        "sanitised": dict(sanitised),
    }


def summary_line(stats):
    """A one-line summary for Blender's status bar and the log."""
    p = stats["phases"]
    return (
        f"Whitted | {stats['settings']['width']}x{stats['settings']['height']} "
        f"in {p['total']:.2f} s (export {p['export']:.2f}, BVH "
        f"{p['mesh_bvh'] + p['scene_bvh']:.2f}, trace {p['trace']:.2f}, write-back "
        f"{p['writeback']:.3f}) | {stats['rays']['total'] / 1e6:.2f} M rays, "
        f"{stats['rays_per_second'] / 1e6:.1f} M rays/s on {stats['threads']} threads"
    )


def write_json(path, stats):
    with open(path, "w", encoding="utf-8") as out:
        json.dump(stats, out, indent=2)
