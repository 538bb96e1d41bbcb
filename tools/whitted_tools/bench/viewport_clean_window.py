"""The viewport's time to a clean image after an edit, in one Blender 3.4 window
(whitted_tools bench-viewport-clean runs this under Xvfb; the figures are computed
outside Blender from the captures it saves).

The 3D view fills the window in camera view, Rendered, without overlays or gizmos.
For each repeat and, within it, each row in turn (Cycles, Whitted, Whitted with its
viewport denoise): the row's engine renders the scene with the edited object at its
start position for a moment, then the object moves a little (the edit) and the area
is captured (screen.screenshot_area, what the window last drew) at times growing from
every 0.1 s, until Whitted's viewport log says it is done, or the time limit (Cycles
gives no sign: Blender 3.4's Python cannot read its viewport's sample count). Then each
engine's reference: the same edit with the converged settings (Cycles' 1024 viewport
samples without adaptive sampling, Whitted's Reference preset as the viewport preset),
let run long; its last capture counts.
"""

import hashlib
import os
import time
from functools import partial

import bpy

from whitted_tools import viewport_driver as driver
from whitted_tools.blender import SEED_QUALITY
from whitted_tools.cycles_scenes import set_cycles_reference

# (row, engine, Whitted's viewport denoise)
ROWS = (
    ("cycles", "CYCLES", False),
    ("whitted", "WHITTED", False),
    ("whitted_denoised", "WHITTED", True),
)
REFERENCES = (("cycles", "CYCLES"), ("whitted", "WHITTED"))
# Whitted's converged viewport: the Reference preset; Cycles': 1024 viewport samples
# (its default) with adaptive sampling off.
WHITTED_REFERENCE_PRESET = "REFERENCE"
CYCLES_REFERENCE_SAMPLES = 1024
# Cycles traces what Whitted does: glossy, transmission and transparent bounces, no
# diffuse or volume bounce (cycles_scenes.set_cycles_reference).
SPECULAR_BOUNCES = 8
MOVE = 0.1  # the edit: the object moves this far along x
# Capture times: every FIRST_INTERVAL at first, then a tenth of the time since the
# edit, at most MAX_INTERVAL apart.
FIRST_INTERVAL = 0.1
GROWTH = 0.1
MAX_INTERVAL = 1.0
# Cycles' reference is done when the captures stop changing for this long: its display
# updates came 2 to 5 s apart after the first 10 s (on a loaded 2-core machine).
CYCLES_STABLE_SECONDS = 30.0


def add_arguments(parser):
    parser.add_argument("--edited", required=True, help="the object the edit moves")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--limit", type=float, default=30.0, help="seconds per edit")
    parser.add_argument("--reference-limit", type=float, default=240.0)
    parser.add_argument("--before", type=float, default=2.0, help="seconds before an edit")


def new_scene_settings(scene):
    """Whitted's settings as a new scene has them (the scene builders use SEED_QUALITY),
    Cycles' viewport at its defaults with the bounces limited, without denoising."""
    for name in SEED_QUALITY:
        scene.whitted.property_unset(name)
    for name in ("viewport_preset", "filter_width"):
        scene.whitted.property_unset(name)
    set_cycles_reference(scene, scene.cycles.samples, specular_bounces=SPECULAR_BOUNCES)
    scene.cycles.use_preview_denoising = False
    scene.cycles.preview_samples = CYCLES_REFERENCE_SAMPLES
    cycles = scene.cycles
    return {
        "whitted_viewport_preset": scene.whitted.viewport_preset,
        "whitted_pixel_filter": [scene.whitted.pixel_filter_type, scene.whitted.filter_width],
        "cycles_preview_samples": cycles.preview_samples,
        "cycles_preview_adaptive": cycles.use_preview_adaptive_sampling,
        "cycles_preview_adaptive_threshold": cycles.preview_adaptive_threshold,
        "cycles_pixel_filter": [cycles.pixel_filter_type, cycles.filter_width],
        "view_transform": scene.view_settings.view_transform,
    }


