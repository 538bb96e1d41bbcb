"""Lights as Cycles defines them, so a diffuse surface is as bright as in Cycles.

Blender gives a point, spot or area light's power P in watts and a sun's
strength S as irradiance in W/m^2. Cycles multiplies them by the light colour,
by the blackbody colour when `use_temperature` is on (4.x+) and by
2^exposure (4.x+). The tracer takes each light's own unit:
    point, spot:  radiant intensity  I = P / (4 pi)      W/sr
    sun:          irradiance         E = S                W/m^2
    area:         radiance           L = P / (pi A)       W/(m^2 sr), one-sided,
                                     L = P / (4 A) before Blender 4.0
Blender 4.0 changed the area light's flux-to-radiance factor from 1/4 to 1/pi
(Blender issue #109404; measured: Cycles 5.0 renders an area light 4/pi times
as bright as Cycles 3.4 does). With `normalize` off (4.x+), Cycles does not
divide the power by the light's area: each quantity above is multiplied by
Cycles' `Light::area()`, which is 4 pi r^2 for a point or spot of radius r
(4 when r = 0), A for an area light and pi sin^2(angle / 2) for a sun (1 when
the angle is 0). A light shines along its local -Z axis.
"""

import math
from dataclasses import dataclass, replace

import bpy
import numpy as np
from mathutils import Matrix

from ..native import load_native
from .instance import instance_name
from .light_linking import ALL_SETS
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT
from .nodes.program import emit
from .nodes.shaders import surface
from .nodes.values import Lowering

Vector = tuple[float, float, float]

# Shadow feelers per axis of a sized light whose own setting is 0 (4 x 4), unless
# the scene says otherwise (scene.whitted.light_samples).
DEFAULT_LIGHT_SAMPLES = 4

# Radiance of an area light per watt and square metre of its area (see above).
AREA_WATTS_TO_RADIANCE = 1.0 / math.pi if bpy.app.version >= (4, 0, 0) else 0.25

# Blender's area shapes -> the tracer's two shapes (a square is a rectangle with
# size_y = size, a disk an ellipse).
_AREA_SHAPES = {
    "SQUARE": "RECTANGLE",
    "RECTANGLE": "RECTANGLE",
    "DISK": "ELLIPSE",
    "ELLIPSE": "ELLIPSE",
}


@dataclass(frozen=True)
class LightData:
    name: str
    type: str  # "POINT", "SPOT", "SUN" or "AREA"
    color: Vector  # W/sr (point, spot), W/m^2 (sun), W/(m^2 sr) (area)
    position: Vector  # world space
    direction: Vector  # unit, the way the light travels
    spot_size: float = 0.0  # full cone angle, radians
    spot_blend: float = 0.0
    # Cycles before Blender 4.0 multiplies the cone falloff by the cosine to the axis
    # (measured: Cycles 3.4 / Whitted equalled that cosine to 1e-5 over a 120-degree cone).
    spot_cosine_falloff: bool = False
    size: tuple[float, float] = (0.0, 0.0)  # area extents along axis_u, axis_v (world units)
    axis_u: Vector = (1.0, 0.0, 0.0)  # unit
    axis_v: Vector = (0.0, 1.0, 0.0)  # unit
    shape: str = "RECTANGLE"  # "RECTANGLE" or "ELLIPSE"
    radius: float = 0.0  # point and spot: sphere radius (world units)
    angle: float = 0.0  # sun: full apex angle of its cone of directions, radians
    spread: float = math.pi  # area: the full angle its light spreads over, radians
    samples: int = 1  # feelers per axis: n x n for a sized light, 1 otherwise
    cast_shadows: bool = True
    # Its ray visibility (Object > Visibility > Ray Visibility, Cycles'): whether it
    # lights diffuse surfaces and shows in glossy ones (highlights, glossy lobes).
    diffuse: bool = True
    glossy: bool = True
    # Which rays see its shape (an area light's rectangle or ellipse, a point or spot
    # light's sphere), as Cycles' Ray Visibility: camera, glossy (reflected) and
    # transmission (refracted) rays; the bounced ones only with Multiple Importance on
    # (light.cycles.use_multiple_importance_sampling), as in Cycles. Blender creates lamp
    # objects hidden from the camera. None in the Lecture local model, whose lamps are the
    # seed's lights that no ray meets.
    visibility: tuple[bool, bool, bool] = (False, True, True)
    # Cycles' Max Bounces (light.cycles): it lights only what at most this many
    # reflections and refractions reach.
    max_bounces: int = 1024
    # Light linking (export/light_linking.py): the receivers' light sets it lights, the
    # blockers' shadow sets that cast its shadows, a bit per set.
    light_sets: int = ALL_SETS
    shadow_sets: int = ALL_SETS
    # A node tree whose emission varies over the lamp (Light Falloff's ray length, the
    # point on it): a nodes.program.ProgramData whose register `program_output` (xyz)
    # multiplies `color` per feeler and where a ray sees the lamp (native
    # scene/light.cpp lamp_emission); None: `color` alone, the tree's constant folded in.
    program: object = None
    program_output: int = 0


