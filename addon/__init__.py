"""Whitted: a Blender render engine whose core is a native C++ Whitted ray tracer.

The package registers the engine, its scene settings and their panel. The
controls take their defaults and ranges from the native module's tables at import
(native_tables.py); where the module does not import (not built, or not for this
Blender's Python) the add-on and its exporters still import and register, and a
render says what to do (native.py).
"""

import bpy

from . import engine, operators, preferences
from .properties import light as light_properties
from .properties import material as material_properties
from .properties import scene as scene_properties
from .properties import view_layer as view_layer_properties
from .ray_tree import draw as ray_tree_draw
from .ray_tree import operators as ray_tree_operators
from .ui import light as light_ui
from .ui import material as material_ui
from .ui import passes as passes_ui
from .ui import ray_tree as ray_tree_ui
from .ui import render as render_ui

bl_info = {
    "name": "Whitted",
    "author": "The Whitted authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > Whitted",
    "description": "A classic Whitted ray tracer (C++, Embree) as a render engine",
    "category": "Render",
}

# Registered in this order, unregistered in reverse.
classes = (
    preferences.WhittedPreferences,
    scene_properties.WhittedEstimate,
    scene_properties.WhittedSceneProperties,
    view_layer_properties.WhittedViewLayerProperties,
    light_properties.WhittedLightProperties,
    material_properties.WhittedMaterialProperties,
    engine.WhittedRenderEngine,
    operators.WHITTED_OT_apply_preset,
    operators.WHITTED_OT_estimate,
    render_ui.WHITTED_RENDER_PT_sampling,
    render_ui.WHITTED_RENDER_PT_sampling_viewport,
    render_ui.WHITTED_RENDER_PT_sampling_render,
    render_ui.WHITTED_RENDER_PT_denoise,
    render_ui.WHITTED_RENDER_PT_sampling_rays,
    render_ui.WHITTED_RENDER_PT_estimate,
    render_ui.WHITTED_RENDER_PT_light_paths,
    render_ui.WHITTED_RENDER_PT_film,
    render_ui.WHITTED_RENDER_PT_performance,
    render_ui.WHITTED_RENDER_PT_last_render,
    light_ui.WHITTED_LIGHT_PT_settings,
    material_ui.WHITTED_MATERIAL_PT_settings,
    passes_ui.WHITTED_VIEWLAYER_PT_passes_data,
    passes_ui.WHITTED_VIEWLAYER_PT_passes_light,
    passes_ui.WHITTED_VIEWLAYER_PT_passes_whitted,
    ray_tree_operators.WHITTED_OT_inspect_ray_tree,
    ray_tree_operators.WHITTED_OT_clear_ray_tree,
    ray_tree_operators.WHITTED_OT_ray_tree_to_curve,
    ray_tree_draw.WHITTED_GT_ray_tree,
    ray_tree_draw.WHITTED_GGT_ray_tree,
    ray_tree_ui.WHITTED_VIEW3D_PT_ray_tree,
    ray_tree_ui.WHITTED_IMAGE_PT_ray_tree,
)

# Blender's own panels that also make sense for Whitted. Names differ between
# Blender versions, so a name missing from bpy.types is skipped.
COMPAT_PANELS = (
    # Output properties: dimensions, frame range, output file.
    "RENDER_PT_format",
    "RENDER_PT_frame_range",
    "RENDER_PT_output",
    "RENDER_PT_color_management",
    # Camera.
    "DATA_PT_context_camera",
    "DATA_PT_lens",
    "DATA_PT_camera",
    # Light: colour, power, radius, spot and area shape.
    "DATA_PT_context_light",
    "DATA_PT_EEVEE_light",
    "DATA_PT_spot",
    # Material slots, the preview (rendered by Whitted) and the surface node tree.
    "MATERIAL_PT_preview",
    "EEVEE_MATERIAL_PT_context_material",
    "EEVEE_MATERIAL_PT_surface",
    # World, and Cycles' world settings Whitted reads: Ray Visibility (Diffuse, Glossy),
    # Settings > Surface (Sampling, Map Resolution, Max Bounces).
    "WORLD_PT_context_world",
    "EEVEE_WORLD_PT_surface",
    "CYCLES_WORLD_PT_ray_visibility",
    "CYCLES_WORLD_PT_settings",
    "CYCLES_WORLD_PT_settings_surface",
    # View layer: its name and use, and the Passes panel that Whitted's own pass
    # sub-panels (ui/passes.py) go under, as Cycles' do.
    "VIEWLAYER_PT_context_layer",
    "VIEWLAYER_PT_layer",
    "VIEWLAYER_PT_layer_passes",
)


def _compat_panels():
    return [panel for name in COMPAT_PANELS if (panel := getattr(bpy.types, name, None))]


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    for panel in _compat_panels():
        panel.COMPAT_ENGINES.add(engine.WhittedRenderEngine.bl_idname)


def unregister():
    for panel in _compat_panels():
        panel.COMPAT_ENGINES.discard(engine.WhittedRenderEngine.bl_idname)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
