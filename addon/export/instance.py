"""The instances that place a geometry: for each object the evaluated depsgraph yields,
its name, transform, material per slot, ray visibility, holdout, shadow catcher,
Object Info, Cryptomatte ids and light linking sets (InstanceData)."""

from dataclasses import dataclass

import numpy as np

from .. import cryptomatte
from .light_linking import NO_LINKS, UNLINKED
from .properties import instance_attribute

# Blender pads unused levels of DepsgraphObjectInstance.persistent_id with INT_MAX.
_UNUSED_ID = 2**31 - 1


@dataclass(frozen=True)
class RayVisibility:
    """Which rays see an instance (Object Properties > Visibility > Ray Visibility)."""

    camera: bool = True  # visible_camera
    shadow: bool = True  # visible_shadow
    reflection: bool = True  # visible_glossy
    refraction: bool = True  # visible_transmission


def instance_name(object_instance):
    """A name that stays the same across renders for one depsgraph object instance.

    A real object is named after itself; an instance (collection, geometry nodes,
    particles) after its instancer, the instanced object and its persistent id.
    """
    obj = object_instance.object
    if not object_instance.is_instance:
        return obj.original.name_full
    path = ".".join(str(i) for i in object_instance.persistent_id if i != _UNUSED_ID)
    return f"{object_instance.parent.original.name_full}/{obj.original.name_full}/{path}"


def ray_visibility(object_instance):
    """The rays that see this instance: as in Cycles, an instance must be visible
    both by its own object's flags and by its instancer's."""
    visibility = _object_visibility(object_instance.object)
    if object_instance.is_instance:
        parent = _object_visibility(object_instance.parent)
        visibility = RayVisibility(
            camera=visibility.camera and parent.camera,
            shadow=visibility.shadow and parent.shadow,
            reflection=visibility.reflection and parent.reflection,
            refraction=visibility.refraction and parent.refraction,
        )
    return visibility


