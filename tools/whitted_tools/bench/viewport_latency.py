"""How fast the Whitted viewport answers an edit (whitted_tools bench-viewport runs this).

The demo in camera view, Rendered; after each edit, from the viewport's event log:
the time from the start of the sync (view_update) to the first view_draw that shows
a pass of the new state, and to the one that shows the full-resolution pass at one
sample per pixel. Then, once converged, the CPU time Blender uses while nothing
changes, and the frames drawn meanwhile (none expected).
"""

import resource
import time

import bpy

from whitted_tools import viewport_driver as driver

REPEATS = 3
IDLE_SECONDS = 3.0


def _cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)  # every thread of Blender
    return usage.ru_utime + usage.ru_stime


def _latency(events, mark):
    """(sync ms, first image ms, its pixel size, full resolution 1 spp ms) after `mark`."""
    after = events[mark:]
    sync = next(e for e in after if e["event"] == "sync")
    started = sync["t"] - sync["seconds"]
    frames = [e for e in after if e["event"] == "frame" and e["t"] >= sync["t"]]
    first = frames[0]
    full = next(e for e in frames if e["pixel_size"] == 1)

    def drawn(frame):
        return next(
            e["t"]
            for e in after
            if e["event"] == "draw" and e["frame"] >= frame["frame"] and e["t"] >= frame["t"]
        )

    return (
        1000.0 * sync["seconds"],
        1000.0 * (drawn(first) - started),
        first["pixel_size"],
        1000.0 * (drawn(full) - started),
    )


def scenario(h):
    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    yield h.maximise()
    h.setup_view("SOLID")
    yield 0.5
    h.record("region", [h.region.width, h.region.height])
    mark = h.log.mark()
    h.set_shading("RENDERED")
    yield h.until_converged(mark)
    cube = bpy.data.objects["Cube"]
    material = bpy.data.materials["Diffuse Blue"]
    principled = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    light = bpy.data.objects["Point Light"].data
    changes = {
        "move": lambda i: setattr(cube.location, "z", cube.location.z + (0.2 if i % 2 else -0.2)),
        "material": lambda i: setattr(
            principled.inputs["Base Color"], "default_value", (0.1 + 0.2 * (i % 2), 0.3, 0.8, 1)
        ),
        "light": lambda i: setattr(light, "energy", light.energy * (1.5 if i % 2 else 0.7)),
    }
    edits = []
    for name, change in changes.items():
        for i in range(REPEATS):
            mark = h.log.mark()
            h.step(f"edit {name} {i}")
            change(i)
            yield h.until_converged(mark)
            sync_ms, first_ms, pixel_size, full_ms = _latency(h.log.poll(), mark)
            edits.append(
                {
                    "name": name,
                    "sync_ms": sync_ms,
                    "first_ms": first_ms,
                    "first_pixel_size": pixel_size,
                    "full_ms": full_ms,
                }
            )
    h.record("edits", edits)
    mark = h.log.mark()
    cpu = _cpu_seconds()
    started = time.perf_counter()
    yield IDLE_SECONDS
    seconds = time.perf_counter() - started
    drawn = [e for e in h.log.poll()[mark:] if e["event"] in ("frame", "draw")]
    h.record(
        "idle",
        {
            "seconds": seconds,
            "cpu_percent": 100.0 * (_cpu_seconds() - cpu) / seconds,
            "frames": len(drawn),
        },
    )


driver.main(scenario)
