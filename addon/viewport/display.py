"""The viewport's GPU texture: the newest pass of the job, drawn over the region.

The `gpu` module only (no `bgl`, which Blender 5.0 removed). The job's display
pixels are scene-linear, premultiplied RGBA, already clamped below the
half-float maximum (the native film does it); Blender applies the scene's view
transform when it composites the viewport, as for Cycles.
"""

import gpu
from gpu_extras.presets import draw_texture_2d


class Display:
    def __init__(self):
        self._texture = None

    @property
    def ready(self):
        return self._texture is not None

    def upload(self, pixels):
        """Make float32[h, w, 4] C-contiguous `pixels` the texture. The gpu Buffer
        wraps the array's memory (no copy in Python); the texture is made from it
        once per pass, never per redraw."""
        height, width = pixels.shape[:2]
        buffer = gpu.types.Buffer("FLOAT", pixels.size, pixels)
        self._texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=buffer)

    def draw(self, x, y, width, height):
        """Draw the texture stretched over region pixels (x, y, width, height);
        False when there is nothing to draw yet."""
        if self._texture is None:
            return False
        gpu.state.blend_set("ALPHA_PREMULT")
        draw_texture_2d(self._texture, (x, y), width, height)
        gpu.state.blend_set("NONE")
        return True
