"""The Whitted panel in Light Properties: the shadow switch the engine reads and
the soft-shadow sample count."""

import bpy

from ..export.light import shadow_switch


class WHITTED_LIGHT_PT_settings(bpy.types.Panel):
    bl_label = "Whitted"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"
    COMPAT_ENGINES = {"WHITTED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and context.light is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        light = context.light
        column = layout.column()
        column.prop(*shadow_switch(light), text="Cast Shadow")
        column.prop(light.whitted, "samples")
