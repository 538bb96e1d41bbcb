"""The world: the background a missed ray sees, and the ambient light Ia.

The Background node's Color and Strength may be driven by a graph (an
Environment Texture of an HDRI, with its Mapping, say): then, when the native
module runs shader programs, the world gets one (export/nodes), evaluated by
direction for every ray that misses; `background` is its mean.
"""

from dataclasses import dataclass

import numpy as np

from .nodes import input_value, ops, surface_node, uses_nodes
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT, evaluate
from .nodes.program import emit
from .nodes.values import Lowering

Color = tuple[float, float, float]


@dataclass(frozen=True)
class WorldData:
    background: Color  # radiance of a ray that hits nothing, W/(m^2 sr) (its mean)
    ambient: Color  # Ia of the Phong ambient term ka * Ia * kd
    program: object = None  # nodes.program.ProgramData: radiance by direction, or None
    output: int = 0  # the register holding the radiance after the program
    textures: tuple = ()  # ImageTextureSpec the program samples


def convert_world(world, ambient_strength, warnings, programs=False):
    """Convert the scene's world (None renders black, as in Cycles).

    `ambient_strength` (scene.whitted.ambient_strength) scales the ambient light
    the world gives; 0 turns the ambient term off. `programs`: whether the native
    module runs shader programs (for a graph-driven background).
    """
    program, output, textures = None, 0, ()
    if world is None:
        background = (0.0, 0.0, 0.0)
    elif uses_nodes(world):
        background = None
        if programs:
            found = _programmed(world, warnings)
            if found is not None:
                background, program, output, textures = found
        if background is None:
            background = _background_node_radiance(world, warnings)
    else:
        background = tuple(world.color)
    # A uniform sky of radiance L lights an open surface with irradiance pi*L, of
    # which the diffuse term kd/pi * E keeps kd*L: the ambient term with Ia = L,
    # which the scene's ambient strength scales (for a sky that varies, L is its
    # mean over all directions). A world set not to light diffuse surfaces
    # (Cycles' ray visibility) gives no ambient light.
    if world is not None and not lights_diffuse(world):
        ambient_strength = 0.0
    ambient = tuple(c * ambient_strength for c in background)
    return WorldData(background, ambient, program, output, textures)


def lights_diffuse(world):
    """Whether the world lights diffuse surfaces: World > Settings > Ray Visibility >
    Diffuse, `world.cycles_visibility.diffuse` (Cycles' property group, in Blender 3.x
    and 4.x/5.x alike; absent only without the Cycles add-on: then it does)."""
    visibility = getattr(world, "cycles_visibility", None)
    return True if visibility is None else bool(visibility.diffuse)


def _background_node_radiance(world, warnings):
    owner = f"world '{world.name}'"
    node = surface_node(world.node_tree)
    if node is None:
        return (0.0, 0.0, 0.0)
    if node.bl_idname != "ShaderNodeBackground":
        warnings.append(
            f"Whitted: {owner}: the surface shader '{node.name}' is not a Background node; "
            "using the world's viewport colour"
        )
        return tuple(world.color)
    color = input_value(node, ("Color",), (0.05, 0.05, 0.05, 1.0), owner, warnings)
    strength = input_value(node, ("Strength",), 1.0, owner, warnings)
    # The Background node emits Color * Strength as radiance.
    return tuple(c * strength for c in color[:3])


def _programmed(world, warnings):
    """(mean radiance, ProgramData, output register, textures) of a Background node
    whose inputs vary by direction; None when they are constant or it is not a
    Background node (then the constant path reads it)."""
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
    if radiance.is_const:
        return None
    for message in messages:
        _warn(warnings, message)
    program, outputs = emit({"emission": radiance})
    textures = tuple(lowering.textures[name] for name in program.textures)
    means = {spec.name: _mean_radiance(spec, warnings) for spec in textures}

    def stand_in(expr):
        # A texture counts as its mean over the sphere; anything else as 0.
        if expr.op in (ops.ENVIRONMENT, ops.IMAGE):
            return means[expr.e]
        return (0.0, 0.0, 0.0, 0.0)

    mean = evaluate(radiance, stand_in)
    return tuple(mean[:3]), program, outputs["emission"], textures


def _mean_radiance(spec, warnings):
    """An equirectangular image's mean over the sphere: each row weighted by the
    solid angle it covers (cos latitude)."""
    from .texture import image_pixels

    pixels = image_pixels(spec.image, warnings).astype(np.float64)
    height = pixels.shape[0]
    latitude = (np.arange(height) + 0.5) / height * np.pi - np.pi / 2.0
    weights = np.cos(latitude)
    rows = pixels.mean(axis=1)
    mean = (rows * weights[:, None]).sum(axis=0) / weights.sum()
    return tuple(float(x) for x in mean)
