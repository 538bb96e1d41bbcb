"""Names, ray visibility, holdout and Cryptomatte ids of the objects that the evaluated
depsgraph yields."""

from dataclasses import dataclass

from .. import cryptomatte

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
