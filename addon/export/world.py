"""The world: the background a missed ray sees, and the ambient light Ia.

The Background node's Color and Strength may be driven by a graph (an
Environment Texture of an HDRI, with its Mapping, say): then the world gets a
shader program (export/nodes), evaluated by
direction for every ray that misses; `background` is its mean over the sphere and
the ambient light its cosine-weighted mean over the upper hemisphere (below).
"""

from dataclasses import dataclass

import numpy as np

from .nodes import ops, surface_node, uses_nodes
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT, evaluate
from .nodes.program import emit, run
from .nodes.values import Lowering
from .unrendered import volume_warning

Color = tuple[float, float, float]


@dataclass(frozen=True)
class WorldData:
    background: Color  # radiance of a ray that hits nothing, W/(m^2 sr) (its mean)
    ambient: Color  # Ia of the Phong ambient term ka * Ia * kd
    program: object = None  # nodes.program.ProgramData: radiance by direction, or None
    output: int = 0  # the register holding the radiance after the program
    textures: tuple = ()  # ImageTextureSpec the program samples


def convert_world(world, ambient_strength, warnings):
    """Convert the scene's world (None renders black, as in Cycles).

    `ambient_strength` (scene.whitted.ambient_strength) scales the ambient light
    the world gives; 0 turns the ambient term off.
    """
    program, output, textures = None, 0, ()
    sky = None  # the ambient's radiance when it differs from the background's
    if world is None:
        background = (0.0, 0.0, 0.0)
    elif uses_nodes(world):
        output_node = world.node_tree.get_output_node("CYCLES")
        volume = (
            None if output_node is None else volume_warning(f"world '{world.name}'", output_node)
        )
        if volume is not None:
            warnings.append(volume)
        found = _programmed(world, warnings)
        if found is not None:
            background, sky, program, output, textures = found
        else:
            background = _other_surface(world, warnings)
    else:
        background = tuple(world.color)
    # A uniform sky of radiance L lights an open surface with irradiance pi*L, of
    # which the diffuse term kd/pi * E keeps kd*L: the ambient term with Ia = L,
    # which the scene's ambient strength scales. For a sky that varies, L is what a
    # surface facing up (+Z) receives: E/pi, the sky's cosine-weighted mean over the
    # upper hemisphere. A world set not to light diffuse surfaces (Cycles' ray
    # visibility) gives no ambient light.
    if world is not None and not lights_diffuse(world):
        ambient_strength = 0.0
    ambient = tuple(c * ambient_strength for c in (background if sky is None else sky))
    return WorldData(background, ambient, program, output, textures)


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


def _programmed(world, warnings):
    """(mean radiance, up-facing ambient radiance, ProgramData, output register,
    textures) of a Background node whose inputs vary by direction; for a graph that
    folds to a constant (an RGB node, maths on constants), (that radiance, None, None,
    0, ()); None when it is not a Background node (then the constant path reads it)."""
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
        return tuple(radiance.value[:3]), None, None, 0, ()
    program, outputs = emit({"emission": radiance})
    textures = tuple(lowering.textures[name] for name in program.textures)
    means = {spec.name: _mean_radiance(spec, warnings) for spec in textures}

    def stand_in(expr):
        # A texture counts as its mean over the sphere; anything else as 0.
        if expr.op in (ops.ENVIRONMENT, ops.IMAGE):
            return means[expr.e]
        return (0.0, 0.0, 0.0, 0.0)

    mean = evaluate(radiance, stand_in)
    sky = _cosine_mean(program, outputs["emission"], textures, warnings)
    return tuple(mean[:3]), sky, program, outputs["emission"], textures


# The ambient's quadrature: this many by this many cells of the unit square, mapped to
# directions over the upper hemisphere with density cos(theta)/pi (Malley's method),
# one direction at each cell's centre.
AMBIENT_CELLS = 24


def _cosine_mean(program, output, textures, warnings):
    """The world's radiance averaged over the upper hemisphere with weight
    cos(theta)/pi, theta from +Z: E/pi for a surface facing up. The program runs in
    Python (program.run) at AMBIENT_CELLS^2 directions, the images read at their
    nearest texel; None (then the sphere mean is used) for an Image Texture or an op
    without a Python definition."""
    if any(int(row[0]) == ops.IMAGE for row in program.code):
        return None  # an Image Texture by direction: its projections are not modelled here
    lookups = {spec.name: _texture_lookup(spec, warnings) for spec in textures}
    centres = (np.arange(AMBIENT_CELLS) + 0.5) / AMBIENT_CELLS
    total = np.zeros(3)
    for u1 in centres:
        radius, z = np.sqrt(u1), np.sqrt(1.0 - u1)
        for u2 in centres:
            phi = 2.0 * np.pi * u2
            direction = (radius * np.cos(phi), radius * np.sin(phi), z, 0.0)
            try:
                registers = run(program, _world_inputs(direction), lookups)
            except KeyError:
                return None  # an op the Python reference does not define
            total += registers[output][:3]
    return tuple(float(x) for x in total / AMBIENT_CELLS**2)


def _world_inputs(direction):
    # What the world program reads for a ray leaving in `direction` (the contract's
    # world inputs), as a diffuse ray one bounce deep.
    x, y, z, _ = direction
    inputs = {
        mode: direction
        for mode in (ops.IN_POSITION, ops.IN_NORMAL, ops.IN_GENERATED, ops.IN_OBJECT)
    }
    inputs[ops.IN_INCOMING] = (-x, -y, -z, 0.0)
    for mode in range(ops.IN_IS_CAMERA_RAY, ops.IN_IS_SINGULAR_RAY + 1):
        inputs[mode] = (0.0,) * 4
    inputs[ops.IN_IS_DIFFUSE_RAY] = (1.0,) * 4
    inputs[ops.IN_RAY_DEPTH] = (1.0,) * 4
    return _ZeroDefault(inputs)


class _ZeroDefault(dict):
    # Inputs a world does not have read 0, as the native world program's do.
    def __missing__(self, key):
        return (0.0,) * 4


def _texture_lookup(spec, warnings):
    """function(vector, mode) -> rgba of an ENVIRONMENT image (equirectangular or
    mirror ball, the native program's mappings), nearest texel."""
    from .texture import image_pixels

    pixels = image_pixels(spec.image, warnings).astype(np.float64)
    height, width = pixels.shape[:2]

    def texel(u, v):
        x = int(np.floor(u * width)) % width
        y = min(max(int(np.floor(v * height)), 0), height - 1)
        return tuple(pixels[y, x])

    def lookup(vector, mode):
        x, y, z = vector[:3]
        length = float(np.sqrt(x * x + y * y + z * z))
        if length == 0.0:
            return texel(0.0, 0.0)
        x, y, z = x / length, y / length, z / length
        if mode == 0:  # equirectangular
            u = (np.arctan2(y, x) - np.pi) / (-2.0 * np.pi)
            v = (np.arccos(min(max(z, -1.0), 1.0)) - np.pi) / -np.pi
            return texel(u, v)
        # Mirror ball, seen from -Y.
        y -= 1.0
        div = 2.0 * np.sqrt(max(-0.5 * y, 0.0))
        if div > 0.0:
            x, z = x / div, z / div
        return texel(0.5 * (x + 1.0), 0.5 * (z + 1.0))

    return lookup


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
