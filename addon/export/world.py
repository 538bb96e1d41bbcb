"""The world: the background a missed ray sees, and the light it gives surfaces.

In the Blender local model the world is a light at infinite distance (native
scene/world_light.h): feelers go to it from every shading point, drawn from an
importance map of its radiance, wherever it lights diffuse surfaces (its Ray
Visibility), as Cycles shows direct light. In the Lecture model, or where it lights
nothing, the seed's ambient term `Ia * ka` stands for it.

The Background node's Color and Strength may be driven by a graph (an
Environment Texture of an HDRI, with its Mapping, say): then the world gets a
shader program (export/nodes), which the native scene runs by direction for
every ray that misses, and from which it takes the ambient light: its
cosine-weighted mean over the upper hemisphere (scene.h world_upward_mean).
"""

import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from .nodes import ops, surface_node, uses_nodes
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT, evaluate
from .nodes.program import emit
from .nodes.values import UNBOUNDED_AO_DISTANCE, Lowering
from .unrendered import volume_warning
from .volume import Medium, NotRendered, volume_medium

Color = tuple[float, float, float]


@dataclass(frozen=True)
class WorldData:
    background: Color  # radiance of a ray that hits nothing, W/(m^2 sr), without program
    ambient: Color  # Ia of the Phong ambient term ka * Ia * kd, without program
    program: object = None  # nodes.program.ProgramData: radiance by direction, or None
    output: int = 0  # the register holding the radiance after the program
    textures: tuple = ()  # ImageTextureSpec the program samples
    # With a program: Ia is this times its upward mean, computed by the native scene.
    ambient_strength: float = 0.0
    # A Sky Texture's sun disc seen in the program's output: (unit direction towards it,
    # world space, Blender's axes; its angular diameter in radians), else None.
    sun: tuple | None = None
    light: "WorldLightData" = None  # how it lights surfaces (None: no world)
    # World > Ray Visibility: whether camera, glossy (reflected) and transmission
    # (refracted) rays see it; the others see black, as in Cycles.
    visibility: tuple = (True, True, True)
    # The world's Volume output: an export.volume.Medium filling all space, or None.
    medium: object = None


# Cycles' importance map when World > Settings > Sampling is Auto and no image sets it,
# and the widest map Auto takes from an image (evaluating the world at every texel is
# the map's cost: 2048 x 1024 texels, 4 directions each).
AUTO_MAP = (1024, 512)
AUTO_MAP_LIMIT = 2048


@dataclass(frozen=True)
class WorldLightData:
    """The native Scene.set_world_light's arguments (scene/world_light.h)."""

    on: bool
    why: str  # the effects report's words, on or off
    width: int = 0  # importance map texels; 0 x 0: none (one colour, Sampling None)
    height: int = 0
    diffuse: bool = True  # Ray Visibility > Diffuse
    glossy: bool = True  # Ray Visibility > Glossy
    max_bounces: int = 1024  # World > Settings > Light Paths > Max Bounces
    # A sky's sun disc (WorldData.sun): unit direction towards it, angular diameter
    # (radians; 0: none).
    sun_direction: tuple = (0.0, 0.0, 1.0)
    sun_angle: float = 0.0


def ao_distance(world):
    """The distance Ambient Occlusion nodes of unlinked Distance 0 reach: the World's AO
    distance (Cycles' Fast GI Distance, World.light_settings.distance, Blender units), or
    unbounded without a world (Cycles' default)."""
    return UNBOUNDED_AO_DISTANCE if world is None else world.light_settings.distance


def convert_world(world, ambient_strength, warnings, local_model="BLENDER"):
    """Convert the scene's world (None renders black, as in Cycles).

    `local_model` (scene.whitted.local_model): BLENDER lights surfaces with the world
    as a light where it lights diffuse surfaces (then there is no ambient term);
    LECTURE keeps the seed's ambient term, which `ambient_strength`
    (scene.whitted.ambient_strength) scales (0 turns it off).
    """
    data = _convert_world(world, ambient_strength, warnings)
    data = replace(
        data,
        light=world_light(world, data, local_model),
        visibility=_seen_by(world),
        medium=world_medium(world, warnings),
    )
    if data.light.on:
        black = (0.0, 0.0, 0.0)
        return replace(data, ambient=black, ambient_strength=0.0)
    return data


def world_medium(world, warnings):
    """The world's Volume output as a homogeneous Medium filling all space, as Cycles
    fills it (export/volume.py's coefficients); None where nothing is linked, or where it
    is a volume shader not rendered here (then warned)."""
    if world is None or not uses_nodes(world):
        return None
    output_node = world.node_tree.get_output_node("CYCLES")
    if output_node is None:
        return None
    owner = f"world '{world.name}'"
    try:
        found = volume_medium(output_node, Lowering(owner, []))
    except NotRendered as why:
        warnings.append(volume_warning(owner, output_node, str(why)))
        return None
    if found is not None and not isinstance(found, Medium):
        warnings.append(
            volume_warning(owner, output_node, "a world's volume that nodes drive is not rendered")
        )
        return None
    return found


