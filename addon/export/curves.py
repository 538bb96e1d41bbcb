"""Hair, curves and point clouds as plain data: keys and spheres (x, y, z, radius, in
the object's own space) read from the evaluated depsgraph, as Cycles reads them
(intern/cycles/blender/curves.cpp, pointcloud.cpp).

- Curves objects (Blender 3.3+ hair curves, curves from geometry nodes on a Curves
  object): the control points as keys, the `radius` point attribute (Cycles' 0.005
  where there is none), a material slot per curve from `material_index`.
- Particle hair (a Hair particle system drawn as Path): each strand's keys as Blender
  evaluates them for the render (children when there are any, as Cycles takes them;
  `(1 << steps) + 1` keys a strand), through ParticleSystem.co_hair, the only way
  Blender gives children's keys: one call a key (about 1 microsecond, measured in 3.4
  and 5.2), world space made object space here. The radius along a strand as Cycles
  shapes it from the particle settings' root and tip (below).
- Point clouds: the points and their `radius` attribute (Cycles' 0.01 where none).

The curves' shape is the scene's (Render > Curves > Shape, `scene.cycles_curves`): Thick
(round tubes), Ribbons (`flat`: ribbons facing each ray, shaded as tubes; Cycles' default)
or, in 5.x, Thick Linear (`linear`), which 5.x also takes for poly curves.

Units: Blender's scene units (metres), the radius a radius (Blender's root and tip
"radius" of particle hair is halved, as Cycles halves it: the settings are diameters).
"""

import itertools
from dataclasses import dataclass

import numpy as np

# The object types whose data is curves or points.
STRAND_TYPES = ("CURVES", "POINTCLOUD")

# Blender's curve type POLY (the `curve_type` attribute): straight from point to point.
CURVE_TYPE_POLY = 1

# Cycles' radii where the data has no radius attribute.
DEFAULT_CURVE_RADIUS = 0.005
DEFAULT_POINT_RADIUS = 0.01


@dataclass(frozen=True)
class CurvesData:
    """Strands: keys float32[K, 4] (x, y, z, radius), counts uint32[C] keys of each
    strand in order, slots int32[C] material slot of each."""

    keys: np.ndarray
    counts: np.ndarray
    slots: np.ndarray
    # Straight from key to key (Cycles' Thick Linear), not Catmull-Rom through the keys.
    linear: bool = False
    # Flat ribbons facing each ray, shaded as round tubes (Cycles' Ribbons), not tubes.
    flat: bool = False

    def __len__(self):
        return len(self.counts)


@dataclass(frozen=True)
class PointsData:
    """Spheres float32[P, 4] (x, y, z, radius) and slots int32[P]."""

    spheres: np.ndarray
    slots: np.ndarray

    def __len__(self):
        return len(self.spheres)


def _attribute(geometry, name, domain, data_type, size, width=1):
    # A named attribute of `geometry` (Curves, PointCloud) as float32 or int32[size *
    # width] read in one call, or None when it has no such attribute.
    attribute = geometry.attributes.get(name)
    if attribute is None or attribute.domain != domain or attribute.data_type != data_type:
        return None
    dtype = np.int32 if data_type == "INT" else np.float32
    out = np.empty(size * width, dtype=dtype)
    field = {"FLOAT_VECTOR": "vector", "FLOAT": "value", "INT": "value"}[data_type]
    attribute.data.foreach_get(field, out)
    return out


def thick_linear(scene):
    """Whether Cycles here draws poly curves straight (Thick Linear, Blender 5.0+), and
    the scene's curve shape (Render > Curves) asks for it on the rest."""
    settings = getattr(scene, "cycles_curves", None)
    if settings is None:
        return False, False
    shapes = {item.identifier for item in settings.bl_rna.properties["shape"].enum_items}
    return "THICK_LINEAR" in shapes, settings.shape == "THICK_LINEAR"


def flat_curves(scene):
    """Whether the scene's curve shape (Render > Curves > Shape) is Ribbons, Cycles'
    default: strands as flat ribbons turned to face each ray."""
    settings = getattr(scene, "cycles_curves", None)
    return settings is not None and settings.shape == "RIBBONS"


