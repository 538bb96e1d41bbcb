"""Whitted's pass switches in View Layer Properties > Passes.

As Cycles does, Whitted joins Blender's own "View Layer" and "Passes" panels
(their COMPAT_ENGINES, see __init__.COMPAT_PANELS) and adds sub-panels of its
own under "Passes", drawn from result.PASSES: only the passes Whitted writes
are offered, with Blender's own view-layer switches where the pass is one of
Blender's, and a "Whitted" sub-panel for the passes no other engine has.
"""

import bpy

from .. import result

PANEL_PARENT = "VIEWLAYER_PT_layer_passes"


class _WhittedPassesPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "view_layer"
    bl_parent_id = PANEL_PARENT
    COMPAT_ENGINES = {"WHITTED"}
    PANEL = ""  # the PassSpec.panel this one draws

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        view_layer = context.view_layer
        columns = {}
        for spec in result.PASSES:
            if spec.panel != self.PANEL or not spec.toggle:
                continue
            holder, prop = spec.switch(view_layer)
            if holder is None:
                continue  # Cycles' switch, with Cycles disabled
            if spec.heading not in columns:
                columns[spec.heading] = layout.column(heading=spec.heading, align=True)
            label = {"text": spec.label} if spec.label else {}
            columns[spec.heading].prop(holder, prop, **label)
        self.draw_more(layout, view_layer)

    def draw_more(self, layout, view_layer):
        """What a panel shows besides the pass switches."""


class WHITTED_VIEWLAYER_PT_passes_data(_WhittedPassesPanel, bpy.types.Panel):
    bl_label = "Data"
    PANEL = "DATA"

    def draw_more(self, layout, view_layer):
        layout.prop(view_layer, "pass_alpha_threshold")


class WHITTED_VIEWLAYER_PT_passes_light(_WhittedPassesPanel, bpy.types.Panel):
    bl_label = "Light"
    PANEL = "LIGHT"


class WHITTED_VIEWLAYER_PT_passes_whitted(_WhittedPassesPanel, bpy.types.Panel):
    bl_label = "Whitted"
    PANEL = "WHITTED"

    def draw_more(self, layout, view_layer):
        column = layout.column(align=True)
        column.prop(view_layer.whitted, "use_pass_contributions")
        row = column.row()
        row.enabled = view_layer.whitted.use_pass_contributions
        row.prop(view_layer.whitted, "contribution_depth")
