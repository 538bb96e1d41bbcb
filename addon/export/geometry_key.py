"""Geometry keys: the names under which a geometry is exported once for all the
instances that show it, stable across depsgraph re-evaluations."""


class GeometryKeys:
    """The geometry keys of one evaluation of a depsgraph (`geometry_key`): every
    user of one evaluated mesh gets one key, and two different evaluated meshes
    never share one (the second of them is numbered, in the depsgraph's order:
    several geometries of one instancer, or a mesh whose users evaluate
    differently)."""

    def __init__(self, render):
        self._render = render
        self._by_address = {}  # evaluated mesh address -> key
        self._taken = set()

    def key(self, object_instance):
        address = object_instance.object.data.as_pointer()
        key = self._by_address.get(address)
        if key is None:
            base = key = geometry_key(object_instance, self._render)
            count = 1
            while key in self._taken:
                key = f"{base}#{count}"
                count += 1
            self._by_address[address] = key
            self._taken.add(key)
        return key


def geometry_key(object_instance, render):
    """A name for the geometry of a mesh instance that survives re-evaluation, as
    Cycles keys its geometry: the original mesh data-block when the object shows it
    as it is (every user shares it), the original object where modifiers or
    geometry nodes make the geometry its own, and the instancer for geometry an
    instancer generates (geometry nodes, curves made into meshes)."""
    original = object_instance.object.original
    if object_instance.is_instance:
        owner = object_instance.parent.original
        # A generated geometry's temporary object reports its instancer as original.
        if original == owner or original.type != "MESH":
            return f"object:{owner.name_full}"
    if original.type != "MESH" or _own_geometry(original, render):
        return f"object:{original.name_full}"
    return f"mesh:{original.data.name_full}"


def key_owner(key):
    """The name of the data-block a geometry key is made from (its mesh's, object's or
    instancer's: what follows geometry_key's "mesh:" or "object:")."""
    return key.partition(":")[2] or key


def _own_geometry(obj, render):
    # Modifiers (geometry nodes among them) or edit mode make an object's evaluated
    # mesh its own: no other user of the data-block shares it.
    enabled = "show_render" if render else "show_viewport"
    return obj.mode == "EDIT" or any(getattr(m, enabled) for m in obj.modifiers)
