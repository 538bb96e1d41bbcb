"""Prove the harness with Blender's own engines: Workbench Solid, EEVEE and Cycles Rendered.

Each engine's camera view is screenshotted; Workbench and EEVEE are also F12-rendered
at the camera frame's size, so the pytest side can check the frame alignment the
Whitted comparison relies on with engines that work today.
"""

import bpy
from whitted_tools import viewport_driver as driver


def frame_size(h):
    left, top, right, bottom = h.camera_frame()
    return round(right - left), round(bottom - top)


def scenario(h):
    scene = bpy.context.scene
    h.step("maximise")
    yield h.maximise()
    h.setup_view("SOLID")
    scene.render.engine = "BLENDER_WORKBENCH"
    # The world colour behind the scene, as the F12 render has, instead of the theme's grey.
    h.space.shading.background_type = "WORLD"
    yield 1.0
    h.step("workbench solid")
    yield from h.screenshot("workbench_solid")
    # Same lighting and colours as the Solid view, so F12 and viewport can match.
    shading = h.space.shading
    scene.display.shading.light = shading.light
    scene.display.shading.color_type = shading.color_type
    h.render_still("workbench_f12", *frame_size(h))
    yield 0.5
    # The render changed the resolution by a pixel at most: shoot again at the
    # final frame so the crop uses the same frame as the render.
    yield from h.screenshot("workbench_solid_final")

    h.step("eevee rendered")
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.taa_samples = 16
    scene.eevee.taa_render_samples = 16
    h.set_shading("RENDERED")
    yield 8.0
    yield from h.screenshot("eevee_rendered")
    h.render_still("eevee_f12", *frame_size(h))
    yield 0.5
    yield from h.screenshot("eevee_rendered_final")

    h.step("cycles rendered")
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.preview_samples = 4
    h.set_shading("RENDERED")
    yield 8.0
    yield from h.screenshot("cycles_rendered")
    h.record("done", True)


driver.main(scenario)
