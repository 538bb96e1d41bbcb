"""Whitted's own passes, switched on per view layer as `view_layer.whitted`.

Blender's passes (Depth, Normal, Diffuse Direct, ...) keep their switches on the
view layer itself (`view_layer.use_pass_z`, ...); result.PASSES says which
property enables each pass.
"""

import bpy
from bpy.props import BoolProperty, IntProperty, PointerProperty

from ..native_tables import setting


class WhittedViewLayerProperties(bpy.types.PropertyGroup):
    use_pass_rays: BoolProperty(
        name="Rays",
        description='The "Whitted Rays" pass: rays traced for each pixel (camera, shadow, '
        "reflection, refraction and transparent; in fog and smoke, the feelers from their "
        "scatter points and the rays through their bounds), where the time of a frame goes",
        default=True,
    )
    use_pass_denoising_data: BoolProperty(
        name="Denoising Data",
        description='The "Noisy Image", "Denoising Normal" and "Denoising Albedo" passes: '
        "the image before denoising and the denoiser's guides, for denoising in the "
        "compositor",
        default=False,
    )
    use_pass_cut_weight: BoolProperty(
        name="Cut Weight",
        description='The "Whitted Cut Weight" pass: the share of each pixel\'s ray tree '
        "that the maximum depth or the cutoff left untraced (0: nothing cut), a bound on "
        "what raising the depth or lowering the cutoff could still change",
        default=False,
    )
    use_pass_sample_count: BoolProperty(
        name="Sample Count",
        description='The "Debug Sample Count" pass (as Cycles\'): the camera samples each '
        "pixel took, fewer where noise-driven sampling stopped it early",
        default=False,
    )
    use_pass_contributions: BoolProperty(
        name="Per-Depth Contributions",
        description='The "Whitted Depth N" passes: what the ray tree adds at each depth '
        "(0: emission and local term at the camera hit, 1: at the surfaces its mirror and "
        "refracted rays meet, ...), the last one at that depth and beyond; they sum to "
        "Combined",
        default=False,
    )
    contribution_depth: IntProperty(
        name="Separate Depths",
        description="Depths with a pass of their own (0 .. this - 1); one more pass holds "
        "this depth and beyond",
        **setting("contribution_depth"),
    )

    @classmethod
    def register(cls):
        bpy.types.ViewLayer.whitted = PointerProperty(
            name="Whitted", description="Whitted render passes", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.ViewLayer.whitted
