"""The Whitted panels in Render Properties: quality (presets and controls), the
estimate of each preset's render time and error, and the last render's statistics."""

import json

import bpy

from ..properties.presets import PRESETS, matching_preset, preset_label


class _WhittedRenderPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"WHITTED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class WHITTED_RENDER_PT_settings(_WhittedRenderPanel, bpy.types.Panel):
    bl_label = "Whitted"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.whitted
        current = matching_preset(settings)
        layout.label(text=f"Quality: {preset_label(current) if current else 'Custom'}")
        row = layout.row(align=True)
        for key, label, _, _ in PRESETS:
            row.operator("whitted.apply_preset", text=label, depress=key == current).preset = key
        layout.use_property_split = True
        layout.use_property_decorate = False
        column = layout.column()
        column.prop(settings, "local_model")
        column.prop(settings, "max_depth")
        column.prop(settings, "cutoff")
        column.prop(settings, "aa_mode")
        if settings.aa_mode == "ADAPTIVE":
            column.prop(settings, "aa_threshold")
            column.prop(settings, "aa_depth")
        else:
            column.prop(settings, "aa_samples")
        column.prop(settings, "light_samples")
        glossy = column.row()
        glossy.active = settings.local_model == "BLENDER"
        glossy.prop(settings, "glossy_samples")
        column.prop(settings, "emitter_samples")
        column.prop(settings, "fresnel")
        column.prop(settings, "glass_shadows")
        column.prop(settings, "texture_filter")
        column.prop(settings, "ambient_strength")
        column.prop(settings, "tile_size")
        column.prop(settings, "use_waves")
        column.prop(settings, "viewport_preset")
        column.prop(settings, "viewport_display")
        column.prop(context.scene.render, "preview_pixel_size", text="Viewport Pixel Size")
        column.prop(context.scene.render, "threads_mode")
        row = column.row()
        row.enabled = context.scene.render.threads_mode == "FIXED"
        row.prop(context.scene.render, "threads")


class WHITTED_RENDER_PT_estimate(_WhittedRenderPanel, bpy.types.Panel):
    bl_label = "Time and Error Estimate"
    bl_parent_id = "WHITTED_RENDER_PT_settings"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.whitted
        layout.operator("whitted.estimate", icon="TIME")
        if not settings.estimates:
            return
        layout.label(text=settings.estimate_probe)
        if settings.estimate_caveat:
            layout.label(text=f"Renders differ: {settings.estimate_caveat}", icon="ERROR")
        layout.label(text=f"Memory: about {settings.estimate_memory_mib:,.0f} MiB")
        # preset | time | display RMSE against Reference in 8-bit levels
        # (addon/estimate_model.py) | rays per pixel
        table = layout.grid_flow(row_major=True, columns=4, even_columns=True, align=True)
        for heading in ("Preset", "Time", "Error (/255)", "Rays/px"):
            table.label(text=heading)
        for estimate in settings.estimates:
            table.label(text=preset_label(estimate.preset))
            table.label(text=f"{estimate.seconds:.2f} s")
            table.label(text=f"{estimate.error:.2f}")
            table.label(text=f"{estimate.rays_per_pixel:.0f}")


class WHITTED_RENDER_PT_last_render(_WhittedRenderPanel, bpy.types.Panel):
    bl_label = "Last Render"
    bl_parent_id = "WHITTED_RENDER_PT_settings"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        text = context.scene.whitted.last_stats
        if not text:
            layout.label(text="No Whitted render of this scene yet")
            return
        stats = json.loads(text)
        rays = stats["rays"]
        phases = stats["phases"]
        column = layout.column(align=True)
        for line in (
            f"{phases['total']:.2f} s: export {phases['export']:.2f}, BVH "
            f"{phases['mesh_bvh'] + phases['scene_bvh']:.2f}, trace {phases['trace']:.2f}, "
            f"write-back {phases['writeback']:.3f}",
            f"{rays['total']:,} rays, {stats['rays_per_second'] / 1e6:.1f} M rays/s",
            f"camera {rays['camera']:,}, shadow {rays['shadow']:,}",
            f"reflection {rays['reflection']:,}, refraction {rays['refraction']:,}",
            f"transparent {rays['transparent']:,}, TIR {stats['total_internal_reflections']:,}",
            f"cut by depth {stats['depth_limited']:,}, by cutoff {stats['cutoff_skipped']:,}",
            f"{stats['samples_per_pixel']:.2f} samples/px, peak {stats['peak_memory_mib']:.0f} MiB",
        ):
            column.label(text=line)
