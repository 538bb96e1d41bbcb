"""The Whitted panels in Render Properties, laid out as Cycles' (Sampling with its
Viewport, Render and Denoise parts, Light Paths, Film, Performance), with the estimate
of each preset's render time and error beside the presets, and the last render's
statistics."""

import json

import bpy

from .. import stats as render_stats
from ..properties.presets import PRESETS, matching_preset, preset_label


class _WhittedRenderPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"WHITTED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class WHITTED_RENDER_PT_sampling(_WhittedRenderPanel, bpy.types.Panel):
    """Sampling, as Cycles lays it out: the presets, then the viewport's and the
    render's sampling, their denoising, and the per-sample ray budget."""

    bl_label = "Sampling"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.whitted
        current = matching_preset(settings)
        layout.label(text=f"Quality: {preset_label(current) if current else 'Custom'}")
        row = layout.row(align=True)
        for key, label, _, _ in PRESETS:
            row.operator("whitted.apply_preset", text=label, depress=key == current).preset = key


class _SamplingSubPanel(_WhittedRenderPanel):
    bl_parent_id = "WHITTED_RENDER_PT_sampling"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        self.draw_settings(layout, context.scene)

    def draw_settings(self, layout, scene):
        """The panel's controls."""


class WHITTED_RENDER_PT_sampling_viewport(_SamplingSubPanel, bpy.types.Panel):
    bl_label = "Viewport"

    def draw_settings(self, layout, scene):
        settings = scene.whitted
        layout.prop(settings, "viewport_preset", text="Quality")
        layout.prop(settings, "use_viewport_denoising", text="Denoise")
        layout.prop(settings, "viewport_display", text="Display")
        layout.prop(scene.render, "preview_pixel_size", text="Pixel Size")


class WHITTED_RENDER_PT_sampling_render(_SamplingSubPanel, bpy.types.Panel):
    bl_label = "Render"

    def draw_settings(self, layout, scene):
        settings = scene.whitted
        row = layout.row(heading="Noise Threshold")
        row.prop(settings, "adaptive_sampling", text="")
        value = row.row()
        value.active = settings.adaptive_sampling
        value.prop(settings, "noise_threshold", text="")
        column = layout.column(align=True)
        column.prop(settings, "aa_samples", text="Max Samples per Axis")
        n = settings.aa_samples
        column.label(text=f"{n} x {n} = {n * n} samples per pixel at most")
        minimum = layout.row()
        minimum.active = settings.adaptive_sampling
        minimum.prop(settings, "adaptive_min_samples")
        limit = layout.row()
        limit.active = settings.adaptive_sampling
        limit.prop(settings, "time_limit")


class WHITTED_RENDER_PT_denoise(_SamplingSubPanel, bpy.types.Panel):
    bl_label = "Denoise"
    bl_parent_id = "WHITTED_RENDER_PT_sampling_render"
    bl_options = {"DEFAULT_CLOSED"}

    def draw_header(self, context):
        self.layout.prop(context.scene.whitted, "use_denoising", text="")

    def draw_settings(self, layout, scene):
        settings = scene.whitted
        layout.active = settings.use_denoising and settings.local_model == "BLENDER"
        if settings.local_model == "LECTURE":
            layout.label(text="Off in the Lecture local model", icon="INFO")
        layout.prop(settings, "denoising_input_passes")
        layout.prop(settings, "denoising_prefilter")
        layout.prop(settings, "denoising_quality")


class WHITTED_RENDER_PT_sampling_rays(_SamplingSubPanel, bpy.types.Panel):
    """What one camera sample traces: where its samples lie in the pixel, and the
    feelers and lobe rays it sends."""

    bl_label = "Rays per Sample"
    bl_options = {"DEFAULT_CLOSED"}

    def draw_settings(self, layout, scene):
        settings = scene.whitted
        layout.prop(settings, "aa_mode")
        if settings.aa_mode == "ADAPTIVE":
            layout.prop(settings, "aa_threshold")
            layout.prop(settings, "aa_depth")
        layout.prop(settings, "light_samples")
        glossy = layout.row()
        glossy.active = settings.local_model == "BLENDER"
        glossy.prop(settings, "glossy_samples")
        layout.prop(settings, "emitter_samples")
        layout.prop(settings, "texture_filter")
        seed = layout.row(align=True)
        seed.prop(settings, "seed")
        seed.prop(settings, "use_animated_seed", text="", icon="TIME")


