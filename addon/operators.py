"""Operators of the Render Properties panel: apply a preset, estimate each preset's
render time and error."""

import bpy
from bpy.props import EnumProperty

from .estimate import estimate_presets, render_differences
from .export import ExportError
from .memory import MIB
from .native import load_native
from .properties.presets import PRESETS, apply_quality, preset


class WHITTED_OT_apply_preset(bpy.types.Operator):
    bl_idname = "whitted.apply_preset"
    bl_label = "Apply Quality Preset"
    bl_description = "Set every Whitted quality control to the preset's value"
    bl_options = {"REGISTER", "UNDO"}

    preset: EnumProperty(
        name="Preset",
        items=[(key, label, description) for key, label, description, _ in PRESETS],
    )

    def execute(self, context):
        apply_quality(context.scene.whitted, preset(self.preset))
        return {"FINISHED"}


class WHITTED_OT_estimate(bpy.types.Operator):
    bl_idname = "whitted.estimate"
    bl_label = "Estimate"
    bl_description = (
        "Render a sample of the frame's pixels with each preset and predict the render "
        "time of each and its error against Reference"
    )

    def execute(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        try:
            native = load_native()
            probe, estimates, needed = estimate_presets(depsgraph, native)
        except (ImportError, ExportError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except (ValueError, RuntimeError) as error:
            self.report({"ERROR"}, f"Whitted: the renderer refused the scene: {error}")
            return {"CANCELLED"}
        whitted = context.scene.whitted
        whitted.estimates.clear()
        for estimate in estimates:
            item = whitted.estimates.add()
            item.preset = estimate.preset
            item.seconds = estimate.seconds
            item.error = estimate.error
            item.rays_per_pixel = estimate.rays_per_pixel
        whitted.estimate_probe = probe.describe()
        whitted.estimate_memory_mib = needed.bytes / MIB
        differences = render_differences(depsgraph)
        whitted.estimate_caveat = "; ".join(differences)
        if differences:
            self.report(
                {"WARNING"},
                "Whitted: the Estimate measured the viewport's geometry, and a render's "
                f"will differ: {whitted.estimate_caveat}",
            )
        return {"FINISHED"}
