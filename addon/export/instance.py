"""Names of the objects that the evaluated depsgraph yields, instances included."""

# Blender pads unused levels of DepsgraphObjectInstance.persistent_id with INT_MAX.
_UNUSED_ID = 2**31 - 1


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
