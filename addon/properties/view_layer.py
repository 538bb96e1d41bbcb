"""Whitted's own passes, switched on per view layer as `view_layer.whitted`.

Blender's passes (Depth, Normal, Diffuse Direct, ...) keep their switches on the
view layer itself (`view_layer.use_pass_z`, ...); result.PASSES says which
property enables each pass.
"""

import bpy
from bpy.props import BoolProperty, PointerProperty


class WhittedViewLayerProperties(bpy.types.PropertyGroup):
    use_pass_rays: BoolProperty(
        name="Rays",
        description='The "Whitted Rays" pass: rays traced for each pixel (camera, shadow, '
        "reflection, refraction and transparent), where the time of a frame goes",
        default=True,
    )

    @classmethod
    def register(cls):
        bpy.types.ViewLayer.whitted = PointerProperty(
            name="Whitted", description="Whitted render passes", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.ViewLayer.whitted
