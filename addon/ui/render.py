"""The Whitted panel in Render Properties."""

import bpy


class WHITTED_RENDER_PT_settings(bpy.types.Panel):
    bl_label = "Whitted"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"WHITTED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.whitted
        column = layout.column()
        column.prop(settings, "max_depth")
        column.prop(settings, "aa_samples")
        column.prop(settings, "fresnel")
        column.prop(settings, "ambient_strength")
        column.prop(settings, "tile_size")
        column.prop(context.scene.render, "threads_mode")
        row = column.row()
        row.enabled = context.scene.render.threads_mode == "FIXED"
        row.prop(context.scene.render, "threads")
