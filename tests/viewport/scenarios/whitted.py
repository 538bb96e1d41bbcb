"""The Whitted Rendered viewport in a real window: --mode compare | dof | denoise | edits |
stop.

compare: the converged camera view, and an F12 render at the camera frame's size.
denoise: the camera view with a strong depth of field at the Draft viewport preset,
         converged without denoising, then with Sampling > Viewport > Denoise.
edits:   converged screenshots before and after each of: move the cube, recolour it,
         brighten the point light, delete the cylinder (rects of the objects recorded).
stop:    leave Rendered mode once converged and once mid-render; times recorded; then
         quit Blender mid-render.

Waits use the events the viewport appends to WHITTED_VIEWPORT_LOG (see
whitted_tools/viewport_driver.py).
"""

import time

import bpy
from whitted_tools import viewport_driver as driver


def add_arguments(parser):
    parser.add_argument(
        "--mode", choices=("compare", "dof", "denoise", "edits", "stop"), required=True
    )


def start(h):
    """Maximised camera view, Whitted as engine, render size = camera frame size, Solid."""
    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    yield h.maximise()
    h.setup_view("SOLID")
    yield 0.3
    # The frame's aspect follows the render size: set it from the frame twice so the
    # second frame (drawn at the new size) is within a pixel of the render size.
    for _ in range(2):
        left, top, right, bottom = h.camera_frame()
        scene.render.resolution_x = round(right - left)
        scene.render.resolution_y = round(bottom - top)
        scene.render.resolution_percentage = 100
        h.region.tag_redraw()
        yield 0.3


def enter_rendered(h):
    mark = h.log.mark()
    h.step("shading RENDERED")
    h.set_shading("RENDERED")
    yield h.until_converged(mark)


def compare(h):
    yield from start(h)
    scene = bpy.context.scene
    h.step("F12 render")
    h.render_still("whitted_f12", scene.render.resolution_x, scene.render.resolution_y)
    yield from enter_rendered(h)
    yield from h.screenshot("whitted_rendered")


def dof(h):
    """The camera view with the camera's depth of field (as Cycles' viewport shows it),
    beside F12 renders with and without it."""
    yield from start(h)
    scene = bpy.context.scene
    camera = scene.camera
    width, height = scene.render.resolution_x, scene.render.resolution_y
    h.step("F12 renders, sharp and with depth of field")
    h.render_still("whitted_f12_sharp", width, height)
    camera.data.dof.use_dof = True
    camera.data.dof.aperture_fstop = 0.05
    # In focus 2 m in front of the scene's centre: the whole scene blurs, the far side
    # most.
    camera.data.dof.focus_distance = max(0.5, camera.matrix_world.translation.length - 2.0)
    h.render_still("whitted_f12_dof", width, height)
    yield from enter_rendered(h)
    yield from h.screenshot("whitted_dof")


def denoise(h):
    """A grainy view (depth of field at f/0.05, Draft), then the same view denoised."""
    yield from start(h)
    scene = bpy.context.scene
    camera = scene.camera
    camera.data.dof.use_dof = True
    camera.data.dof.aperture_fstop = 0.05
    camera.data.dof.focus_distance = max(0.5, camera.matrix_world.translation.length - 2.0)
    scene.whitted.viewport_preset = "DRAFT"
    scene.whitted.use_viewport_denoising = False
    yield from enter_rendered(h)
    yield from h.screenshot("whitted_noisy")
    mark = h.log.mark()
    h.step("Viewport > Denoise on")
    scene.whitted.use_viewport_denoising = True
    # A click on the checkbox redraws the window; set from a script, ask for it.
    h.region.tag_redraw()
    yield h.until(lambda: h.log.since(mark, "denoised"), 60.0, "a 'denoised' event")
    yield 0.3
    yield from h.screenshot("whitted_denoised")


def edit(h, name, change):
    """Apply change(), wait until the viewport converged on it, screenshot as NAME."""
    mark = h.log.mark()
    h.step(f"edit: {name}")
    h.record(f"t_{name}", time.perf_counter())
    change()
    yield h.until_converged(mark)
    yield from h.screenshot(name)


def edits(h):
    yield from start(h)
    objects = bpy.data.objects
    cube, cylinder = objects["Cube"], objects["Cylinder"]
    yield from enter_rendered(h)
    h.record("cube_before", h.object_rect(cube))
    h.record("cylinder", h.object_rect(cylinder))
    yield from h.screenshot("base")

    def move():
        # Up by 1 m: the cube and its shadows move, the left of the picture does not.
        cube.location.z += 1.0

    yield from edit(h, "moved", move)
    h.record("cube_after", h.object_rect(cube))

    def recolour():
        material = cube.active_material
        red = (0.8, 0.05, 0.05, 1.0)
        material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = red
        material.diffuse_color = red

    yield from edit(h, "recoloured", recolour)

    def brighten():
        objects["Point Light"].data.energy *= 4.0

    yield from edit(h, "brighter", brighten)

    def delete():
        objects.remove(cylinder)

    yield from edit(h, "deleted", delete)


def stop(h):
    yield from start(h)
    yield from enter_rendered(h)
    # 1. Leave Rendered mode after convergence.
    h.record("t_solid_1", time.perf_counter())
    h.set_shading("SOLID")
    yield 3.0
    # 2. Enter again and leave as soon as the first pass is on the GPU: the job is busy.
    mark = h.log.mark()
    h.record("t_rendered_2", time.perf_counter())
    h.set_shading("RENDERED")
    yield h.until(lambda: h.log.since(mark, "frame"), 60.0, "a first 'frame' event")
    h.record("converged_before_solid_2", bool(h.log.since(mark, "converged")))
    h.record("t_solid_2", time.perf_counter())
    h.set_shading("SOLID")
    yield 3.0
    h.record("t_end", time.perf_counter())
    # 3. Enter again and quit Blender while the job renders (the run then ends): the
    # engine is freed with its job running, and Blender must still exit cleanly.
    mark = h.log.mark()
    h.set_shading("RENDERED")
    yield h.until(lambda: h.log.since(mark, "frame"), 60.0, "a first 'frame' event")
    h.record("quit_mid_render", not h.log.since(mark, "converged"))


def scenario(h):
    mode = h.args.mode
    modes = {"compare": compare, "dof": dof, "denoise": denoise, "edits": edits, "stop": stop}
    yield from modes[mode](h)


driver.main(scenario, add_arguments)