def instance_light(
    object_instance, warnings, default_samples=DEFAULT_LIGHT_SAMPLES, local_model="BLENDER"
):
    """LightData of a light object instance of the evaluated depsgraph (named by
    instance_name, with its instancer's ray visibility), or None with a warning.
    `local_model` (scene.whitted.local_model): in LECTURE no ray sees a lamp's shape."""
    obj = object_instance.object
    instancer = object_instance.parent if object_instance.is_instance else None
    light = convert_light(
        instance_name(object_instance),
        obj.data,
        object_instance.matrix_world,
        warnings,
        default_samples,
        rays=lamp_rays(obj, instancer),
    )
    if light is None or local_model != "LECTURE":
        return light
    return replace(light, visibility=(False, False, False))


def lamp_rays(obj, instancer=None):
    """(diffuse, glossy, camera, transmission): whether light object `obj` lights
    diffuse surfaces, shows in glossy ones, is seen by the camera and through
    refractions (its Ray Visibility, which Cycles reads on the object since 3.0); an
    instance needs its instancer's too, as in Cycles."""
    owners = (obj,) if instancer is None else (obj, instancer)
    return tuple(
        all(getattr(o, name, default) for o in owners)
        for name, default in (
            ("visible_diffuse", True),
            ("visible_glossy", True),
            ("visible_camera", False),
            ("visible_transmission", True),
        )
    )


def convert_light(
    name,
    light,
    matrix_world,
    warnings,
    default_samples=DEFAULT_LIGHT_SAMPLES,
    rays=(True, True, False, True),
):
    """One light placed by `matrix_world` (object to world) as LightData, or None
    (with a warning) when Whitted cannot render it; `rays`: lamp_rays of its object."""
    if light.type == "AREA" and getattr(getattr(light, "cycles", None), "is_portal", False):
        return None  # a portal only guides Cycles' sampling of the world; it emits nothing
    matrix = np.array(matrix_world, dtype=np.float64)
    # The columns of the object-to-world matrix are the light's axes in world
    # space; their lengths are the object's scale.
    axes = matrix[:3, :3]
    scale = np.linalg.norm(axes, axis=0)
    if not np.all(scale > 0.0):
        warnings.append(f"Whitted: light '{name}' has a zero scale; skipped")
        return None
    data = _convert_light(name, light, matrix, axes / scale, scale, default_samples, warnings)
    if data is None:
        return None
    # Cycles' Max Bounces (light.cycles), or LightData's default without Cycles' settings.
    cycles = getattr(light, "cycles", None)
    bounces = getattr(cycles, "max_bounces", LightData.max_bounces)
    # Bounced rays meet a lamp only with Multiple Importance on (Cycles' lights_intersect).
    mis = getattr(cycles, "use_multiple_importance_sampling", True)
    diffuse, glossy, camera, transmission = rays
    return replace(
        data,
        diffuse=diffuse,
        glossy=glossy,
        max_bounces=bounces,
        visibility=(camera, glossy and mis, transmission and mis),
    )


