"""What a scene holds that Cycles renders and Whitted does not yet: found while the
depsgraph is walked, so that nothing vanishes from the image without a report line
naming it (the object, what it is, and why).

Cycles renders, and Whitted skips: the world's Volume output, and a material's Volume
output that is not a constant (homogeneous) one (export/volume.py says which are
rendered). A Volume object that cannot be read is reported by sync/volumes.py.
Cycles renders otherwise, and Whitted as ordinary objects: shadow catchers
(Object > Visibility > Shadow Catcher). (Hair curves, point
clouds and particle hair are rendered: export/curves.py. A geometry-nodes curve on a
mesh object reaches a render as an empty legacy curve, which Cycles skips too: it is not
listed.)
"""

from .nodes.graph import source

# The object types whose Shadow Catcher flag Cycles reads: geometry. Blender 3.4 sets the
# flag on every new lamp (a new point lamp reads True), where it means nothing.
GEOMETRY_TYPES = frozenset(
    {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME"}
)

# What the report says of each kind's objects, and why.
PHRASE = {
    "shadow catchers": "set as shadow catchers, rendered as ordinary objects",
}
WHY = {
    "shadow catchers": "Cycles shows only the shadows cast on them; Whitted has no shadow "
    "catcher yet",
}

# At most this many names in a report line, then "...".
MAX_NAMES = 3


def unrendered_kind(object_instance):
    """The kind (a PHRASE key) of what `object_instance` of an evaluated depsgraph
    shows otherwise in Cycles than in Whitted, or None."""
    obj = object_instance.object
    if obj.original.hide_render:
        return None
    if obj.type in GEOMETRY_TYPES and getattr(obj.original, "is_shadow_catcher", False):
        return "shadow catchers"
    return None


def unrendered_warnings(found):
    """Report lines for `found`: kind -> the names of the objects (a set)."""
    lines = []
    for kind in sorted(found):
        names = sorted(found[kind])
        shown = ", ".join(f"'{name}'" for name in names[:MAX_NAMES])
        more = "..." if len(names) > MAX_NAMES else ""
        lines.append(f"Whitted: {len(names)} object(s) {PHRASE[kind]} ({shown}{more}): {WHY[kind]}")
    return lines


def volume_warning(owner, output_node, why):
    """A report line when the Volume input of a material's or world's output node
    `output_node` is linked (`owner`: "material 'Smoke'"), saying `why` it is not
    rendered, else None."""
    socket = output_node.inputs.get("Volume")
    if socket is None or source(socket)[0] is None:  # reroutes followed, muted links not
        return None
    return f"Whitted: {owner} has a volume shader, which is not rendered: {why}"
