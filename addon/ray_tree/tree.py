"""Tracing one pixel again and recording its ray tree, as plain data.

Pure functions of the depsgraph and the native module: no operator or UI state. The
tree is what native `RenderJob.inspect` returns (see native/python/ray_tree.cpp), with
the scene's instance keys turned back into Blender object names and a summary added.
"""

import json
from dataclasses import dataclass

from ..export.film import convert_film
from ..export.instance import instance_name
from ..export.motion import scene_frame_set
from ..properties.presets import preset
from ..settings import native_settings
from ..sync.frame import sync_frame
from ..sync.native_data import native_camera
from ..sync.scene import SceneSync, SyncParams

# Where a ray that hits nothing is drawn to: this far along its direction, in units of
# the scene's size (the distance from the origin to the farthest ray point).
MISS_LENGTH = 0.5
# Ray kinds in the order the panel lists their counts ("volume": a ray's segment inside
# media, the parent of the feelers from its scatter points; "ambient_occlusion" and "bevel":
# the rays an Ambient Occlusion node or a Bevel node traced from its parent's surface).
KINDS = (
    "camera",
    "shadow",
    "reflection",
    "refraction",
    "tir",
    "transparent",
    "glossy",
    "volume",
    "ambient_occlusion",
    "bevel",
)


def feeler_source(ray):
    """What a feeler samples: its lamp's name, the emissive object's, or "world"."""
    return "world" if ray.get("world") else ray["light"] or ray.get("emitter")


@dataclass(frozen=True)
class PixelView:
    """A 3D view to inspect instead of the scene camera: its region's size in pixels
    and the camera it renders through (viewport.session.region_camera)."""

    width: int
    height: int
    camera: object  # a viewport.camera.ViewCamera


def inspect_pixel(depsgraph, native, x, y, sample=-1, view=None):
    """The ray tree of pixel (x, y), counted from the bottom-left: of the final frame
    (the scene camera at the render resolution, the scene's quality controls), or of
    `view` (a PixelView, at the viewport's quality preset). Raises export.ExportError
    when the scene cannot be rendered, IndexError for a pixel outside the image and
    ValueError for a sample the anti-aliasing mode does not have."""
    scene = depsgraph.scene
    if view is None:
        frame = sync_frame(depsgraph, native, frame_set=scene_frame_set(scene))
        job = frame.job(native)
        source = {"source": "render", "width": frame.width, "height": frame.height}
    else:
        quality = preset(scene.whitted.viewport_preset)
        sync = SceneSync(native)
        sync.sync(depsgraph, SyncParams.of(scene, quality))
        film = convert_film(scene, view.width, view.height, region=(0, 0, view.width, view.height))
        settings = native_settings(native, scene, view.width, view.height, film, quality)
        job = native.RenderJob(sync.scene, settings, camera=native_camera(native, view.camera))
        source = {"source": "viewport", "width": view.width, "height": view.height}
    tree = job.inspect(x, y, sample)
    names = _object_names(depsgraph, {ray["object"] for ray in tree["rays"]} - {None})
    for index, ray in enumerate(tree["rays"]):
        ray["id"] = index
        key = ray["object"]
        ray["instance"] = key if key is not None and names.get(key) != key else None
        ray["object"] = names.get(key, key)
    tree.update(source, x=x, y=y, sample=sample)
    tree["summary"] = summarise(tree)
    return tree


def _object_names(depsgraph, keys):
    """Blender object name of each native instance key (export/instance.py): a real
    object is keyed by its own name, an instance by its instancer's and its own."""
    names = {}
    wanted = set(keys)
    for object_instance in depsgraph.object_instances:
        if not wanted:
            break
        key = instance_name(object_instance)
        if key in wanted:
            names[key] = object_instance.object.original.name_full
            wanted.discard(key)
    return names


