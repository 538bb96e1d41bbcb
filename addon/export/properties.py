"""The Attribute node's Object, Instancer and View Layer attributes: a custom or RNA
property of an object, its instancer or the view layer, read as an RGBA value the way
Cycles looks them up (Blender's find_property_rgba, BKE_object_dupli_find_rgba_attribute
and BKE_view_layer_find_rgba_attribute, read there and written anew here).

Pure functions of Blender data to plain tuples; `None` is "not found here", MISSING what
the node reads where nothing has the name."""

from numbers import Real

# What Cycles gives for a name none of the places looked at has: all four components 0
# (the alpha too).
MISSING = (0.0, 0.0, 0.0, 0.0)


def property_rgba(owner, name):
    """`owner`'s (an ID or a struct with custom properties, or None) custom property
    `name`, else the RNA property at path `name`, as RGBA: a number v (a boolean as 0 or
    1) -> (v, v, v, 1); an array of 1 to 4 numbers fills the first components of
    (0, 0, 0, 1); None for anything else (no such property, a string, a longer array, a
    pointer)."""
    if owner is None or not name:
        return None
    keys = owner.keys() if hasattr(owner, "keys") else ()
    if name in keys:
        value = owner[name]
    else:
        try:
            value = owner.path_resolve(name)
        except ValueError:  # no property at that path
            return None
    return _rgba(value)


def _rgba(value):
    if isinstance(value, Real):  # booleans too
        return (float(value),) * 3 + (1.0,)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        return None
    items = list(value)
    if not 1 <= len(items) <= 4:
        return None
    if any(isinstance(x, bool) or not isinstance(x, Real) for x in items):
        return None  # booleans, or rows of a matrix
    return tuple(float(x) for x in items) + (0.0, 0.0, 0.0, 1.0)[len(items) :]


def instance_attribute(object_instance, name, instancer):
    """The Object (`instancer` False) or Instancer (True) attribute `name` of a depsgraph
    object instance, as Cycles finds it: for Instancer on an instance, its particle
    system's settings, then its instancer (the dupli parent); then the instanced object,
    then its data (the mesh); MISSING where none has it. Geometry nodes' instance
    attributes are not read (the Python API does not give them)."""
    places = []
    if instancer and object_instance.is_instance:
        system = object_instance.particle_system
        if system is not None:
            places.append(system.settings)
        places.append(object_instance.parent)
    obj = object_instance.object
    places += [obj, obj.data]
    return _first(places, name)


def view_layer_attribute(view_layer, name):
    """The View Layer attribute `name`: the view layer's property, else its scene's,
    else the scene's world's; MISSING where none has it."""
    scene = view_layer.id_data
    return _first((view_layer, scene, scene.world), name)


def _first(places, name):
    for place in places:
        value = property_rgba(place, name)
        if value is not None:
            return value
    return MISSING
