"""The world: the background a missed ray sees, and the ambient light Ia.

The Background node's Color and Strength may be driven by a graph (an
Environment Texture of an HDRI, with its Mapping, say): then the world gets a
shader program (export/nodes), which the native scene runs by direction for
every ray that misses, and from which it takes the ambient light: its
cosine-weighted mean over the upper hemisphere (scene.h world_upward_mean).
"""

import math
from dataclasses import dataclass

import numpy as np

from .nodes import ops, surface_node, uses_nodes
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT, evaluate
from .nodes.program import emit
from .nodes.values import Lowering
from .unrendered import volume_warning

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


def convert_world(world, ambient_strength, warnings):
    """Convert the scene's world (None renders black, as in Cycles).

    `ambient_strength` (scene.whitted.ambient_strength) scales the ambient light
    the world gives; 0 turns the ambient term off.
    """
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
        output_node = world.node_tree.get_output_node("CYCLES")
        volume = (
            None if output_node is None else volume_warning(f"world '{world.name}'", output_node)
        )
        if volume is not None:
            warnings.append(volume)
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
