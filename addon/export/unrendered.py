"""What a scene holds that Cycles renders and Whitted does not yet: found while the
depsgraph is walked, so that nothing vanishes from the image without a report line
naming it (the object, what it is, and why).

Cycles renders, and Whitted skips: the world's Volume output, and a material's Volume
output that is not a constant (homogeneous) one (export/volume.py says which are
rendered). A Volume object that cannot be read is reported by sync/volumes.py.
(Hair curves, point clouds and particle hair are rendered: export/curves.py; shadow
catchers too: export/instance.py is_shadow_catcher. A geometry-nodes curve on a mesh
object reaches a render as an empty legacy curve, which Cycles skips too: it is not
listed.)
"""

from .nodes.graph import source


def volume_warning(owner, output_node, why):
    """A report line when the Volume input of a material's or world's output node
    `output_node` is linked (`owner`: "material 'Smoke'"), saying `why` it is not
    rendered, else None."""
    socket = output_node.inputs.get("Volume")
    if socket is None or source(socket)[0] is None:  # reroutes followed, muted links not
        return None
    return f"Whitted: {owner} has a volume shader, which is not rendered: {why}"