def _luminance(rgb):
    # Rec. 709 weights: how much of the pixel's brightness a term is.
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def summarise(tree):
    """What each depth of the tree adds to the pixel, and what was cut.

    `depths[d]` is the summed contribution of the rays at depth d (a feeler counts at
    the depth of the surface it leaves); `cut` counts the rays the depth limit and the
    cutoff stopped, with the largest weight on the pixel among them (a bound on the
    light each could still have brought, relative to its radiance)."""
    rays = tree["rays"]
    depth_count = 1 + max((ray["depth"] for ray in rays), default=0)
    depths = [[0.0, 0.0, 0.0] for _ in range(depth_count)]
    for ray in rays:
        for c in range(3):
            depths[ray["depth"]][c] += ray["contribution"][c]
    cut = {}
    for reason in ("depth", "cutoff"):
        stopped = [ray for ray in rays if ray["cut"] == reason]
        cut[reason] = {
            "rays": len(stopped),
            "max_weight": max((max(ray["weight"]) for ray in stopped), default=0.0),
        }
    counts = {kind: sum(ray["kind"] == kind for ray in rays) for kind in KINDS}
    blocked = sum(ray["blocked"] is True for ray in rays)
    return {
        "depths": depths,
        "cut": cut,
        "counts": counts,
        "blocked_feelers": blocked,
        "media": _media(rays),
        "text": summary_text(tree["pixel"], depths, cut),
    }


def _media(rays):
    """What the segments in media add: their count, the feelers sent from their scatter
    points, the points their programs ran at, and their emission and scattered light."""
    segments = [ray for ray in rays if ray["kind"] == "volume"]
    feelers = [ray for ray in rays if ray.get("scatter")]
    return {
        "segments": len(segments),
        "feelers": sum(ray["cut"] is None for ray in feelers),
        "steps": sum(ray["steps"] for ray in segments),
        "emission": [sum(ray["emission"][c] for ray in segments) for c in range(3)],
        "scattered": [sum(ray["contribution"][c] for ray in feelers) for c in range(3)],
    }


def summary_text(pixel, depths, cut):
    """One line: each depth's share of the pixel's luminance, and what was cut."""
    total = _luminance(pixel)
    if total > 0.0:
        shares = ", ".join(
            f"depth {d} {100.0 * _luminance(rgb) / total:.1f}%" for d, rgb in enumerate(depths)
        )
    else:
        shares = "a black pixel"
    stopped = [
        f"{info['rays']} by the {label} (weight <= {info['max_weight']:.3g})"
        for reason, label in (("depth", "depth limit"), ("cutoff", "cutoff"))
        if (info := cut[reason])["rays"]
    ]
    return f"{shares}; cut: {', '.join(stopped) if stopped else 'nothing'}"


def segments(tree):
    """The tree as line segments for drawing: (kind, start, end, weight, blocked) per
    ray that was traced, a segment in media along its ray; a ray that hits nothing ends a
    scene-sized length along its direction, a feeler to the sun likewise."""
    rays = [ray for ray in tree["rays"] if ray["cut"] not in ("depth", "cutoff")]
    points = [ray["origin"] for ray in rays] + [ray["end"] for ray in rays if ray["end"]]
    extent = max((sum(c * c for c in p) ** 0.5 for p in points), default=1.0)
    length = max(1.0, MISS_LENGTH * 2.0 * extent)
    out = []
    for ray in rays:
        if ray["kind"] == "shadow" and ray["cut"] is not None:
            continue  # no feeler was sent
        origin, direction = ray["origin"], ray["direction"]
        end = ray["end"] or [o + length * d for o, d in zip(origin, direction, strict=True)]
        out.append(
            (
                ray["kind"],
                tuple(ray["origin"]),
                tuple(end),
                max(ray["weight"]),
                ray["blocked"] is True,
            )
        )
    return out


def dumps(tree):
    return json.dumps(tree, separators=(",", ":"))


def loads(text):
    """The stored tree, or None when there is none (or it cannot be read)."""
    if not text:
        return None
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return None
