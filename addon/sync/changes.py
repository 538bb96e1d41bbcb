"""What one depsgraph update says changed, as plain sets of names.

`depsgraph.updates` lists the evaluated data-blocks that changed since the last
evaluation, with flags for transform, geometry and shading. It never lists an
object that was removed or hidden: those show only as an update of the Scene and
of a Collection, so such an update makes the sync compare the set of instances
it exported with the depsgraph's (`SceneSync`).
"""

from dataclasses import dataclass, field

# Data-block types whose update the sync handles without walking every instance.
_MATERIAL = "Material"
_WORLD = "World"
_IMAGE = "Image"
_NODE_TREES = {"ShaderNodeTree"}
_LIGHTS = {"Light", "PointLight", "SpotLight", "SunLight", "AreaLight"}
_CAMERAS = {"Camera"}


@dataclass
class Changes:
    """Names of the original data-blocks an update touched, by what it touched."""

    transformed: set = field(default_factory=set)  # objects moved (or their children)
    reshaped: set = field(default_factory=set)  # objects whose geometry changed
    objects: set = field(default_factory=set)  # every object listed, for any reason
    evaluated_objects: list = field(default_factory=list)  # those objects, evaluated
    meshes: set = field(default_factory=set)  # mesh data-blocks whose geometry changed
    materials: set = field(default_factory=set)
    images: set = field(default_factory=set)
    lights: set = field(default_factory=set)  # light data-blocks
    node_groups: bool = False  # a shared (not a material's own) node tree changed
    world: bool = False
    scene: bool = False  # the scene itself: settings, and objects added/removed/hidden
    structure: bool = False  # a collection or another data-block the sync cannot place


def classify(updates):
    """Changes from `depsgraph.updates` (a sequence of DepsgraphUpdate)."""
    changes = Changes()
    for update in updates:
        block = update.id
        kind = type(block).__name__
        name = block.original.name_full
        if kind == "Object":
            changes.objects.add(name)
            changes.evaluated_objects.append(block)
            if update.is_updated_transform:
                changes.transformed.add(name)
            if update.is_updated_geometry:
                changes.reshaped.add(name)
        elif kind == "Mesh":
            if update.is_updated_geometry:
                changes.meshes.add(name)
        elif kind == _MATERIAL:
            changes.materials.add(name)
        elif kind == _IMAGE:
            changes.images.add(name)
        elif kind in _LIGHTS:
            changes.lights.add(name)
        elif kind == _WORLD:
            changes.world = True
        elif kind in _NODE_TREES:
            # A material's own tree is listed with its material; a node group is not.
            changes.node_groups |= not block.is_embedded_data
        elif kind == "Scene":
            changes.scene = True
        elif kind not in _CAMERAS:
            # Collections (objects added, removed, hidden), and any data-block that
            # objects use in ways the sync does not track (armatures, curves, shape
            # keys, geometry-node trees, ...): compare every instance.
            changes.structure = True
    return changes
