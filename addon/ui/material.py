"""The Whitted panel in Material Properties: the override of the node mapping."""

import bpy


class WHITTED_MATERIAL_PT_settings(bpy.types.Panel):
    bl_label = "Whitted"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"
    COMPAT_ENGINES = {"WHITTED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and context.material is not None

    def draw_header(self, context):
        self.layout.prop(context.material.whitted, "use_override", text="")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.material.whitted
        column = layout.column()
        column.active = settings.use_override
        if not settings.use_override:
            column.label(text="Off: the values are derived from the material's nodes")
        column.prop(settings, "ambient")
        column.prop(settings, "diffuse_weight")
        column.prop(settings, "diffuse_color")
        column.prop(settings, "specular_weight")
        column.prop(settings, "specular_color")
        column.prop(settings, "shininess")
        column.prop(settings, "reflectivity")
        column.prop(settings, "transmissivity")
        column.prop(settings, "ior")
