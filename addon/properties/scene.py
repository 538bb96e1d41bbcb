"""Render settings stored on each scene as `scene.whitted`."""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty


class WhittedSceneProperties(bpy.types.PropertyGroup):
    max_depth: IntProperty(
        name="Max Depth",
        description="Reflection and refraction bounces after the camera ray; "
        "0 traces camera rays and shadow feelers only",
        default=5,
        min=0,
        max=256,
    )
    aa_samples: IntProperty(
        name="AA Samples",
        description="Anti-aliasing samples per pixel along each axis (an n x n grid)",
        default=2,
        min=1,
        max=16,
    )
    fresnel: EnumProperty(
        name="Fresnel",
        description="How reflection and refraction share a transmissive surface's light",
        items=(
            ("OFF", "Off", "Fixed weights: reflectivity and transmissivity as given"),
            ("SCHLICK", "Schlick", "Schlick's approximation of the Fresnel equations"),
            ("EXACT", "Exact", "The exact dielectric Fresnel equations"),
        ),
        default="EXACT",
    )
    ambient_strength: FloatProperty(
        name="Ambient Strength",
        description="Scale of the ambient light Ia that the world's colour gives every "
        "surface (the Phong ambient term); 0 disables it",
        default=1.0,
        min=0.0,
        soft_max=2.0,
    )
    tile_size: IntProperty(
        name="Tile Size",
        description="Width and height in pixels of the tiles the threads render",
        default=32,
        min=8,
        max=4096,
    )

    @classmethod
    def register(cls):
        bpy.types.Scene.whitted = PointerProperty(
            name="Whitted", description="Whitted render settings", type=cls
        )

    @classmethod
    def unregister(cls):
        del bpy.types.Scene.whitted
