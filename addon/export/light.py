"""Lights in the units Cycles uses, so a diffuse surface is as bright as in Cycles.

Blender gives a point, spot or area light's power P in watts and a sun's
strength as irradiance in W/m^2. The tracer takes each light's own unit,
light colour included:
    point, spot:  radiant intensity  I = P / (4 pi)      W/sr
    sun:          irradiance         E = strength         W/m^2
    area:         radiance           L = P / (4 A)        W/(m^2 sr)
A light shines along its local -Z axis.
"""

import math
from dataclasses import dataclass

import numpy as np

from .instance import instance_name

Vector = tuple[float, float, float]

# Shadow feelers per axis of an area light (4 x 4 per shading point).
AREA_SAMPLES = 4

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
    size: tuple[float, float] = (0.0, 0.0)  # area extents along axis_u, axis_v (world units)
    axis_u: Vector = (1.0, 0.0, 0.0)  # unit
    axis_v: Vector = (0.0, 1.0, 0.0)  # unit
    shape: str = "RECTANGLE"  # "RECTANGLE" or "ELLIPSE"
    samples: int = 1  # per axis, area lights only
    cast_shadows: bool = True


def convert_lights(depsgraph, warnings):
    """Every renderable light of the evaluated depsgraph, instances included."""
    lights = []
    for object_instance in depsgraph.object_instances:
        obj = object_instance.object
        if obj.type != "LIGHT" or obj.original.hide_render:
            continue
        name = instance_name(object_instance)
        matrix = np.array(object_instance.matrix_world, dtype=np.float64)
        # The columns of the object-to-world matrix are the light's axes in world
        # space; their lengths are the object's scale.
        axes = matrix[:3, :3]
        scale = np.linalg.norm(axes, axis=0)
        if not np.all(scale > 0.0):
            warnings.append(f"Whitted: light '{name}' has a zero scale; skipped")
            continue
        light = _convert_light(name, obj.data, matrix[:3, 3], axes / scale, scale, warnings)
        if light is not None:
            lights.append(light)
    return lights


def _convert_light(name, light, position, unit_axes, scale, warnings):
    common = {
        "name": name,
        "type": light.type,
        "position": tuple(position),
        # The light travels along its local -Z axis.
        "direction": tuple(-unit_axes[:, 2]),
        "cast_shadows": light.use_shadow,
    }
    color = _light_color(light)
    if light.type in {"POINT", "SPOT"}:
        # Power P in W spread over the whole sphere: I = P / (4 pi) W/sr. Cycles does
        # not renormalise a spot to its cone, so neither do we.
        intensity = tuple(light.energy / (4.0 * math.pi) * c for c in color)
        if light.type == "POINT":
            return LightData(color=intensity, **common)
        return LightData(
            color=intensity, spot_size=light.spot_size, spot_blend=light.spot_blend, **common
        )
    if light.type == "SUN":
        # Strength is the irradiance on a surface facing the sun, W/m^2.
        return LightData(color=tuple(light.energy * c for c in color), **common)
    if light.type == "AREA":
        shape = _AREA_SHAPES[light.shape]
        # size (and size_y for rectangles and ellipses) are local lengths: the
        # object's scale along local X and Y makes them world lengths.
        size_y = light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size
        size = (light.size * scale[0], size_y * scale[1])
        area = size[0] * size[1] * (math.pi / 4.0 if shape == "ELLIPSE" else 1.0)
        # One-sided radiance L = P / (4 A) W/(m^2 sr), as Cycles. Blender 4.x's
        # `normalize` off keeps the power per unit area: L = P / 4 whatever the size.
        normalize = getattr(light, "normalize", True)
        per_area = 1.0 / area if normalize and area > 0.0 else 1.0
        return LightData(
            color=tuple(light.energy / 4.0 * per_area * c for c in color),
            size=size,
            axis_u=tuple(unit_axes[:, 0]),
            axis_v=tuple(unit_axes[:, 1]),
            shape=shape,
            samples=AREA_SAMPLES,
            **common,
        )
    warnings.append(f"Whitted: light '{name}' is of type {light.type}, which Whitted skips")
    return None


def _light_color(light):
    color = tuple(light.color)
    # Blender 4.x+: a blackbody temperature can tint the colour ...
    if getattr(light, "use_temperature", False):
        color = tuple(c * t for c, t in zip(color, light.temperature_color, strict=True))
    # ... and the exposure (in stops) scales the power: x 2^exposure.
    exposure = 2.0 ** getattr(light, "exposure", 0.0)
    return tuple(exposure * c for c in color)
