"""Per-light settings stored on each light as `light.whitted`."""

import bpy
from bpy.props import IntProperty, PointerProperty

from ..native_tables import bounds


class WhittedLightProperties(bpy.types.PropertyGroup):
    samples: IntProperty(
        name="Shadow Samples",
        description="Shadow feelers per axis for a light with a size (area, radius or angle): "
        "n x n stratified feelers per shading point; 0 uses the scene's Shadow Samples. "
        "A light of size 0 always sends one",
        default=0,
        # The native range of a light's samples, and 0 for the scene's.
        **{**bounds("light_samples"), "min": 0},
    )

    @classmethod
    def register(cls):
        bpy.types.Light.whitted = PointerProperty(
            name="Whitted", description="Whitted light settings", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.Light.whitted