def _seen_by(world):
    """(camera, glossy, transmission): World > Ray Visibility's, all on without one."""
    visibility = None if world is None else getattr(world, "cycles_visibility", None)
    if visibility is None:
        return (True, True, True)
    return (bool(visibility.camera), bool(visibility.glossy), bool(visibility.transmission))


def world_light(world, data, local_model):
    """The WorldLightData of a converted world: on in the Blender local model wherever
    the world lights diffuse surfaces and is not black."""
    if world is None:
        return WorldLightData(False, "no world")
    if local_model == "LECTURE":
        return WorldLightData(
            False, "the Lecture local model: the ambient term Ia*ka stands for it"
        )
    if not lights_diffuse(world):
        return WorldLightData(
            False, "the world lights no diffuse surface (World > Ray Visibility > Diffuse off)"
        )
    if data.program is None and max(data.background) <= 0.0:
        return WorldLightData(False, "the world is black")
    visibility = getattr(world, "cycles_visibility", None)
    glossy = True if visibility is None else bool(visibility.glossy)
    settings = getattr(world, "cycles", None)
    bounces = 1024 if settings is None else int(getattr(settings, "max_bounces", 1024))
    common = {"glossy": glossy, "max_bounces": bounces}
    if data.program is None:
        return WorldLightData(True, "a world of one colour: feelers by the cosine", **common)
    wanted = _map(world, data.textures)
    if wanted is None:
        return WorldLightData(
            True,
            "no importance map (World > Settings > Sampling None): feelers by the cosine",
            **common,
        )
    (width, height), source = wanted
    why = f"map {width}x{height} ({source})"
    if data.sun is not None:
        # A sky's sun disc: sampled as its own part, so a tiny bright disc gives no
        # fireflies (the map alone would spread it over a texel or two).
        direction, diameter = data.sun
        common.update(sun_direction=tuple(direction), sun_angle=float(diameter))
        why += f", sun disc {math.degrees(diameter):.2g} degrees sampled apart"
    return WorldLightData(True, why, width, height, **common)


def map_size(world):
    """The importance map a world's light asks for, (width, height), read from its
    settings and images alone (the memory guard's estimate, before any export): (0, 0)
    where it has none."""
    if world is None or not uses_nodes(world) or not lights_diffuse(world):
        return (0, 0)
    images = [
        SimpleNamespace(image=node.image)
        for node in world.node_tree.nodes
        if node.bl_idname == "ShaderNodeTexEnvironment" and node.image is not None
    ]
    wanted = _map(world, images)
    return (0, 0) if wanted is None else wanted[0]