def shadow_switch(light):
    """(owner, property name) of the per-light shadow switch Cycles reads:
    Blender 3.x's Cycles has its own (`light.cycles.cast_shadow`; `use_shadow`
    is EEVEE's there); from 4.0 both engines read `light.use_shadow`."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and hasattr(cycles, "cast_shadow"):
        return cycles, "cast_shadow"
    return light, "use_shadow"


def _convert_light(name, light, matrix, unit_axes, scale, default_samples, warnings):
    owner, switch = shadow_switch(light)
    common = {
        "name": name,
        "type": light.type,
        "position": tuple(matrix[:3, 3]),
        # The light travels along its local -Z axis.
        "direction": tuple(-unit_axes[:, 2]),
        "cast_shadows": getattr(owner, switch),
    }
    shader, program, output = light_shader(name, light, matrix, warnings)
    color = tuple(c * f for c, f in zip(_light_color(light), shader, strict=True))
    if program is not None:
        common |= {"program": program, "program_output": output}
    # Blender 3.x always normalises; 4.x+ lets the artist turn it off.
    normalize = getattr(light, "normalize", True)
    if light.type in {"POINT", "SPOT"}:
        # The radius is not scaled by the object, as in Cycles.
        radius = max(0.0, light.shadow_soft_size)
        # Power P in W spread over the whole sphere: I = P / (4 pi) W/sr. Cycles does
        # not renormalise a spot to its cone, so neither do we.
        watts_to_intensity = 1.0 / (4.0 * math.pi)
        if not normalize:
            watts_to_intensity *= 4.0 * math.pi * radius * radius if radius > 0.0 else 4.0
        if light.type == "SPOT":
            common |= {
                "spot_size": light.spot_size,
                "spot_blend": light.spot_blend,
                "spot_cosine_falloff": bpy.app.version < (4, 0, 0),
            }
        return LightData(
            color=tuple(light.energy * watts_to_intensity * c for c in color),
            radius=radius,
            samples=_samples(light, default_samples, sized=radius > 0.0),
            **common,
        )
    if light.type == "SUN":
        angle = min(max(0.0, light.angle), math.pi)  # full apex angle, radians
        # Strength is the irradiance on a surface facing the sun, W/m^2.
        irradiance = light.energy
        if not normalize and angle > 0.0:
            irradiance *= math.pi * math.sin(0.5 * angle) ** 2
        return LightData(
            color=tuple(irradiance * c for c in color),
            angle=angle,
            samples=_samples(light, default_samples, sized=angle > 0.0),
            **common,
        )
    if light.type == "AREA":
        shape = _AREA_SHAPES[light.shape]
        # size (and size_y for rectangles and ellipses) are local lengths: the
        # object's scale along local X and Y makes them world lengths.
        size_y = light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size
        size = (light.size * scale[0], size_y * scale[1])
        area = size[0] * size[1] * (math.pi / 4.0 if shape == "ELLIPSE" else 1.0)
        if area <= 0.0:
            warnings.append(f"Whitted: area light '{name}' has no area; skipped, as in Cycles")
            return None
        # One-sided radiance L = P / (pi A) W/(m^2 sr) (P / (4 A) before 4.0), as
        # Cycles; with normalize off, L = P / pi whatever the size.
        watts_to_radiance = AREA_WATTS_TO_RADIANCE / (area if normalize else 1.0)
        return LightData(
            color=tuple(light.energy * watts_to_radiance * c for c in color),
            size=size,
            axis_u=tuple(unit_axes[:, 0]),
            axis_v=tuple(unit_axes[:, 1]),
            shape=shape,
            spread=min(max(0.0, light.spread), math.pi),
            samples=_samples(light, default_samples, sized=True),
            **common,
        )
    warnings.append(f"Whitted: light '{name}' is of type {light.type}, which Whitted skips")
    return None


def _samples(light, default_samples, sized):
    """Shadow feelers per axis: the light's own setting (0: `default_samples`) when
    it has a size, one when it is a point."""
    if not sized:
        return 1
    return light.whitted.samples or default_samples


def light_shader(name, light, matrix, warnings):
    """What a light's node tree (Use Nodes; always on in 5.x) multiplies its colour by, as
    Cycles reads it: the emission its active Light Output receives, lowered as a
    material's surface is (export/nodes: Emission, Mix and Add Shader, Blackbody, RGB,
    Math, ...). (factor, None, 0) where that folds to a constant; (1, 1, 1), the
    ProgramData and its output register where it varies over the lamp and the program
    is one a lamp runs (native lamp_program_refusal: a point, spot or area lamp's,
    reading the lamp's point, normal, incoming direction and ray length, and its object
    space through constants); else (1, 1, 1) and a warning. An output fed by nothing emits
    nothing. A node the lowering does not support is warned by name and its input keeps
    its unlinked value."""
    white = (1.0, 1.0, 1.0)
    tree = light.node_tree if getattr(light, "use_nodes", False) else None
    if tree is None:
        return white, None, 0
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputLight"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    if output is None:
        return (0.0, 0.0, 0.0), None, 0  # no Light Output: Cycles' light emits nothing
    # The lamp's object-to-world `matrix` (numpy, 4 x 4), whose space its tree may read.
    lowering = Lowering(f"light '{name}'", warnings, lamp_matrix=Matrix(matrix.tolist()))
    emission = surface(lowering, output).fields["emission"]
    if emission.is_const:
        return _exact_emission(lowering, output) or tuple(emission.value[:3]), None, 0
    program, registers = emit({"emission": emission})
    why = _unrunnable(program, light.type, registers["emission"])
    if why is not None:
        _warn(
            warnings,
            f"Whitted: light '{name}''s node tree is not read: its emission varies over the "
            f"lamp and {why}; it lights with its colour and power",
        )
        return white, None, 0
    return white, program, registers["emission"]


def _exact_emission(lowering, output):
    """Color x Strength of an Emission node feeding `output` with constant inputs, in
    double precision, or None: the factor as it was read before lamp trees were lowered,
    so that those lamps render the same pixels (the lowering's fold multiplies in the
    program's float32, an ulp apart)."""
    found, _ = source(output.inputs["Surface"])
    if found is None or found.node.bl_idname != "ShaderNodeEmission":
        return None
    color = lowering.value(found.node.inputs["Color"], found.scope, COLOR)
    strength = lowering.value(found.node.inputs["Strength"], found.scope, FLOAT)
    if not (color.is_const and strength.is_const):
        return None
    return tuple(c * strength.value[0] for c in color.value[:3])


def _unrunnable(program, light_type, output):
    """Why a lamp of `light_type` cannot run `program` per feeler, or None: the native
    rule (scene/light.h lamp_program_refusal), which the native Light applies too."""
    native = load_native()
    return native.lamp_program_refusal(
        program.native(native), getattr(native.LightType, light_type), output
    )


def _light_color(light):
    color = tuple(light.color)
    # Blender 4.x+: a blackbody temperature tints the colour; Cycles multiplies by
    # Blender's own `temperature_color` (linear RGB), so Whitted uses the same.
    if getattr(light, "use_temperature", False):
        color = tuple(c * t for c, t in zip(color, light.temperature_color, strict=True))
    # ... and the exposure (in stops) scales the power: x 2^exposure.
    exposure = 2.0 ** getattr(light, "exposure", 0.0)
    return tuple(exposure * c for c in color)
