"""The viewport's drawing code (addon/viewport/display.py) where no window exists.

Blender gives a GPU context only to the render() of an engine with
bl_use_gpu_context = True (in `blender -b` and in the bpy module alike), so a small
test engine draws there: a known image uploaded as the Display's texture, drawn
stretched into an offscreen buffer, read back.
"""

import bpy
import numpy as np
import pytest
from whitted.viewport.display import Display

SIZE = 8  # the offscreen is SIZE x SIZE; the image half of that, stretched


class _DrawEngine(bpy.types.RenderEngine):
    bl_idname = "WHITTED_TEST_DRAW"
    bl_label = "Whitted display test"
    bl_use_gpu_context = True

    # What render() read back, for the test (one instance per render).
    results = []

    def render(self, depsgraph):
        import gpu

        image = np.zeros((SIZE // 2, SIZE // 2, 4), dtype=np.float32)
        image[..., 0] = np.linspace(0.0, 1.0, SIZE // 2)[None, :]  # red ramp along x
        image[..., 3] = 1.0
        display = Display()
        empty = display.draw(0, 0, SIZE, SIZE)
        display.upload(image)
        offscreen = gpu.types.GPUOffScreen(SIZE, SIZE, format="RGBA16F")
        with offscreen.bind():
            framebuffer = gpu.state.active_framebuffer_get()
            framebuffer.clear(color=(0.0, 0.0, 0.0, 0.0))
            with gpu.matrix.push_pop():
                # Region pixels, as in a 3D view's view_draw.
                gpu.matrix.load_matrix(_pixel_projection())
                gpu.matrix.load_projection_matrix(_identity())
                drawn = display.draw(0, 0, SIZE, SIZE)
            pixels = np.array(framebuffer.read_color(0, 0, SIZE, SIZE, 4, 0, "FLOAT").to_list())
        offscreen.free()
        type(self).results.append((empty, drawn, pixels.reshape(SIZE, SIZE, 4)))


def _identity():
    from mathutils import Matrix

    return Matrix.Identity(4)


def _pixel_projection():
    # Pixel (x, y) of a SIZE x SIZE region to normalised device coordinates.
    from mathutils import Matrix

    scale = Matrix.Diagonal((2.0 / SIZE, 2.0 / SIZE, 1.0, 1.0))
    return Matrix.Translation((-1.0, -1.0, 0.0)) @ scale


@pytest.fixture
def draw_engine():
    bpy.utils.register_class(_DrawEngine)
    _DrawEngine.results.clear()
    yield _DrawEngine
    bpy.utils.unregister_class(_DrawEngine)


def test_display_draws_the_uploaded_pass_stretched_over_the_region(empty_scene, draw_engine):
    empty_scene.render.engine = draw_engine.bl_idname
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera  # Blender renders nothing without one
    empty_scene.render.resolution_x = empty_scene.render.resolution_y = 4
    bpy.ops.render.render()
    ((empty, drawn, pixels),) = draw_engine.results
    assert not empty  # nothing uploaded yet: nothing drawn
    assert drawn
    # Each texel covers 2x2 pixels; red rises along x, the same on every row.
    red = pixels[..., 0]
    assert np.all(pixels[..., 3] == pytest.approx(1.0))
    np.testing.assert_allclose(red, np.repeat(red[:1], SIZE, axis=0))
    assert red[0, 0] == pytest.approx(0.0, abs=1e-3)
    assert red[0, -1] == pytest.approx(1.0, abs=1e-2)
    assert np.all(np.diff(red[0]) >= -1e-3)