def capture(h, path):
    """The area as the window last drew it, saved to `path`: (seconds taken, hash)."""
    started = time.perf_counter()
    with h.override():
        result = bpy.ops.screen.screenshot_area(filepath=path)
    if result != {"FINISHED"} or not os.path.exists(path):
        raise driver.ScenarioError(f"screenshot_area returned {result} and wrote no {path}")
    with open(path, "rb") as file:
        digest = hashlib.sha1(file.read()).hexdigest()
    return time.perf_counter() - started, digest


def whitted_done(h, mark, captures, denoised):
    """The Whitted viewport converged after `mark` (and denoised, if asked) and drew it."""
    events = h.log.poll()
    index = h.log.converged_since(mark)
    if index is None:
        return False
    if denoised:
        index = next(
            (i for i in range(index, len(events)) if events[i]["event"] == "denoised"), None
        )
        if index is None:
            return False
    return h.log.drawn_after(index)


def cycles_done(h, mark, captures):
    """The captures have shown the same image for CYCLES_STABLE_SECONDS."""
    last = captures[-1]
    first_same = last
    for previous in reversed(captures):
        if previous["hash"] != last["hash"]:
            break
        first_same = previous
    return last["t"] - first_same["t"] >= CYCLES_STABLE_SECONDS


def edit_run(h, name, obj, start, done, limit, before):
    """Render at `start` for `before` s, move `obj`, capture until done(h, mark, captures)
    (None: never) or `limit`: a generator whose run record ends in h.result["data"]["runs"]."""
    obj.location.x = start
    h.region.tag_redraw()
    yield before
    folder = os.path.join(h.out_dir, name)
    os.makedirs(folder, exist_ok=True)
    mark = h.log.mark()
    h.step(f"edit {name}")
    started = time.perf_counter()
    obj.location.x = start + MOVE
    captures = []
    next_at = 0.0
    settled = False
    while True:
        t = time.perf_counter() - started
        if t >= next_at:
            path = os.path.join(folder, f"{len(captures):04d}.png")
            seconds, digest = capture(h, path)
            captures.append({"t": t, "path": path, "hash": digest, "seconds": seconds})
            next_at = t + min(MAX_INTERVAL, max(FIRST_INTERVAL, GROWTH * t))
            settled = done is not None and done(h, mark, captures)
        if settled or t > limit:
            break
        yield 0.02
    h.result["data"]["runs"].append(
        {
            "name": name,
            "settled": settled,
            "seconds": time.perf_counter() - started,
            "captures": captures,
        }
    )


def scenario(h):
    from whitted.native import load_native  # the add-on, enabled by driver.main

    oidn = load_native().oidn_status()
    if not oidn["ok"]:
        raise driver.ScenarioError(f"Whitted's viewport Denoise cannot run: {oidn['report']}")
    scene = bpy.context.scene
    obj = bpy.data.objects[h.args.edited]
    start = obj.location.x
    h.record("settings", new_scene_settings(scene))
    h.record("runs", [])
    yield h.maximise()
    h.setup_view("SOLID")
    yield 0.5
    h.record("region", [h.region.width, h.region.height])
    h.record("camera_frame", h.camera_frame())
    h.set_shading("RENDERED")
    whitted = scene.whitted
    default_preset = whitted.viewport_preset
    for repeat in range(h.args.repeats):
        for row, engine, denoised in ROWS:
            scene.render.engine = engine
            whitted.use_viewport_denoising = denoised
            done = None
            if engine == "WHITTED":
                done = partial(whitted_done, denoised=denoised)
            yield from edit_run(h, f"{row}-{repeat}", obj, start, done, h.args.limit, h.args.before)
    whitted.use_viewport_denoising = False
    whitted.viewport_preset = WHITTED_REFERENCE_PRESET
    scene.cycles.use_preview_adaptive_sampling = False
    for row, engine in REFERENCES:
        scene.render.engine = engine
        done = cycles_done if engine == "CYCLES" else partial(whitted_done, denoised=False)
        yield from edit_run(
            h, f"{row}-reference", obj, start, done, h.args.reference_limit, h.args.before
        )
    whitted.viewport_preset = default_preset


driver.main(scenario, add_arguments)