# The object types whose Shadow Catcher flag Cycles reads: geometry. Blender 3.4 sets the
# flag on every new lamp (a new point lamp reads True), where it means nothing.
GEOMETRY_TYPES = frozenset(
    {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME"}
)


def is_shadow_catcher(object_instance):
    """Whether this instance is a shadow catcher (Object > Visibility > Shadow Catcher):
    camera rays that meet it show only the shadows other objects cast on it
    (integrator/catcher.h). Read on geometry only, as Cycles reads it; an instance is one
    when its object or its instancer is, as in Cycles' object sync."""
    obj = object_instance.object
    if obj.type not in GEOMETRY_TYPES:
        return False
    if obj.original.is_shadow_catcher:
        return True
    return object_instance.is_instance and object_instance.parent.original.is_shadow_catcher


def is_holdout(object_instance, view_layer):
    """Whether camera rays that hit this instance leave colour 0 and alpha 0.

    `holdout_get` covers both the object's own Holdout switch and the holdout of
    a collection it is in (per view layer); an instance takes its instancer's,
    as Cycles does. `view_layer` is the depsgraph's evaluated view layer, whose
    bases hold the evaluated objects.
    """
    owner = object_instance.parent if object_instance.is_instance else object_instance.object
    return owner.holdout_get(view_layer=view_layer)


def writes_cryptomatte(view_layer):
    """Whether the view layer asks for any Cryptomatte layer."""
    return (
        view_layer.use_pass_cryptomatte_object
        or view_layer.use_pass_cryptomatte_material
        or view_layer.use_pass_cryptomatte_asset
    )


def cryptomatte_ids(obj):
    """(object id, asset id, (material id per slot)) of evaluated object `obj`, as
    Blender hashes them: the names of the object, of its topmost parent (the asset) and
    of each slot's material (an empty slot: no id, 0)."""
    original = obj.original
    materials = tuple(
        cryptomatte.id_float(slot.material.original.name) if slot.material is not None else 0.0
        for slot in obj.material_slots
    )
    object_id = cryptomatte.id_float(original.name)
    return object_id, cryptomatte.id_float(_asset(original).name), materials or (0.0,)


def cryptomatte_names(depsgraph):
    """{kind: the names its ids come from} of the mesh instances of the depsgraph, for
    the manifests (cryptomatte.metadata)."""
    names = {kind: set() for kind in cryptomatte.KINDS}
    for object_instance in depsgraph.object_instances:
        obj = object_instance.object
        if obj.type != "MESH":
            continue
        names["CryptoObject"].add(obj.original.name)
        names["CryptoAsset"].add(_asset(obj.original).name)
        names["CryptoMaterial"].update(
            slot.material.original.name for slot in obj.material_slots if slot.material is not None
        )
    return names


def _asset(obj):
    # An object's asset is its topmost parent (itself without one), as in Blender.
    while obj.parent is not None:
        obj = obj.parent
    return obj


def _object_visibility(obj):
    return RayVisibility(
        camera=obj.visible_camera,
        shadow=obj.visible_shadow,
        reflection=obj.visible_glossy,
        refraction=obj.visible_transmission,
    )


# The tracer's default material: what an empty material slot renders with.
# Blender names are never empty, so it cannot clash with a material's name.
DEFAULT_MATERIAL = ""


@dataclass(frozen=True)
class InstanceData:
    name: str
    mesh: str  # MeshData.name
    transform: np.ndarray  # float64[4,4], row-major, object to world
    materials: tuple[str, ...]  # material name per slot, DEFAULT_MATERIAL if empty
    visibility: RayVisibility  # which rays see it
    holdout: bool  # camera rays that hit it give colour 0 and alpha 0
    # Camera rays that hit it show only the shadows cast on it (is_shadow_catcher).
    shadow_catcher: bool = False
    # (location xyz, random, pass index, colour rgba) for Object Info; None when no
    # material of the instance reads it.
    info: tuple | None = None
    # Its Object and Instancer attributes, (r, g, b, a) each, by the index its materials'
    # programs read (instance_attributes); () when none reads one.
    attributes: tuple = ()
    # (object id, asset id, (material id per slot)): its Cryptomatte ids (cryptomatte.py);
    # None when the view layer writes no Cryptomatte.
    cryptomatte: tuple | None = None
    # Its transforms over the shutter (export/motion.py MotionData), () when still.
    motion: tuple = ()
    # Light linking: (light set, shadow set, light sets it lights, shadow sets that
    # block it), export/light_linking.py.
    links: tuple = UNLINKED
    # A Volume object's grids placed in the world (whitted_native.VolumeObject, read by
    # sync/volumes.py), which its material reads inside `mesh`; None for a mesh.
    volume: object = None


def instance_data(object_instance, mesh, view_layer, info=(), links=NO_LINKS, attributes=()):
    """InstanceData of a mesh instance placing geometry `mesh` (its key).

    `view_layer` is the depsgraph's evaluated view layer (holdout is per layer);
    `info` the names of the materials that read Object Info. An object with a pass
    index sends its Object Info too, for the IndexOB pass. `links`: the scene's
    light_linking.LightLinks. `attributes`: the Object and Instancer attributes its
    materials read, ("OBJECT" | "INSTANCER", name) by index (mesh_layers.attribute_keys)."""
    materials = slot_materials(object_instance.object)
    reads_info = any(m in info for m in materials) or object_instance.object.pass_index != 0
    return InstanceData(
        name=instance_name(object_instance),
        mesh=mesh,
        # Valid only while iterating: copy it now.
        transform=np.array(object_instance.matrix_world, dtype=np.float64),
        materials=materials,
        visibility=ray_visibility(object_instance),
        holdout=is_holdout(object_instance, view_layer),
        shadow_catcher=is_shadow_catcher(object_instance),
        info=object_info(object_instance) if reads_info else None,
        attributes=instance_attributes(object_instance, attributes),
        cryptomatte=cryptomatte_ids(object_instance.object)
        if writes_cryptomatte(view_layer)
        else None,
        links=links.of_object(
            object_instance.object, object_instance.parent if object_instance.is_instance else None
        ),
    )


def object_info(object_instance):
    """(location xyz, random, pass index, colour rgba): what Object Info gives, as
    Cycles computes it: the instance's world location; its random id (an unsigned
    32-bit hash) times 1 / 0xFFFFFFFF in float32, in [0, 1]; the object's pass index
    and its colour (Object Properties > Viewport Display).

    The depsgraph gives instances their `random_id` and real objects 0; Cycles then
    hashes the object's name (hash_uint2(hash_string(name), 0), util/hash.h)."""
    obj = object_instance.object
    location = tuple(float(x) for x in object_instance.matrix_world.translation)
    random_id = getattr(object_instance, "random_id", 0) & 0xFFFFFFFF
    if random_id == 0:
        random_id = _hash_uint2(_hash_string(obj.name), 0)
    random = float(np.float32(np.float32(random_id) * np.float32(1.0 / 0xFFFFFFFF)))
    return (*location, random, float(obj.pass_index), *(float(c) for c in obj.color))


def instance_attributes(object_instance, keys):
    """The values of Object and Instancer attributes `keys` (("OBJECT" | "INSTANCER",
    name) each) for a depsgraph object instance, as Cycles looks them up
    (properties.instance_attribute): a tuple of (r, g, b, a)."""
    return tuple(
        instance_attribute(object_instance, name, instancer=kind == "INSTANCER")
        for kind, name in keys
    )


def _hash_string(text):
    # Cycles' hash_string: i = i * 37 + c over the bytes, in uint32.
    value = 0
    for byte in text.encode():
        value = (value * 37 + byte) & 0xFFFFFFFF
    return value


def _rot(x, k):
    return ((x << k) | (x >> (32 - k))) & 0xFFFFFFFF


def _hash_uint2(kx, ky):
    # Bob Jenkins' lookup3 final mix of two words (Cycles' hash_uint2).
    a = b = c = (0xDEADBEEF + (2 << 2) + 13) & 0xFFFFFFFF
    b = (b + ky) & 0xFFFFFFFF
    a = (a + kx) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 14)) & 0xFFFFFFFF
    a ^= c
    a = (a - _rot(c, 11)) & 0xFFFFFFFF
    b ^= a
    b = (b - _rot(a, 25)) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 16)) & 0xFFFFFFFF
    a ^= c
    a = (a - _rot(c, 4)) & 0xFFFFFFFF
    b ^= a
    b = (b - _rot(a, 14)) & 0xFFFFFFFF
    c ^= b
    c = (c - _rot(b, 24)) & 0xFFFFFFFF
    return c


def slot_materials(obj):
    # The evaluated object's slots already resolve object- versus data-linked materials.
    names = tuple(
        slot.material.name_full if slot.material is not None else DEFAULT_MATERIAL
        for slot in obj.material_slots
    )
    return names or (DEFAULT_MATERIAL,)
