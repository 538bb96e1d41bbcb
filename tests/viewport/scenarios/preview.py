"""Material previews rendered by Whitted (bl_use_preview): --result/--out only.

Two materials, each previewed in turn with ed.lib_id_generate_preview (the
operator behind "Generate Preview"; it starts the same preview job as the
Material Properties panel, and it kills other preview jobs, hence one at a time):

* "Red": Principled Base Color red;
* "Override": Base Color blue in the nodes, but the Whitted override set to red. Only
  Whitted reads the override, so a red preview shows Whitted rendered it (no other
  engine stands in: without bl_use_preview Blender leaves the preview empty).

For each, the mean colour of the covered pixels (alpha > 0.5) and the coverage, and
what the preview renders made of Blender's preview scene's world: the native scene's
world light ({on, why, map, bytes}) and the world feelers the renders sent, read from
the frames the engine synced (its sync_frame wrapped for the scenario's length).
"""

import time

import bpy
import numpy as np
import whitted.engine
from whitted_tools import viewport_driver as driver

RED = (0.8, 0.03, 0.03, 1.0)
BLUE = (0.03, 0.1, 0.8, 1.0)


def material(name, base_color):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    principled = material.node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = base_color
    material.diffuse_color = base_color
    return material


def preview_pixels(material):
    preview = material.preview
    if preview is None or preview.image_size[0] == 0:
        return None
    pixels = np.array(preview.image_pixels_float[:], dtype=np.float32)
    return pixels.reshape(-1, 4)


def settled(material, state):
    """True once the preview has pixels and has not changed for 1 s (jobs are progressive)."""
    pixels = preview_pixels(material)
    if pixels is None or not pixels[:, 3].any():
        return False
    checksum = float(pixels.sum())
    now = time.perf_counter()
    if state.get("checksum") != checksum:
        state.update(checksum=checksum, since=now)
        return False
    return now - state["since"] > 1.0


def add_arguments(parser):
    # Another engine proves the scenario itself (tests/viewport uses WHITTED).
    parser.add_argument("--engine", default="WHITTED")


def scenario(h):
    scene = bpy.context.scene
    scene.render.engine = h.args.engine
    red = material("Red", RED)
    override = material("Override", BLUE)
    override.whitted.use_override = True  # copies the derived (blue) values first
    override.whitted.diffuse_color = RED[:3]
    override.whitted.diffuse_weight = 1.0
    # Every frame the engine renders, with its job: (frame, job).
    renders = []
    synced = whitted.engine.sync_frame

    def sync_and_keep(*args, **kwargs):
        frame = synced(*args, **kwargs)
        make_job = frame.job

        def job(*job_args, **job_kwargs):
            started = make_job(*job_args, **job_kwargs)
            renders.append((frame, started))
            return started

        frame.job = job
        return frame

    whitted.engine.sync_frame = sync_and_keep
    try:
        yield 0.5
        for item in (red, override):
            h.step(f"preview {item.name}")
            first = len(renders)
            with bpy.context.temp_override(window=bpy.context.window_manager.windows[0], id=item):
                bpy.ops.ed.lib_id_generate_preview()
            state = {}
            yield h.until(lambda item=item, state=state: settled(item, state), 60.0, item.name)
            pixels = preview_pixels(item)
            covered = pixels[pixels[:, 3] > 0.5]
            previews = renders[first:]
            h.record(
                item.name,
                {
                    "size": list(item.preview.image_size),
                    "coverage": float(len(covered) / len(pixels)),
                    "mean_rgb": covered[:, :3].mean(axis=0).tolist() if len(covered) else None,
                    "renders": len(previews),
                    "world_light": [frame.sync.scene.world_light for frame, _ in previews],
                    "world_feelers": [job.stats()["world_feelers"] for _, job in previews],
                },
            )
    finally:
        whitted.engine.sync_frame = synced


driver.main(scenario, add_arguments)
