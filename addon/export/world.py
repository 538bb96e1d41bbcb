"""The world: the background a missed ray sees, and the ambient light Ia."""

from dataclasses import dataclass

from .nodes import input_value, surface_node, uses_nodes

Color = tuple[float, float, float]


@dataclass(frozen=True)
class WorldData:
    background: Color  # radiance of a ray that hits nothing, W/(m^2 sr)
    ambient: Color  # Ia of the Phong ambient term ka * Ia * kd


def convert_world(world, ambient_strength, warnings):
    """Convert the scene's world (None renders black, as in Cycles).

    `ambient_strength` (scene.whitted.ambient_strength) scales the ambient light
    the world gives; 0 turns the ambient term off.
    """
    if world is None:
        background = (0.0, 0.0, 0.0)
    elif uses_nodes(world):
        background = _background_node_radiance(world, warnings)
    else:
        background = tuple(world.color)
    # A uniform sky of radiance L lights an open surface with irradiance pi*L, of
    # which the diffuse term kd/pi * E keeps kd*L: the ambient term with Ia = L,
    # which the scene's ambient strength scales. A world set not to light diffuse
    # surfaces (Cycles' ray visibility) gives no ambient light.
    if world is not None and not lights_diffuse(world):
        ambient_strength = 0.0
    ambient = tuple(c * ambient_strength for c in background)
    return WorldData(background=background, ambient=ambient)


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