class _TopPanel(_WhittedRenderPanel):
    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        self.draw_settings(layout.column(), context.scene)


class WHITTED_RENDER_PT_light_paths(_TopPanel, bpy.types.Panel):
    bl_label = "Light Paths"

    def draw_settings(self, column, scene):
        settings = scene.whitted
        column.prop(settings, "local_model")
        column.prop(settings, "max_depth")
        column.prop(settings, "cutoff")
        column.prop(settings, "fresnel")
        column.prop(settings, "glass_shadows")
        column.prop(settings, "volume_step_rate")
        column.prop(settings, "volume_max_steps")
        # The Blender model lights surfaces with the world itself (its Ray Visibility);
        # the ambient term is the Lecture model's.
        ambient = column.row()
        ambient.active = settings.local_model == "LECTURE"
        ambient.prop(settings, "ambient_strength")


class WHITTED_RENDER_PT_film(_TopPanel, bpy.types.Panel):
    bl_label = "Film"
    bl_options = {"DEFAULT_CLOSED"}

    def draw_settings(self, column, scene):
        settings = scene.whitted
        filtered = column.column()
        # Whitted's adaptive anti-aliasing samples each pixel's square.
        filtered.active = settings.aa_mode != "ADAPTIVE"
        filtered.prop(settings, "pixel_filter_type")
        if settings.pixel_filter_type != "BOX":  # the pixel's square, as Cycles' Box
            filtered.prop(settings, "filter_width")
        column.prop(scene.render, "film_transparent")


class WHITTED_RENDER_PT_performance(_TopPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_options = {"DEFAULT_CLOSED"}

    def draw_settings(self, column, scene):
        render = scene.render
        column.prop(render, "threads_mode")
        row = column.row()
        row.enabled = render.threads_mode == "FIXED"
        row.prop(render, "threads")
        column.prop(scene.whitted, "tile_size")
        column.prop(scene.whitted, "use_waves")


class WHITTED_RENDER_PT_estimate(_WhittedRenderPanel, bpy.types.Panel):
    bl_label = "Time and Error Estimate"
    bl_parent_id = "WHITTED_RENDER_PT_sampling"

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
            f"{phases['mesh_bvh'] + phases['scene_bvh']:.2f}, world map "
            # Statistics saved before the phase was split from scene_bvh lack it.
            f"{phases.get('world_light', 0.0):.2f}, trace {phases['trace']:.2f}, "
            f"write-back {phases['writeback']:.3f}",
            f"{rays['total']:,} rays, {stats['rays_per_second'] / 1e6:.1f} M rays/s",
            f"camera {rays['camera']:,}, shadow {rays['shadow']:,}",
            f"reflection {rays['reflection']:,}, refraction {rays['refraction']:,}",
            f"transparent {rays['transparent']:,}, TIR {stats['total_internal_reflections']:,}",
            # Only where Ambient Occlusion or Bevel nodes traced some (older statistics
            # lack them).
            ", ".join(
                f"{label} {rays[kind]:,}"
                for kind, label in render_stats.PROGRAM_RAYS.items()
                if rays.get(kind)
            ),
            f"cut by depth {stats['depth_limited']:,}, by cutoff {stats['cutoff_skipped']:,}",
            f"samples/px {stats['samples_per_pixel']:.2f} (max "
            f"{stats['pixel_samples']['max'] or '?'}), peak {stats['peak_memory_mib']:.0f} MiB",
            render_stats.media_text(stats),
        ):
            if line:  # the media's line only where the render had media
                column.label(text=line)