def curves_data(curves, scene=None):
    """CurvesData of an evaluated Curves data-block (a CURVES object's data). As Cycles
    5.x, poly curves (by the first curve's type) are straight from point to point, round
    whatever the scene's shape; other curves take the scene's shape."""
    points = len(curves.points)
    count = len(curves.curves)
    positions = _attribute(curves, "position", "POINT", "FLOAT_VECTOR", points, 3)
    if count == 0 or points == 0 or positions is None:  # (5.x keeps no offsets for none)
        return CurvesData(
            keys=np.zeros((0, 4), np.float32),
            counts=np.zeros(0, np.uint32),
            slots=np.zeros(0, np.int32),
        )
    offsets = np.empty(count + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    radius = _attribute(curves, "radius", "POINT", "FLOAT", points)
    keys = np.empty((points, 4), dtype=np.float32)
    keys[:, :3] = positions.reshape(points, 3)
    keys[:, 3] = DEFAULT_CURVE_RADIUS if radius is None else radius
    slots = _attribute(curves, "material_index", "CURVE", "INT", count)
    poly_straight, shape_straight = thick_linear(scene) if scene is not None else (False, False)
    types = curves.attributes.get("curve_type")
    poly = types is not None and len(types.data) > 0 and types.data[0].value == CURVE_TYPE_POLY
    return CurvesData(
        keys=keys,
        counts=np.diff(offsets).astype(np.uint32),
        slots=np.zeros(count, dtype=np.int32) if slots is None else slots,
        linear=(poly and poly_straight) or shape_straight,
        flat=not (poly and poly_straight) and scene is not None and flat_curves(scene),
    )


def strands_data(obj, scene):
    """The CurvesData or PointsData of an evaluated CURVES or POINTCLOUD object."""
    return curves_data(obj.data, scene) if obj.type == "CURVES" else points_data(obj.data)


def points_data(pointcloud):
    """PointsData of an evaluated PointCloud data-block."""
    count = len(pointcloud.points)
    positions = _attribute(pointcloud, "position", "POINT", "FLOAT_VECTOR", count, 3)
    if count == 0 or positions is None:  # (5.x keeps no positions for no points)
        return PointsData(spheres=np.zeros((0, 4), np.float32), slots=np.zeros(0, np.int32))
    radius = _attribute(pointcloud, "radius", "POINT", "FLOAT", count)
    spheres = np.empty((count, 4), dtype=np.float32)
    spheres[:, :3] = positions.reshape(count, 3)
    spheres[:, 3] = DEFAULT_POINT_RADIUS if radius is None else radius
    slots = _attribute(pointcloud, "material_index", "POINT", "INT", count)
    return PointsData(
        spheres=spheres, slots=np.zeros(count, dtype=np.int32) if slots is None else slots
    )


def hair_systems(obj, render):
    """The particle systems of evaluated object `obj` a render draws as strands: Hair
    systems rendered as Path whose modifier is on (for renders, or in the viewport)."""
    enabled = "show_render" if render else "show_viewport"
    systems = []
    for modifier in obj.modifiers:
        if modifier.type != "PARTICLE_SYSTEM" or not getattr(modifier, enabled):
            continue
        system = modifier.particle_system
        if system.settings.type == "HAIR" and system.settings.render_type == "PATH":
            systems.append(system)
    return systems


def particle_hair_data(obj, render, scene=None):
    """CurvesData of the particle hair of evaluated object `obj` (hair_systems), in its
    object space, or None when it has none."""
    parts = [_system_strands(obj, system, render) for system in hair_systems(obj, render)]
    parts = [part for part in parts if part is not None]
    if not parts:
        return None
    return CurvesData(
        keys=np.concatenate([p.keys for p in parts]),
        counts=np.concatenate([p.counts for p in parts]),
        slots=np.concatenate([p.slots for p in parts]),
        linear=scene is not None and thick_linear(scene)[1],
        flat=scene is not None and flat_curves(scene),
    )


def _strands(system, render):
    # (keys a strand, the first strand drawn, the strands drawn) of a hair system. With
    # children, Cycles draws only them (the parents guide them).
    settings = system.settings
    steps = (1 << (settings.render_step if render else settings.display_step)) + 1
    if settings.kink == "SPIRAL":
        steps += settings.kink_extra_steps
    parents = len(system.particles)
    children = len(system.child_particles)
    if not render:
        children = int(children * settings.display_percentage / 100)
    first = parents if settings.child_type != "NONE" and children > 0 else 0
    return steps, first, parents + children - first


def hair_keys(system, render):
    """The keys of a hair system's strands as a render draws them (a count only)."""
    steps, _, strands = _strands(system, render)
    return steps * strands


def _system_strands(obj, system, render):
    settings = system.settings
    steps, first, strands = _strands(system, render)
    if strands <= 0:
        return None
    co = system.co_hair
    world = np.fromiter(
        itertools.chain.from_iterable(
            co(obj, particle_no=p, step=s)
            for p in range(first, first + strands)
            for s in range(steps)
        ),
        dtype=np.float32,
        count=strands * steps * 3,
    ).reshape(strands, steps, 3)
    # World to object space: the hair moves with its emitter's instances.
    inverse = np.array(obj.matrix_world.inverted(), dtype=np.float32)
    local = world @ inverse[:3, :3].T + inverse[:3, 3]
    keys = np.empty((strands, steps, 4), dtype=np.float32)
    keys[..., :3] = local
    keys[..., 3] = strand_radius(local, settings)
    return CurvesData(
        keys=keys.reshape(-1, 4),
        counts=np.full(strands, steps, dtype=np.uint32),
        slots=np.full(strands, max(settings.material - 1, 0), dtype=np.int32),
    )


def strand_radius(keys, settings):
    """float32[S, K]: the radius at each key of strands keys float32[S, K, 3], as Cycles
    shapes particle hair: from half the root's Diameter to half the tip's (times Radius
    Scale) along the strand's length, bent by Shape (negative: thin sooner, positive:
    thick longer), the last key 0 with Close Tip."""
    lengths = np.linalg.norm(np.diff(keys, axis=1), axis=2)
    along = np.concatenate([np.zeros((len(keys), 1), np.float32), np.cumsum(lengths, axis=1)], 1)
    total = along[:, -1:]
    share = np.divide(along, total, out=np.zeros_like(along), where=total > 0)
    left = 1.0 - share
    shape = settings.shape
    if shape < 0.0:
        left = left ** (1.0 + shape)
    elif shape > 0.0:
        left = left ** (1.0 / max(1.0 - shape, 1e-6))
    root = 0.5 * settings.radius_scale * settings.root_radius
    tip = 0.5 * settings.radius_scale * settings.tip_radius
    radius = (left * (root - tip) + tip).astype(np.float32)
    if settings.use_close_tip:
        radius[:, -1] = 0.0
    return radius