def _map(world, textures):
    """((width, height), its source) of the importance map World > Settings > Sampling
    asks for (None: Sampling None). Manual: its Map Resolution by half of it; Auto: the
    widest image the world reads (`textures`' images), by half of it, at most
    AUTO_MAP_LIMIT wide, else AUTO_MAP."""
    settings = getattr(world, "cycles", None)
    method = "AUTOMATIC" if settings is None else settings.sampling_method
    if method == "NONE":
        return None
    if method == "MANUAL":
        side = int(settings.sample_map_resolution)
        return (side, max(1, side // 2)), "Manual"
    widths = [spec.image.size[0] for spec in textures if hasattr(spec, "image")]
    widths = [w for w in widths if w > 0]
    if not widths:
        return AUTO_MAP, "Auto, procedural"
    width = min(max(widths), AUTO_MAP_LIMIT)
    return (width, max(1, width // 2)), f"Auto, image {max(widths)} wide"


def _convert_world(world, ambient_strength, warnings):
    # A uniform sky of radiance L lights an open surface with irradiance pi*L, of
    # which the diffuse term kd/pi * E keeps kd*L: the ambient term with Ia = L,
    # which the scene's ambient strength scales. For a sky that varies (a program), L
    # is what a surface facing up (+Z) receives: E/pi, the sky's cosine-weighted mean
    # over the upper hemisphere, which the native scene computes by running the
    # program. A world set not to light diffuse surfaces (Cycles' ray visibility)
    # gives no ambient light.
    if world is not None and not lights_diffuse(world):
        ambient_strength = 0.0
    if world is None:
        background = (0.0, 0.0, 0.0)
    elif uses_nodes(world):
        found = _programmed(world, ambient_strength, warnings)
        if isinstance(found, WorldData):
            return found
        background = _other_surface(world, warnings) if found is None else found
    else:
        background = tuple(world.color)
    ambient = tuple(c * ambient_strength for c in background)
    return WorldData(background, ambient)


def lights_diffuse(world):
    """Whether the world lights diffuse surfaces: World > Settings > Ray Visibility >
    Diffuse, `world.cycles_visibility.diffuse` (Cycles' property group, in Blender 3.x
    and 4.x/5.x alike; absent only without the Cycles add-on: then it does)."""
    visibility = getattr(world, "cycles_visibility", None)
    return True if visibility is None else bool(visibility.diffuse)


def _other_surface(world, warnings):
    """The radiance of a world whose surface is not a Background node: none without a
    shader, else the world's viewport colour, warned."""
    node = surface_node(world.node_tree)
    if node is None:
        return (0.0, 0.0, 0.0)
    warnings.append(
        f"Whitted: world '{world.name}': the surface shader '{node.name}' is not a "
        "Background node; using the world's viewport colour"
    )
    return tuple(world.color)


def _programmed(world, ambient_strength, warnings):
    """The WorldData of a Background node whose inputs vary by direction; for a graph
    that folds to a constant (an RGB node, maths on constants), that radiance; None
    when it is not a Background node (then the constant path reads it)."""
    output_node = world.node_tree.get_output_node("CYCLES")
    if output_node is None:
        return None
    found, _ = source(output_node.inputs["Surface"])
    if found is None or found.node.bl_idname != "ShaderNodeBackground":
        return None
    owner = f"world '{world.name}'"
    messages = []
    lowering = Lowering(owner, messages, world=True)
    node = found.node
    color = lowering.value(node.inputs["Color"], found.scope, COLOR)
    strength = lowering.value(node.inputs["Strength"], found.scope, FLOAT)
    radiance = lowering.b.vmul(color, strength)
    for message in messages:
        _warn(warnings, message)
    if radiance.is_const:
        return tuple(radiance.value[:3])
    program, outputs = emit({"emission": radiance})
    textures = tuple(lowering.textures[name] for name in program.textures)
    black = (0.0, 0.0, 0.0)
    sun = _visible_sun(lowering.suns, radiance)
    return WorldData(black, black, program, outputs["emission"], textures, ambient_strength, sun)


# The INPUT modes that give a world program the ray's direction.
_DIRECTION_INPUTS = ("IN_POSITION", "IN_NORMAL", "IN_GENERATED", "IN_OBJECT")


def _at(expr, direction):
    """`expr` (four floats) for the world ray `direction`: NaN where it reads anything
    but the direction (an image, say)."""
    modes = {getattr(ops, name) for name in _DIRECTION_INPUTS}

    def leaf(node):
        if node.op == ops.INPUT and node.mode in modes:
            return (*direction, 0.0)
        return (math.nan,) * 4

    return np.array(evaluate(expr, leaf)[:3], dtype=np.float64)


def _world_direction(vector, target):
    """The world direction that `vector` (a sky's Vector, an Expr of the ray's
    direction) maps to `target`, when that map is linear (the node's or a Mapping
    node's rotation and scale, no translation); else None."""
    basis = np.eye(3)
    columns = np.stack([_at(vector, axis) for axis in basis], axis=1)
    origin = _at(vector, (0.0, 0.0, 0.0))
    linear = np.allclose(origin, 0.0, atol=1e-6) and np.allclose(
        _at(vector, (1.0, 1.0, 1.0)), columns.sum(axis=1), rtol=1e-4, atol=1e-6
    )
    if not (np.all(np.isfinite(columns)) and linear) or abs(np.linalg.det(columns)) < 1e-12:
        return None
    direction = np.linalg.solve(columns, np.asarray(target, dtype=np.float64))
    return direction / np.linalg.norm(direction)


def _visible_sun(suns, radiance):
    """(direction, angular diameter) of the first sky sun disc that the world's
    `radiance` shows: at its centre at least twice as bright as beside it (a disc the
    graph darkens away, or mixes out, is not a sun). None without one."""
    for vector, target, diameter in suns:
        direction = _world_direction(vector, target)
        if direction is None:
            continue
        # Beside the disc: turned away from it by three diameters about a perpendicular.
        side = np.cross(direction, (0.0, 0.0, 1.0) if abs(direction[2]) < 0.9 else (1.0, 0, 0))
        side /= np.linalg.norm(side)
        angle = max(3.0 * diameter, 0.01)
        beside = direction * math.cos(angle) + side * math.sin(angle)
        centre, around = _at(radiance, direction).sum(), _at(radiance, beside).sum()
        if math.isfinite(centre) and math.isfinite(around) and centre > 2.0 * around:
            return (tuple(float(x) for x in direction), float(diameter))
    return None
